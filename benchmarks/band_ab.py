"""The band of the box's map: valid share, length and modulus of continuity of refined plans
in the box with the band of :data:`pmplan.workspace.BAND` (1/8, pmplan's default) against wider
ones, per row.

Usage (from the repository root)::

    python benchmarks/band_ab.py                  # seeds 1, 2, 4-21, about 10 minutes
    python benchmarks/band_ab.py --picture-only   # redraw docs/band_ab.png from the JSON

A plan in a box is the plan of the query mapped out of the box by a homeomorphism that is the
identity on the inner box and stretches a band of ``BAND`` times the side along each wall to
infinity (Mathematics §8); the planner's lanes beyond the obstacles come back squeezed into
that band. The band is a design choice that no theorem fixes: any width keeps the domains and
the labels. This benchmark measures what it changes.

Rows: the scene families of ``benchmarks/scenes.py`` (room, swap, room_walls, swap_walls,
room3d) with n = 2, 4, 8 and 16, 16 queries each; pmplan's default plan in the box
(``bounds=(0, 10)``) refined at its default effort with radius = obstacle_radius = r/2. Four
variants, in one process on the same queries: the band 1/8 (pmplan's), 3/16, 1/4 and 5/16 (the
band of :mod:`pmplan.running`'s map set for the measurement, ``pmplan.running.BAND``;
nothing else changes). Per row and variant: the queries valid (keep the radii and stay in the
box, decided exactly), why the others are not (``Plan.radius_reason``), the median length / LB,
and the modulus of continuity: every point of each query moved by delta times a vector uniform
in [-1, 1]^d (the same moves for every variant), replanned, K = sup change of the path / delta
over the moves that keep the domain label, at delta = 1e-6, 1e-9 and 1e-12 (as in
``scenes_compare.py``); the row's largest K. Then per variant and group of seeds the totals:
rows meeting issue 25's valid share (>= 95 % for n <= 8, >= 80 % for n = 16) and its
continuity goal (K <= 1e3 at every delta), and the length against the band 1/8. Seeds 1, 2, 4
and 5 were looked at while choosing the variants; 6 to 21 were held out then, and their valid
shares and lengths (14 to 21: for 1/8 and 5/16, in total) seen before the modulus was
measured, which was seen before this run on seeds 1 and 2 alone.

Writes ``benchmarks/band_ab.json`` and ``.md``, and ``docs/band_ab.png``: per seed group and
band, the share of rows meeting the valid share against the share meeting the continuity goal.
Not a test module.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes
import scenes_compare
from scenes_section import VALID_GOAL

FAMILIES = ["room", "swap", "room_walls", "swap_walls", "room3d"]
NS = [2, 4, 8, 16]
BANDS = {"1/8": None, "3/16": 3 / 16, "1/4": 1 / 4, "5/16": 5 / 16}
VARIANTS = list(BANDS)
#: the seeds looked at while choosing the variants, and those held out then
DESIGN = {1, 2, 4, 5}
SEEN = set(range(6, 14))
RUNNING = importlib.import_module("pmplan.running")
_BAND = RUNNING.BAND
#: the moved queries of the continuity probe: scenes_compare's pmplan default in the box
_PROBE = scenes_compare.PmplanRunner(None, bounded=True)


def variant(name: str) -> None:
    """Switch pmplan's map of the box to the band of one variant (None: pmplan's own)."""
    band = BANDS[name]
    RUNNING.BAND = _BAND if band is None else band


def row(fam: str, n: int, seed: int, count: int) -> dict:
    """One row: every variant on the same queries and the same probe moves
    (:func:`scenes_compare.continuity` from the same seed), each query planned once."""
    qs = scenes.queries(fam, n, count, seed)
    out = {"family": fam, "n": n, "seed": seed, "variants": {}}
    for name in VARIANTS:
        variant(name)
        plans = []

        def plan(o, s, g, plans=plans):
            plans.append(scenes.refined_in_box(o, s, g))
            return plans[-1]

        cell = scenes.summary(f"seed {seed} {fam} n={n} band {name}", qs, plan)
        rng = np.random.default_rng([seed, scenes.FAMILIES[fam].index, n, 99])
        cell.update(scenes_compare.probe_summary(
            [c for q, p in zip(qs, plans)
             for c in scenes_compare.continuity(_PROBE, *q, (p, p.path.waypoints), rng)]))
        out["variants"][name] = cell
    variant(VARIANTS[0])
    return out


def _meets(cell: dict, n: int) -> bool:
    """Issue 25's valid share (:data:`scenes_section.VALID_GOAL`)."""
    return cell["valid"] / cell["count"] >= VALID_GOAL[n]


def _totals(rows: list) -> list[str]:
    """Per variant over ``rows``: valid, gap / contact counts, rows meeting the valid share,
    rows with every K <= the goal, the geometric mean and the largest of the row's median len/LB
    over the band 1/8's."""
    out = []
    for v in VARIANTS:
        cells = [(r["variants"][v], r["n"], r["variants"]["1/8"]) for r in rows]
        gap = sum(c["why"].get("gap", 0) for c, _, _ in cells)
        contact = sum(sum(c["why"].values()) for c, _, _ in cells) - gap
        meets = sum(_meets(c, n) for c, n, _ in cells)
        out.append(f"{scenes.valid_total([c for c, _, _ in cells])}, {gap} / {contact}, "
                   f"{meets}/{len(cells)}, "
                   f"{scenes.continuity_total([c for c, _, _ in cells])}, "
                   f"{scenes.length_total([(c, b) for c, _, b in cells])}")
    return out


