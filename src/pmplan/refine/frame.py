"""The refinement's normalised frame: one rule for every query, no switch (issue 24). The map
runs on the path scaled by powers of two and translated to its first obstacle, so that its
arithmetic neither overflows nor underflows at any magnitude and a query scaled by ``2**k``
gives the same bits (``docs/refinement.md``).
"""

from __future__ import annotations

import numpy as np

from .grid import MAX_TARGET, dot

__all__ = ["from_frame", "limits_to_frame", "to_frame"]


# --- the frame -------------------------------------------------------------------------------

def to_frame(raw: np.ndarray, target: np.ndarray):
    """The normalised frame of every raw path (B, K, P, d) and its targets (B, 2): ``(y, tgt,
    back)``. One rule for every query, no switch:

    1. ``z = raw 2**-e1``, e1 the exponent of the path's largest ``|coordinate|`` (``z`` depends
       only on the real values ``raw 2**-e1``, so a query scaled by ``2**k`` gives the same
       bits, subnormals included);
    2. ``u = z - c``, c the first point at the start (an obstacle: it never moves), so that a
       small scene far from the origin is not lost in its offset;
    3. ``y = u 2**-e2``, e2 the exponent of the largest norm of a point of u (a norm: the frame
       commutes with rotations): the whole path (start, goal, every configuration and lift)
       lies in the unit ball of one frame, its extent in [1/2, 1).

    In the frame the refinement's arithmetic neither overflows nor underflows (squares of
    coordinates below 1, of distances above 2**-480; see docs/refinement.md), so it is the
    same for every magnitude. The targets are scaled by ``2**-(e1 + e2)`` and held to
    ``[2**-900, MAX_TARGET]`` (a target beyond a million extents is out of reach anyway).
    :func:`from_frame` maps back."""
    b = raw.shape[0]
    with np.errstate(invalid="ignore"):
        amax = np.abs(raw).reshape(b, -1).max(axis=1, initial=0.0)
    good = np.isfinite(amax) & (amax > 0)
    e1 = np.where(good, np.frexp(np.where(good, amax, 1.0))[1], 0)
    with np.errstate(under="ignore"):
        z = np.ldexp(raw, -e1[:, None, None, None])
    c = z[:, :1, :1, :].copy()
    u = z - c
    umax = np.sqrt(dot(u, u)).reshape(b, -1).max(axis=1, initial=0.0)
    e2 = np.where(umax > 0, np.frexp(np.where(umax > 0, umax, 1.0))[1], 0)
    with np.errstate(under="ignore"):
        y = np.ldexp(u, -e2[:, None, None, None])
        tgt = np.ldexp(np.asarray(target, dtype=float), -(e1 + e2)[:, None])
    tgt = np.clip(tgt, 2.0**-900, MAX_TARGET)
    return y, tgt, (e1, e2, c)


def from_frame(y: np.ndarray, back) -> np.ndarray:
    """The paths of the frame ``y`` (B, W, P, d) in the query's coordinates (the caller
    restores the fixed waypoints and the obstacles exactly)."""
    e1, e2, c = back
    with np.errstate(over="ignore", under="ignore"):
        z = np.ldexp(y, e2[:, None, None, None]) + c
        return np.ldexp(z, e1[:, None, None, None])


def limits_to_frame(limits: np.ndarray, back) -> np.ndarray:
    """Coordinates (B, 2, d) -- a workspace's limits -- in the frame of :func:`to_frame`
    (``back``), by the same operations as the points (the frame is a scaling by powers of two
    and a translation)."""
    e1, e2, c = back
    with np.errstate(under="ignore"):
        z = np.ldexp(limits, -e1[:, None, None]) - c[:, 0]
        return np.ldexp(z, -e2[:, None, None])
