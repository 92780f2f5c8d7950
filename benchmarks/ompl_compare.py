"""pmplan next to OMPL's sampling-based planners on the same point-robot queries.

Usage (from the repository root; needs the optional extra ``pmplan[bench]``, i.e. ``ompl``)::

    python benchmarks/ompl_compare.py            # about 3-5 minutes
    python benchmarks/ompl_compare.py --quick    # a handful of queries per row
    python benchmarks/run.py --ompl              # the same, after the pmplan suite

Scene (unit square, scale 1): obstacles o1 = (0.35, 0.5), o2 = (0.65, 0.5); n = 1, 2, 4, 8
robots; clearance r = 0.05. OMPL plans in R^(2n) (``RealVectorStateSpace`` bounded by the
square) with a state validity checker requiring every robot-obstacle and robot-robot distance
to be >= r, checked along each motion at resolution r/4. Planners: ``RRTConnect`` (then
``simplifySolution``) and the asymptotically optimal ``RRTstar`` with a fixed time budget.
pmplan answers the same queries with :func:`pmplan.plan`.

Two query families, both with every start/goal distance >= 1.1 r:

* *generic*: uniform starts and goals;
* *blocked*: the straight-line motion collides -- a robot's segment passes within r/2 of an
  obstacle, and for n >= 2 robots 1 and 2 swap places.

Reported per (n, family, planner): success rate, median time per query, median path length over
the straight-line lower bound sum_i |x'_i - x_i|, the continuity probe (perturb every start by
1e-6, re-plan, resample both paths at 201 equal arc-length parameters, sup over samples and
robots of the distance), the exact minimum distance along the returned polyline, and how many
paths keep distance >= r all along. pmplan treats robots as POINTS (its certificate is
clearance > 0, not >= r). The row *pmplan refined* (issue 14) plans the same queries with
``refine=True, radius=r/2, obstacle_radius=r/2``: robots and obstacles are discs of radius r/2,
so its certified robot-robot and robot-obstacle distances are >= r, OMPL's requirement.

Writes ``benchmarks/ompl_results.json`` and replaces the OMPL section of ``benchmarks/RESULTS.md``,
which the documentation includes (every other section is kept). Not a test module
(``benchmarks/conftest.py``).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import OMPL_JSON, ROOT, exit_after_ompl, ompl_section, start_ompl

import pmplan
from pmplan import PiecewiseLinearPath

__all__ = ["LIFT", "OBSTACLES", "R", "RADIUS", "main"]

OBSTACLES = np.array([[0.35, 0.5], [0.65, 0.5]])
#: robot clearance required by OMPL's validity checker (5 % of the unit scene)
R = 0.05
#: radius of the robots and of the obstacles of the refined row: distances >= 2 (r/2) = r
RADIUS = R / 2
#: pmplan's lift scale, scene-sized (the paper's lift = 1 would leave the unit square)
LIFT = 0.1
#: time budget of the asymptotically optimal planner, seconds
BUDGET = 0.5
#: time limit of RRTConnect, seconds
RRTC_LIMIT = 5.0
#: resampling of the continuity probe
PROBE_SAMPLES = 201
PROBE_DELTA = 1e-6


# --------------------------------------------------------------------------- queries
def _ok(points: np.ndarray, margin: float) -> bool:
    """All robot-robot and robot-obstacle distances >= margin (points: (n, 2))."""
    if np.any(np.hypot(*(points[:, None, :] - OBSTACLES[None]).transpose(2, 0, 1)) < margin):
        return False
    diff = points[:, None, :] - points[None, :, :]
    dist = np.hypot(diff[..., 0], diff[..., 1])
    np.fill_diagonal(dist, np.inf)
    return bool(np.all(dist >= margin))


def _uniform_config(rng, n: int) -> np.ndarray:
    while True:
        pts = rng.uniform(R, 1 - R, size=(n, 2))
        if _ok(pts, 1.1 * R):
            return pts


def straight_line_clearance(start: np.ndarray, goal: np.ndarray) -> float:
    """Exact-form minimum distance between any two points along the straight-line motion."""
    wp = np.stack([np.concatenate([OBSTACLES, start]), np.concatenate([OBSTACLES, goal])])
    return _clearance(wp)


def _clearance(wp: np.ndarray) -> float:
    """Minimum distance between two points along a polyline of configurations (K, m+n, 2)."""
    try:  # pmplan's certificate arithmetic (closed form per piece, exact when tiny)
        from pmplan.certify import clearance

        return float(clearance(wp[None], OBSTACLES.shape[0])[0])
    except ImportError:  # pragma: no cover - same closed form, float only
        p = wp.shape[1]
        i, j = np.triu_indices(p, 1)
        keep = j >= OBSTACLES.shape[0]
        rel = wp[:, i[keep]] - wp[:, j[keep]]
        r0, v = rel[:-1], rel[1:] - rel[:-1]
        vv = (v * v).sum(-1)
        t = np.clip(-(r0 * v).sum(-1) / np.where(vv > 0, vv, 1), 0, 1)
        q = r0 + t[..., None] * v
        return float(np.sqrt((q * q).sum(-1)).min())


def generic_query(rng, n: int):
    """Uniform start and goal, every distance >= 1.1 r."""
    return _uniform_config(rng, n), _uniform_config(rng, n)


def _through_obstacle(rng) -> tuple[np.ndarray, np.ndarray]:
    """A start/goal pair whose segment passes within r/2 of a random obstacle."""
    while True:
        o = OBSTACLES[rng.integers(len(OBSTACLES))]
        ang = rng.uniform(0, 2 * np.pi)
        u = np.array([math.cos(ang), math.sin(ang)])
        a, b = rng.uniform(0.12, 0.4, size=2)
        off = rng.uniform(-0.5, 0.5) * R * np.array([-u[1], u[0]])
        x, y = o - a * u + off, o + b * u + off
        if np.all((x > R) & (x < 1 - R) & (y > R) & (y < 1 - R)):
            return x, y


def blocked_query(rng, n: int):
    """A query whose straight-line motion collides (obstacle crossing; swap for n >= 2)."""
    while True:
        start, goal = _uniform_config(rng, n), _uniform_config(rng, n)
        if n >= 2:
            goal[0], goal[1] = start[1].copy(), start[0].copy()
        for i in [0] if n == 1 else range(2, n, 2):
            start[i], goal[i] = _through_obstacle(rng)
        if _ok(start, 1.1 * R) and _ok(goal, 1.1 * R) and straight_line_clearance(start, goal) < R:
            return start, goal


# --------------------------------------------------------------------------- paths
def _full(robots: np.ndarray) -> np.ndarray:
    """Robot waypoints (K, n, 2) -> configurations (K, m+n, 2), obstacles first."""
    k = robots.shape[0]
    return np.concatenate([np.broadcast_to(OBSTACLES, (k,) + OBSTACLES.shape), robots], axis=1)


def _path(wp: np.ndarray) -> PiecewiseLinearPath:
    return PiecewiseLinearPath(np.linspace(0.0, 1.0, wp.shape[0]), wp)


def _arc_samples(path: PiecewiseLinearPath) -> np.ndarray:
    return path.arc_length_reparametrised()(np.linspace(0.0, 1.0, PROBE_SAMPLES))


def _sup_distance(a: PiecewiseLinearPath, b: PiecewiseLinearPath) -> float:
    """Sup over 201 equal arc-length parameters and over points of the distance."""
    d = _arc_samples(a) - _arc_samples(b)
    return float(np.sqrt((d * d).sum(-1)).max())


def _lower_bound(start: np.ndarray, goal: np.ndarray) -> float:
    return float(np.hypot(*(goal - start).T).sum())


# --------------------------------------------------------------------------- OMPL
def solve(ss, start, goal, limit: float, simplify: bool, n: int, d: int):
    """Solve the SimpleSetup ``ss`` from the OMPL state ``start`` to ``goal`` within ``limit``
    seconds (then ``simplifySolution`` when ``simplify``): ``(seconds, robots (K, n, d))``, or
    ``(seconds, None)`` when no exact solution was found."""
    ss.clear()
    ss.setStartAndGoalStates(start, goal)
    t0 = time.perf_counter()
    ss.solve(limit)
    ok = ss.haveExactSolutionPath()
    if ok and simplify:
        ss.simplifySolution()
    dt = time.perf_counter() - t0
    if not ok:
        return dt, None
    p = ss.getSolutionPath()
    k = p.getStateCount()
    return dt, np.array([p.getState(i)[0 : n * d] for i in range(k)]).reshape(k, n, d)


def set_planner(ss, optimal: bool, rrtc_limit: float, budget: float) -> float:
    """Give the SimpleSetup ``ss`` RRTConnect, or RRT* with the path-length objective
    (``optimal``), set it up, and return its time limit (``rrtc_limit`` or ``budget``)."""
    from ompl import base as ob
    from ompl import geometric as og

    si = ss.getSpaceInformation()
    if optimal:
        ss.setPlanner(og.RRTstar(si))
        ss.setOptimizationObjective(ob.PathLengthOptimizationObjective(si))
    else:
        ss.setPlanner(og.RRTConnect(si))
    ss.setup()
    return budget if optimal else rrtc_limit


class OmplRunner:
    """One OMPL SimpleSetup for n robots in the unit square (state space R^(2n))."""

    def __init__(self, n: int, planner: str):
        from ompl import base as ob
        from ompl import geometric as og

        self.n, self.dim, self.name = n, 2 * n, planner
        self.space = ob.RealVectorStateSpace(self.dim)
        self.space.setBounds(0.0, 1.0)
        self.ss = og.SimpleSetup(self.space)
        obs = [tuple(o) for o in OBSTACLES.tolist()]
        r2, dim = R * R, self.dim

        def valid(state) -> bool:
            v = state[0:dim]
            for i in range(0, dim, 2):
                x, y = v[i], v[i + 1]
                for ox, oy in obs:
                    if (x - ox) ** 2 + (y - oy) ** 2 < r2:
                        return False
                for j in range(i + 2, dim, 2):
                    if (x - v[j]) ** 2 + (y - v[j + 1]) ** 2 < r2:
                        return False
            return True

        self._valid = valid  # keep the callback alive
        self.ss.setStateValidityChecker(valid)
        si = self.ss.getSpaceInformation()
        si.setStateValidityCheckingResolution((R / 4) / self.space.getMaximumExtent())
        self.limit = set_planner(self.ss, planner == "RRT*", RRTC_LIMIT, BUDGET)

    def _state(self, pts: np.ndarray):
        s = self.space.allocState()
        s[0 : self.dim] = [float(v) for v in pts.reshape(-1)]
        return s

    def plan(self, start: np.ndarray, goal: np.ndarray):
        """Return (seconds, PiecewiseLinearPath or None)."""
        dt, robots = solve(self.ss, self._state(start), self._state(goal), self.limit,
                           self.name == "RRTConnect", self.n, 2)
        return dt, None if robots is None else _path(_full(robots))


class PmplanRunner:
    """pmplan.plan on the same queries (lift = LIFT): robots as points, or refined with radii.

    ``refine=True``: ``pmplan.plan(..., refine=True, radius=RADIUS, obstacle_radius=RADIUS)``,
    robots and obstacles discs of radius r/2, so a path that respects the radii keeps every
    distance >= r. ``claims`` counts the plans that say so (``Plan.respects_radius``).
    """

    def __init__(self, refine: bool = False):
        self.refine = refine
        self.name = "pmplan refined" if refine else "pmplan"
        self.options = (dict(refine=True, radius=RADIUS, obstacle_radius=RADIUS) if refine
                        else {})
        self.claims = 0

    def plan(self, start: np.ndarray, goal: np.ndarray):
        t0 = time.perf_counter()
        try:
            p = pmplan.plan(OBSTACLES, start, goal, lift=LIFT, **self.options)
        except pmplan.PmplanError:
            return time.perf_counter() - t0, None
        dt = time.perf_counter() - t0
        self.claims += bool(getattr(p, "respects_radius", False))
        return dt, p.path


def evaluate(runner, queries, probe_dirs) -> dict:
    """Success, times, length ratios, continuity probe and clearances of one planner."""
    times, ratios, probes, clears = [], [], [], []
    success = claims = 0
    for (start, goal), dirs in zip(queries, probe_dirs):
        before = getattr(runner, "claims", 0)
        dt, path = runner.plan(start, goal)
        claims += getattr(runner, "claims", 0) - before
        times.append(dt)
        if path is None:
            continue
        success += 1
        lb = _lower_bound(start, goal)
        ratios.append(path.length() / lb if lb > 0 else np.nan)
        clears.append(_clearance(path.waypoints))
        _, path2 = runner.plan(start + PROBE_DELTA * dirs, goal)
        if path2 is not None:
            probes.append(_sup_distance(path, path2))

    def med(v):
        v = [x for x in v if np.isfinite(x)]
        return float(np.median(v)) if v else float("nan")

    return {
        "success": success,
        "count": len(queries),
        "time_ms_median": med(times) * 1e3,
        "length_ratio_median": med(ratios),
        "probe_median": med(probes),
        "probe_max": max(probes) if probes else float("nan"),
        "probes": [float(v) for v in probes],
        "clearance_median": med(clears),
        "clearance_min": min(clears) if clears else float("nan"),
        "clear_r": int(sum(c >= R for c in clears)),
        "probed": len(probes),
        # pmplan: a path is returned only with its certificate; the refined row also says
        # whether it keeps the radii (Plan.respects_radius), checked against clear_r
        "certified": success if isinstance(runner, PmplanRunner) else None,
        "claims_r": claims if getattr(runner, "refine", False) else None,
    }


PM, PR, RC, RS = "pmplan", "pmplan refined", "OMPL RRTConnect", "OMPL RRT*"
#: the goals of issue 14 (item 6) for the refined row
GOAL_SHARE = 0.95
GOAL_PROBE_MEDIAN = 1e-5
GOAL_PROBE_MAX = 1e-4


def _by_planner(rows: list[dict]) -> dict:
    by: dict = {}
    for r in rows:
        by.setdefault(r["planner"], []).append(r)
    return by


def _agg(by: dict, name: str, key: str, fn=np.nanmedian) -> float:
    vals = [r[key] for r in by.get(name, []) if r.get(key) is not None and np.isfinite(r[key])]
    return float(fn(vals)) if vals else float("nan")


def _total(by: dict, name: str, key: str) -> int:
    return sum(r[key] or 0 for r in by.get(name, []))


def _who(pm_val: float, ompl_vals: list[float], smaller_is_better: bool = True) -> str:
    best = min(ompl_vals) if smaller_is_better else max(ompl_vals)
    if pm_val == best:
        return "a tie"
    return "pmplan wins" if (pm_val < best) == smaller_is_better else "OMPL wins"


def refined_goals(rows: list[dict]) -> list[dict]:
    """The issue's goals for the refined row, measured: goal, target, measured, met."""
    by = _by_planner(rows)
    lpr, lrc = _agg(by, PR, "length_ratio_median"), _agg(by, RC, "length_ratio_median")
    succ, count = _total(by, PR, "success"), _total(by, PR, "count")
    keep = _total(by, PR, "clear_r")
    probes = [v for r in by.get(PR, []) for v in r.get("probes", [])]
    pmed = float(np.median(probes)) if probes else float("nan")
    pmax = float(max(probes)) if probes else float("nan")
    cert = _total(by, PR, "certified")
    return [
        {"goal": "median over rows of the median length / lower bound",
         "target": f"<= {RC}'s ({lrc:.3g})", "measured": f"{lpr:.3g}", "met": lpr <= lrc},
        {"goal": "paths keeping every distance >= r", "target": f">= {GOAL_SHARE:.0%}",
         "measured": f"{keep}/{succ} ({keep / max(succ, 1):.1%})",
         "met": succ > 0 and keep >= GOAL_SHARE * succ},
        {"goal": "continuity probe (1e-6 perturbation): median",
         "target": f"<= {GOAL_PROBE_MEDIAN:g}", "measured": f"{pmed:.2g}",
         "met": pmed <= GOAL_PROBE_MEDIAN},
        {"goal": "continuity probe: max", "target": f"<= {GOAL_PROBE_MAX:g}",
         "measured": f"{pmax:.2g}", "met": pmax <= GOAL_PROBE_MAX},
        {"goal": "every path certified", "target": f"{count}/{count}",
         "measured": f"{cert}/{count}", "met": cert == count},
    ]


