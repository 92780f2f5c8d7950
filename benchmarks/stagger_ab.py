"""Staggered slides: whether the refined plans' contacts in a room come from robots that pass
one place at the same time, per row: pmplan's compact lanes, every robot sliding along its lane
at once, against the same lanes slid in two turns.

Usage (from the repository root)::

    python benchmarks/stagger_ab.py        # seeds 11, 12, 13, about 6 minutes

In the rooms and swaps whose obstacles may sit near a wall, most contacts the refinement leaves
are two robots of the same side of the obstacle line pressed together, at a time inside the
slide of the section (tau in [4/9, 5/9]), at a gap with room for one robot only
(``misses.md``). If they met there because they slide at the same time, a section that slides
the lanes in turns would leave fewer. The *staggered* variant is such a section, on the same
domains with the same labels: the section of Mathematics §4.2 with one more breakpoint, the
robots whose lane is the k-th of its side with k odd sliding from X + h nu to X' + h nu on
the first half of the slide, the others on the second half (at most every other lane of a
side moves at a time; the waypoints are the same continuous functions of the query, so the
section is continuous where pmplan's is, and two points never meet: the robots that wait sit
at their lanes' ends, which pmplan's section passes as well). The raw plans come from the numpy
reference, :func:`pmplan.planners.obstacle_line.two_configuration_path` and
:func:`~pmplan.planners.obstacle_line.path_times` called with this section (``build=``,
``section_times=``; 9 breakpoints for 2 configurations instead of 8) for the measurement, in
the box ``(0, 10)``, refined at the default effort with
radius = obstacle_radius = r/2 (``scenes_compare.ab_row``). Per row and variant: the valid
queries, the median len/LB, the raw clearance, the largest K at delta = 1e-6, 1e-9, 1e-12, and
the invalid ones by their reason (*gap*: the path crosses a gap narrower than a robot;
*contact*: a contact the refinement did not clear). Rows of seed 11 were looked at while the
variant was tried (room and swap, n = 8 and 16); seeds 12 and 13 were not.

Writes ``benchmarks/stagger_ab.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import sys
from functools import partial
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes
import scenes_compare

from pmplan.path import PiecewiseLinearPath
from pmplan.planners import base, obstacle_line

FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [4, 8, 16]
VARIANTS = ["together", "staggered"]
#: the seeds whose rows were looked at while trying the variant
DESIGN = {11}
_COMPOSE, _TIMES = obstacle_line.two_configuration_path, obstacle_line.path_times
#: the section's breakpoints: up to the lanes, the first turn, the second, down
_SECTION = (0.0, 1.0 / 3.0, 0.5, 2.0 / 3.0, 1.0)


def _first_turn(n: int) -> np.ndarray:
    """The robots (n,) that slide in the first turn: the k-th lane of its side, k odd."""
    k = np.ceil(np.arange(1, n + 1) / 2.0)
    return (k % 2.0) == 1.0


def staggered_section(fr, x_start, x_goal, heights, m: int) -> PiecewiseLinearPath:
    """:func:`pmplan.planners.obstacle_line.section` with the slide in two turns."""
    off = np.zeros_like(x_start)
    off[:, m:] = heights[..., None] * fr.nu[:, None, :]
    up, across = x_start + off, x_goal + off
    half = up.copy()
    first = np.flatnonzero(_first_turn(heights.shape[1])) + m
    half[:, first] = across[:, first]
    return PiecewiseLinearPath(np.array(_SECTION),
                               np.stack([x_start, up, half, across, x_goal], axis=1))


def variant(name: str) -> None:
    """Switch the raw construction to a variant (the breakpoints the planner shares with it)."""
    stagger = name == "staggered"
    obstacle_line.two_configuration_path = (partial(_COMPOSE, build=staggered_section)
                                            if stagger else _COMPOSE)
    obstacle_line.path_times = partial(_TIMES, section_times=_SECTION) if stagger else _TIMES
    base._shared_times.cache_clear()


def row(fam: str, n: int, seed: int, count: int) -> dict:
    """One row: both variants on the same queries and probe moves (``scenes_compare.ab_row``)."""
    return scenes_compare.ab_row(fam, n, seed, count, variant, VARIANTS)


def markdown(res: dict) -> str:
    prose = (scenes.run_head(res, "The scene families") + "; *together*: "
             "pmplan's compact lanes, every robot sliding at once; *staggered*: the robots on "
             "the odd lanes of each side slide first, the others then (one more breakpoint). "
             + scenes_compare.AB_COLUMNS + " Rows of seed 11 were looked at while trying the "
             "variant; seeds 12 and 13 were not.")
    out = scenes_compare.ab_markdown(res, "Staggered slides: contacts, length, continuity",
                                     prose, DESIGN, "together")
    lines = ["", ("The invalid queries by reason, valid / gap / contact (gap: the path crosses a "
                  "gap narrower than a robot; contact: a contact the refinement did not clear), "
                  "per group of seeds and family:"), "",
             "| seeds | family | " + " | ".join(VARIANTS) + " |",
             "|---|---|" + "---|" * len(VARIANTS)]
    for group, seeds in (("design", DESIGN), ("held out", None)):
        for fam in FAMILIES:
            rows = [r for r in res["rows"] if r["family"] == fam
                    and (r["seed"] in DESIGN) == (seeds is not None)]
            if not rows:
                continue
            cells = scenes_compare.reason_cells(rows, VARIANTS)
            names = ", ".join(str(s) for s in sorted({r["seed"] for r in rows}))
            lines.append(f"| {group} {names} | {fam} | " + " | ".join(cells) + " |")
    return out + "\n".join(lines) + "\n"


def main(argv=None) -> int:
    """Run the rows (``scenes.rows_main``)."""
    return scenes.rows_main("stagger_ab", __doc__, row, markdown, FAMILIES, NS, "11,12,13",
                            argv, count=48)


if __name__ == "__main__":
    raise SystemExit(main())
