"""The refinement's effort for a crowd of 16 robots in the plane: what more waypoints, more
steps or more clearing-only steps buy in valid plans, length and continuity, and what they cost
in time.

Usage (from the repository root)::

    python benchmarks/crowd_effort.py              # about 10 minutes, two processes, then alone
    python benchmarks/crowd_effort.py --from-json  # rewrite the report
    python benchmarks/crowd_effort.py --timing     # measure the time again (alone), rewrite

Issue 25 asks, with 16 robots, for refined plans that keep the radii on at least 80 % of the
queries of every row, in at most 20 ms per query, continuous (K <= 1e3 at every probe). A
refined plan of 16 robots in the plane takes the one-side lanes (``CROWD_LANES``) and the
crowd's effort: ``CROWD_WAYPOINTS`` sub-pieces per piece, ``CROWD_STEPS`` steps, then
``CROWD_FINAL`` times as many clearing-only steps (``pmplan.refine.grid.final_steps``). Its
misses are of two kinds: a gap narrower than a robot, which no planner continuous on these
domains avoids on every query (Mathematics §8) and no effort clears, and a contact that the
refinement's steps do not clear. This script measures the second kind against the effort, on
the same raw plans.

Every query is planned as a user would plan it (``pmplan.plan(o, s, g, refine=True,
radius=r/2, obstacle_radius=r/2, bounds=(0, 10))``, everything else at its default). Its raw
plan (the same planner and unit) is then refined again at each effort of ``EFFORTS``:
(waypoints, steps, clearing-only steps), the last set through ``CROWD_FINAL`` for the
measurement (the first effort is the default and repeats the plan; the second is the default
before this script, 4 / 224 + 56). Rows: room, swap, room_walls and swap_walls with 16 robots,
100 queries each; seeds 11 and 12 are those on which ``CROWD_LANES`` was chosen and the
efforts were tried, seeds 20 and 21 were looked at for the choice between the two efforts
with 192 or 224 clearing steps (the time decided). Per row and effort: the valid plans (keep
the radii and the walls, decided exactly); at the default the gap misses; per part the median
len/LB of the valid plans and the paired length ratio to the default.

Continuity, for the default and the default before: ``scenes_compare.continuity``'s probes
(every point moved by delta times a uniform vector in [-1, 1]^d, delta = 1e-6, 1e-9, 1e-12),
16 queries of each family and seeds 1-4 (``scenes_compare.py``'s draws 1 and 2, 3 and 4 not
looked at before), the pairs with K > 1e3 and the largest K.

Time, measured after the rows, alone: the first ``TIME_COUNT`` queries of room and swap (seed
11), each effort's refinement of every raw plan in turn, ``TIME_ROUNDS`` rounds interleaved;
per effort the median over the queries of each query's fastest round (CPU time of the
process, ms), and its ratio to the default's. The refinement is most of a refined plan's time;
the whole plan's time is ``scenes_time.py``'s.

Writes ``benchmarks/crowd_effort.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import importlib
import json
import multiprocessing
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes
import scenes_compare
from _common import rewrite_report, write_report

import pmplan
from pmplan.refine import default_effort
from pmplan.refine.grid import final_steps

GRID = importlib.import_module("pmplan.refine.grid")
_DEFAULT = (*default_effort(16), final_steps(default_effort(16)[1], 16, 2))
#: (waypoints, steps, clearing-only steps); the first is the default of 16 robots in the
#: plane, the second the default before
EFFORTS = [_DEFAULT, (4, 224, 56), (4, 112, 224), (4, 224, 224), (4, 448, 112), (8, 224, 56)]
FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
#: (part, seeds); 100 queries per row, 16 robots
PARTS = (("design", (11, 12)), ("held out", (20, 21)))
COUNT = 100
N = 16
HALF = scenes.R / 2
#: the goal of issue 25 for 16 robots: the valid share of every row, the time per query (ms)
VALID_GOAL, TIME_GOAL = 0.8, 20.0
TIME_COUNT, TIME_ROUNDS = 12, 3


def _name(effort) -> str:
    return f"{effort[0]}/{effort[1]} + {effort[2]}"


def _raw(o, s, g):
    """The default refined plan of a query and its raw plan (the same planner and unit)."""
    p = pmplan.plan(o, s, g, refine=True, radius=HALF, obstacle_radius=HALF,
                    bounds=(0.0, scenes.SIZE))
    raw = pmplan.plan(o, s, g, planner=p.planner, lift=2 * HALF, bounds=(0.0, scenes.SIZE))
    return p, raw


def _refine(raw, effort):
    """``raw`` refined at ``effort`` (the clearing-only steps set through ``CROWD_FINAL``)."""
    keep = GRID.CROWD_FINAL
    GRID.CROWD_FINAL = effort[2] / effort[1]
    try:
        if final_steps(effort[1], N, 2) != effort[2]:
            raise AssertionError(f"not {effort[2]} clearing-only steps")
        return pmplan.refine(raw, radius=HALF, obstacle_radius=HALF, waypoints=effort[0],
                             steps=effort[1])
    finally:
        GRID.CROWD_FINAL = keep


def cell(fam: str, seed: int) -> dict:
    """One row: per effort the valid plans; at the default the gap misses."""
    qs = scenes.queries(fam, N, COUNT, seed)
    valid = {_name(e): 0 for e in EFFORTS}
    lens = {_name(e): [] for e in EFFORTS}
    gap = 0
    for o, s, g in qs:
        p, raw = _raw(o, s, g)
        gap += not p.respects_radius and p.radius_miss.category == "gap"
        lb = float(np.linalg.norm(g - s, axis=1).sum())
        for e in EFFORTS:
            q = p if e == EFFORTS[0] else _refine(raw, e)
            valid[_name(e)] += bool(q.respects_radius)
            lens[_name(e)].append(q.path.length() / lb if q.respects_radius else None)
        if not np.array_equal(_refine(raw, EFFORTS[0]).waypoints, p.waypoints):
            raise AssertionError("the default effort does not repeat the default plan")
    out = {"family": fam, "seed": seed, "count": len(qs), "gap": gap, "valid": valid,
           "len_lb": lens}
    print(out, flush=True)
    return out


#: the continuity part: seeds, queries per row, the efforts probed (the default, before)
CONTINUITY = ((1, 2, 3, 4), 16, (0, 1))


def continuity_cell(fam: str, seed: int, k: int) -> dict:
    """One row of the continuity part for effort ``EFFORTS[k]`` (set as the crowd's default
    through ``CROWD_STEPS`` and ``CROWD_FINAL``): the probes that kept the label, the pairs
    with K > 1e3, the largest K."""
    w, steps, final = EFFORTS[k]
    if w != GRID.CROWD_WAYPOINTS:
        raise AssertionError("the continuity part sets the crowd's steps, not its waypoints")
    keep = GRID.CROWD_STEPS, GRID.CROWD_FINAL
    GRID.CROWD_STEPS, GRID.CROWD_FINAL = steps, final / steps
    try:
        qs = scenes.queries(fam, N, CONTINUITY[1], seed)
        runner = scenes_compare.PmplanRunner(None, bounded=True)
        rng = np.random.default_rng([seed, scenes.FAMILIES[fam].index, N, 77])
        ks = []
        for o, s, g in qs:
            _, res = runner.plan(o, s, g)
            if res is not None:
                ks += [c["K"] for c in scenes_compare.continuity(runner, o, s, g, res, rng)
                       if c["returned"] and not c["label_change"]]
    finally:
        GRID.CROWD_STEPS, GRID.CROWD_FINAL = keep
    out = {"family": fam, "seed": seed, "effort": _name(EFFORTS[k]), "probes": len(ks),
           "k_over": sum(x > scenes_compare.CONT_GOAL for x in ks), "k_max": max(ks)}
    print(out, flush=True)
    return out


def _seed_rows(job) -> list[dict]:
    part, seed, k = job
    if part == "continuity":
        return [continuity_cell(f, seed, k) for f in FAMILIES]
    return [dict(cell(f, seed), part=part) for f in FAMILIES]


def timing() -> dict:
    """Per effort: the median over the queries of each query's fastest refinement (ms)."""
    raws = [_raw(*q)[1] for fam in ("room", "swap") for q in scenes.queries(fam, N, TIME_COUNT, 11)]
    for e in EFFORTS:  # (compiled and warm)
        _refine(raws[0], e)
    best = {_name(e): np.full(len(raws), np.inf) for e in EFFORTS}
    for _ in range(TIME_ROUNDS):
        for i, raw in enumerate(raws):
            for e in EFFORTS:
                t0 = time.process_time()
                _refine(raw, e)
                best[_name(e)][i] = min(best[_name(e)][i], 1e3 * (time.process_time() - t0))
    return {k: float(np.median(v)) for k, v in best.items()}