def ompl_wins(rows: list[dict]) -> list[str]:
    """The rows (n, family) where an OMPL planner beats pmplan refined, and on what."""
    cells: dict = {}
    for r in rows:
        cells.setdefault((r["n"], r["family"]), {})[r["planner"]] = r
    out = []
    for (n, family), c in cells.items():
        pr = c.get(PR)
        if pr is None:
            continue
        what = []
        for name in (RC, RS):
            o = c.get(name)
            if o is None or not o["success"]:
                continue
            if o["length_ratio_median"] < pr["length_ratio_median"]:
                what.append(f"{name} shorter ({o['length_ratio_median']:.3g} vs "
                            f"{pr['length_ratio_median']:.3g})")
            if o["clear_r"] / o["success"] > pr["clear_r"] / max(pr["success"], 1):
                what.append(f"{name} keeps >= r more often ({o['clear_r']}/{o['success']} vs "
                            f"{pr['clear_r']}/{pr['success']})")
            if o["success"] / o["count"] > pr["success"] / pr["count"]:
                what.append(f"{name} succeeds more often")
        if what:
            out.append(f"n = {n} {family}: " + "; ".join(what))
    return out


def _verdict(rows: list[dict]) -> str:
    """Plain sentences: where OMPL wins and where pmplan does, from the measured rows."""
    by = _by_planner(rows)
    lpm, lpr, lrc, lrs = (_agg(by, x, "length_ratio_median") for x in (PM, PR, RC, RS))
    tpm, tpr, trc, trs = (_agg(by, x, "time_ms_median") for x in (PM, PR, RC, RS))
    ppm, ppr, prc, prs = (_agg(by, x, "probe_median") for x in (PM, PR, RC, RS))
    s_pm, s_pr, s_rc, s_rs = ((_total(by, x, "success"), _total(by, x, "count"))
                              for x in (PM, PR, RC, RS))
    lines = ["**Verdict (computed from the rows above).**", ""]
    lines.append(
        f"* Path length: refined, {_who(lpr, [lrc, lrs])}. Median over rows of the median length "
        f"/ lower bound: pmplan refined {lpr:.3g}, {RC} {lrc:.3g}, {RS} {lrs:.3g}; unrefined "
        f"pmplan {lpm:.3g} (the paper's fixed construction -- deform to the line L, lift, slide, "
        "descend -- optimal in the number of domains of continuity, not in length; the "
        "refinement keeps the domains and shortens it)."
    )
    lines.append(
        f"* Robot size: OMPL enforces the clearance r = {R} at its checked states. pmplan "
        f"refined, with radius = obstacle_radius = r/2: {_total(by, PR, 'clear_r')}/{s_pr[0]} "
        f"of its paths keep >= r all along (exact minimum), and {_total(by, PR, 'claims_r')} say "
        f"so (`respects_radius`). Unrefined pmplan treats robots as points (clearance > 0): "
        f"{_total(by, PM, 'clear_r')}/{s_pm[0]} keep >= r."
    )
    lines.append(
        f"* Time: {_who(tpr, [trc, trs])}. Median over rows of the median time per query: "
        f"pmplan refined {tpr:.3g} ms, pmplan {tpm:.3g} ms (one `pmplan.plan` call, validation "
        f"and certificates included), {RC} {trc:.3g} ms, {RS} {trs:.3g} ms (it always spends "
        "its budget)."
    )
    lines.append(
        f"* Success: pmplan refined {s_pr[0]}/{s_pr[1]}, pmplan {s_pm[0]}/{s_pm[1]}, {RC} "
        f"{s_rc[0]}/{s_rc[1]}, {RS} {s_rs[0]}/{s_rs[1]}. pmplan is complete by construction "
        "(every valid query gets a certified path or a clear error); sampling planners can "
        "time out."
    )
    lines.append(
        f"* Continuity: {_who(ppr, [prc, prs])}. After moving every start by 1e-6, the refined "
        f"path moves by a median {ppr:.2g} (max {_agg(by, PR, 'probe_max', np.nanmax):.2g}), "
        f"the unrefined one by {ppm:.2g} (max {_agg(by, PM, 'probe_max', np.nanmax):.2g}); "
        f"{RC} {prc:.2g}, {RS} {prs:.2g} (a randomised planner returns a different path on "
        "each call; where the straight line is valid RRTConnect returns it, which is "
        "continuous too)."
    )
    below = [r for name in (RC, RS) for r in by.get(name, []) if r["clear_r"] < r["success"]]
    n_below = sum(r["success"] - r["clear_r"] for r in below)
    n_ompl = s_rc[0] + s_rs[0]
    deepest = min((r["clearance_min"] for r in below), default=float("nan"))
    lines.append(
        "* Certificate: every pmplan path, refined or not, comes with an exact closed-form "
        "clearance and a domain label. OMPL checks motions only at states spaced by its "
        f"resolution: {n_below}/{n_ompl} of its paths come closer than r between checked "
        "states" + (f" (the deepest to r - {R - deepest:.1e})" if n_below else "")
        + ", which the exact clearance column reveals."
    )
    wins = ompl_wins(rows)
    lines += ["", "**Where OMPL still wins against pmplan refined** (per row):", ""]
    lines += [f"* {w}" for w in wins] or ["* nowhere: no row has a shorter OMPL median, a "
                                          "larger share >= r, or more successes"]
    goals = refined_goals(rows)
    lines += ["", "**Goals of issue 14 for the refined row:**", "",
              "| goal | target | measured | met |", "|---|---|---|---|"]
    lines += [f"| {g['goal']} | {g['target']} | {g['measured']} | {'yes' if g['met'] else 'no'} |"
              for g in goals]
    missed = [g["goal"] for g in goals if not g["met"]]
    lines += ["", ("Every goal is met." if not missed else
                   "Missed: " + "; ".join(missed) + "." + _probe_note(rows))]
    return "\n".join(lines)


