"""How often must ANY planner continuous on pmplan's domains miss the radii in a room? A lower
bound, measured.

Usage (from the repository root)::

    python benchmarks/gap_bound.py --count 400 --seeds 11
    python benchmarks/gap_bound.py --count 400 --seeds 30,31 --keep earlier.json  # add seeds
    python benchmarks/gap_bound.py --from-json   # rewrite the report from its JSON

Mathematics §8 proves that no planner continuous on the domains of the obstacle-line planners
(in the box ``bounds``, conjugated by the box's map ``phi``) keeps the radii on every query of
a room whose obstacles may sit closer to a wall than ``2 radius + obstacle_radius``. This
script measures *how often* such a planner must miss them, on the scene families' own
distribution (``benchmarks/scenes.py``), whatever its section, refinement or effort.

The argument (Mathematics §8, "How often"): let ``y = phi^-1(q)`` be the query in R^d, ``e``
and ``nu(e)`` its frame, and move one obstacle ``o_k`` (k >= 3), or ``o_1`` and ``o_2``
together, along ``nu(e)`` in R^d. No column changes, so the query stays in its piece (Mathematics
§4.2) and the planner is continuous along the move. A robot whose start and goal columns lie on
either side of ``o_k``'s column crosses the line through ``o_k`` along ``nu`` an odd number of
times, hence exactly one of the two rays from ``o_k`` (towards ``+nu`` or ``-nu``) an odd number
of times; that parity cannot change during the move (the path would have to pass through
``o_k``). So the robot passes ``o_k`` on one fixed side along the whole move. In the box that
side is the image ``phi(ray)``, a curve from ``o_k`` to the boundary. It is *closed* to the
robot when a segment ``sigma`` from ``o_k`` to its foot on a wall is shorter than ``2 radius +
obstacle_radius`` and ``sigma`` with that curve cuts the box into two parts with the robot's
start and goal in one (:func:`closed_sides`): the path then crosses ``sigma``, where it is too
close to ``o_k`` or to the wall. Along the move, let ``a_+`` and
``a_-`` be the shares of the family's positions of ``o_k`` (its conditional law on the line:
the box measure pulled back, ``det D phi``, on the positions the family allows) at which the
``+`` or the ``-`` side is closed. Every continuous planner misses the radii on a share at
least ``min(a_+, a_-)`` of that line, whichever side it chose.

Per query the script reports that share for the worst unit (``bound_max``: a lower bound on the
probability of missing, given the rest of the query, up to the approximations below) and, as
the positions of different obstacles along their lines are nearly independent under the
family, ``1 - prod(1 - share)`` over the units (``bound_all``). The row's bound is the mean
over its queries. Approximations, all small and stated: the family draws its points one at a
time with rejection (``scenes._draw``), so the law of one obstacle along its line is uniform
(in the box measure) only up to the later draws' normalisers, which an obstacle near a wall
changes by at most the area of one clipped exclusion disc (~2% per obstacle, ~0.4% per robot
drawn after it); the sides are decided on a grid of step ``STEP`` along the line in R^d, and
only a segment ``sigma`` shorter than the limit by ``STEP`` counts as narrow, which can only
make a side look open (conservative).

Writes ``benchmarks/gap_bound.json`` (the command and the rows) and ``.md``; the report marks
the seeds that are not ``DESIGN_SEEDS`` held out. Not a test module.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes

from pmplan import frame
from pmplan.planners.base import CROWD_LANES, WALL_LANES
from pmplan.workspace import from_box_linear, into_box_linear, into_box_linear_slope

HERE = Path(__file__).resolve().parent
#: radius = obstacle_radius = R / 2, as in the scene benchmark
RADIUS = scenes.R / 2
#: a segment from an obstacle to a wall shorter than CLOSE_O + CLOSE_W is narrower than a
#: robot: every point of it is within CLOSE_O of the obstacle or within CLOSE_W of the wall
CLOSE_O = 2 * RADIUS
CLOSE_W = RADIUS
#: the line through o_k along nu in R^d is sampled at this step for |t| <= REACH
STEP = 0.005
REACH = 60.0
FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [2, 4, 8, 16]
#: the seeds pmplan's defaults were chosen on (``benchmarks/still_ab.py``'s design seeds); the
#: report marks the others held out
DESIGN_SEEDS = (11, 12)


def _wall(p: np.ndarray, box: np.ndarray) -> np.ndarray:
    """Distance of box points (..., 2) to the nearest wall."""
    return np.minimum(p - box[0], box[1] - p).min(-1)


def _orient(a, b, c):
    """Sign of the orientation of (a, b, c) for arrays of points (..., 2)."""
    return np.sign((b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
                   - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0]))


def _cross(p, q, a, b) -> np.ndarray:
    """Whether segment pq properly crosses the segments ab (a, b: (..., 2))."""
    return ((_orient(p, q, a) * _orient(p, q, b) < 0)
            & (_orient(a, b, p) * _orient(a, b, q) < 0))


def _feet(P: np.ndarray, box: np.ndarray):
    """The feet of box points (T, 2) on the four walls, (4, T, 2), and their distances (4, T)."""
    feet = np.repeat(P[None], 4, axis=0)
    feet[0, :, 0] = box[0, 0]
    feet[1, :, 0] = box[1, 0]
    feet[2, :, 1] = box[0, 1]
    feet[3, :, 1] = box[1, 1]
    return feet, np.hypot(*(feet - P[None]).transpose(2, 0, 1))


def closed_sides(P: np.ndarray, j: np.ndarray, start: np.ndarray, goal: np.ndarray,
                 box: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For an obstacle at the grid points ``j`` of its sampled line ``P`` (T, 2) (the image of
    its line along nu), and one robot from ``start`` to ``goal`` that must pass it: whether the
    ``+`` side (the curve beyond j) and the ``-`` side (before j) are closed to that robot.

    A side is closed when some segment ``sigma`` from the obstacle to its foot on a wall is
    shorter than ``CLOSE_O + CLOSE_W`` (every point of it is too close to the obstacle or to the
    wall) and ``sigma`` together with that side's curve cuts the box into two parts with the
    robot's start and goal in the same one: a path crossing the side's curve an odd number of
    times then crosses ``sigma`` an odd number of times too (it cannot cross the walls). Same
    part: the segment from start to goal crosses the cut an even number of times."""
    edges = _cross(start, goal, P[:-1], P[1:]).astype(np.int64)  # (T-1,)
    before = np.concatenate([[0], np.cumsum(edges)])  # crossings of P[:j]: before[j]
    after = before[-1] - before  # crossings of P[j:]
    feet, dist = _feet(P[j], box)
    narrow = dist < CLOSE_O + CLOSE_W - STEP  # (slack: only a clearly narrow segment counts)
    sig = _cross(start, goal, P[j][None], feet)  # (4, J)
    plus = np.any(narrow & ((after[j][None] + sig) % 2 == 0), axis=0)
    minus = np.any(narrow & ((before[j][None] + sig) % 2 == 0), axis=0)
    return plus, minus