def _median(values) -> float:
    v = [x for x in values if x is not None]
    return float(np.median(v)) if v else float("nan")


def markdown(res: dict) -> str:
    names = [_name(e) for e in res["efforts"]]
    default = names[0]
    lines = ["# The refinement's effort for a crowd of 16 robots", "",
             f"`{res['command']}` ({res['date']}, {res['seconds']:.0f} s). Rooms 10 x 10, "
             f"r = 0.3, {res['count']} queries per row, 16 robots, pmplan's default refined "
             "plan in the box (the one-side lanes, radius = obstacle_radius = r/2) and its raw "
             "plan refined again at each effort (waypoints per piece / steps + clearing-only "
             f"steps; {default} is the default and repeats the plan, {names[1]} the default "
             "before). *valid*: keeps the radii and the walls, decided exactly; *gap*: the "
             "default's misses that cross a gap narrower than a robot, which no effort clears "
             "(Mathematics §8). Goal of issue 25 with 16 robots: "
             f"{VALID_GOAL:.0%} of every row, {TIME_GOAL:g} ms per query, K <= 1e3.", "",
             "| part | seed | row | gap | " + " | ".join(f"valid {n}" for n in names) + " |",
             "|---|---|---|---|" + "---|" * len(names)]
    for r in res["rows"]:
        lines.append(f"| {r['part']} | {r['seed']} | {r['family']} n = 16 | {r['gap']} | "
                     + " | ".join(str(r["valid"][n]) for n in names) + " |")
    lines += ["", "Per effort and part: the rows below the goal's share, the least row and the "
              "valid plans in total; the median len/LB of the valid plans; the median over "
              "the queries both keep valid of the length over the default's; the time of the "
              f"refinement alone (median over {2 * TIME_COUNT} raw plans of room and swap, "
              f"seed 11, of each plan's fastest of {TIME_ROUNDS} interleaved rounds, CPU "
              "time, one core, alone) and its ratio to the default's.", "",
              "| effort | part | rows below, least, total | len/LB | paired / default "
              "| refinement (ms) | time / default |", "|---|---|---|---|---|---|---|"]
    t = res["timing"]
    for n in names:
        for part, _ in PARTS:
            rows = [r for r in res["rows"] if r["part"] == part]
            v = [r["valid"][n] for r in rows]
            below = sum(x < VALID_GOAL * r["count"] for x, r in zip(v, rows))
            mine = [x for r in rows for x in r["len_lb"][n]]
            base = [x for r in rows for x in r["len_lb"][default]]
            paired = [x / y for x, y in zip(mine, base) if x is not None and y is not None]
            lines.append(f"| {n} | {part} | {below} of {len(rows)}, {min(v)}, {sum(v)} of "
                         f"{sum(r['count'] for r in rows)} | {_median(mine):.3f} | "
                         f"{_median(paired):.3f} | {t[n]:.1f} | {t[n] / t[default]:.2f} |")
    cont = res.get("continuity", [])
    if cont:
        lines += ["", f"Continuity (seeds {', '.join(map(str, CONTINUITY[0]))}, "
                  f"{CONTINUITY[1]} queries per row, the probes of `scenes_compare.py`): per "
                  "effort and family, the pairs with K > 1e3 over the probes that kept their "
                  "label, and the largest K.", "",
                  "| effort | " + " | ".join(FAMILIES) + " | all |",
                  "|---|" + "---|" * (len(FAMILIES) + 1)]
        for n in dict.fromkeys(c["effort"] for c in cont):
            cells = []
            for fam in [*FAMILIES, None]:
                cs = [c for c in cont if c["effort"] == n and (fam is None or c["family"] == fam)]
                cells.append(f"{sum(c['k_over'] for c in cs)} of {sum(c['probes'] for c in cs)}"
                             f", {scenes.fmt_k(max(c['k_max'] for c in cs))}" if cs else "n/a")
            lines.append(f"| {n} | " + " | ".join(cells) + " |")
    lines.append("")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--from-json", action="store_true", help="rewrite the .md from the .json")
    ap.add_argument("--timing", action="store_true",
                    help="measure the time part again, alone, into the .json, and rewrite")
    args = ap.parse_args(argv)
    if args.from_json:
        rewrite_report("crowd_effort", markdown)
        return 0
    if args.timing:
        path = Path(__file__).resolve().parent / "crowd_effort.json"
        res = json.loads(path.read_text())
        res["timing"] = timing()
        res["timing_date"] = _dt.date.today().isoformat()
        write_report("crowd_effort", res, markdown)
        return 0
    t0 = time.perf_counter()
    jobs = [(part, seed, None) for part, seeds in PARTS for seed in seeds]
    jobs += [("continuity", seed, k) for k in CONTINUITY[2] for seed in CONTINUITY[0]]
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        out = pool.map(_seed_rows, jobs)
    rows = [r for (part, _, _), rs in zip(jobs, out) if part != "continuity" for r in rs]
    cont = [r for (part, _, _), rs in zip(jobs, out) if part == "continuity" for r in rs]
    res = {"command": " ".join(["python benchmarks/crowd_effort.py", *(argv or sys.argv[1:])]),
           "date": _dt.date.today().isoformat(), "count": COUNT, "efforts": EFFORTS,
           "rows": rows, "continuity": cont, "timing": timing(),  # (alone, after the pool)
           "seconds": time.perf_counter() - t0}
    write_report("crowd_effort", res, markdown)
    return 0


if __name__ == "__main__":
    sys.exit(main())
