"""How much longer than the straight lines must ANY planner continuous on pmplan's domains go?
A lower bound on the price of continuity in length, measured in the scene rooms.

Usage (from the repository root; ``--ompl`` needs ``pmplan[bench]``, i.e. ``ompl``)::

    python benchmarks/length_bound.py --ompl        # seeds 11 and 12, 400 queries per row

The argument (Mathematics §8, "How long"). Let ``y = phi^-1(q)`` be a planar query in R^2
(``phi``: the box's map, :mod:`pmplan.workspace`), ``L`` the line through ``y``'s ``o_1`` and
``o_2``, and scale every point's signed distance to ``L`` by ``1 - 2t``, t in [0, 1]: the move
ends at the mirror image of ``y`` in ``L``, and ``q* = phi(mirror image)`` is a query in the
box. No column (Mathematics §3.1) changes, so the move stays in one piece (Mathematics §4.2)
and every planner continuous on these domains (in the box: conjugated by ``phi``) is
continuous along it. Close robot i's path with the segment from its goal ``B`` back to its start
``A``: the winding number of that loop around an obstacle ``o_k`` changes only when ``o_k``
passes through the segment. For the obstacles ``S_i`` that pass through it an odd number of
times along the move (in R^2: exactly those whose column lies strictly between ``A``'s and
``B``'s, once, at t = 1/2; in the box it is counted on the move, :func:`crossing_parity`), the
winding numbers at ``q`` and at ``q*`` differ, so robot i's path encloses ``o_k`` at ``q`` or at
``q*``. A path whose loop encloses a set ``T`` of points is at least ``P(T) =
perimeter(conv(A, B, T)) - |AB|`` long (the convex hull of the loop contains ``T``, and a
closed curve is at least as long as its hull's perimeter). Hence

    len(q) / LB(q) + len(q*) / LB(q*) >= sum_i min_T (P_q(T) + P_q*(S_i \\ T)) / LB,

with each ``P`` and ``LB`` (the sum of the straight distances) in its own query, and the bound
of a query is half the right-hand side: the mean len/LB over ``q`` and ``q*`` of any planner
continuous on pmplan's domains. The row's bound is its mean over the queries. Obstacles are
points here (the radii only lengthen paths) and each robot is alone (the others only lengthen
its path): the bound is loose, never wrong. It is a bound on the law of the pair (a query of the
family, then it or its mirror image with equal chances), not on the family's law alone: the
family is not symmetric under the mirror, but a planner continuous on these domains cannot tell
``q`` from ``q*`` by any choice it keeps along the move.

Beside it, on the same pairs: pmplan's refined plan in the box with its default's section on
these domains (``scenes.refined_on_domains``: the compact lanes, the one-side lanes from 8
robots; pmplan's default in a box, ``obstacle_line_walls``, has its domains cut along the wall
of sides, which the mirror move crosses, so the bound does not bind it) and,
with ``--ompl``, OMPL RRTConnect (as ``scenes_compare.py``: simplified, exact motion validator,
one run per query). ``q*`` may bring two points closer than the radii (the map into the box
compresses the band along the walls); such pairs count for the bound but not in the planners'
columns, which are over the pairs both planners solve (pmplan returns a plan, RRTConnect
solves both queries validly).

Writes ``benchmarks/length_bound.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import itertools
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import scenes
import scenes_compare as sc
from _common import rewrite_report, write_report

import pmplan
from pmplan.frame import nu
from pmplan.workspace import from_box_linear, into_box_linear

FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [2, 4, 8]
BOX = np.array([[0.0, 0.0], [scenes.SIZE, scenes.SIZE]])
#: a box whose map is the identity on every point of the families and of their mirror images
#: (its band starts 1e4 from the scene): the plane itself
PLANE = np.array([[-1e5, -1e5], [1e5, 1e5]])
#: the mirror move is sampled at this many parameters t (a crossing of the segment shows as a
#: jump of the angle it subtends across +-pi, whatever the step)
SAMPLES = 2001


def hull_perimeter(pts: np.ndarray) -> float:
    """The perimeter of the convex hull of planar points (k, 2) (Andrew's monotone chain; two
    distinct points: twice their distance)."""
    p = np.unique(np.asarray(pts, dtype=float), axis=0)
    if len(p) < 2:
        return 0.0

    def chain(points):
        out = []
        for q in points:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (q[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (q[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(q)
        return out

    hull = np.array(chain(p)[:-1] + chain(p[::-1])[:-1])
    return float(np.linalg.norm(np.roll(hull, -1, axis=0) - hull, axis=1).sum())


def in_strip(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Whether each obstacle's column (along ``o[1] - o[0]``) lies strictly between ``a``'s and
    ``b``'s: in R^2, the obstacles the mirror move carries through the segment ``ab``."""
    e = o[1] - o[0]
    ca, cb, co = (a - o[0]) @ e, (b - o[0]) @ e, (o - o[0]) @ e
    return (co > min(ca, cb)) & (co < max(ca, cb))


