"""Walls in the refinement: valid share, time and length of refined plans in the box with the
refinement's walls (pmplan's defaults) against the refinement without them, per row.

Usage (from the repository root)::

    python benchmarks/walls_ab.py --seeds 1,2,4

Rows: the 2-D scene families of ``benchmarks/scenes.py`` (room, swap, room_walls, swap_walls)
with n = 2, 4, 8 and 16, 16 queries each; pmplan's default plan in the box (``bounds=(0, 10)``)
refined at its default effort with radius = obstacle_radius = r/2. Three variants, in one
process on the same queries:

* ``walls`` -- pmplan's default: the refinement pushes the robots back from the walls' limits
  and holds its moves toward them; the final map into the box has the band ``SQUEEZE`` (1/256);
* ``band`` -- the refinement without walls, the same narrow band;
* ``before`` -- the refinement without walls and the band of 1/64 it had before the walls.

The variants without walls are pmplan's stage with its walls switched off (its ``_walls``
method replaced for the measurement; nothing else changes). Per row and variant: the queries
valid (keep the radii and stay in the box, decided exactly), the median time per query (plan
and refinement, one core) and the median length / LB. Seed 1 is the design draw; 2 and 4 are
held out.

Writes ``benchmarks/walls_ab.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes  # noqa: E402

HERE = Path(__file__).resolve().parent
FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [2, 4, 8, 16]
VARIANTS = ["walls", "band", "before"]
STAGE = importlib.import_module("pmplan.refine.stage")
_WALLS = STAGE.RefineStage._walls
_SQUEEZE = STAGE.SQUEEZE


def _no_walls(self, b, back):
    return None


def variant(name: str) -> None:
    """Switch pmplan's refinement stage to one variant."""
    STAGE.RefineStage._walls = _WALLS if name == "walls" else _no_walls
    STAGE.SQUEEZE = 1.0 / 64.0 if name == "before" else _SQUEEZE


def row(fam: str, n: int, seed: int, count: int) -> dict:
    return scenes.variants_row(fam, n, seed, count,
                               {name: (lambda name=name: variant(name)) for name in VARIANTS})


def markdown(res: dict) -> str:
    return scenes.variants_markdown(
        res, "Walls in the refinement: valid share, time, length",
        "*walls*: pmplan's default (the refinement sees the walls, band 1/256); *band*: no "
        "walls in the refinement, the same band; *before*: no walls, band 1/64. Seed 1 is the "
        "design draw; the others are held out.", VARIANTS, "walls", "before")


def main(argv=None) -> int:
    return scenes.rows_main("walls_ab", __doc__, row, markdown, FAMILIES, NS, "1,2,4", argv)


if __name__ == "__main__":
    raise SystemExit(main())