def query_bound(o: np.ndarray, s: np.ndarray, g: np.ndarray, box: np.ndarray,
                wall_gap: float) -> dict:
    """The shares of every unit of one query (module docstring)."""
    m = len(o)
    yo, ys, yg = (from_box_linear(x, box) for x in (o, s, g))
    e = frame.unit(yo[1] - yo[0])
    nu = frame.nu(yo[1] - yo[0])[0]  # (Mathematics §3.4)
    co, cs, cg = ((y - yo[0]) @ e for y in (yo, ys, yg))  # columns
    lo_c, hi_c = np.minimum(cs, cg), np.maximum(cs, cg)
    t = np.arange(-REACH, REACH + STEP / 2, STEP)
    robots = np.concatenate([s, g])
    units = [[0, 1]] + [[k] for k in range(2, m)]
    shares = []
    for unit in units:
        passing = [np.flatnonzero((lo_c < co[k]) & (co[k] < hi_c)) for k in unit]
        if not any(len(p) for p in passing):
            shares.append(0.0)
            continue
        others = np.delete(o, unit, axis=0)
        valid = np.ones(len(t), bool)
        dens = np.ones(len(t))
        curves = []
        for k in unit:
            yk = yo[k][None] + t[:, None] * nu[None]
            P = into_box_linear(yk, box)
            curves.append(P)
            dens = dens * into_box_linear_slope(yk, box).prod(-1)
            valid &= _wall(P, box) >= wall_gap
            if len(others):
                valid &= np.hypot(*(P[:, None] - others[None]).transpose(2, 0, 1)).min(1) \
                    >= scenes.OBSTACLE_GAP
            valid &= np.hypot(*(P[:, None] - robots[None]).transpose(2, 0, 1)).min(1) \
                >= scenes.MARGIN * scenes.R
        j = np.flatnonzero(valid)
        if j.size == 0:
            shares.append(0.0)
            continue
        wts = dens[j] / dens[j].sum()
        # each robot that must pass an obstacle of the unit passes it on one side along the
        # whole move, and misses the radii wherever that side is closed to it: whichever side
        # the planner chose, at least the smaller closed share of the two
        best = 0.0
        for k, P, pas in zip(unit, curves, passing):
            near = np.flatnonzero(_wall(P[j], box) < CLOSE_O + CLOSE_W)
            if near.size == 0:
                continue
            wn = wts[near]
            for i in pas:
                plus, minus = closed_sides(P, j[near], s[i], g[i], box)
                best = max(best, min(float(wn[plus].sum()), float(wn[minus].sum())))
        shares.append(best)
    shares = np.asarray(shares)
    return {"shares": shares.tolist(), "max": float(shares.max()),
            "all": float(1.0 - np.prod(1.0 - shares))}


