"""Queries at extreme magnitudes: plan them scaled by a power of two, which is exact.

Multiplying by ``2**k`` changes only the exponent of a double, so as long as nothing overflows
or underflows it is exact, and every float operation of the planners commutes with it: the
obstacle-line planner (paper Section 3, Mathematics §4) maps a query scaled by ``2**k`` with its
``lift`` scaled by ``2**k`` to the exactly scaled path, bit for bit. A query whose coordinates
(or lift) lie far outside the normal range -- beyond ``2**LIMIT`` ~ 2.8e129, where squared
distances overflow, or, with a lift as small, below ``2**-LIMIT`` -- is therefore planned as
the query scaled by ``2**-k`` that brings ``S = max(max |coordinate|, lift)`` into [2**-64, 1),
with ``lift * 2**-k``, and the waypoints are scaled back by ``2**k``; the certificate
(:mod:`pmplan.certify`) is then checked on what is actually returned.

A query is scaled only when every coordinate and the lift survive the scaling exactly
(``ldexp(ldexp(x, -k), k) == x``); otherwise -- a scene that spans more than the whole float
range -- it is planned as given, and its certificate decides. Queries inside the normal range
are never touched, so ordinary queries keep their speed and their bitwise equality with the
reference.
"""

from __future__ import annotations

import numpy as np

__all__ = ["LIMIT", "STEP", "exponents", "needs_scaling"]

#: queries with S beyond 2**LIMIT or, with lift below it too, below 2**-LIMIT are scaled
LIMIT = 430
#: the exponents are multiples of STEP, so that a batch needs few groups (one planner call each)
STEP = 64


def _max_abs(arrays) -> np.ndarray:
    """Per query (first axis), the largest |coordinate| over the arrays (B, ., d)."""
    out = None
    for a in arrays:
        v = np.abs(a).reshape(a.shape[0], -1).max(axis=1, initial=0.0)
        out = v if out is None else np.maximum(out, v)
    return out


def _up(e):
    """The multiple of STEP at or above e (integer arrays)."""
    return -((-e) // STEP) * STEP


def _down(e):
    """The multiple of STEP at or below e."""
    return (e // STEP) * STEP


def needs_scaling(arrays, lift) -> bool:
    """Return whether some query of a chunk may need scaling (see :func:`exponents`): a cheap test.

    ``arrays`` are the query arrays (B, ., d); ``lift`` a float or an array (B,), 0.0 for
    ``lift="scene"`` (:data:`pmplan.planners.base.SCENE_CODE`). Reads each
    array once (its max and min), allocates nothing of the batch's size.
    """
    hi = 2.0**LIMIT
    lift_arr = np.asarray(lift, dtype=float)
    scene = lift_arr <= 0
    if scene.any():  # lift="scene" (SCENE_CODE, 0.0) is as small as the query: look at its size
        size = _max_abs(arrays)
        if (np.broadcast_to(scene, size.shape) & (size < 1.0 / hi)).any():
            return True
        lift_arr = lift_arr[~scene]
    lift_max = lift_arr.max(initial=0.0)
    lift_min = lift_arr.min(initial=np.inf)
    if not lift_max < hi or not lift_min > 1.0 / hi:
        return True
    for a in arrays:
        if a.size and (a.max() >= hi or a.min() <= -hi):
            return True
    return False


def exponents(arrays, lift) -> np.ndarray:
    """The power of two ``k`` (B,) each query is to be planned at (as ``2**-k`` times itself).

    0 for a query whose ``S = max(max |coordinate|, lift)`` lies in ``[2**-LIMIT, 2**LIMIT)``
    and for one that does not survive the scaling exactly; otherwise a multiple of :data:`STEP`
    with ``S * 2**-k`` in ``[2**-STEP, 1)`` -- or, if that takes the coordinates or the lift out
    of ``[2**-LIMIT, 2**LIMIT)``, the nearest that keeps both in it (when none does, the
    coordinates in it: they are what the exact predicates read).

    Examples
    --------
    >>> q = np.array([[[1e300, 0.0]], [[1.0, 2.0]], [[1e-300, 0.0]]])
    >>> exponents([q], 1.0).tolist(), exponents([q], 1e-300).tolist()
    ([1024, 0, 0], [0, 0, -960])
    """
    b = arrays[0].shape[0]
    lift_b = np.broadcast_to(np.asarray(lift, dtype=float), (b,))
    size = _max_abs(arrays)
    # lift="scene" (SCENE_CODE, 0.0): the unit is u(O) <= 2 size, so it takes the coordinates'
    # band, and 0.0 scales to itself
    lift_b = np.where(lift_b > 0, lift_b, size)
    s = np.maximum(size, lift_b)
    hi = 2.0**LIMIT
    extreme = ~((s < hi) & (s >= 1.0 / hi))
    k = np.zeros(b, np.int64)
    if not extreme.any():
        return k
    _, e = np.frexp(s[extreme])  # s = f 2**e, f in [0.5, 1)
    _, e_size = np.frexp(size[extreme])
    _, e_lift = np.frexp(lift_b[extreme])
    want = _up(e)  # the multiple of STEP at or above e: S 2**-k in [2**-STEP, 1)

    def band(ex):  # the k (multiples of STEP) that bring 2**(ex-1)..2**ex into the band
        return _up(ex - LIMIT), _down(ex - 1 + LIMIT)

    lo_s, hi_s = band(e_size)
    lo_l, hi_l = band(e_lift)
    lo, hi_ = np.maximum(lo_s, lo_l), np.minimum(hi_s, hi_l)
    # both in the band if possible, else the coordinates (the predicates' inputs) first
    meet = lo <= hi_
    k[extreme] = np.where(meet, np.clip(want, lo, np.maximum(lo, hi_)), np.clip(want, lo_s, hi_s))
    # exact round trip of every coordinate and of the lift
    for i in np.flatnonzero(extreme):
        vals = [np.asarray(a[i], dtype=float) for a in arrays] + [lift_b[i : i + 1]]
        with np.errstate(over="ignore", under="ignore"):
            if not all(np.array_equal(np.ldexp(np.ldexp(v, -k[i]), k[i]), v) for v in vals):
                k[i] = 0
    return k
