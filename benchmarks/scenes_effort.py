"""The refinement's default effort (pmplan.refine.default_effort): valid share, time and
length of the refined plans in the box against the refinement's effort, per row.

Usage (from the repository root)::

    python benchmarks/scenes_effort.py --seeds 1,2,4,5,6

Rows: the 2-D scene families of ``benchmarks/scenes.py`` (room, swap, room_walls, swap_walls)
with n = 2, 4, 8 and 16, 16 queries each; pmplan's default plan in the box (``bounds=(0, 10)``,
``lift`` the robots' diameter) refined with radius = obstacle_radius = r/2 at the efforts
(waypoints/steps) 2/56 (the default before the refinement saw the walls), 4/56 (the default up
to ``CROWD`` robots), 4/112 (the crowd's default before ``benchmarks/crowd_ab.py``), 4/224 (the
crowd's default), 8/224 and 8/448. Per row and effort: the queries that keep the radii (``respects_radius``, decided
exactly), the median time per query (plan and refinement, one core), the median length / LB.
The crowd's steps 112 were chosen on seed 1 (2 and 4 held out), the waypoints 4 against 2 on
seeds 1, 2 and 4; seeds 5 and 6 are held out from both; 224 on ``benchmarks/crowd_ab.py``.

Writes ``benchmarks/scenes_effort.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pmplan

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes  # noqa: E402

HERE = Path(__file__).resolve().parent
EFFORTS = [(2, 56), (4, 56), (4, 112), (4, 224), (8, 224), (8, 448)]
FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [2, 4, 8, 16]
HALF = scenes.R / 2


def row(fam: str, n: int, seed: int, count: int) -> dict:
    qs = scenes.queries(fam, n, count, seed)
    out = {"family": fam, "n": n, "seed": seed, "efforts": {}}
    for w, k in EFFORTS:
        out["efforts"][f"{w}/{k}"] = scenes.summary(
            f"seed {seed} {fam} n={n} {w}/{k}", qs,
            lambda o, s, g, w=w, k=k: pmplan.refine(
                pmplan.plan(o, s, g, bounds=(0.0, scenes.SIZE), lift=scenes.R), radius=HALF,
                obstacle_radius=HALF, waypoints=w, steps=k))
    return out


def markdown(res: dict) -> str:
    lines = ["# The refinement's effort: valid share, time, length", "",
             f"Command: `{res['command']}` ({res['date']}). Rooms 10 x 10, r = {scenes.R}, "
             f"{res['count']} queries per row, pmplan's default plan in the box refined at "
             "radius = obstacle_radius = r/2 with `waypoints/steps` below; valid = keeps the "
             "radii (decided exactly); time = median ms per query (plan + refinement, one core; "
             "a shared machine: compare within a row); len/LB = median length / sum of the "
             "straight distances. 4/56 is the default up to 8 robots (2/56 before the refinement saw the "
             "walls), 4/224 the default for "
             "more (`pmplan.refine.default_effort`; 4/112 before). The crowd's 112 steps were "
             "chosen on seed 1 (2 and 4 held out), 4/56 against 2/56 on seeds 1, 2 and 4; seeds "
             "5 and 6 were not looked at before that choice; 224 against 112 was measured by "
             "`benchmarks/crowd_ab.py` on these seeds and on seeds 42-49.", "",
             "| seed | row | " + " | ".join(f"{w}/{k}: valid, ms, len/LB" for w, k in EFFORTS)
             + " |", "|---|---|" + "---|" * len(EFFORTS)]
    for r in res["rows"]:
        cells = [f"{e['valid']}/{e['count']}, {e['time_ms']:.1f}, {e['len_lb']:.2f}"
                 for e in r["efforts"].values()]
        lines.append(f"| {r['seed']} | {r['family']} n = {r['n']} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    return scenes.rows_main("scenes_effort", __doc__, row, markdown, FAMILIES, NS, "1,2,4,5,6", argv)


if __name__ == "__main__":
    raise SystemExit(main())
