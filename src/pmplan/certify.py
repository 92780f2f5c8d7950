"""The certificate of a piecewise-linear motion (SPEC section 5).

A path with waypoints ``P_0..P_K`` at times ``0 = t_0 < ... < t_K = 1`` is *certified* for the
query (C, C') when

* ``P_0 == C`` and ``P_K == C'`` exactly,
* the obstacle rows are the same in every waypoint (obstacles fixed), and
* its *clearance* -- the minimum over pieces and over pairs of points of the distance between
  the two linearly moving points -- is > 0.

On one piece the relative position of two points is ``r(t) = r0 + t v`` (``t in [0, 1]``), so
its squared norm is a quadratic in t minimised in closed form at
``t* = clip(-r0.v / |v|^2, 0, 1)``. The float value is trusted when it is large against the
rounding error of its evaluation; otherwise (a genuine clearance can be ~1e-15 of the scene's
scale) the minimum is recomputed **exactly** in rational arithmetic on the waypoint floats,
which are the path that is returned. Obstacle-obstacle pairs never move and are checked once.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

__all__ = ["segment_clearance", "clearance", "certify"]

# a float minimum below _REL * (scale of the pair on that piece) is re-decided exactly
_REL = 1e-9


def _pairs(p: int, m: int) -> tuple[np.ndarray, np.ndarray]:
    """Index pairs (i < j) with at least one moving point (index >= m)."""
    i, j = np.triu_indices(p, k=1)
    keep = j >= m
    return i[keep], j[keep]


def segment_clearance(r0: np.ndarray, r1: np.ndarray) -> np.ndarray:
    """Return ``min_{t in [0,1]} |r0 + t (r1 - r0)|`` in floating point, over the last axis."""
    # overflow gives inf/nan here; such pairs are re-decided exactly by the caller
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        v = r1 - r0
        vv = (v * v).sum(-1)
        r0v = (r0 * v).sum(-1)
        t = np.where(vv > 0, np.clip(-r0v / np.where(vv > 0, vv, 1.0), 0.0, 1.0), 0.0)
        q = r0 + t[..., None] * v
        return np.sqrt((q * q).sum(-1))


def _exact_segment_clearance(a0, b0, a1, b1) -> float:
    """Exact min distance between points moving linearly a0->a1 and b0->b1 (rational)."""
    r0 = [Fraction(x) - Fraction(y) for x, y in zip(a0.tolist(), b0.tolist())]
    r1 = [Fraction(x) - Fraction(y) for x, y in zip(a1.tolist(), b1.tolist())]
    v = [q - p for p, q in zip(r0, r1)]
    vv = sum(x * x for x in v)
    if vv == 0:
        t = Fraction(0)
    else:
        t = min(max(-sum(p * q for p, q in zip(r0, v)) / vv, Fraction(0)), Fraction(1))
    sq = sum((p + t * q) ** 2 for p, q in zip(r0, v))
    if sq == 0:
        return 0.0
    try:
        val = math.sqrt(float(sq))
    except OverflowError:
        val = math.inf
    if val == 0.0 or not math.isfinite(val):  # outside the float range: go through logarithms
        val = math.exp(0.5 * (math.log(sq.numerator) - math.log(sq.denominator)))
    if val == 0.0:  # positive but below the float range: report the smallest positive float
        val = 5e-324
    return val


def clearance(waypoints: np.ndarray, m: int) -> np.ndarray:
    """Return the exact-where-it-matters clearance of a batch of paths.

    Parameters
    ----------
    waypoints : ndarray, shape (B, K, P, d)
        Waypoints with the m obstacles first.
    m : int
        Number of obstacles (rows that must not move).

    Returns
    -------
    ndarray, shape (B,)
        Minimum distance between two points along the whole motion; 0.0 where two points meet;
        NaN where a waypoint is not finite.

    Examples
    --------
    A robot passing exactly through an obstacle has clearance 0; a tiny detour is positive:

    >>> wp = np.array([[[[0, 0], [-1, 0]], [[0, 0], [1, 0]]],
    ...                [[[0, 0], [-1, 1e-300]], [[0, 0], [1, 1e-300]]]], dtype=float)
    >>> clearance(wp, m=1)
    array([0.e+000, 1.e-300])
    """
    wp = np.asarray(waypoints, dtype=float)
    b, k, p, d = wp.shape
    pi, pj = _pairs(p, m)
    out = np.full(b, np.inf)
    if pi.size == 0:
        return out
    rel = wp[:, :, pi, :] - wp[:, :, pj, :]  # (B, K, pairs, d)
    r0, r1 = rel[:, :-1], rel[:, 1:]
    dist = segment_clearance(r0, r1)  # (B, K-1, pairs)
    scale = np.maximum(np.abs(r0).max(-1), np.abs(r1).max(-1))
    absval = np.maximum(
        np.maximum(np.abs(wp[:, :-1, pi]).max(-1), np.abs(wp[:, :-1, pj]).max(-1)),
        np.maximum(np.abs(wp[:, 1:, pi]).max(-1), np.abs(wp[:, 1:, pj]).max(-1)),
    )
    finite = np.isfinite(r0).all(-1) & np.isfinite(r1).all(-1)
    suspect = ~(dist > _REL * np.maximum(scale, absval * 1e-6)) & finite
    dist[~finite] = np.nan  # not a path: its certificate fails below
    for bi, ki, qi in zip(*np.nonzero(suspect)):
        dist[bi, ki, qi] = _exact_segment_clearance(
            wp[bi, ki, pi[qi]], wp[bi, ki, pj[qi]], wp[bi, ki + 1, pi[qi]], wp[bi, ki + 1, pj[qi]]
        )
    out = dist.reshape(b, -1).min(axis=1, initial=np.inf)
    out[np.isnan(dist.reshape(b, -1)).any(axis=1)] = np.nan
    if m >= 2:
        oi, oj = np.triu_indices(m, k=1)
        od = wp[:, 0, oi] - wp[:, 0, oj]
        out = np.minimum(out, np.sqrt((od * od).sum(-1)).min(axis=1))
    return out


def certify(waypoints: np.ndarray, start: np.ndarray, goal: np.ndarray, m: int):
    """Check the whole certificate of SPEC section 5 for a batch of paths.

    Parameters
    ----------
    waypoints : ndarray, shape (B, K, P, d)
    start, goal : ndarray, shape (B, P, d)
        The query configurations C and C' (obstacles first).
    m : int
        Number of obstacles.

    Returns
    -------
    clearance : ndarray, shape (B,)
        The certified clearance.
    ok : ndarray of bool, shape (B,)
        True where endpoints match exactly, obstacles stay fixed and clearance > 0.
    """
    wp = np.asarray(waypoints, dtype=float)
    ends = (wp[:, 0] == start).all(axis=(1, 2)) & (wp[:, -1] == goal).all(axis=(1, 2))
    fixed = (wp[:, :, :m] == wp[:, :1, :m]).all(axis=(1, 2, 3))
    clr = clearance(wp, m)
    ok = ends & fixed & (clr > 0) & np.isfinite(wp).all(axis=(1, 2, 3))
    return clr, ok