def row(fam: str, n: int, seed: int, count: int) -> dict:
    box = np.array([[0.0, 0.0], [scenes.SIZE, scenes.SIZE]])
    fam_ = scenes.FAMILIES[fam]
    qs = scenes.queries(fam, n, count, seed)
    res = [query_bound(o, s, g, box, fam_.wall) for o, s, g in qs]
    # pmplan's plan in the box on the same queries with the section of its default on the
    # domains of Mathematics §4.2 (without the wall side, which cuts them): "" (valid), gap,
    # contact
    why = []
    for o, s, g in qs:
        p = scenes.refined_on_domains(o, s, g)
        why.append("" if p.respects_radius else
                   "gap" if p.radius_miss.category == "gap" else "contact")
    mx = np.array([r["max"] for r in res])
    al = np.array([r["all"] for r in res])

    def se(a):
        return float(a.std(ddof=1) / np.sqrt(len(a)))

    return {"family": fam, "n": n, "seed": seed, "count": count,
            "bound_max": float(mx.mean()), "bound_max_se": se(mx),
            "bound_all": float(al.mean()), "bound_all_se": se(al),
            "share_any": float((mx > 0).mean()),
            "pmplan_valid": why.count("") / count, "pmplan_gap": why.count("gap") / count,
            "pmplan_contact": why.count("contact") / count}