def mirror_move(o, s, g, box=BOX, samples=SAMPLES, t=None,
                maps=(from_box_linear, into_box_linear)) -> np.ndarray:
    """The mirror move of a query in the box: in R^2 (``phi^-1``) every point's signed distance
    to the line through ``o_1`` and ``o_2`` scaled by ``1 - 2t``, mapped back into the box
    (``phi``). The points (samples, m + 2n, 2) at ``t = 0, .., 1`` (or at the times ``t``): the
    query (up to the map's rounding) at t = 0, its mirror image ``q*`` at t = 1. ``maps``:
    ``(phi^-1, phi)``, by default those of ``plan(bounds=)``."""
    out_of, into = maps
    y = out_of(np.concatenate([o, s, g]), box)
    v = nu(y[1] - y[0])[0]
    h = (y - y[0]) @ v
    t = np.linspace(0.0, 1.0, samples) if t is None else np.asarray(t, dtype=float)
    return into(y[None] - (2.0 * t)[:, None, None] * h[None, :, None] * v, box)


def crossing_parity(move: np.ndarray, m: int, n: int) -> np.ndarray:
    """(n, m): whether obstacle k passes through robot i's segment from start to goal an odd
    number of times along ``move`` (:func:`mirror_move`): the signed angle the segment
    subtends at the obstacle jumps across +-pi exactly there."""
    o, a, b = move[:, :m], move[:, m:m + n], move[:, m + n:]
    u = a[:, :, None] - o[:, None]
    w = b[:, :, None] - o[:, None]
    ang = np.arctan2(u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0], (u * w).sum(-1))
    return (np.abs(np.diff(ang, axis=0)) > np.pi).sum(0) % 2 == 1


def pair_bound(q, q_star, odd: np.ndarray) -> float:
    """Half of ``sum_i min_T (P_q(T) + P_q*(S_i \\ T)) / LB`` (module docstring): the least
    mean len/LB over ``q`` and ``q*`` of a path pair whose robots enclose, at ``q`` or at
    ``q*``, every obstacle ``odd`` marks."""
    (o, s, g), (o2, s2, g2) = q, q_star
    lb1, lb2 = sc._lb(s, g), sc._lb(s2, g2)
    total = 0.0
    for i in range(len(s)):
        k = np.flatnonzero(odd[i])
        ab, ab2 = float(np.linalg.norm(g[i] - s[i])), float(np.linalg.norm(g2[i] - s2[i]))
        best = np.inf
        for mask in itertools.product([False, True], repeat=len(k)):
            mk = np.array(mask, dtype=bool)
            p1 = hull_perimeter(np.vstack([s[i], g[i], o[k[mk]]])) - ab
            p2 = hull_perimeter(np.vstack([s2[i], g2[i], o2[k[~mk]]])) - ab2
            best = min(best, (p1 / lb1 + p2 / lb2) / 2.0)
        total += best
    return total


def mirror_pair(o, s, g, box=BOX):
    """``(q, q*, bound)``: the query, its mirror image (:func:`mirror_move`) and the bound of the
    pair (:func:`pair_bound`)."""
    m, n = len(o), len(s)
    move = mirror_move(o, s, g, box)
    end = move[-1]
    q_star = (end[:m], end[m:m + n], end[m + n:])
    return (o, s, g), q_star, pair_bound((o, s, g), q_star, crossing_parity(move, m, n))


def _len_lb(plan, s, g) -> float:
    return plan.path.length() / sc._lb(s, g)