def _probe_note(rows: list[dict]) -> str:
    """Where the refined row's largest continuity probe is, next to how close the raw paths of
    that row come to a collision (the unrefined row's minimum clearance, same queries)."""
    refined = [r for r in rows if r["planner"] == PR and r.get("probes")]
    if not refined:
        return ""
    top = max(refined, key=lambda r: r["probe_max"])
    raw = next((r for r in rows if r["planner"] == PM and r["n"] == top["n"]
                and r["family"] == top["family"]), None)
    return (f" The largest refined probe, {top['probe_max']:.2g}, is in row n = {top['n']} "
            f"{top['family']} ({sum(v > GOAL_PROBE_MAX for v in top['probes'])} of its "
            f"{len(top['probes'])} probes above {GOAL_PROBE_MAX:g}; the row's median "
            f"{top['probe_median']:.2g})" + (
                f", where the raw paths come as close as {raw['clearance_min']:.2g} to a "
                "collision (the unrefined row, same queries): the refinement's moves are capped "
                "by the room between points, and near a raw near-collision its modulus of "
                "continuity grows (docs/refinement.md)" if raw else "") + ".")


#: where the comparison is written: (file, its heading of the section)
SECTIONS = (
    (ROOT / "benchmarks" / "RESULTS.md", "## Comparison with OMPL"),
)


