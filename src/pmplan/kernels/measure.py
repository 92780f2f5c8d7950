"""The kernels the certificate's radius report shares with the refinement: the closed-form
minimum distance of every pair on every piece of a path (:func:`minima`, in
:func:`pmplan.certify.clearance`'s arithmetic, bit for bit) and the measure of refined paths
(:func:`measure_batch`): their clearance, robot and obstacle distances and the flags that send a
row to the exact decision of :func:`pmplan.certify.radius_report`.
"""

from __future__ import annotations

import math

import numpy as np

from ..certify import point_pairs
from .common import BAND_ABS, BAND_REL, OBSTACLE_TINY2, OPTS, REL, TINY_DIST, njit

__all__ = ["CLOSE", "SHORT", "SUSPECT", "measure_batch", "minima", "minima_scratch", "pair_rel"]


@njit(**OPTS)
def pair_rel(x, pa, pb, rel):  # pragma: no cover - compiled
    """The relative position ``x_pa - x_pb`` at every waypoint into ``rel`` (W, d)."""
    w, _, dd = x.shape
    for j in range(w):
        for k in range(dd):
            rel[j, k] = x[j, pa, k] - x[j, pb, k]


@njit(**OPTS)
def minima_scratch(w, d, npair):  # pragma: no cover - compiled
    """The scratch ``rel_t`` of :func:`minima` for paths of ``w`` waypoints in dimension ``d``
    and ``npair`` pairs: (d + 1, pairs W)."""
    return np.empty((d + 1, max(npair * w, 1)))


@njit(**OPTS)
def minima(x, a, b, dmin, rel_t):  # pragma: no cover - compiled
    """The closed-form minimum distance of every pair on every piece into ``dmin`` (W-1,
    pairs), in :func:`pmplan.refine.grid.piece_minima`'s (and :func:`pmplan.certify.clearance`'s)
    arithmetic, bit for bit. ``rel_t`` (d + 1, pairs W) is scratch: the relative positions of
    every pair, pair after pair, coordinate-major, then the minima, so that one loop runs over
    every piece of every pair (and one step across each pair's boundary, whose value is not
    used) and vectorises; d = 2 and 3 written out (the sums in the same order as the general
    loop). 1.3-2.5x faster than a loop over the pieces of one pair at a time (W = 8 to 29,
    14 to 22 points)."""
    w, _, dd = x.shape
    npair = a.shape[0]
    if rel_t.shape[0] < dd + 1 or rel_t.shape[1] < npair * w:
        raise ValueError("minima: the scratch rel_t must be (d + 1, pairs W), as minima_scratch makes it")
    for q in range(npair):
        pa, pb = a[q], b[q]
        base = q * w
        for k in range(dd):
            for j in range(w):
                rel_t[k, base + j] = x[j, pa, k] - x[j, pb, k]
    nf = npair * w - 1
    out = rel_t[dd]
    if dd == 2:
        xs = rel_t[0]
        ys = rel_t[1]
        for f in range(nf):
            r0x = xs[f]
            r0y = ys[f]
            vx = xs[f + 1] - r0x
            vy = ys[f + 1] - r0y
            vv = (0.0 + vx * vx) + vy * vy
            num = -((0.0 + r0x * vx) + r0y * vy)
            qq = num / vv  # (vv = 0: replaced below)
            qq = 1.0 if num >= vv else qq
            qq = 0.0 if num <= 0 else qq
            qq = qq if vv > 0 else 0.0
            qx = r0x + qq * vx
            qy = r0y + qq * vy
            out[f] = math.sqrt((0.0 + qx * qx) + qy * qy)
    elif dd == 3:
        xs = rel_t[0]
        ys = rel_t[1]
        zs = rel_t[2]
        for f in range(nf):
            r0x = xs[f]
            r0y = ys[f]
            r0z = zs[f]
            vx = xs[f + 1] - r0x
            vy = ys[f + 1] - r0y
            vz = zs[f + 1] - r0z
            vv = ((0.0 + vx * vx) + vy * vy) + vz * vz
            num = -(((0.0 + r0x * vx) + r0y * vy) + r0z * vz)
            qq = num / vv
            qq = 1.0 if num >= vv else qq
            qq = 0.0 if num <= 0 else qq
            qq = qq if vv > 0 else 0.0
            qx = r0x + qq * vx
            qy = r0y + qq * vy
            qz = r0z + qq * vz
            out[f] = math.sqrt(((0.0 + qx * qx) + qy * qy) + qz * qz)
    else:
        for f in range(nf):
            vv = 0.0
            r0v = 0.0
            for k in range(dd):
                v = rel_t[k, f + 1] - rel_t[k, f]
                vv = vv + v * v
                r0v = r0v + rel_t[k, f] * v
            num = -r0v
            qq = num / vv
            qq = 1.0 if num >= vv else qq
            qq = 0.0 if num <= 0 else qq
            qq = qq if vv > 0 else 0.0
            sq = 0.0
            for k in range(dd):
                qx = rel_t[k, f] + qq * (rel_t[k, f + 1] - rel_t[k, f])
                sq = sq + qx * qx
            out[f] = math.sqrt(sq)
    for q in range(npair):
        base = q * w
        for j in range(w - 1):
            dmin[j, q] = out[base + j]