def markdown(rows: list, argv: list) -> str:
    out = ["# How often any continuous planner must miss the radii in a room: a lower bound", "",
           (f"Command: `python benchmarks/gap_bound.py {' '.join(argv)}`. "
           "Rooms 10 x 10, r = 0.3, radius = obstacle_radius = r/2, the scene families' own "
           "draws (`benchmarks/scenes.py`). For each query, one obstacle (or o1 and o2 "
           "together) is moved along nu(e) in R^d, which keeps the query in its piece: every "
           "planner continuous on pmplan's domains (in the box, conjugated by its map) keeps "
           "one side of it for every robot that must pass it, and misses the radii wherever "
           "that side is closed (Mathematics §8). *bound (worst obstacle)*: the mean over the "
           "queries of the least share, over the two sides, of the line on which the side is "
           "closed, for the worst obstacle; *bound (all obstacles)*: the same with the "
           "obstacles' moves taken as independent; +- one standard error over the queries; "
           "*queries exposed*: the share of queries with a positive share. Seeds "
           f"{', '.join(map(str, DESIGN_SEEDS))} are those pmplan's defaults were chosen on; "
           "the others are held out. *pmplan, these domains*: pmplan's refined plan in the box "
           f"with the section of its default on these domains (the compact lanes up to "
           f"{CROWD_LANES - 1} robots, the one-side lanes on the side of nu(e) from "
           f"{CROWD_LANES} on); pmplan's default in a box from {WALL_LANES} robots on, "
           "`obstacle_line_walls`, has its domains cut along the wall of sides, which these "
           "moves cross, so this bound does not bind it (Mathematics §8, \"The side of the "
           "lanes\"; `benchmarks/sides_ab.md`)."), "",
           ("| seed | row | queries | queries exposed | bound (worst obstacle) "
           "| bound (all obstacles) | best valid share any continuous planner can expect "
           "| pmplan, these domains: valid | misses: gap | misses: contact |"),
           "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        seed = f"{r['seed']}" + ("" if r["seed"] in DESIGN_SEEDS else " (held out)")
        out.append(f"| {seed} | {r['family']} n = {r['n']} | {r['count']} | "
                   f"{r['share_any']:.3f} | {r['bound_max']:.4f} +- {r['bound_max_se']:.4f} | "
                   f"{r['bound_all']:.4f} +- {r['bound_all_se']:.4f} | "
                   f"{1 - r['bound_all']:.3f} | {r['pmplan_valid']:.3f} | "
                   f"{r['pmplan_gap']:.3f} | {r['pmplan_contact']:.3f} |")
    seeds = sorted({r["seed"] for r in rows})
    exposed = [(f, n) for f in dict.fromkeys(r["family"] for r in rows)
               for n in sorted({r["n"] for r in rows if r["family"] == f})
               if any(r["bound_all"] > 0 for r in rows if (r["family"], r["n"]) == (f, n))]
    if exposed:
        by = {(r["seed"], r["family"], r["n"]): r for r in rows}
        out += ["", "pmplan's gap misses over the bound (all obstacles), per seed: 1 is as few "
                "as the bound says any continuous planner expects (an expectation: a draw of "
                f"{rows[0]['count']} queries may fall below it); the rows whose bound is 0 are "
                "left out. Up "
                f"to {CROWD_LANES - 1} robots the section is the compact lanes, "
                f"from {CROWD_LANES} on the one-side lanes.", "",
                "| row | " + " | ".join(f"seed {x}" for x in seeds) + " |",
                "|---|" + "---|" * len(seeds)]
        for f, n in exposed:
            cells = [by.get((x, f, n)) for x in seeds]
            out.append(f"| {f} n = {n} | " + " | ".join(
                "" if c is None else f"{c['pmplan_gap'] / c['bound_all']:.2f}" for c in cells)
                + " |")
    kept = sorted({r["kept"] for r in rows if r.get("kept")})
    if kept:
        parts = []
        for k in kept:
            ks = [r for r in rows if r.get("kept") == k]
            ns = ", ".join(str(n) for n in sorted({r["n"] for r in ks}))
            from_seeds = ", ".join(str(x) for x in sorted({r["seed"] for r in ks}))
            by_argv = next((r["kept_argv"] for r in ks if r.get("kept_argv")), None)
            run = "" if by_argv is None else \
                f", written by `python benchmarks/gap_bound.py {' '.join(by_argv)}`"
            parts.append(f"n = {ns} (seeds {from_seeds}, {len(ks)} rows) from "
                         f"`{Path(k).name}`{run}")
        out += ["", "Rows kept from an earlier run (`--keep`), not planned again: "
                + "; ".join(parts) + "."]
    return "\n".join(out) + "\n"


def _kept_rows(path) -> list:
    """The rows of an earlier run's JSON (``{"argv": ..., "rows": [...]}``, or a bare list of
    rows from the runs before the JSON kept its command), each marked with where it was kept
    from: ``kept``, the file, and ``kept_argv``, the command that wrote it, when known."""
    data = json.loads(Path(path).read_text())
    rows, argv = (data["rows"], data["argv"]) if isinstance(data, dict) else (data, None)
    return [r if r.get("kept") else dict(r, kept=str(path), kept_argv=argv) for r in rows]


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=400)
    ap.add_argument("--seeds", default="11")
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--ns", default=",".join(map(str, NS)))
    ap.add_argument("--out", default=str(HERE / "gap_bound"))
    ap.add_argument("--keep", default=None, metavar="JSON",
                    help="an earlier run's JSON: its rows this run does not plan are kept (the "
                    "report says which)")
    ap.add_argument("--from-json", action="store_true",
                    help="rewrite the report from the JSON at --out, planning nothing")
    a = ap.parse_args(argv)
    if a.from_json:
        data = json.loads(Path(a.out + ".json").read_text())
        Path(a.out + ".md").write_text(markdown(data["rows"], data["argv"]))
        return 0
    rows = []
    for seed in (int(x) for x in a.seeds.split(",")):
        for fam in a.families.split(","):
            for n in (int(x) for x in a.ns.split(",")):
                r = row(fam, n, seed, a.count)
                rows.append(r)
                print(f"seed {seed} {fam} n={n}: exposed {r['share_any']:.3f}, "
                      f"bound {r['bound_max']:.4f} / {r['bound_all']:.4f}", flush=True)
    if a.keep:
        done = {(r["seed"], r["family"], r["n"]) for r in rows}
        kept = [r for r in _kept_rows(a.keep) if (r["seed"], r["family"], r["n"]) not in done]
        order = {f: i for i, f in enumerate(FAMILIES)}
        rows = sorted(rows + kept, key=lambda r: (r["seed"], order.get(r["family"], 99), r["n"]))
    Path(a.out + ".json").write_text(json.dumps({"argv": argv, "rows": rows}, indent=1))
    Path(a.out + ".md").write_text(markdown(rows, argv))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
