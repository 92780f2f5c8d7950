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

import pmplan

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes  # noqa: E402

HERE = Path(__file__).resolve().parent
FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [2, 4, 8, 16]
HALF = scenes.R / 2
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
    qs = scenes.queries(fam, n, count, seed)
    out = {"family": fam, "n": n, "seed": seed, "variants": {}}
    for name in VARIANTS:
        variant(name)
        out["variants"][name] = scenes.summary(
            f"seed {seed} {fam} n={n} {name}", qs,
            lambda o, s, g: pmplan.plan(o, s, g, bounds=(0.0, scenes.SIZE), refine=True,
                                        radius=HALF, obstacle_radius=HALF))
    variant("walls")
    return out


def markdown(res: dict) -> str:
    lines = ["# Walls in the refinement: valid share, time, length", "",
             f"Command: `{res['command']}` ({res['date']}). Rooms 10 x 10, r = {scenes.R}, "
             f"{res['count']} queries per row, pmplan's default plan in the box refined at its "
             "default effort, radius = obstacle_radius = r/2. *walls*: pmplan's default (the "
             "refinement sees the walls, band 1/256); *band*: no walls in the refinement, the "
             "same band; *before*: no walls, band 1/64. valid = keeps the radii and the walls "
             "(decided exactly); time = median ms per query (plan + refinement, one core; a "
             "shared machine: compare within a row); len/LB = median length / sum of the "
             "straight distances. Seed 1 is the design draw; the others are held out.", "",
             "| seed | row | " + " | ".join(f"{v}: valid, ms, len/LB" for v in VARIANTS)
             + " |", "|---|---|" + "---|" * len(VARIANTS)]
    for r in res["rows"]:
        cells = [f"{e['valid']}/{e['count']}, {e['time_ms']:.1f}, {e['len_lb']:.2f}"
                 for e in r["variants"].values()]
        lines.append(f"| {r['seed']} | {r['family']} n = {r['n']} | " + " | ".join(cells) + " |")
    lines += ["", "Totals (valid queries of all rows of a seed):", "",
              "| seed | " + " | ".join(VARIANTS) + " | rows where walls beat before / lose |",
              "|---|" + "---|" * (len(VARIANTS) + 1)]
    for seed in sorted({r["seed"] for r in res["rows"]}):
        rows = [r for r in res["rows"] if r["seed"] == seed]
        tot = [sum(r["variants"][v]["valid"] for r in rows) for v in VARIANTS]
        den = sum(r["variants"]["walls"]["count"] for r in rows)
        gain = sum(r["variants"]["walls"]["valid"] > r["variants"]["before"]["valid"]
                   for r in rows)
        loss = sum(r["variants"]["walls"]["valid"] < r["variants"]["before"]["valid"]
                   for r in rows)
        lines.append(f"| {seed} | " + " | ".join(f"{t}/{den}" for t in tot)
                     + f" | {gain} / {loss} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    return scenes.rows_main("walls_ab", __doc__, row, markdown, FAMILIES, NS, "1,2,4", argv)


if __name__ == "__main__":
    raise SystemExit(main())