def query_row(o, s, g, ompl=None) -> dict:
    """One query: the bound in the box, pmplan's (and RRTConnect's) len/LB at ``q`` and ``q*``
    there; the bound in the plane (the mirror image in R^2 itself, which may leave the box) and
    pmplan's len/LB without the box at ``q`` and that ``q*``."""
    m = len(o)
    q, q_star, bound = mirror_pair(o, s, g)
    out = {"bound": bound}
    for name, (oo, ss, gg) in (("q", q), ("mirror", q_star)):
        try:  # the map into the box may bring q*'s points closer than the radii
            out[f"pmplan_{name}"] = _len_lb(scenes.refined_on_domains(oo, ss, gg), ss, gg)
        except pmplan.PmplanError:
            out[f"pmplan_{name}"] = float("nan")
        if ompl is not None:
            out[f"rrtc_{name}"] = float("nan")
            if scenes.check(oo, ss, gg):  # OMPL's start and goal must keep the radii
                _, res = ompl.plan(oo, ss, gg)
                if res is not None and sc.valid(res[1], m)[0]:
                    out[f"rrtc_{name}"] = sc._length(res[1]) / sc._lb(ss, gg)
    q, q_star, out["plane_bound"] = mirror_pair(o, s, g, PLANE)
    for name, (oo, ss, gg) in (("q", q), ("mirror", q_star)):
        plan = pmplan.plan(oo, ss, gg, refine=True, radius=scenes.R / 2,
                           obstacle_radius=scenes.R / 2)  # (a mirror keeps every distance)
        out[f"plane_{name}"] = _len_lb(plan, ss, gg)
    return out


def row(fam: str, n: int, seed: int, count: int, kernels=None) -> dict:
    t0 = time.perf_counter()
    ompl = None
    if kernels is not None:
        ompl = sc.OmplRunner(n, 2, sc.RC, kernels)
    per = [query_row(o, s, g, ompl) for o, s, g in scenes.queries(fam, n, count, seed)]
    b = np.array([p["bound"] for p in per])
    out = {"family": fam, "n": n, "seed": seed, "count": count, "bound": float(b.mean()),
           "bound_se": float(b.std(ddof=1) / np.sqrt(len(b))),
           "share_above_1": float((b > 1.0 + 1e-9).mean())}
    keys = ["pmplan_q", "pmplan_mirror"] + (["rrtc_q", "rrtc_mirror"] if ompl else [])
    both = [p for p in per if all(np.isfinite(p[k]) for k in keys)]
    out["pairs"] = len(both)
    for who in ("pmplan", "rrtc") if ompl else ("pmplan",):
        out[who] = float(np.mean([(p[f"{who}_q"] + p[f"{who}_mirror"]) / 2 for p in both]))
    out["bound_pairs"] = float(np.mean([p["bound"] for p in both]))
    out["pmplan_below"] = sum((p["pmplan_q"] + p["pmplan_mirror"]) / 2 < p["bound"] - 1e-9
                              for p in both)
    out["plane_bound"] = float(np.mean([p["plane_bound"] for p in per]))
    out["plane_pmplan"] = float(np.mean([(p["plane_q"] + p["plane_mirror"]) / 2 for p in per]))
    out["plane_below"] = sum((p["plane_q"] + p["plane_mirror"]) / 2 < p["plane_bound"] - 1e-9
                             for p in per)
    out["seconds"] = time.perf_counter() - t0
    print(f"seed {seed} {fam} n={n}: bound {out['bound']:.3f} +- {out['bound_se']:.3f}; over "
          f"{len(both)} pairs bound {out['bound_pairs']:.3f}, pmplan {out['pmplan']:.3f} "
          f"({out['pmplan_below']} below)"
          + (f", RRTConnect {out['rrtc']:.3f}" if ompl else "")
          + f"; plane: bound {out['plane_bound']:.3f}, pmplan {out['plane_pmplan']:.3f} "
          f"({out['plane_below']} below) [{out['seconds']:.0f} s]", flush=True)
    return out