#: flags of :func:`measure_batch`: the certificate's exact re-decision is needed (a piece
#: minimum not clearly above its rounding, an obstacle pair that may underflow, a non-finite
#: value), a piece minimum lies in the band of :func:`pmplan.certify.radius_report` around a
#: radius bound (decided exactly), the radii are certainly not kept
SUSPECT = 1
CLOSE = 2
SHORT = 4


@njit(**OPTS)
def _measure(x, m, a, b, need, out, flags):  # pragma: no cover - compiled
    """Per path of ``x`` (B, W, P, d): ``out[i] = (clearance, robot distance, obstacle
    distance)`` in :func:`pmplan.certify.clearance`'s arithmetic (d < 8: its sums are
    sequential) and the flags above; ``need`` = (2 radius, radius + obstacle_radius)."""
    bsz, w, _p, dd = x.shape
    rel = np.empty((w, dd))
    rel_t = minima_scratch(w, dd, a.shape[0])
    dmin = np.empty((w - 1, a.shape[0]))
    for i in range(bsz):
        xi = x[i]
        fl = 0
        clr = np.inf
        rob = np.inf
        obs = np.inf
        minima(xi, a, b, dmin, rel_t)
        for q in range(a.shape[0]):
            pa, pb = a[q], b[q]
            nd = need[0] if pa >= m else need[1]
            pair_rel(xi, pa, pb, rel)
            for j in range(w - 1):
                dq = dmin[j, q]
                scale = 0.0
                absval = 0.0
                for jj in range(j, j + 2):
                    for k in range(dd):
                        scale = max(scale, abs(rel[jj, k]))
                        absval = max(absval, abs(xi[jj, pa, k]), abs(xi[jj, pb, k]))
                # (a distance below 2**-480 may hold an underflowed square: measured exactly)
                if not (dq > REL * max(scale, absval * 1e-6)) or not math.isfinite(dq) \
                        or not math.isfinite(absval) or not dq > TINY_DIST:
                    fl |= SUSPECT
                clr = min(clr, dq)
                if pa >= m:
                    rob = min(rob, dq)
                else:
                    obs = min(obs, dq)
                if nd > 0:  # the band of pmplan.certify.radius_report
                    band = BAND_REL * (nd + absval) + BAND_ABS
                    if dq < nd - band:
                        fl |= SHORT
                    elif not dq > nd + band:
                        fl |= CLOSE
        for k1 in range(m):
            for k2 in range(k1 + 1, m):
                s = 0.0
                for k in range(dd):
                    dk = xi[0, k1, k] - xi[0, k2, k]
                    s = s + dk * dk
                if not s >= OBSTACLE_TINY2 or not math.isfinite(s):
                    fl |= SUSPECT
                clr = min(clr, math.sqrt(s))
        out[i, 0] = clr
        out[i, 1] = rob
        out[i, 2] = obs
        flags[i] = fl


def measure_batch(waypoints: np.ndarray, m: int, need: tuple[float, float]):
    """The clearance, robot and obstacle distances (B, 3) of refined paths and their flags
    (B,) uint8 (:data:`SUSPECT`, :data:`CLOSE`, :data:`SHORT`); see :func:`_measure`."""
    b = waypoints.shape[0]
    a, bb = (v.astype(np.int64) for v in point_pairs(waypoints.shape[2], m))
    out = np.empty((b, 3))
    flags = np.zeros(b, np.uint8)
    if b:
        _measure(waypoints, m, a, bb, np.array(need, dtype=float), out, flags)
    return out, flags
