"""The crowd's refinement steps: valid share, length and modulus of continuity of refined
plans with 16 robots at ``CROWD_STEPS = 224`` against 112, per row.

Usage (from the repository root)::

    python benchmarks/crowd_ab.py     # seeds 1, 2, 4, 5, 6 and 42-49, about 5 minutes

The refinement's default effort depends on the dimension and the number of robots alone
(:func:`pmplan.refine.default_effort`), so that it stays continuous on every domain: for more
than ``CROWD`` = 8 robots it is ``CROWD_WAYPOINTS`` sub-pieces and ``CROWD_STEPS`` steps in the
plane, ``SPACE_CROWD_STEPS`` in d >= 3. This benchmark measures doubling the steps (224 against
112, 4 sub-pieces both).

Rows: the scene families of ``benchmarks/scenes.py`` (room, swap, room_walls, swap_walls and
room3d) with n = 16, 16 queries each; pmplan's default plan in the box (``bounds=(0, 10)``)
refined with radius = obstacle_radius = r/2 at the crowd's default effort, with
``pmplan.refine.grid.CROWD_STEPS`` and ``SPACE_CROWD_STEPS`` (the plane's and the space's)
both set for the measurement (the default effort reads them at every call; nothing else
changes). pmplan takes 224 in the plane and keeps 112 in d >= 3 (``SPACE_CROWD_STEPS``: see
its comment in ``pmplan/refine/grid.py``). Per row and variant (the same queries and probe moves):
the queries valid (keep the radii and stay in the box, decided exactly), the median length /
LB, the raw plan's clearance and the modulus of continuity at delta = 1e-6, 1e-9 and 1e-12
(``scenes_compare.ab_row``). Seeds 1, 2, 4, 5 and 6 were looked at before the choice; 42-49
were drawn for it and not looked at before.

Writes ``benchmarks/crowd_ab.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes
import scenes_compare

FAMILIES = ["room", "swap", "room_walls", "swap_walls", "room3d"]
NS = [16]
GRID = importlib.import_module("pmplan.refine.grid")
_STEPS = GRID.CROWD_STEPS, GRID.SPACE_CROWD_STEPS
#: the variants: the crowd's steps
VARIANTS = {"steps 224": 224, "steps 112": 112}
#: the seeds looked at before the choice
DESIGN = {1, 2, 4, 5, 6}


def variant(name: str) -> None:
    """Set the crowd's default steps, in the plane and in space."""
    GRID.CROWD_STEPS = GRID.SPACE_CROWD_STEPS = VARIANTS[name]


def row(fam: str, n: int, seed: int, count: int) -> dict:
    """One row: both variants on the same queries and probe moves (``ab_row``), then the
    default restored."""
    out = scenes_compare.ab_row(fam, n, seed, count, variant, list(VARIANTS))
    GRID.CROWD_STEPS, GRID.SPACE_CROWD_STEPS = _STEPS
    return out


def markdown(res: dict) -> str:
    prose = (f"Command: `{res['command'].strip()}` ({res['date']}). Rooms 10 x 10 (m = 6) and "
             f"10 x 10 x 10 (m = 4), r = {scenes.R}, {res['count']} queries per row, 16 robots, "
             "pmplan's default plan in the box refined with radius = obstacle_radius = r/2 at "
             "4 sub-pieces and *steps 224* or *steps 112* (the crowd's default before; in 3-D "
             "still the default, `SPACE_CROWD_STEPS`), in every dimension. "
             + scenes_compare.AB_COLUMNS + " Seeds 1, 2, 4, 5 and 6 were looked at before the "
             "choice; 42-49 were not.")
    return scenes_compare.ab_markdown(
        res, "The crowd's refinement steps: valid share, length, continuity (16 robots)",
        prose, DESIGN, "steps 112")


def main(argv=None) -> int:
    """Run the rows (``scenes.rows_main``)."""
    return scenes.rows_main("crowd_ab", __doc__, row, markdown, FAMILIES, NS,
                            "1,2,4,5,6," + ",".join(str(s) for s in range(42, 50)), argv)


if __name__ == "__main__":
    raise SystemExit(main())