def markdown(res: dict) -> str:
    ompl = "rrtc" in res["rows"][0]
    lines = ["# How much longer must a continuous planner go? A lower bound", "",
             (f"Command: `{res['command'].strip()}` ({res['date']}). Planar scene families of "
              f"`benchmarks/scenes.py` (box [0, 10]^2, r = {scenes.R}), {res['count']} "
              "queries per row, each with its mirror image q* (Mathematics §8, \"How long\"). "
              "*Bound*: a lower bound on the mean len/LB (LB = the sum of the straight "
              "distances) over a query and its mirror image of ANY planner continuous on "
              "pmplan's domains in the box (obstacles as points, robots alone: loose, never "
              "wrong), mean over the row +- one standard error; *> 1*: the share of queries "
              "whose bound exceeds the straight lines. Then over the pairs that every planner "
              "of the table solves (q* may bring points closer than the radii): the bound, "
              "pmplan's refined plan in the box with its default's section on these domains "
              "(radius = obstacle_radius = r/2; the compact lanes, the one-side lanes from 8 "
              "robots: pmplan's default in a box, `obstacle_line_walls`, has its domains cut "
              "along the wall of sides, which the mirror move crosses, so the bound does not "
              "bind it, Mathematics §8, \"The side of the lanes\")"
              + (", OMPL RRTConnect (one run per query)" if ompl else "") + ", means over "
              "the pairs of len/LB averaged over q and q*, and the pairs where pmplan's mean "
              "is below the bound: its refined box plans start from the chords of the mapped "
              "motion at the raw breakpoints, not from the motion (Mathematics §8, \"The "
              "refinement's start\"), so the bound, which holds for the conjugated planner, "
              "need not hold for them"
              + ("; *bound / RRTConnect*: the least mean ratio to RRTConnect a planner "
                 "continuous on these domains can reach on these pairs, and pmplan's" if ompl
                 else "") + ". *Plane*: the same without the box (q* the mirror image in the "
              "plane itself, which may leave the box): the bound, and pmplan's default plan "
              "without the box, refined, continuous on these domains, so below the bound on "
              "no pair."), "",
             "| seed | row | bound | > 1 | pairs | bound (pairs) | pmplan (below) |"
             + (" RRTConnect | bound / RRTConnect | pmplan / RRTConnect |" if ompl else "")
             + " plane: bound, pmplan (below) |",
             "|---|---|---|---|---|---|---|" + ("---|---|---|" if ompl else "") + "---|"]
    for r in res["rows"]:
        line = (f"| {r['seed']} | {r['family']} n = {r['n']} | {r['bound']:.3f} +- "
                f"{r['bound_se']:.3f} | {r['share_above_1']:.2f} | {r['pairs']} | "
                f"{r['bound_pairs']:.3f} | {r['pmplan']:.3f} ({r['pmplan_below']}) |")
        if ompl:
            line += (f" {r['rrtc']:.3f} | {r['bound_pairs'] / r['rrtc']:.3f} | "
                     f"{r['pmplan'] / r['rrtc']:.3f} |")
        line += f" {r['plane_bound']:.3f}, {r['plane_pmplan']:.3f} ({r['plane_below']}) |"
        lines.append(line)
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="11,12")
    ap.add_argument("--count", type=int, default=400)
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--ns", default=",".join(str(n) for n in NS))
    ap.add_argument("--ompl", action="store_true", help="RRTConnect on the same pairs")
    ap.add_argument("--from-json", action="store_true", help="rewrite the .md from the .json")
    args = ap.parse_args(argv)
    if args.from_json:
        rewrite_report("length_bound", markdown)
        return 0
    kernels = None
    if args.ompl:
        from _common import start_ompl

        if start_ompl(1) is None:
            return 2
        kernels = sc._kernels()
    o, s, g = scenes.queries("room", 2, 1, 0)[0]  # warm-up / JIT
    scenes.refined_in_box(o, s, g)
    rows = [row(f, int(n), int(seed), args.count, kernels) for seed in args.seeds.split(",")
            for f in args.families.split(",") for n in args.ns.split(",")]
    res = {"command": "python benchmarks/length_bound.py " + " ".join(
               argv if argv is not None else sys.argv[1:]),
           "date": _dt.date.today().isoformat(), "count": args.count, "rows": rows}
    write_report("length_bound", res, markdown)
    return 0


if __name__ == "__main__":
    from _common import exit_after_ompl

    exit_after_ompl(main())
