"""Plans in the box that are the conjugated motion exactly (pmplan's ``plan(bounds=)``): a
piecewise-linear map onto the box, and the polyline through every point where a robot crosses
one of its kinks.

Usage (from the repository root)::

    python benchmarks/box_exact.py               # seeds 13 and 14, 200 queries per row (~5 min)
    python benchmarks/box_exact.py --from-json   # rewrite the .md from the .json

pmplan returned, in a box, the polyline through ``phi`` of the raw path's waypoints, ``phi`` the
coordinatewise map of :mod:`pmplan.workspace` with an algebraic tail. Its chords are not the
conjugated motion ``phi o s`` and may pass an obstacle on the other side (Mathematics §8, "What
the chords are not"; ``benchmarks/box_chords.py``). The map of ``plan(bounds=)`` is now the
tail's dyadic piecewise-linear interpolation: in the box's unit coordinates, the nodes ``z_k =
b + f (2^k - 1)`` beyond the inner edge ``b = 1 - f`` (``f`` = :data:`pmplan.workspace.BAND`)
go to ``1 - f 2^-k``, the algebraic tail's own values there, and the map is affine between them
with slope ``2^(-2k-1)`` (the mirror image below ``f``; the identity between). It is a
homeomorphism of R onto (0, 1), so the conjugated planner keeps the domains and labels
(Mathematics §8), and on every cell of the product of these intervals it is affine: the image
of a straight piece of the raw path is exactly the polyline through the images of the points
where some robot crosses a node in some coordinate. That polyline *is* ``phi o s``: the
certificate can refuse it only for rounding, and a robot passes every obstacle on the side
``phi o s`` does, at every query.

This script measures what it costs and gives on the scene families of ``benchmarks/scenes.py``
(pmplan's default plan in the box at the refined plans' unit, the robots' diameter), per row:
the breakpoints of the plan (the raw plan has 8; every piece gets as many new ones as its
piece with the most crossings), whether some robot's class (winding number of its path closed
by the segment from goal to start, planar rows) differs from the same map's raw path cut into
``REFERENCE`` pieces, and the raw clearance of the plan and of the polyline through the mapped
waypoints alone (the chords, which the refinement starts from) over the reference's.

Writes ``benchmarks/box_exact.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import scenes
from box_chords import REFERENCE, windings
from refine_continuity import sup_paths

import pmplan
from pmplan.certify import clearance
from pmplan.configuration import default_lift
from pmplan.path import PiecewiseLinearPath, cut_along
from pmplan.workspace import from_box_linear, into_box_linear

FAMILIES = ["room", "swap", "room_walls", "swap_walls", "room3d"]
NS = [2, 4, 8, 16]


#: the continuity probe: the first PROBED queries of a row, every point moved by delta times a
#: vector uniform in [-1, 1]^d at each of DELTAS, replanned; K = sup change / delta where the
#: domain label is kept
PROBED = 25
DELTAS = (1e-6, 1e-9, 1e-12)


def _motions(o, s, g, box, lift):
    """The raw plan's label and its exact and chord motions in the box."""
    p = pmplan.plan(*(from_box_linear(x, box) for x in (o, s, g)), lift=lift)
    times, raw = p.path.times, p.path.waypoints
    m = len(o)
    plan = pmplan.plan(o, s, g, bounds=box, lift=lift)
    assert plan.domain == p.domain
    out = {"exact": (plan.path.times, plan.path.waypoints.copy()),
           "chord": (times, into_box_linear(raw, box)),
           "ref": (None, into_box_linear(cut_along(raw, REFERENCE, 0), box))}
    for _, w in out.values():
        w[:, :m] = o  # (the obstacles, bit for bit)
    return p.domain, raw, out


