"""The refinement's default effort (pmplan.refine.default_effort): valid share, time and
length of the refined plans in the box against the refinement's effort, per row.

Usage (from the repository root)::

    python benchmarks/scenes_effort.py --seeds 1,2,4,5,6

Rows: the 2-D scene families of ``benchmarks/scenes.py`` (room, swap, room_walls, swap_walls)
with n = 2, 4, 8 and 16, 16 queries each; the raw plan in the box (``bounds=(0, 10)``,
``lift`` the robots' diameter) of pmplan's default planner for a refined plan
(``obstacle_line_compact``, ``obstacle_line_oneside`` from ``CROWD_LANES`` = 8 robots on),
refined with radius = obstacle_radius = r/2 at the efforts (waypoints/steps) 2/56 (the default
before the refinement saw the walls), 4/56 (the default up to ``SETTLE`` = 4 robots), 4/72 (the
default for 5 to 8, ``PLANE_STEPS``), 4/96 (the default for more before the still pieces,
``benchmarks/still_ab.py``), 4/112 (the default for more), 4/224 (the crowd's default before
``benchmarks/crowd_effort.py``), 8/224 and 8/448; every effort ends with the clearing-only steps of
:func:`pmplan.refine.grid.final_steps`. Per row and effort: the queries that keep the radii
(``respects_radius``, the walls included, decided exactly), the median time per query (plan
and refinement, one core), the median length / LB; then per family and robot count the totals
over the seeds, with the invalid plans by reason (*gap*: the path crosses a gap narrower than
a robot, which no planner continuous on these domains avoids on every query, Mathematics §8).
The waypoints 4 against 2 were chosen on seeds 1, 2 and 4, the crowd's steps 112 on seed 1 (2
and 4 held out); seeds 5 and 6 are held out from both.

Writes ``benchmarks/scenes_effort.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pmplan
from pmplan.planners.base import default_planner
from pmplan.refine import default_effort

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes  # noqa: E402

HERE = Path(__file__).resolve().parent
EFFORTS = [(2, 56), (4, 56), (4, 72), (4, 96), (4, 112), (4, 224), (8, 224), (8, 448)]
FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [2, 4, 8, 16]
HALF = scenes.R / 2


def _label(effort: tuple[int, int]) -> str:
    """An effort's name in the report: ``waypoints/steps``."""
    return "{}/{}".format(*effort)


def row(fam: str, n: int, seed: int, count: int) -> dict:
    qs = scenes.queries(fam, n, count, seed)
    planner = default_planner(2, n, scenes.FAMILIES[fam].m, refining=True)
    out = {"family": fam, "n": n, "seed": seed, "planner": planner, "efforts": {}}
    for w, k in EFFORTS:
        out["efforts"][_label((w, k))] = scenes.summary(
            f"seed {seed} {fam} n={n} {_label((w, k))}", qs,
            lambda o, s, g, w=w, k=k: pmplan.refine(
                pmplan.plan(o, s, g, bounds=(0.0, scenes.SIZE), lift=scenes.R, planner=planner),
                radius=HALF, obstacle_radius=HALF, waypoints=w, steps=k))
    return out


def markdown(res: dict) -> str:
    lines = ["# The refinement's effort: valid share, time, length", "",
             f"Command: `{res['command']}` ({res['date']}). Rooms 10 x 10, r = {scenes.R}, "
             f"{res['count']} queries per row; the raw plan in the box of pmplan's default "
             "planner for a refined plan (the compact lanes, the one-side lanes from 8 robots "
             "on) refined at radius = obstacle_radius = r/2 with `waypoints/steps` below, each "
             "followed by its clearing-only steps (`pmplan.refine.grid.final_steps`); valid = "
             "keeps the radii and the walls (decided exactly); time = median ms per query (plan "
             "+ refinement, one core; a shared machine: compare within a row); len/LB = median "
             "length / sum of the straight distances. The default effort "
             "(`pmplan.refine.default_effort`) is 4/56 up to 4 robots, 4/72 for 5 to 8, 4/112 "
             "for more (in bold). 2/56 was the default before the refinement saw the walls, "
             "4/224 the crowd's before `benchmarks/crowd_effort.py`, 4/96 before the still "
             "pieces (`benchmarks/still_ab.py`). The waypoints 4 against 2 were "
             "chosen on seeds 1, 2 and 4, the crowd's steps 112 on seed 1 (2 and 4 held out); "
             "seeds 5 and 6 were not looked at for either.", "",
             "| seed | row | " + " | ".join(f"{_label(e)}: valid, ms, len/LB" for e in EFFORTS)
             + " |", "|---|---|" + "---|" * len(EFFORTS)]
    for r in res["rows"]:
        default = _label(default_effort(r["n"]))
        cells = []
        for name, e in r["efforts"].items():
            cell = f"{e['valid']}/{e['count']}, {e['time_ms']:.1f}, {e['len_lb']:.2f}"
            cells.append(f"**{cell}**" if name == default else cell)
        lines.append(f"| {r['seed']} | {r['family']} n = {r['n']} | " + " | ".join(cells) + " |")
    seeds = ", ".join(sorted({str(r["seed"]) for r in res["rows"]}, key=int))
    lines += ["", f"Totals over the seeds ({seeds}) per family and robot count: valid plans of "
              "the queries, and in brackets the invalid ones that cross a gap narrower than a "
              "robot (no planner continuous on these domains avoids them all: "
              "[gap_bound](gap_bound.md)); the rest of the invalid plans are contacts the "
              "refinement left. The default effort in bold.", "",
              "| row | " + " | ".join(_label(e) for e in EFFORTS) + " |",
              "|---|" + "---|" * len(EFFORTS)]
    for fam in FAMILIES:
        for n in NS:
            rows = [r for r in res["rows"] if r["family"] == fam and r["n"] == n]
            if not rows:
                continue
            default = _label(default_effort(n))
            cells = []
            for effort in EFFORTS:
                es = [r["efforts"][_label(effort)] for r in rows]
                cell = (f"{sum(e['valid'] for e in es)}/{sum(e['count'] for e in es)} "
                        f"({sum(e['why'].get('gap', 0) for e in es)})")
                cells.append(f"**{cell}**" if _label(effort) == default else cell)
            lines.append(f"| {fam} n = {n} | " + " | ".join(cells) + " |")
    most = _label(EFFORTS[-1])
    gains: dict[int, int] = {}
    for r in res["rows"]:
        e = r["efforts"]
        g = e[most]["valid"] - e[_label(default_effort(r["n"]))]["valid"]
        gains[g] = gains.get(g, 0) + 1
    lines += ["", f"The most effort, {most}, against the default, per row (of {len(res['rows'])}"
              "): " + ", ".join(f"{c} row{'s' if c != 1 else ''} {'+' if g > 0 else ''}{g}"
                                for g, c in sorted(gains.items())) + " valid plans."]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    return scenes.rows_main("scenes_effort", __doc__, row, markdown, FAMILIES, NS, "1,2,4,5,6",
                            argv)


if __name__ == "__main__":
    raise SystemExit(main())
