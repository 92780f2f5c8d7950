"""Plans in the box with their raw pieces cut before the map: what following the conjugated
motion more closely costs the refined plans (``pmplan.workspace.RAW_CUTS`` = 1 against 2, 4).

Usage (from the repository root)::

    python benchmarks/chords_ab.py        # seeds 1, 2 and 42-45, about 10 minutes

In a box pmplan returns the polyline through the mapped waypoints of the raw plan; its chords
can pass an obstacle on the other side than the curve the map makes of a raw piece (Mathematics
§8, "What the chords are not"; ``benchmarks/box_chords.py`` counts how often). Cutting every
raw piece into ``RAW_CUTS`` equal pieces in R^d before the map follows that curve more closely.
The refinement then starts from a finer path: the variants keep its finest level where it is
(``waypoints`` = 4 / cuts, set through ``pmplan.refine.grid``'s defaults, 28 pieces per leg
for all three) and so give up its coarse levels, which is what the cut costs at the same effort.

Rows: the scene families of ``benchmarks/scenes.py`` in the box, n = 2, 4, 8, 16, 16 queries
each; pmplan's default plan in the box refined with radius = obstacle_radius = r/2, through
``scenes_compare.ab_row`` (the same queries and probe moves for every variant): valid, median
len/LB, the raw clearance and the modulus of continuity at delta = 1e-6, 1e-9, 1e-12. Seeds 1
and 2 were looked at while writing it, 42-45 not.

Writes ``benchmarks/chords_ab.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes
import scenes_compare

from pmplan import workspace

FAMILIES = ["room", "swap", "room_walls", "swap_walls", "room3d"]
NS = [2, 4, 8, 16]
GRID = importlib.import_module("pmplan.refine.grid")
_DEFAULTS = workspace.RAW_CUTS, GRID.DEFAULT_WAYPOINTS, GRID.CROWD_WAYPOINTS
#: the variants: raw cuts (the refinement's sub-pieces are 4 / cuts)
VARIANTS = {"cuts 1": 1, "cuts 2": 2, "cuts 4": 4}
#: the seeds looked at while writing it
DESIGN = {1, 2}


def variant(name: str) -> None:
    """Cut the raw pieces ``VARIANTS[name]`` times and refine with 4 / cuts sub-pieces."""
    cuts = VARIANTS[name]
    workspace.RAW_CUTS = cuts
    GRID.DEFAULT_WAYPOINTS = GRID.CROWD_WAYPOINTS = _DEFAULTS[1] // cuts


def row(fam: str, n: int, seed: int, count: int) -> dict:
    """One row: every variant on the same queries and probe moves, then the defaults back."""
    try:
        return scenes_compare.ab_row(fam, n, seed, count, variant, list(VARIANTS))
    finally:
        workspace.RAW_CUTS, GRID.DEFAULT_WAYPOINTS, GRID.CROWD_WAYPOINTS = _DEFAULTS


def markdown(res: dict) -> str:
    prose = (f"Command: `{res['command'].strip()}` ({res['date']}). Rooms 10 x 10 (m = 6) and "
             f"10 x 10 x 10 (m = 4), r = {scenes.R}, {res['count']} queries per row, pmplan's "
             "default plan in the box, every raw piece cut into 1 (the default), 2 or 4 "
             "pieces in R^d before the map into the box, refined with radius = "
             "obstacle_radius = r/2 with 4, 2 or 1 sub-pieces (the same finest level, fewer "
             "coarse ones). " + scenes_compare.AB_COLUMNS + " Seeds 1 and 2 were looked at "
             "while writing it; 42-45 were not.")
    return scenes_compare.ab_markdown(
        res, "Plans in the box: the raw pieces cut before the map", prose, DESIGN, "cuts 1")


def main(argv=None) -> int:
    """Run the rows (``scenes.rows_main``)."""
    return scenes.rows_main("chords_ab", __doc__, row, markdown, FAMILIES, NS,
                            "1,2,42,43,44,45", argv)


if __name__ == "__main__":
    raise SystemExit(main())
