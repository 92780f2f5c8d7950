"""The refinement's final clearing-only steps: valid share, time and length of refined plans in
the box with ``FINAL = 1/4`` of the steps (pmplan's default) against ``1/8`` (before), per row.

Usage (from the repository root)::

    python benchmarks/final_ab.py --seeds 1,2,4,5,6

Rows: the 2-D scene families of ``benchmarks/scenes.py`` (room, swap, room_walls, swap_walls)
with n = 2, 4, 8 and 16, 16 queries each; pmplan's default plan in the box (``bounds=(0, 10)``)
refined at its default effort with radius = obstacle_radius = r/2, in one process on the same
queries, with ``pmplan.refine.grid.FINAL`` set for the measurement (the kernel reads the number
of final steps from it at every call; nothing else changes). Per row and variant: the queries
valid (keep the radii and stay in the box, decided exactly), the median time per query (plan and
refinement, one core) and the median length / LB. Seed 1 is the design draw (1/4 was chosen
there); 2, 4, 5 and 6 are held out. Since ``PLANE_FINAL`` and ``CROWD_FINAL``, ``FINAL`` sets the
clearing-only steps of up to ``SETTLE`` = 4 robots in the plane (and in d >= 3) only: run again,
the rows of 8 and 16 robots would repeat the default in both variants
(``benchmarks/plane_final.py``, ``benchmarks/crowd_effort.py`` measure those).

Writes ``benchmarks/final_ab.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes  # noqa: E402

FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [2, 4, 8, 16]
GRID = importlib.import_module("pmplan.refine.grid")
_FINAL = GRID.FINAL
VARIANTS = {"final 1/4": {"FINAL": _FINAL}, "final 1/8": {"FINAL": 0.125}}


def row(fam: str, n: int, seed: int, count: int) -> dict:
    return scenes.variants_row(fam, n, seed, count, scenes.attribute_variants(GRID, VARIANTS))


def markdown(res: dict) -> str:
    return scenes.variants_markdown(
        res, "The refinement's final clearing-only steps: valid share, time, length",
        f"*final 1/4*: pmplan's default (`FINAL = {_FINAL}`: the last quarter of the steps "
        "clear without shortening, 14 of 56 and 28 of 112); *final 1/8*: the default before "
        "(7 and 14). Seed 1 is the design draw; the others are held out.",
        list(VARIANTS), "final 1/4", "final 1/8")


def main(argv=None) -> int:
    return scenes.rows_main("final_ab", __doc__, row, markdown, FAMILIES, NS, "1,2,4,5,6", argv)


if __name__ == "__main__":
    raise SystemExit(main())
