"""What the numba kernels share: the numba import, the flag bits, the thresholds, the
error-free transformations and the distance of a piece.

One source for each: the flag bits a kernel returns for every query (:data:`FALLBACK`,
:data:`SUSPECT`, :data:`NONFINITE`, :data:`BROKEN`, :data:`INVALID`; what the caller does with
each: :func:`pmplan.planners.base.redecide`), the constants of the float filter and of the
certificate (read from :mod:`pmplan.predicates` and :mod:`pmplan.certify`, whose values numba
compiles in as constants), the compile options (:data:`_OPTS`), TwoSum / TwoProduct
(:func:`_two_sum`, :func:`_two_prod`) and the closed-form squared distance of a piece in the
plane (:func:`_segment_dist2_plane`). Without numba, :data:`AVAILABLE` is False, ``njit`` leaves
the functions as Python, and the numpy references plan everything (:mod:`pmplan.backend`).
"""

from __future__ import annotations

# one source: the unit roundoff and the underflow bound of pmplan.predicates' filter, and the
# thresholds of pmplan.certify (numba reads these module globals as compile-time constants)
from ..certify import _MAXF, _OBSTACLE_TINY2, _REL, _SURE  # noqa: F401 (the kernels import them here)
from ..predicates import _TINY, _U  # noqa: F401

try:
    from numba import njit

    AVAILABLE = True
except ImportError:  # pragma: no cover - numba is a dependency; keep the numpy path usable
    AVAILABLE = False

    def njit(*args, **kwargs):
        return lambda f: f

__all__ = ["AVAILABLE", "BROKEN", "FALLBACK", "INVALID", "NONFINITE", "SUSPECT"]

FALLBACK = 1
SUSPECT = 2
NONFINITE = 4
BROKEN = 8
INVALID = 16

_BIG = 2.0**900  # TwoProduct's split overflows beyond this (as in pmplan.predicates)
_SMALL = 2.0**-900  # below this TwoProduct's error term may underflow (as in pmplan.predicates)
# an obstacle pair whose squared distance is below _OBSTACLE_TINY2 (pmplan.certify's) is
# SUSPECT: the square may have underflowed; pmplan.certify.clearance decides it exactly

_OPTS = {"cache": True, "nogil": True, "error_model": "numpy"}
#: the small helpers: compiled once each and inlined by LLVM where it pays. Not numba's
#: ``inline="always"``, which copies them into every caller before typing and cost about three
#: seconds of every first run's compilation, with the same machine code speed (README, "first
#: run"; the floating-point operations are the same either way: no fast-math, no contraction)
_INLINE = _OPTS


@njit(**_INLINE)
def _two_sum(a, b):  # pragma: no cover - compiled
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@njit(**_INLINE)
def _two_prod(a, b):  # pragma: no cover - compiled
    p = a * b
    c = 134217729.0 * a
    ah = c - (c - a)
    al = a - ah
    c = 134217729.0 * b
    bh = c - (c - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl



@njit(**_INLINE)
def _segment_param(num, vv):  # pragma: no cover - compiled
    """The parameter of the point of a piece closest to the origin, as
    :func:`pmplan.certify.segment_clearance` computes it: ``num / vv`` (``num = -r0.v``,
    ``vv = |v|^2``) clipped to [0, 1], and 0 when ``vv`` is not positive. Branch-free (selects),
    so that the loops calling it vectorise."""
    q = num / vv
    q = 1.0 if num >= vv else q
    q = 0.0 if num <= 0 else q
    return q if vv > 0 else 0.0


@njit(**_INLINE)
def _segment_dist2_plane(rx, ry, r1x, r1y):  # pragma: no cover - compiled
    """Squared minimum distance to the origin of the plane piece r0 -> r1 (relative
    positions), in :func:`pmplan.certify.segment_clearance`'s arithmetic and order."""
    vx = r1x - rx
    vy = r1y - ry
    vv = (0.0 + vx * vx) + vy * vy
    q = _segment_param(-((0.0 + rx * vx) + ry * vy), vv)
    qx = rx + q * vx
    qy = ry + q * vy
    return (0.0 + qx * qx) + qy * qy
