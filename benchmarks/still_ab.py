"""The still pieces of the refinement's grid: valid share, time and length of refined plans in
the box when the pieces a planner declares still (``Planner.still_pieces``: the
obstacle-line planner's desingularization and its reverse, constant paths for almost every
query) stay one piece, against every piece cut into ``waypoints`` sub-pieces, per row.

Usage (from the repository root)::

    python benchmarks/still_ab.py                   # about 8 minutes
    python benchmarks/still_ab.py --from-json       # rewrite the report

Rows: the scene families of ``benchmarks/scenes.py`` (room, swap, room_walls, swap_walls and
room3d) with n = 2, 4, 8 and 16, 100 queries each; pmplan's default plan in the box
(``bounds=(0, 10)``) refined at its default effort with radius = obstacle_radius = r/2, in one
process on the same queries. Variants, switched for the measurement (the refinement asks the
planner class for its still pieces and ``pmplan.refine.grid`` for the effort at every call):

* *still*: pmplan's default -- still pieces kept whole, ``PLANE_STEPS`` steps for 5 to 8
  robots in the plane and ``CROWD_STEPS`` for more;
* *still, steps before*: still pieces kept whole at the steps before (56 and 96);
* *cut, steps before*: every piece cut, 56 and 96 steps (the refinement before).

Per row and variant: the queries valid (keep the radii and stay in the box, decided exactly),
the median time per query (plan and refinement, one core; a shared machine) and the median
length / LB. Seeds 11 and 12 are the design draws: the steps were chosen there, in a
prototype of this script with 400 queries per row of up to 8 robots and 150 of 16, among 1,
1.15 and 1.3 times the steps before (and 1.5 with 8 robots in room and swap): with 8 robots 1.3
(72) kept the radii on 1,458 of 1,600 room and swap plans against 1,438 before, 1.5 on 1,465
at 20 % more time than before, near the 5 ms asked; with 16 robots 1.15 (112 rounded) on as
many or more in every row at the time of before, 1.3 passed 19 ms. Seeds 30 and 31 are held
out.

Writes ``benchmarks/still_ab.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes  # noqa: E402

from pmplan.planners.obstacle_line import ObstacleLinePlanner  # noqa: E402

FAMILIES = ["room", "swap", "room_walls", "swap_walls", "room3d"]
NS = [2, 4, 8, 16]
GRID = importlib.import_module("pmplan.refine.grid")
_STILL = ObstacleLinePlanner.still_pieces
_STEPS = {"PLANE_STEPS": GRID.PLANE_STEPS, "CROWD_STEPS": GRID.CROWD_STEPS}
_BEFORE = {"PLANE_STEPS": GRID.DEFAULT_STEPS, "CROWD_STEPS": 96}


_DECLARED = (ObstacleLinePlanner, "still_pieces")


def _none(self, r: int):
    return None


#: name -> the attributes it sets (the grid's steps, the planner's declaration); the first is
#: pmplan's default
VARIANTS = {"still": {_DECLARED: _STILL, **_STEPS},
            "still, steps before": {_DECLARED: _STILL, **_BEFORE},
            "cut, steps before": {_DECLARED: _none, **_BEFORE}}


def row(fam: str, n: int, seed: int, count: int) -> dict:
    return scenes.variants_row(fam, n, seed, count, scenes.attribute_variants(GRID, VARIANTS))


def markdown(res: dict) -> str:
    return scenes.variants_markdown(
        res, "The still pieces of the refinement's grid: valid share, time, length",
        f"*still*: pmplan's default (the obstacle-line planner's still pieces, the "
        f"desingularization and its reverse, one piece each: 22 pieces a leg; "
        f"`PLANE_STEPS = {_STEPS['PLANE_STEPS']}` steps for 5 to 8 robots in the plane, "
        f"`CROWD_STEPS = {_STEPS['CROWD_STEPS']}` for more); *still, steps before*: the "
        f"same grid at {_BEFORE['PLANE_STEPS']} and {_BEFORE['CROWD_STEPS']} steps; *cut, "
        "steps before*: every piece cut in 4 (28 pieces a leg) at those steps, the "
        "refinement before. With up to 4 robots and in space the steps are the same in all "
        "three. Seeds 11 and 12 are the design draws; 30 and 31 are held out.",
        list(VARIANTS), "still", "cut, steps before")


def main(argv=None) -> int:
    return scenes.rows_main("still_ab", __doc__, row, markdown, FAMILIES, NS, "11,12,30,31",
                            argv, count=100)


if __name__ == "__main__":
    raise SystemExit(main())
