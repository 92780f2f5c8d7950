"""How faithful is the polyline of a plan in the box to the conjugated motion ``phi o s``?

Usage (from the repository root)::

    python benchmarks/box_chords.py                # seeds 11 and 12, 400 queries per row (~10 min)
    python benchmarks/box_chords.py --from-json    # rewrite the .md from the .json

In a box pmplan plans the query mapped out of the box, ``y = phi^-1(q)``, and returns the
polyline through ``phi`` of the raw path's waypoints (Mathematics §8). ``phi`` bends straight
pieces, so that polyline meets the conjugated motion ``phi o s`` at the waypoints only; between
them its chords may pass an obstacle on the other side than the curve ``phi o s`` does. This
script measures how often, on the planar scene families (``benchmarks/scenes.py``, pmplan's
default raw plan in the box at the refined plans' unit, the robots' diameter): for every robot
and obstacle, the winding number of the robot's path closed by the segment from its goal to its
start (its class relative to the obstacle), for the polyline through ``phi`` of the raw path with
every piece cut into ``N`` equal pieces in R^2 first (``pmplan.workspace.RAW_CUTS``; N = 1,
the default, is the path pmplan returns), against
the same with ``REFERENCE`` pieces (``phi o s`` to within its chords' sagitta). Per row and N:
the share of queries where some robot's class differs, and the raw clearance of the polyline
over the reference's (median and smallest). A class that differs means that, inside the
query's domain, the chords of pmplan's box plans cross an obstacle somewhere on the way from
a query where they follow ``phi o s`` to this one: there the certificate refuses the plan, and
near it the raw clearance tends to 0 (Mathematics §8, "What the chords are not").

Writes ``benchmarks/box_chords.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import scenes

import pmplan
from pmplan.certify import clearance
from pmplan.configuration import default_lift
from pmplan.path import cut_along
from pmplan.workspace import from_box, into_box

FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [2, 4, 8, 16]
CUTS = [1, 2, 4, 8, 16]
REFERENCE = 128
BOX = np.array([[0.0, 0.0], [scenes.SIZE, scenes.SIZE]])


def windings(paths: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(n, m) winding numbers of the robots' polylines ``paths`` (K, n, 2), each closed by the
    segment from its last point back to its first, around ``points`` (m, 2)."""
    v = paths[:, :, None, :] - points[None, None]
    a = np.arctan2(v[..., 1], v[..., 0])
    a = np.concatenate([a, a[:1]], axis=0)
    d = (np.diff(a, axis=0) + np.pi) % (2 * np.pi) - np.pi
    return np.round(d.sum(axis=0) / (2 * np.pi)).astype(int)


def row(fam: str, n: int, seed: int, count: int) -> dict:
    t0 = time.perf_counter()
    lift = default_lift(None, scenes.R / 2, scenes.R / 2, refining=True)
    differs = {c: 0 for c in CUTS}
    ratios = {c: [] for c in CUTS}
    for o, s, g in scenes.queries(fam, n, count, seed):
        m = len(o)
        raw = pmplan.plan(*(from_box(x, BOX) for x in (o, s, g)), lift=lift).path.waypoints
        ref = into_box(cut_along(raw, REFERENCE, 0), BOX)
        w_ref, c_ref = windings(ref[:, m:], o), float(clearance(ref[None], m)[0])
        for c in CUTS:
            poly = into_box(cut_along(raw, c, 0), BOX)
            differs[c] += bool((windings(poly[:, m:], o) != w_ref).any())
            ratios[c].append(float(clearance(poly[None], m)[0]) / c_ref)
    out = {"family": fam, "n": n, "seed": seed, "count": count,
           "differs": {str(c): differs[c] / count for c in CUTS},
           "clearance_median": {str(c): float(np.median(ratios[c])) for c in CUTS},
           "clearance_min": {str(c): float(np.min(ratios[c])) for c in CUTS},
           "seconds": time.perf_counter() - t0}
    print(f"seed {seed} {fam} n={n}: class differs " + ", ".join(
        f"N={c} {out['differs'][str(c)]:.3f}" for c in CUTS) + f" [{out['seconds']:.0f} s]",
        flush=True)
    return out


def markdown(res: dict) -> str:
    lines = ["# Plans in the box: the polyline against the conjugated motion", "",
             (f"Command: `{res['command'].strip()}` ({res['date']}). Planar scene families of "
              f"`benchmarks/scenes.py` (box [0, 10]^2), {res['count']} queries per row, "
              "pmplan's default raw plan in the box at the refined plans' unit. *N*: every "
              "piece of the raw path cut into N in R^2 before the map into the box (N = 1 is "
              "what pmplan returns); against the same with "
              f"{REFERENCE} pieces (the conjugated motion phi o s to within its chords): "
              "the share of queries where some robot passes some obstacle in another class "
              "(winding number of its path closed by the segment from goal to start), and the "
              "raw clearance of the polyline over the reference's, median (smallest)."), "",
             "| seed | row | " + " | ".join(f"N = {c}: class differs, clearance" for c in CUTS)
             + " |", "|---|---|" + "---|" * len(CUTS)]
    for r in res["rows"]:
        lines.append(f"| {r['seed']} | {r['family']} n = {r['n']} | " + " | ".join(
            f"{r['differs'][str(c)]:.3f}, {r['clearance_median'][str(c)]:.2f} "
            f"({r['clearance_min'][str(c)]:.2g})" for c in CUTS) + " |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    return scenes.rows_main("box_chords", __doc__, row, markdown, FAMILIES, NS, "11,12", argv,
                            count=400)


if __name__ == "__main__":
    raise SystemExit(main())
