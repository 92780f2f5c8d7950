"""The default section of a refined crowd: the compact lanes against the one-side lanes, per
robot count, on the scene families of issue 25.

Usage (from the repository root)::

    python benchmarks/crowd_default.py              # about 6 minutes, two processes
    python benchmarks/crowd_default.py --from-json  # rewrite the report

The compact lanes (``obstacle_line_compact``) send the odd robots past an obstacle on one side
and the even ones on the other; the one-side lanes (``obstacle_line_oneside``, Mathematics §4.4)
send every robot past every obstacle on the side of ``nu``, in lanes shared by the robots that
keep their order. Both are continuous on the same domains, with the same labels. The one-side
lanes cross fewer narrow gaps between an obstacle and a wall (Mathematics §8), and their lanes
are taller. A refined plan of at least ``pmplan.planners.base.CROWD_LANES`` robots in the
plane takes them by default. This script measures that choice per robot count.

Every query is planned as a user would plan it, with ``pmplan.plan(o, s, g, planner=P,
refine=True, radius=r/2, obstacle_radius=r/2, bounds=(0, 10))``, the unit at its default. The
count is chosen on the *design* part: seeds 11 and 12, n = 4, 6, 8, 12, 16 (the count was 16
until a refinement of 5 to 8 robots in the plane ended with as many clearing-only steps as
steps, ``pmplan.refine.PLANE_FINAL``; it is 8 since). It is confirmed on the *held-out*
part: seeds 20 and 21, never looked at while choosing it, n = 8, 10, 16, 20. The families are
those of ``benchmarks/scenes.py``: room, swap, room_walls, swap_walls, room3d, with 100 queries
per row.

A third part, *continuity*, probes both sections with 8 and 16 robots in every family: every
point of the query moved by delta times a uniform vector in [-1, 1]^d for delta = 1e-6, 1e-9
and 1e-12 (``scenes_compare.continuity``: the same moves for both), replanned, ``K = sup
change / delta`` over the pairs with the same label. Beside the largest K it counts the pairs
with K > 1e3 and those with ``K_eff = K / max(1, r / c_raw) > 1e3`` (c_raw the raw plan's
clearance: issue 24's stated bound lets a pair pushed out from c_raw to r amplify by r /
c_raw). Seeds 1 and 2 are those of ``scenes_compare.py``, whose rows showed the one-side lanes'
probes above 1e3 (that is why this part exists); seeds 3 and 4 were not looked at before. The
default changes in the plane only: in space (room3d) the one-side lanes keep no more plans
valid (the design rows), since a path can go around a gap there.

Per row and planner the table gives:

* valid: the plan keeps the radii and the walls, decided exactly (``Plan.respects_radius``);
* gap: the invalid plans whose miss is a gap narrower than a robot;
* the median len/LB over the valid plans;
* the paired ratio: the one-side plan's length over the compact plan's, median over the
  queries both keep valid.

Writes ``benchmarks/crowd_default.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import multiprocessing
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes
import scenes_compare
from _common import rewrite_report, write_report
from shared_ab import raw_timing, timing_rows

import pmplan
from pmplan.planners.base import CROWD_LANES

PLANNERS = ["obstacle_line_compact", "obstacle_line_oneside"]
SHORT = {"obstacle_line_compact": "compact", "obstacle_line_oneside": "one side"}
FAMILIES = ["room", "swap", "room_walls", "swap_walls", "room3d"]
#: (part, seeds, robot counts); 100 queries per row
PARTS = (("design", (11, 12), (4, 6, 8, 12, 16)), ("held out", (20, 21), (8, 10, 16, 20)))
COUNT = 100
HALF = scenes.R / 2
#: the continuity part: seeds, robot counts, queries per row, the families
CONTINUITY = ((1, 2, 3, 4), (8, 16), 16, ("room", "swap", "room_walls", "swap_walls", "room3d"))
#: issue 24's continuity goal
GOAL = scenes_compare.CONT_GOAL


def cell(fam: str, n: int, seed: int) -> dict:
    """One row: per planner the valid plans, the gap misses, the median len/LB; the paired
    length ratio one side / compact."""
    qs = scenes.queries(fam, n, COUNT, seed)
    out = {"family": fam, "n": n, "seed": seed, "count": len(qs)}
    lens = {}
    for name in PLANNERS:
        valid = gap = 0
        ratio = []
        for o, s, g in qs:
            p = pmplan.plan(o, s, g, planner=name, refine=True, radius=HALF,
                            obstacle_radius=HALF, bounds=(0.0, scenes.SIZE))
            ok = bool(p.respects_radius)
            valid += ok
            gap += not ok and p.radius_miss.category == "gap"
            lb = np.linalg.norm(g - s, axis=1).sum()
            ratio.append(p.path.length() / lb if ok else np.nan)
        lens[name] = np.array(ratio)
        out[name] = {"valid": valid, "gap": gap,
                     "len_lb": float(np.nanmedian(ratio)) if valid else None}
    both = ~np.isnan(lens[PLANNERS[0]]) & ~np.isnan(lens[PLANNERS[1]])
    out["paired"] = (float(np.median(lens[PLANNERS[1]][both] / lens[PLANNERS[0]][both]))
                     if both.any() else None)
    out["paired_count"] = int(both.sum())
    print(out, flush=True)
    return out


def _seed_rows(job) -> list[dict]:
    part, seed, ns = job
    if part == "continuity":
        return [continuity_cell(f, n, seed) for n in CONTINUITY[1] for f in CONTINUITY[3]]
    return [dict(cell(f, n, seed), part=part) for n in ns for f in FAMILIES]


def continuity_cell(fam: str, n: int, seed: int) -> dict:
    """One row of the continuity part: per planner the probes that kept the label, the
    largest K, the pairs with K > 1e3 and with K_eff > 1e3 (the same moves for both)."""
    count = CONTINUITY[2]
    qs = scenes.queries(fam, n, count, seed)
    out = {"family": fam, "n": n, "seed": seed, "count": len(qs)}
    for name in PLANNERS:
        runner = scenes_compare.PmplanRunner(None, bounded=True)
        runner.kw["planner"] = name
        rng = np.random.default_rng([seed, scenes.FAMILIES[fam].index, n, 77])
        ks = []
        for o, s, g in qs:
            _, res = runner.plan(o, s, g)
            if res is None:
                continue
            ks += [(c["K"], c["raw_clearance"])
                   for c in scenes_compare.continuity(runner, o, s, g, res, rng)
                   if c["returned"] and not c["label_change"]]
        keff = [k / max(1.0, scenes.R / c) for k, c in ks]
        out[name] = {"probes": len(ks), "k_max": max(k for k, _ in ks),
                     "k_over": sum(k > GOAL for k, _ in ks),
                     "keff_max": max(keff), "keff_over": sum(k > GOAL for k in keff)}
    print(out, flush=True)
    return out


def _fmt(x, spec=".3g") -> str:
    return "n/a" if x is None else format(x, spec)


def _gain(res: dict, part: str, n: int, fams: tuple) -> str:
    """One side minus compact, valid plans over the rows of ``part``, ``n``, ``fams``."""
    rs = [r for r in res["rows"] if r["part"] == part and r["n"] == n and r["family"] in fams]
    return (f"{sum(r[PLANNERS[1]]['valid'] - r[PLANNERS[0]]['valid'] for r in rs):+d} of "
            f"{sum(r['count'] for r in rs)}")


def markdown(res: dict) -> str:
    lines = [
        "# The default section of a refined crowd",
        "",
        f"`{res['command']}` ({res['date']}, {res['seconds']:.0f} s). {res['count']} queries per "
        "row, refined at radius = obstacle_radius = r/2 in the box (0, 10), the unit at its "
        "default. *compact*: `obstacle_line_compact`; *one side*: `obstacle_line_oneside`. "
        "Per planner: valid (gap misses) and the median len/LB of the valid plans; *paired*: "
        "one side / compact, the median length ratio over the queries both keep valid (their "
        "count in brackets). A refined plan of at least "
        f"{res['crowd']} robots in the plane takes the one-side lanes by default.",
    ]
    lines += ["", "How the count was chosen: *one side* minus *compact*, valid plans per robot "
              "count of the design part, in the rooms whose obstacles may sit near a wall "
              "(room, swap) and in those whose obstacles keep clear of the walls (room_walls, "
              "swap_walls): " + "; ".join(
                  f"n = {n}: {_gain(res, 'design', n, ('room', 'swap'))} and "
                  f"{_gain(res, 'design', n, ('room_walls', 'swap_walls'))}"
                  for n in PARTS[0][2]) + ". `CROWD_LANES` is the smallest of these counts from "
              "which the one-side lanes gain clearly where gaps are narrow, lose at most a few "
              "plans where they are not, and make the paths at most a few percent longer (the "
              "paired "
              "ratios). Below it they do not: with 4 robots the gain is small and the paths are "
              "longer by the most, where pmplan's length against RRTConnect is the tightest of "
              "issue 25's goals; with 6 they lose plans in both kinds of rooms. Above it one "
              "count decides every larger crowd: with 12 robots nothing is gained or lost, with "
              "10, 16 and 20 the held-out seeds gain. (The count was 16 until a refinement of 5 "
              "to 8 robots in the plane ended with as many clearing-only steps as steps, "
              "`PLANE_FINAL`: with a quarter as many, the one-side lanes of 8 robots lost plans "
              "in the rooms with clear walls.) Held out: " + "; ".join(
                  f"n = {n}: {_gain(res, 'held out', n, ('room', 'swap'))} and "
                  f"{_gain(res, 'held out', n, ('room_walls', 'swap_walls'))}"
                  for n in PARTS[1][2]) + "."]
    for part, seeds, ns in PARTS:
        rows = [r for r in res["rows"] if r["part"] == part]
        lines += ["", f"**{part}** (seeds {', '.join(str(s) for s in seeds)}):", "",
                  "| seed | row | compact | one side | paired |", "|---|---|---|---|---|"]
        for r in rows:
            cells = [f"{r[p]['valid']} ({r[p]['gap']}), {_fmt(r[p]['len_lb'])}"
                     for p in PLANNERS]
            lines.append(f"| {r['seed']} | {r['family']} n = {r['n']} | {' | '.join(cells)} | "
                         f"{_fmt(r['paired'])} ({r['paired_count']}) |")
        lines += ["", f"Totals of the {part} part per robot count (valid of queries, "
                  "2-D families; the paired ratio's range over the rows):", "",
                  "| n | families | compact | one side | paired, range |", "|---|---|---|---|---|"]
        for n in ns:
            for label, fams in (("room, swap", ("room", "swap")),
                                ("room_walls, swap_walls", ("room_walls", "swap_walls")),
                                ("room3d", ("room3d",))):
                rs = [r for r in rows if r["n"] == n and r["family"] in fams]
                tot = sum(r["count"] for r in rs)
                vs = [sum(r[p]["valid"] for r in rs) for p in PLANNERS]
                pr = [r["paired"] for r in rs if r["paired"] is not None]
                rng = f"{min(pr):.3g}-{max(pr):.3g}" if pr else "n/a"
                lines.append(f"| {n} | {label} | {vs[0]} of {tot} ({vs[0] / tot:.1%}) | "
                             f"{vs[1]} of {tot} ({vs[1] / tot:.1%}) | {rng} |")
    cont = res.get("continuity", [])
    if cont:
        lines += ["", f"**continuity** ({' and '.join(map(str, CONTINUITY[1]))} robots, seeds "
                  f"{', '.join(str(s) for s in CONTINUITY[0])}, {CONTINUITY[2]} queries per row; "
                  "per planner: probes that kept the label, the largest K, the pairs with K > 1e3, "
                  "the largest K_eff and the pairs with K_eff > 1e3):", "",
                  "| seed | row | compact | one side |", "|---|---|---|---|"]
        for r in cont:
            lines.append(f"| {r['seed']} | {r['family']} n = {r['n']} | " + " | ".join(
                f"{r[p]['probes']}, {_fmt(r[p]['k_max'])}, {r[p]['k_over']}, "
                f"{_fmt(r[p]['keff_max'])}, {r[p]['keff_over']}" for p in PLANNERS) + " |")
        tot = [(sum(r[p]["probes"] for r in cont), sum(r[p]["k_over"] for r in cont),
                sum(r[p]["keff_over"] for r in cont),
                sum(r[p]["k_over"] > 0 for r in cont)) for p in PLANNERS]
        lines += ["", "All rows: " + "; ".join(
            f"*{SHORT[p]}* K > 1e3 on {t[1]} of {t[0]} probes (in {t[3]} of {len(cont)} rows), "
            f"K_eff > 1e3 on {t[2]}" for p, t in zip(PLANNERS, tot)) + "."]
    if res.get("timing"):
        lines += ["", "Raw plan cost (`plan_batch` of generic queries, numba, one core, best of 7 "
                  "calls each, the planners interleaved; microseconds per query): what a "
                  "refined crowd's raw plan costs more with the one-side lanes (the chains are "
                  "computed query by query), a small part of a refined plan's time "
                  "(`scenes_time.py` measures it).", "",
                  *timing_rows(res["timing"], SHORT[PLANNERS[1]])]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--from-json", action="store_true", help="rewrite the .md from the .json")
    args = ap.parse_args(argv)
    if args.from_json:
        rewrite_report("crowd_default", markdown)
        return 0
    t0 = time.perf_counter()
    jobs = [(part, seed, ns) for part, seeds, ns in PARTS for seed in seeds]
    jobs += [("continuity", seed, None) for seed in CONTINUITY[0]]
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        out = pool.map(_seed_rows, jobs)
    rows = [r for (part, _, _), rs in zip(jobs, out) if part != "continuity" for r in rs]
    cont = [r for (part, _, _), rs in zip(jobs, out) if part == "continuity" for r in rs]
    timing = raw_timing(planners={SHORT[p]: p for p in PLANNERS})  # (alone, after the pool)
    res = {"command": " ".join(["python benchmarks/crowd_default.py",
                                *(argv or sys.argv[1:])]),
           "date": _dt.date.today().isoformat(), "count": COUNT, "crowd": CROWD_LANES,
           "seconds": time.perf_counter() - t0, "rows": rows, "continuity": cont,
           "timing": timing}
    write_report("crowd_default", res, markdown)
    return 0


if __name__ == "__main__":
    sys.exit(main())