def _level(line: str) -> int:
    """The level of a markdown heading line (0 for any other line)."""
    return len(line) - len(line.lstrip("#")) if line.startswith("#") else 0


def write_ompl_sections(out: dict) -> None:
    """Save ``ompl_results.json``; replace the OMPL section of RESULTS.md.

    Only the section under the heading of :data:`SECTIONS` is rewritten, up to the next heading
    of the same or a higher level (appended when missing): every other section of the files
    (the suite's tables, the refinement's, the explore load test, the scale run) is kept.
    """
    OMPL_JSON.write_text(json.dumps(out, indent=1, default=float))
    sect = ompl_section(out)[1:]  # without its heading
    for path, head in SECTIONS:
        level = _level(head)
        lines = [head] + ["#" * (level - 2) + s if _level(s) else s for s in sect]
        old = path.read_text().split("\n") if path.exists() else []
        if head in old:
            a = old.index(head)
            b = next((i for i in range(a + 1, len(old)) if 0 < _level(old[i]) <= level),
                     len(old))
            new = old[:a] + lines + old[b:]
        else:
            new = old + [""] + lines
        path.write_text("\n".join(new))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="a handful of queries per row")
    ap.add_argument("--seed", type=int, default=20240611)
    ap.add_argument("--from-json", action="store_true",
                    help="plan nothing: rewrite the sections (verdict included) from "
                    "benchmarks/ompl_results.json")
    args = ap.parse_args(argv)
    if args.from_json:
        out = json.loads(OMPL_JSON.read_text())
        out["verdict"] = _verdict(out["rows"])
        write_ompl_sections(out)
        print(out["verdict"])
        return 0
    if start_ompl(args.seed) is None:
        return 2
    rng = np.random.default_rng(args.seed)
    t_start = time.perf_counter()
    for runner in (PmplanRunner(), PmplanRunner(refine=True)):  # warm-up / JIT
        runner.plan(np.array([[0.1, 0.1]]), np.array([[0.9, 0.9]]))
    rows = []
    for n in (1, 2, 4, 8):
        count = (4 if args.quick else 10) if n == 8 else (5 if args.quick else 25)
        for family, gen in (("generic", generic_query), ("blocked", blocked_query)):
            queries = [gen(rng, n) for _ in range(count)]
            dirs = []
            for _ in queries:
                v = rng.standard_normal((n, 2))
                dirs.append(v / np.hypot(v[:, 0], v[:, 1])[:, None])
            runners = [
                (PM, PmplanRunner()),
                (PR, PmplanRunner(refine=True)),
                (RC, OmplRunner(n, "RRTConnect")),
                (RS, OmplRunner(n, "RRT*")),
            ]
            for label, runner in runners:
                res = evaluate(runner, queries, dirs)
                res.update(n=n, family=family, planner=label)
                rows.append(res)
                print(
                    f"n={n} {family:8s} {label:16s} success {res['success']}/{res['count']}  "
                    f"time {res['time_ms_median']:9.3f} ms  length/LB "
                    f"{res['length_ratio_median']:.3f}  probe {res['probe_median']:.2e}  "
                    f"clearance {res['clearance_median']:.4f}  >=r {res['clear_r']}",
                    flush=True,
                )
    out = {
        "rows": rows,
        "r": R,
        "radius": RADIUS,
        "lift": LIFT,
        "budget": BUDGET,
        "rrtc_limit": RRTC_LIMIT,
        "seed": args.seed,
        "quick": args.quick,
        "total_s": time.perf_counter() - t_start,
        "date": _dt.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
    }
    out["verdict"] = _verdict(rows)
    print(out["verdict"])
    write_ompl_sections(out)
    print(f"total {out['total_s']:.0f} s; wrote " + ", ".join(str(p.relative_to(ROOT))
                                                             for p, _ in SECTIONS))
    return 0


if __name__ == "__main__":
    exit_after_ompl(main())