def markdown(res: dict) -> str:
    prose = (f"Command: `{res['command']}` ({res['date']}). Rooms 10 x 10, r = {scenes.R}, "
             f"{res['count']} queries per row, pmplan's default plan in the box refined at its "
             "default effort, radius = obstacle_radius = r/2, with the band of the "
             "homeomorphism onto the box (Mathematics §8) of each variant: *1/8* is pmplan's "
             "(`pmplan.workspace.BAND`). valid = keeps the radii and the walls (decided "
             "exactly); len/LB = median length / sum of the straight distances; K = the largest "
             "sup change / delta of the row, every point of the query moved by delta = 1e-6, "
             "1e-9 and 1e-12 (the same moves for every variant; moves that change the label "
             "left out), in brackets the probes above 1e3. Seeds 1, 2, 4 and 5 were looked at "
             "while choosing the variants, 6 to 21 for their valid shares and lengths before "
             "this run; the modulus was seen before on seeds 1 and 2 alone.")
    lines = ["# The band of the box's map: valid share, length, continuity", "", prose, "",
             *scenes.variant_rows(res, "valid, len/LB, K",
                                  lambda e: f"{e['valid']}/{e['count']}, {e['len_lb']:.2f}, "
                                            f"{scenes.fmt_k(e['k_max'])}")]
    lines += ["", ("Per variant and group of rows: valid queries; invalid ones crossing a gap "
                   "narrower than a robot / with a contact the refinement did not clear "
                   "(`Plan.radius_reason`); rows meeting issue 25's valid share (>= 95 % for "
                   "n <= 8, >= 80 % for n = 16); rows meeting its continuity goal (K <= 1e3 at "
                   "every delta; in brackets the largest K); the geometric mean over the rows of "
                   "the row's median len/LB over the band 1/8's (in brackets the largest)."), "",
              *scenes.group_table(res, _groups(sorted({r["seed"] for r in res["rows"]})),
                                  _totals, VARIANTS)]
    return "\n".join(lines) + "\n"


def _groups(seeds: list) -> list[tuple[str, set]]:
    """The seed groups of the report: design, held out then (seen), held out."""
    return [("design " + ", ".join(str(s) for s in seeds if s in DESIGN), DESIGN),
            ("held out " + ", ".join(str(s) for s in seeds if s in SEEN), SEEN),
            ("held out " + ", ".join(str(s) for s in seeds if s not in DESIGN | SEEN),
             set(seeds) - DESIGN - SEEN)]


def picture(res: dict, out: Path) -> None:
    """Per seed group and band: the share of rows meeting issue 25's valid share against the
    share meeting its continuity goal (``docs/band_ab.png``)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.6), layout="constrained")
    seeds = sorted({r["seed"] for r in res["rows"]})
    for (name, group), color in zip(_groups(seeds), ("tab:blue", "tab:orange", "tab:green")):
        rows = [r for r in res["rows"] if r["seed"] in group]
        if not rows:
            continue
        xs = [100 * np.mean([r["variants"][v]["k_over"] == 0 for r in rows]) for v in VARIANTS]
        ys = [100 * np.mean([_meets(r["variants"][v], r["n"]) for r in rows]) for v in VARIANTS]
        ax.plot(xs, ys, "-", color=color, lw=1, alpha=0.6)
        for v, x, y in zip(VARIANTS, xs, ys):
            ax.scatter(x, y, color=color, s=60 if v == VARIANTS[0] else 25, zorder=3,
                       edgecolor="black", linewidth=0.5)
            ax.annotate(v, (x, y), textcoords="offset points", xytext=(5, 4), fontsize=8)
        ax.scatter([], [], color=color, label=f"seeds: {name} ({len(rows)} rows)")
    ax.set_xlabel("rows meeting the continuity goal, K <= 1e3 at 1e-6, 1e-9, 1e-12 (%)")
    ax.set_ylabel("rows meeting the valid share (%)")
    ax.set_title("The band of the box's map (pmplan: 1/8, large dot): validity against "
                 "continuity", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    fig.savefig(out, dpi=100)
    plt.close(fig)


def main(argv=None) -> int:
    """Run the rows (``scenes.rows_main``) and draw the picture; ``--picture-only`` redraws it
    from ``benchmarks/band_ab.json``."""
    import json

    here = Path(__file__).resolve().parent
    argv = list(sys.argv[1:] if argv is None else argv)
    if "--picture-only" not in argv:
        rc = scenes.rows_main("band_ab", __doc__, row, markdown, FAMILIES, NS,
                              ",".join(str(s) for s in [1, 2, *range(4, 22)]), argv)
        if rc:
            return rc
    picture(json.loads((here / "band_ab.json").read_text()), here.parent / "docs" / "band_ab.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