def row(fam: str, n: int, seed: int, count: int) -> dict:
    t0 = time.perf_counter()
    d = scenes.FAMILIES[fam].d
    box = np.array([np.zeros(d), np.full(d, scenes.SIZE)])
    lift = default_lift(None, scenes.R / 2, scenes.R / 2, refining=True)
    ks, exact_ratio, chord_ratio, differs, chord_differs, raw_k = [], [], [], 0, 0, 0
    kmax = {"exact": 0.0, "chord": 0.0}
    rng = np.random.default_rng([seed, scenes.FAMILIES[fam].index, n, 7])
    for j, (o, s, g) in enumerate(scenes.queries(fam, n, count, seed)):
        m = len(o)
        label, raw, motions = _motions(o, s, g, box, lift)
        polys = {k: v[1] for k, v in motions.items()}
        raw_k = len(raw)
        if j < PROBED:
            for delta in DELTAS:
                moved = [x + delta * rng.uniform(-1.0, 1.0, x.shape) for x in (o, s, g)]
                label2, _, motions2 = _motions(*moved, box, lift)
                if label2 != label:
                    continue
                for k, top in kmax.items():
                    change = sup_paths(PiecewiseLinearPath(*motions[k]),
                                       PiecewiseLinearPath(*motions2[k]))
                    kmax[k] = max(top, change / delta)
        ks.append(len(polys["exact"]))
        c_ref = float(clearance(polys["ref"][None], m)[0])
        exact_ratio.append(float(clearance(polys["exact"][None], m)[0]) / c_ref)
        chord_ratio.append(float(clearance(polys["chord"][None], m)[0]) / c_ref)
        if d == 2:
            w_ref = windings(polys["ref"][:, m:], o)
            differs += bool((windings(polys["exact"][:, m:], o) != w_ref).any())
            chord_differs += bool((windings(polys["chord"][:, m:], o) != w_ref).any())
    out = {"family": fam, "n": n, "seed": seed, "count": count, "raw_breakpoints": raw_k,
           "breakpoints_median": float(np.median(ks)), "breakpoints_max": int(max(ks)),
           "differs": differs / count if d == 2 else None,
           "chord_differs": chord_differs / count if d == 2 else None,
           "exact_clearance_min": float(min(exact_ratio)),
           "exact_clearance_median": float(np.median(exact_ratio)),
           "chord_clearance_min": float(min(chord_ratio)),
           "chord_clearance_median": float(np.median(chord_ratio)),
           "k_exact": kmax["exact"], "k_chord": kmax["chord"],
           "seconds": time.perf_counter() - t0}
    print(f"seed {seed} {fam} n={n}: breakpoints {out['breakpoints_median']:.0f} (max "
          f"{out['breakpoints_max']}); class differs exact {out['differs']}, chord "
          f"{out['chord_differs']}; clearance / reference: exact min "
          f"{out['exact_clearance_min']:.3f}, chord min {out['chord_clearance_min']:.2g}; "
          f"K exact {out['k_exact']:.3g}, chord {out['k_chord']:.3g}", flush=True)
    return out


def _share(x) -> str:
    return "-" if x is None else f"{x:.3f}"


def markdown(res: dict) -> str:
    lines = ["# Exact plans in the box: a piecewise-linear map", "",
             (f"Command: `{res['command'].strip()}` ({res['date']}). Scene families of "
              f"`benchmarks/scenes.py` (box [0, 10]^d), {res['count']} queries per row, "
              "pmplan's default plan in the box (the query mapped out of the box by the dyadic "
              "piecewise-linear map), at the refined plans' unit. *exact*: the plan, the "
              "polyline through the images of the raw path at every point where a robot crosses "
              "a kink of the map (the conjugated motion itself); *chord*: through the images of "
              "the raw waypoints alone (where the refinement starts). *Breakpoints*: of the "
              "plan, median (largest); the raw plan has "
              f"{res['rows'][0]['raw_breakpoints']}. *Class differs*: the share of queries "
              "where some robot passes some obstacle in another class (winding number, planar "
              f"rows) than the same map's raw path cut into {REFERENCE} pieces. "
              "*Clearance*: the raw clearance over that reference's, median (smallest); the "
              "reference's vertices lie on the exact polyline, so it cuts the exact one's "
              "corners, and an exact clearance below the reference's is such a corner. *K*: "
              f"the continuity probe on the first {PROBED} queries of the row, every point "
              "moved by delta times a vector uniform in [-1, 1]^d at delta = "
              f"{', '.join(f'{x:g}' for x in DELTAS)}, replanned, the largest sup over time of "
              "the change of the motion / delta where the domain label is kept."), "",
             ("| seed | row | breakpoints | class differs: exact / chord | clearance: exact | "
              "clearance: chord | K: exact / chord |"), "|---|---|---|---|---|---|---|"]
    for r in res["rows"]:
        lines.append(
            f"| {r['seed']} | {r['family']} n = {r['n']} | {r['breakpoints_median']:.0f} "
            f"({r['breakpoints_max']}) | {_share(r['differs'])} / {_share(r['chord_differs'])}"
            f" | {r['exact_clearance_median']:.3f} ({r['exact_clearance_min']:.3f}) | "
            f"{r['chord_clearance_median']:.3f} ({r['chord_clearance_min']:.2g}) | "
            f"{r['k_exact']:.3g} / {r['k_chord']:.3g} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    return scenes.rows_main("box_exact", __doc__, row, markdown, FAMILIES, NS, "13,14", argv,
                            count=200)


if __name__ == "__main__":
    raise SystemExit(main())
