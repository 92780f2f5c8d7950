"""A prototype of another box map: conjugation by a radial map of the sup norm, against pmplan's
coordinate-wise map, on the 2-D scene families (issue 25, item 3).

Usage (from the repository root)::

    python benchmarks/radial_ab.py                 # about 4 minutes, one process
    python benchmarks/radial_ab.py --from-json     # rewrite the report

pmplan plans in a box by conjugation, ``s_B = phi o s o phi^-1`` (Mathematics §8): every
homeomorphism ``phi`` of R^d onto the open box keeps the domains, their number and the labels.
Its ``phi`` (:mod:`pmplan.workspace`) acts coordinate by coordinate, so a line of R^d that is
not parallel to an axis ends in a corner of the box. In R^d the lanes and the line along
``nu(e)`` through an obstacle (the line of Mathematics §8, "How often") run to infinity, so in
the box they run into corners, where an obstacle near one wall is often near the other too.

*radial* is the map that keeps the directions from the box's centre ``c`` (in the box's unit
coordinates, ``s = |v|_inf`` for ``v = u - c``): the identity for ``s <= 1/2 - BAND``, beyond
it ``v g(s) / s`` with the algebraic tail ``g(s) = 1/2 - BAND^2 / (s - (1/2 - BAND) + BAND)``
of :func:`pmplan.workspace.into_box`, continuous with its first derivative; a line of R^d then
reaches the wall its direction points to. Both variants here plan the query mapped out of the box
with pmplan's default section of a refined plan and unit (the robots' diameter), map the raw
waypoints into the box (the chords: the start pmplan's refinement takes, ``RAW_CUTS = 1``) and
refine them in the box at the default effort with the planner's still pieces, as
``pmplan.plan(..., bounds=(0, 10), refine=True)`` does; *axis* (pmplan's map) gives pmplan's
plans, which the report checks query by query (*same as pmplan*). The refined paths are
certified exactly either way. What the prototype lacks for a default: the exact image of a raw
path under the radial map (it is not affine on cells, so the chords are not the conjugated motion
between breakpoints, Mathematics §8, "What the chords are not"), its kernels and the gap bound
recomputed for it.

Per row, per variant: valid (the radii and the walls, decided exactly), the median len/LB of the
valid plans, and a continuity probe on the first ``PROBES`` queries: every point moved by delta
times a uniform vector in [-1, 1]^2 for delta = 1e-6, 1e-9, 1e-12 (the same moves for both
variants), ``K = sup change / delta`` of the refined waypoints, its largest value and the probes
above 1e3 (label changes are not left out: both variants see the same moves). Seeds 11 and 12
are the design seeds of pmplan's defaults, 30 and 31 held out from them; the radial variant has
no parameter, so nothing was chosen on any seed (a prototype of it ran on 200 queries of seeds
11, 12, 30 and 31 before this script was written).

Writes ``benchmarks/radial_ab.json`` and ``.md``. Not a test module.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import scenes

import pmplan
from pmplan import workspace
from pmplan.certify import clearance
from pmplan.planners import REGISTRY
from pmplan.planners.base import default_planner
from pmplan.refine.grid import default_effort
from pmplan.refine.stage import RefineStage
from pmplan.running import run_stage

FAMILIES = ["room", "swap", "room_walls", "swap_walls"]
NS = [2, 4, 8, 16]
BOX = np.array([[0.0, 0.0], [scenes.SIZE, scenes.SIZE]])
RADIUS = scenes.R / 2
#: the continuity probe's queries per row, and its moves
PROBES = 16
DELTAS = (1e-6, 1e-9, 1e-12)
_F = workspace.BAND
_A = 0.5 - _F  # the inner box's half-width, in unit coordinates


def _radial(x: np.ndarray, out: bool) -> np.ndarray:
    """The radial map into the box (``out=False``: R^2 -> box) or its inverse (``out=True``)."""
    lo, hi = BOX
    v = (np.asarray(x, dtype=float) - lo) / (hi - lo) - 0.5
    s = np.abs(v).max(-1, keepdims=True)
    safe = np.where(s > _A, s, 1.0)
    if out:
        t = _A - _F + _F * _F / (0.5 - np.minimum(s, 0.5 - 1e-300))
    else:
        t = 0.5 - _F * _F / (s - _A + _F)
    u = np.where(s <= _A, v, v * t / safe)
    return lo + (u + 0.5) * (hi - lo)


MAPS = {"axis": (lambda x: workspace.from_box_linear(x, BOX),
                 lambda y: workspace.into_box_linear(y, BOX)),
        "radial": (lambda x: _radial(x, True), lambda y: _radial(y, False))}


def refined(o, s, g, variant: str):
    """The query planned by conjugation with ``variant``'s map and refined in the box: the
    stage (its ``respects`` and ``waypoints``), or None when the chords leave the raw plan
    without clearance."""
    m, n = len(o), len(s)
    out_of, into = MAPS[variant]
    zo, zs, zg = (out_of(np.asarray(a, dtype=float)) for a in (o, s, g))
    name = default_planner(2, n, m, refining=True)
    raw = pmplan.plan(zo, zs, zg, planner=name, lift=2 * RADIUS)
    times = raw.path.times
    wb = into(raw.path.waypoints)[None]
    fixed = [0, len(times) - 1]  # the obstacles and the endpoints exactly, as pmplan's are
    workspace.restore(wb, m, fixed, [s, g], np.asarray(o)[None])
    clr = clearance(wb, m)
    if not clr[0] > 0:
        return None
    w, steps = default_effort(n, 2)
    stage = RefineStage(times, wb, clr, m, fixed, RADIUS, RADIUS, w, steps, None, box=BOX,
                        still=REGISTRY[name].still_for(times))
    run_stage(stage, progress=False, workers=1)
    return stage


def row(fam: str, n: int, seed: int, count: int) -> dict:
    qs = scenes.queries(fam, n, count, seed)
    rng = np.random.default_rng(seed * 1000 + n)
    moves = [[(d, [rng.uniform(-1.0, 1.0, np.shape(x)) for x in q]) for d in DELTAS]
             for q in qs[:PROBES]]
    out = {"family": fam, "n": n, "seed": seed, "count": count, "same": 0}
    for variant in MAPS:
        valid, lens, ks = 0, [], []
        for k, (o, s, g) in enumerate(qs):
            st = refined(o, s, g, variant)
            ok = st is not None and bool(st.respects[0])
            if variant == "axis":
                out["same"] += ok == bool(scenes.refined_in_box(o, s, g).respects_radius)
            if ok:
                valid += 1
                x = st.waypoints[0, :, len(o):]
                lens.append(np.linalg.norm(np.diff(x, axis=0), axis=-1).sum()
                            / np.linalg.norm(g - s, axis=1).sum())
            if k < PROBES and st is not None:
                for d, (uo, us, ug) in moves[k]:
                    other = refined(o + d * uo, s + d * us, g + d * ug, variant)
                    if other is not None and other.waypoints.shape == st.waypoints.shape:
                        ks.append(float(np.abs(other.waypoints - st.waypoints).max() / d))
        out[variant] = {"valid": valid, "len_lb": float(np.median(lens)) if lens else None,
                        "k_max": max(ks) if ks else None,
                        "k_over": int(sum(k > 1e3 for k in ks)), "probes": len(ks)}
    print(f"seed {seed} {fam} n={n}: axis {out['axis']['valid']}, radial "
          f"{out['radial']['valid']} of {count} (axis = pmplan on {out['same']})", flush=True)
    return out


def _cell(c: dict, count: int) -> str:
    ln = "-" if c["len_lb"] is None else f"{c['len_lb']:.3f}"
    k = "-" if c["k_max"] is None else scenes.fmt_k(c["k_max"])
    return f"{c['valid']}/{count}, {ln}, {k} ({c['k_over']})"


def markdown(res: dict) -> str:
    rows = res["rows"]
    held = lambda r: r["seed"] not in (11, 12)  # noqa: E731
    lines = ["# Another box map: radial against coordinate-wise", "",
             f"Command: `{res['command'].strip()}` ({res['date']}, {res['seconds']:.0f} s). "
             f"Rooms 10 x 10, r = {scenes.R}, {res['count']} queries per row, pmplan's default "
             "section and unit refined in the box at the default effort, radius = "
             "obstacle_radius = r/2 (the module docstring says how). *axis*: pmplan's map "
             "(the plans of `pmplan.plan(..., bounds=(0, 10), refine=True)`: *same* counts the "
             "queries where the prototype agrees with it); *radial*: the sup-norm radial map. "
             "Per variant: valid, median len/LB of the valid plans, the largest K of "
             f"{PROBES} queries moved by 1e-6, 1e-9 and 1e-12 (probes above 1e3 in brackets). "
             "Seeds 11 and 12 are the design seeds, 30 and 31 held out.", "",
             "| seed | row | axis | radial | same |", "|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['seed']}{' (held out)' if held(r) else ''} | {r['family']} n = "
                     f"{r['n']} | {_cell(r['axis'], r['count'])} | "
                     f"{_cell(r['radial'], r['count'])} | {r['same']}/{r['count']} |")
    lines += ["", "Valid plans per robot count, both kinds of room, design and held-out seeds "
              "(axis against radial):", "",
              "| n | rooms | design | held out |", "|---|---|---|---|"]
    for n in sorted({r["n"] for r in rows}):
        for kind, fams in (("room, swap", ("room", "swap")),
                           ("room_walls, swap_walls", ("room_walls", "swap_walls"))):
            cells = []
            for part in (False, True):
                rs = [r for r in rows if r["n"] == n and r["family"] in fams and held(r) == part]
                tot = sum(r["count"] for r in rs)
                cells.append(f"{sum(r['axis']['valid'] for r in rs)} against "
                             f"{sum(r['radial']['valid'] for r in rs)} of {tot}")
            lines.append(f"| {n} | {kind} | {cells[0]} | {cells[1]} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    return scenes.rows_main("radial_ab", __doc__, row, markdown, FAMILIES, NS,
                            "11,12,30,31", argv, count=100)


if __name__ == "__main__":
    raise SystemExit(main())
