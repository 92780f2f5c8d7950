"""The certificate of a piecewise-linear motion (Mathematics §6).

A path with waypoints ``P_0..P_K`` at times ``t_0..t_K`` is *certified* for the query
(C, C') -- through the intermediate configurations C_k at tau_k, for a sequence (Mathematics §4.3) --
when every clause of :data:`CLAUSES` holds, checked in this order:

1. the times are finite, 2. ``t_0 == 0``, 3. ``t_K == 1``, 4. they never decrease;
5. the waypoints are finite;
6. ``P_0 == C`` and 7. ``P_K == C'`` exactly, 8. ``path(tau_k) == C_k`` exactly;
9. the obstacle rows are the same in every waypoint (obstacles fixed);
10. its *clearance* -- the minimum over pieces and over pairs of points of the distance between
the two linearly moving points -- is > 0.

:func:`certificate` returns the clearance and the number of the first clause that fails (0: the
path is certified); :func:`describe` names a clause. Every entry point of :mod:`pmplan.api`
runs the whole certificate on what it returns (the fused kernels compute the clearance
themselves; :mod:`pmplan._check` runs clauses 1-9 after them), so a path failing any clause is
never returned.

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
from functools import lru_cache

import numpy as np

__all__ = [
    "BAND_ABS",
    "BAND_REL",
    "CLAUSES",
    "certificate",
    "certify",
    "check_paths",
    "check_times",
    "clearance",
    "describe",
    "power_of_two_frame",
    "radius_report",
    "segment_clearance",
    "segment_closest",
]

# a float minimum below REL * (scale of the pair on that piece) is re-decided exactly
REL = 1e-9
# (for the kernels) REL * max(scale, 1e-6 absval) <= 2.0000001e-9 * (the largest absolute
# coordinate of the pair's points): a float distance above SURE times that is certainly above
# the threshold of REL
SURE = 2.1e-9
MAXF = 1.7976931348623157e308  # the largest finite float
# an obstacle pair whose squared distance is below this (it may have underflowed), or not finite
# (it overflowed), is measured exactly (the kernels flag it SUSPECT)
OBSTACLE_TINY2 = 2.0**-1000
# paths with waypoints outside [2**-_RANGE, 2**_RANGE) are measured scaled by a power of two
_RANGE = 500
# from this many points on, clearance() evaluates only the pairs _swept cannot exclude
_SWEEP_MIN = 64

#: the clauses of the certificate, by number (0: certified); :func:`certificate` reports the
#: first one that fails
CLAUSES: dict[int, str] = {
    1: "a breakpoint time is not finite",
    2: "the times do not start at 0",
    3: "the times do not end at 1",
    4: "the times decrease",
    5: "a waypoint is not finite",
    6: "the path does not begin exactly at the start",
    7: "the path does not end exactly at the goal",
    8: "the path does not pass exactly through an intermediate configuration",
    9: "an obstacle moves",
    10: "two points meet (the clearance is not positive)",
}
#: the clause number of the clearance (the only one not decided by :func:`check_paths`)
CLEARANCE = 10


def describe(clause: int) -> str:
    """Return the text of clause number ``clause`` (see :data:`CLAUSES`)."""
    return CLAUSES.get(int(clause), "certified") if clause else "certified"


def _rows_increase(t: np.ndarray) -> bool:
    """Whether every row of ``t`` (B, K) never decreases (False for NaN), given that every row
    starts at 0 and ends at 1: then, in the flattened rows, each of the B - 1 steps from the end
    of a row to the start of the next one is a drop (1 to 0), so the rows never decrease iff
    exactly B (K - 1) of the consecutive pairs do not decrease. One contiguous comparison."""
    flat = np.ascontiguousarray(t).reshape(-1)
    return int(np.count_nonzero(flat[1:] >= flat[:-1])) == flat.size - t.shape[0]


def check_times(times) -> np.ndarray:
    """Return the first failing clause among 1-4 of :data:`CLAUSES` (0: all hold).

    ``times`` of shape (K,) gives a scalar, (B, K) one code per path (uint8).

    Examples
    --------
    >>> check_times(np.array([0.0, 0.5, 1.0])), check_times(np.array([0.0, np.nan, 1.0]))
    (np.uint8(0), np.uint8(1))
    >>> check_times(np.array([[0.0, 1.0], [1e-300, 1.0], [0.0, 0.5], [0.0, -1.0]])).tolist()
    [0, 2, 3, 3]
    """
    t = np.asarray(times, dtype=float)
    single = t.ndim == 1
    t = t.reshape(1, -1) if single else t
    codes = np.zeros(t.shape[0], np.uint8)
    if t.shape[1] and not t[:, 0].any() and (t[:, -1] == 1.0).all() and _rows_increase(t):
        # the common case at a glance: from 0 to 1 without decreasing (hence finite: NaN fails
        # every comparison, an infinity cannot lie between 0 and 1)
        return codes[0] if single else codes
    if t.shape[1] == 0:
        codes[:] = 1
    else:
        with np.errstate(invalid="ignore"):
            clauses = [
                (1, np.isfinite(t).all(axis=1)),
                (2, t[:, 0] == 0.0),
                (3, t[:, -1] == 1.0),
                (4, (t[:, 1:] >= t[:, :-1]).all(axis=1)),
            ]
        for number, holds in reversed(clauses):
            codes[~holds] = number
    return codes[0] if single else codes


def check_paths(times, waypoints, start, goal, m: int, via=()) -> np.ndarray:
    """Return, per path, the first failing clause among 1-9 of :data:`CLAUSES` (0: all hold).

    Parameters
    ----------
    times : ndarray, shape (K,) or (B, K)
    waypoints : ndarray, shape (B, K, P, d)
    start, goal : ndarray, shape (B, P, d)
        The query configurations C and C' (obstacles first).
    m : int
        Number of obstacles.
    via : sequence of (float, ndarray (B, P, d))
        Intermediate configurations ``C_k`` the path must pass through exactly at ``tau_k``.

    Returns
    -------
    ndarray of uint8, shape (B,)

    Examples
    --------
    >>> wp = np.array([[[[0.0, 0.0], [0.0, 1.0]], [[0.0, 0.0], [1.0, 1.0]]]])
    >>> check_paths(np.array([0.0, 1.0]), wp, wp[:, 0], wp[:, -1], 1)
    array([0], dtype=uint8)
    >>> check_paths(np.array([0.0, np.nan]), wp, wp[:, 0], wp[:, -1], 1)
    array([1], dtype=uint8)
    """
    wp = np.asarray(waypoints, dtype=float)
    t = np.asarray(times, dtype=float)
    b, k = wp.shape[:2]
    t = np.broadcast_to(t, (b, k)) if t.ndim == 1 else t
    codes = np.zeros(b, np.uint8)
    start = np.asarray(start, dtype=float)
    goal = np.asarray(goal, dtype=float)
    if k == 0 or t.shape != (b, k):  # no breakpoints, or not one per waypoint
        codes[:] = 1
        return codes
    finite_t = np.isfinite(t).all(axis=1)
    clauses = [
        (5, np.isfinite(wp).all(axis=(1, 2, 3))),
        (6, (wp[:, 0] == start).all(axis=(1, 2))),
        (7, (wp[:, -1] == goal).all(axis=(1, 2))),
    ]
    if via:
        hold = np.ones(b, dtype=bool)
        good = finite_t & (t[:, 0] == 0.0) & (t[:, -1] == 1.0)
        if good.any():
            from .path import PiecewiseLinearPath

            g = np.flatnonzero(good)
            path = PiecewiseLinearPath(t[g], wp[g])
            for tau, conf in via:
                with np.errstate(all="ignore"):  # a non-finite waypoint fails clause 5 first
                    at = path(float(tau))
                hold[g] &= (at == np.asarray(conf, dtype=float)[g]).all(axis=(1, 2))
        clauses.append((8, hold))
    clauses.append((9, (wp[:, :, :m] == wp[:, :1, :m]).all(axis=(1, 2, 3))))
    for number, holds in reversed(clauses):
        codes[~holds] = number
    tcodes = check_times(t)  # clauses 1-4 come first
    codes[tcodes != 0] = tcodes[tcodes != 0]
    return codes


@lru_cache(maxsize=256)
def point_pairs(p: int, m: int) -> tuple[np.ndarray, np.ndarray]:
    """Index pairs (i < j) with at least one moving point (index >= m): read-only, cached (one
    per query shape; a refined query asks for them several times)."""
    i, j = np.triu_indices(p, k=1)
    keep = j >= m
    i, j = i[keep], j[keep]
    i.flags.writeable = False
    j.flags.writeable = False
    return i, j


def segment_closest(r0: np.ndarray, r1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return ``(min_{t in [0,1]} |r0 + t (r1 - r0)|, its t)`` in floating point, over the
    last axis (the arithmetic of :func:`segment_clearance`, which is its first part)."""
    # overflow gives inf/nan here; such pairs are re-decided exactly by the caller
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        v = r1 - r0
        vv = (v * v).sum(-1)
        r0v = (r0 * v).sum(-1)
        t = np.where(vv > 0, np.clip(-r0v / np.where(vv > 0, vv, 1.0), 0.0, 1.0), 0.0)
        q = r0 + t[..., None] * v
        return np.sqrt((q * q).sum(-1)), t


def segment_clearance(r0: np.ndarray, r1: np.ndarray) -> np.ndarray:
    """Return ``min_{t in [0,1]} |r0 + t (r1 - r0)|`` in floating point, over the last axis."""
    return segment_closest(r0, r1)[0]


def exact_segment_dist2(a0, b0, a1, b1) -> Fraction:
    """Exact squared min distance between points moving linearly a0->a1 and b0->b1."""
    r0 = [Fraction(x) - Fraction(y) for x, y in zip(a0.tolist(), b0.tolist())]
    r1 = [Fraction(x) - Fraction(y) for x, y in zip(a1.tolist(), b1.tolist())]
    v = [q - p for p, q in zip(r0, r1)]
    vv = sum(x * x for x in v)
    if vv == 0:
        t = Fraction(0)
    else:
        t = min(max(-sum(p * q for p, q in zip(r0, v)) / vv, Fraction(0)), Fraction(1))
    return sum((p + t * q) ** 2 for p, q in zip(r0, v))


def exact_segment_clearance(a0, b0, a1, b1) -> float:
    """Exact min distance between points moving linearly a0->a1 and b0->b1 (rational)."""
    sq = exact_segment_dist2(a0, b0, a1, b1)
    if sq == 0:
        return 0.0
    try:
        val = math.sqrt(float(sq))
    except OverflowError:
        val = math.inf
    if val < 2.0**-500 or not math.isfinite(val):
        # outside the float range of squares (a subnormal square has lost bits): the square
        # root of sq 4**j (exact scaling into the range),
        # scaled back by 2**-j. Above the largest double (two points ~1e308 apart): the largest
        # double, a lower bound; positive but below the float range: the smallest positive one
        j = (sq.denominator.bit_length() - sq.numerator.bit_length()) // 2
        root = math.sqrt(float(sq * Fraction(4) ** j if j >= 0 else sq / Fraction(4) ** -j))
        try:
            val = math.ldexp(root, -j)
        except OverflowError:
            val = MAXF
    if val == 0.0:
        val = 5e-324
    return val


def _decided(a0, b0, a1, b1) -> np.ndarray:
    """The decided minimum distance of every pair on its piece: points a0 -> a1 and b0 -> b1
    (arrays (..., d)); the float closed form, exact (:func:`exact_segment_clearance`) where it
    is small against the pair's scale or not finite (a relative position or a square that
    overflows), NaN where a waypoint is not finite."""
    with np.errstate(over="ignore", invalid="ignore"):  # re-decided exactly below
        r0 = a0 - b0
        r1 = a1 - b1
    dist = segment_clearance(r0, r1)
    scale = np.maximum(np.abs(r0).max(-1), np.abs(r1).max(-1))
    absval = np.maximum(np.maximum(np.abs(a0).max(-1), np.abs(b0).max(-1)),
                        np.maximum(np.abs(a1).max(-1), np.abs(b1).max(-1)))
    finite = np.isfinite(a0).all(-1) & np.isfinite(b0).all(-1) & np.isfinite(a1).all(-1) \
        & np.isfinite(b1).all(-1)
    with np.errstate(invalid="ignore", over="ignore"):
        suspect = (~(dist > REL * np.maximum(scale, absval * 1e-6)) | ~np.isfinite(dist)) \
            & finite
    dist[~finite] = np.nan
    for idx in zip(*np.nonzero(suspect)):
        dist[idx] = exact_segment_clearance(a0[idx], b0[idx], a1[idx], b1[idx])
    return dist


def _directions(w: np.ndarray, m: int) -> list[np.ndarray]:
    """Candidate sweep directions for a path ``w`` (K, P, d): the obstacle line ``o2 - o1``
    (and its normal in the plane), the coordinate axes, and the largest motion of a point on
    each piece (the lift of the obstacle-line paths)."""
    d = w.shape[2]
    dirs = list(np.eye(d))
    line = w[0, 1] - w[0, 0]
    dirs.append(line)
    if d == 2:
        dirs.append(np.array([-line[1], line[0]]))
    move = w[1:] - w[:-1]
    norms = (move * move).sum(-1)
    for t in range(move.shape[0]):
        dirs.append(move[t, int(np.argmax(norms[t]))])
    return [u / np.abs(u).max() for u in dirs if np.abs(u).max() > 0]


def _swept(w: np.ndarray, m: int) -> float:
    """:func:`clearance` of one path ``w`` (K, P, d), evaluating only the pairs of a piece that
    may reach the minimum (NaN where it does not apply: waypoints not finite, or outside
    ``(1e-130, 1e130)``, where the caller evaluates every pair).

    The minimum of the pairs adjacent in each piece's order (below) bounds the result: ``U``.
    On a piece, every point's projection on a direction u (of :func:`_directions`, the one
    whose spans are shortest) spans ``[lo, hi]``; a pair whose gap ``lo_b - hi_a`` exceeds
    ``((U + 1e-14 A) |u| + 2e-15 d A |u|_1) (1 + 1e-9)`` (A the largest |coordinate|) is
    farther than U on the whole piece, exactly and in floating point (the float projection is
    within ``1.0001 d eps A |u|_1`` of the exact one, the float closed form within
    ``17 sqrt(d) eps A`` of an exact point of the piece: see
    :func:`pmplan.kernels.obstacle_line._sweep_min`), so it can neither be the minimum nor
    change it. The others are decided as :func:`clearance` decides every pair
    (:func:`_decided`): the result is the same.
    """
    k, p, d = w.shape
    amax = float(np.abs(w).max())
    if not (np.isfinite(w).all() and 1e-130 < amax < 1e130):
        return np.nan
    dirs = _directions(w, m)
    keys = np.stack([w @ u for u in dirs])  # (directions, K, P)
    lo = np.minimum(keys[:, :-1], keys[:, 1:])  # (directions, K - 1, P)
    hi = np.maximum(keys[:, :-1], keys[:, 1:])
    spread = keys.max(-1) - keys.min(-1)
    score = (hi - lo).sum(-1) / np.maximum(np.minimum(spread[:, :-1], spread[:, 1:]), 1e-300)
    best = np.argmin(score, axis=0)  # the direction of each piece
    pieces = np.arange(k - 1)
    lo, hi = lo[best, pieces], hi[best, pieces]  # (K - 1, P)
    order = np.argsort(lo, axis=1, kind="stable")
    slo = np.take_along_axis(lo, order, 1)
    shi = np.take_along_axis(hi, order, 1)

    def decided(t, i, j):
        a, b = np.minimum(i, j), np.maximum(i, j)
        keep = b >= m
        t, a, b = t[keep], a[keep], b[keep]
        return _decided(w[t, a], w[t, b], w[t + 1, a], w[t + 1, b])

    # U: the neighbours in every piece's order
    tt = np.repeat(pieces, p - 1)
    bound = decided(tt, order[:, :-1].ravel(), order[:, 1:].ravel()).min(initial=np.inf)
    u = np.stack([dirs[i] for i in best])  # (K - 1, d)
    margin = 1e-14 * amax * np.sqrt((u * u).sum(-1)) + 4e-15 * d * amax * np.abs(u).sum(-1)
    thr = ((bound * np.sqrt((u * u).sum(-1)) + margin) * (1 + 1e-9))[:, None]
    ts, ii, jj = [], [], []
    act_t, act_x = np.nonzero(np.ones((k - 1, p - 1), bool))
    step = 1
    while act_t.size:
        inside = act_x + step < p
        act_t, act_x = act_t[inside], act_x[inside]
        near = slo[act_t, act_x + step] - shi[act_t, act_x] <= thr[act_t, 0]
        act_t, act_x = act_t[near], act_x[near]
        ts.append(act_t)
        ii.append(order[act_t, act_x])
        jj.append(order[act_t, act_x + step])
        step += 1
    if ts:
        cand = decided(np.concatenate(ts), np.concatenate(ii), np.concatenate(jj))
        bound = min(bound, cand.min(initial=np.inf))
    return min(bound, float(_obstacle_clearance(w[None], m)[0]))  # (m >= 2 here)


def _scaled_rows(wp: np.ndarray, m: int):
    """The clearance of the paths whose waypoints lie outside ``[2**-_RANGE, 2**_RANGE)``
    (squares would underflow or overflow), computed on the path scaled by the power of two that
    brings them into ``[0.5, 1)`` and scaled back -- exact, since distances scale exactly; a
    positive value below the float range is reported as the smallest positive double. Returns
    ``(rows, values)``, or None when no row needs it (or the scaling is not exact)."""
    b = wp.shape[0]
    if b == 0 or wp.size == 0:
        return None
    with np.errstate(invalid="ignore"):
        amax = np.abs(wp).reshape(b, -1).max(axis=1)
        extreme = np.isfinite(amax) & (amax > 0) & ~((amax >= 2.0**-_RANGE) & (amax < 2.0**_RANGE))
    if not extreme.any():
        return None
    rows, values = [], []
    for i in np.flatnonzero(extreme):
        _, e = np.frexp(amax[i])
        ws = np.ldexp(wp[i], -e)
        if not np.array_equal(np.ldexp(ws, e), wp[i]):
            continue  # bits below the range: the float path decides (exactly where small)
        c = float(clearance(ws[None], m)[0])
        with np.errstate(over="ignore", under="ignore"):
            v = float(np.ldexp(c, e)) if np.isfinite(c) else c
        if c > 0 and v == 0.0:
            v = 5e-324  # positive below the float range (as exact_segment_clearance)
        if np.isfinite(c) and v == np.inf:
            v = MAXF  # above the float range: the largest double, a lower bound
        rows.append(i)
        values.append(v)
    if not rows:
        return None
    return np.array(rows), np.array(values)


def clearance(waypoints: np.ndarray, m: int, *, sweep: bool = True) -> np.ndarray:
    """Return the exact-where-it-matters clearance of a batch of paths.

    Parameters
    ----------
    waypoints : ndarray, shape (B, K, P, d)
        Waypoints with the m obstacles first.
    m : int
        Number of obstacles (rows that must not move).
    sweep : bool
        From ``_SWEEP_MIN`` points on, evaluate only the pairs :func:`_swept` cannot exclude
        (the result is the same; False: every pair).

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
    if sweep and p >= _SWEEP_MIN and 2 <= m < p and k >= 2 and d < 8 and b:
        out = np.array([_swept(row, m) for row in wp])
        rest = np.isnan(out)  # (NaN: a row the sweep does not take)
        if rest.any():
            out[rest] = clearance(wp[rest], m, sweep=False)
        return out
    pi, pj = point_pairs(p, m)
    out = np.full(b, np.inf)
    if pi.size == 0:
        return out
    scaled = _scaled_rows(wp, m)
    if scaled is not None:
        rows, values = scaled
        keep = np.ones(b, dtype=bool)
        keep[rows] = False
        if keep.any():
            out[keep] = clearance(wp[keep], m, sweep=sweep)
        out[rows] = values
        return out
    # a waypoint that is not finite is not a path: its certificate fails below
    dist = _decided(wp[:, :-1, pi], wp[:, :-1, pj], wp[:, 1:, pi], wp[:, 1:, pj])
    out = dist.reshape(b, -1).min(axis=1, initial=np.inf)
    out[np.isnan(dist.reshape(b, -1)).any(axis=1)] = np.nan
    if m >= 2:
        out = np.minimum(out, _obstacle_clearance(wp, m))
    return out


def _obstacle_clearance(wp: np.ndarray, m: int) -> np.ndarray:
    """The smallest distance of two obstacles (they never move: at the first waypoint), (B,),
    for m >= 2; exact where the square may have overflowed or underflowed."""
    oi, oj = np.triu_indices(m, k=1)
    with np.errstate(over="ignore", invalid="ignore"):
        od = wp[:, 0, oi] - wp[:, 0, oj]
        od2 = (od * od).sum(-1)  # (B, pairs), summed as the kernels sum it
        odist = np.sqrt(od2)
        bad = ~(od2 >= OBSTACLE_TINY2) & np.isfinite(wp[:, 0, oi]).all(-1) \
            & np.isfinite(wp[:, 0, oj]).all(-1)
    for bi, qi in zip(*np.nonzero(bad)):  # the square overflowed or may have underflowed
        a, c = wp[bi, 0, oi[qi]], wp[bi, 0, oj[qi]]
        odist[bi, qi] = exact_segment_clearance(a, c, a, c)
    return odist.min(axis=1)


def certificate(waypoints: np.ndarray, start: np.ndarray, goal: np.ndarray, m: int, *,
                times=None, via=()) -> tuple[np.ndarray, np.ndarray]:
    """Check the whole certificate of Mathematics §6 for a batch of paths, clause by clause.

    Parameters
    ----------
    waypoints : ndarray, shape (B, K, P, d)
    start, goal : ndarray, shape (B, P, d)
        The query configurations C and C' (obstacles first).
    m : int
        Number of obstacles.
    times : ndarray, shape (K,) or (B, K), optional
        The breakpoints; default ``linspace(0, 1, K)`` (for a bare list of waypoints).
    via : sequence of (float, ndarray (B, P, d))
        Intermediate configurations and the times the path must pass through them.

    Returns
    -------
    clearance : ndarray, shape (B,)
        The certified clearance (NaN where a waypoint is not finite).
    clause : ndarray of uint8, shape (B,)
        The first clause of :data:`CLAUSES` that fails, 0 where the path is certified.
    """
    wp = np.asarray(waypoints, dtype=float)
    if times is None:
        times = np.linspace(0.0, 1.0, wp.shape[1])
    clause = check_paths(times, wp, start, goal, m, via)
    clr = clearance(wp, m)
    clause[(clause == 0) & ~(clr > 0)] = CLEARANCE
    return clr, clause


def certify(waypoints: np.ndarray, start: np.ndarray, goal: np.ndarray, m: int, *,
            times=None, via=()) -> tuple[np.ndarray, np.ndarray]:
    """Check the whole certificate of Mathematics §6 for a batch of paths.

    Parameters are those of :func:`certificate`.

    Returns
    -------
    clearance : ndarray, shape (B,)
        The certified clearance.
    ok : ndarray of bool, shape (B,)
        True where every clause of :data:`CLAUSES` holds: finite times from 0 to 1 that never
        decrease, finite waypoints beginning exactly at the start and ending exactly at the
        goal (through the ``via`` configurations), obstacles fixed and clearance > 0.
    """
    clr, clause = certificate(waypoints, start, goal, m, times=times, via=via)
    return clr, clause == 0


# --- the radii: exact minimum distances against exact bounds ----------------------------------

#: the band of the radius decision, in the path's power-of-two frame (largest ``|coordinate|`` in
#: [1/2, 1)): a float piece minimum is within ``BAND_REL (need + A) + BAND_ABS`` of the exact
#: one (A the largest ``|coordinate|`` of the pair's points on the piece: the rounding of the
#: relative positions and of the closed form is below 1e-14 A, an underflowed square below
#: 2**-530), with a wide margin; inside the band the exact minimum decides
BAND_REL = 1e-9
#: the absolute part of that band (see :data:`BAND_REL`)
BAND_ABS = 2.0**-500
#: a piece minimum below this may hold an underflowed square: measured exactly (the kernels
#: flag it SUSPECT)
TINY_DIST = 2.0**-480


def power_of_two_frame(wp: np.ndarray):
    """The power-of-two frame of every path of ``wp`` (B, K, P, d): ``(scaled, e, exact)``,
    ``scaled = wp 2**-e`` with the largest ``|coordinate|`` of the path in [1/2, 1) (e = 0 for a
    path at the origin or not finite); ``exact`` (B,): the scaling lost no bit (False only for
    a path whose coordinates span more than the float range: the original floats then decide)."""
    b = wp.shape[0]
    with np.errstate(invalid="ignore"):
        amax = np.abs(wp).reshape(b, -1).max(axis=1, initial=0.0)
    ok = np.isfinite(amax) & (amax > 0)
    e = np.where(ok, np.frexp(np.where(ok, amax, 1.0))[1], 0)
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        scaled = np.ldexp(wp, -e.reshape((b,) + (1,) * (wp.ndim - 1)))
        exact = (np.ldexp(scaled, e.reshape(scaled.shape[:1] + (1,) * (wp.ndim - 1))) == wp) \
            .reshape(b, -1).all(axis=1)
    return scaled, e, exact


def radius_report(waypoints: np.ndarray, m: int, radius: float, obstacle_radius: float):
    """``(robot_distance, obstacle_distance, respects)`` of a batch of paths (B, K, P, d).

    ``respects`` is decided **exactly**, at every magnitude: the true minimum distance between
    two robots is >= ``2 radius`` and between a robot and an obstacle >= ``radius +
    obstacle_radius`` (B,). Each path is measured in its power-of-two frame (:func:`pmplan.certify.power_of_two_frame`,
    exact: no square underflows or overflows there); a float piece minimum decides where it is
    farther than the band of :data:`pmplan.certify.BAND_REL` and
    :data:`pmplan.certify.BAND_ABS` from the bound (it is
    then on the right side exactly), rational arithmetic on the waypoint floats otherwise.

    The distances are the minima over the pieces of the closed-form piece minima in that frame,
    scaled back (``inf`` for the robot-robot one when n = 1): each within ``1e-13 A`` of the
    exact minimum (A the path's largest ``|coordinate|``; re-decided exactly where it is smaller
    than ``1e-9`` of the pair's scale, as :func:`pmplan.certify.clearance` does) -- a bound,
    not an exact value.

    Examples
    --------
    A robot passing an obstacle at distance 1 keeps radius + obstacle_radius = 1, not one ulp
    more, at every magnitude:

    >>> wp = np.array([[[[0.0, 0.0], [-1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0]]]])
    >>> radius_report(wp * 2.0**-1060, 1, 2.0**-1061, 2.0**-1061)[2]
    array([ True])
    >>> radius_report(wp, 1, 0.5, np.nextafter(0.5, 1))[2]
    array([False])
    """
    wp = np.asarray(waypoints, dtype=float)
    bsz, _, p, _ = wp.shape
    if bsz == 0:
        return np.empty(0), np.empty(0), np.ones(0, dtype=bool)
    pa, pb = point_pairs(p, m)
    ws, e, exact = power_of_two_frame(wp)
    with np.errstate(all="ignore"):
        d = _decided(ws[:, :-1, pa], ws[:, :-1, pb], ws[:, 1:, pa], ws[:, 1:, pb])
        A = np.maximum(np.abs(ws[:, :-1, pa]).max(-1), np.abs(ws[:, :-1, pb]).max(-1))
        A = np.maximum(A, np.maximum(np.abs(ws[:, 1:, pa]).max(-1), np.abs(ws[:, 1:, pb]).max(-1)))
    # a pair far smaller than its path (a scene of size 1e-160 lifted to 1): its squares may
    # underflow even in the frame, measured exactly
    for idx in zip(*np.nonzero(d < TINY_DIST)):
        bi, ki, qi = idx
        d[idx] = exact_segment_clearance(ws[bi, ki, pa[qi]], ws[bi, ki, pb[qi]],
                                          ws[bi, ki + 1, pa[qi]], ws[bi, ki + 1, pb[qi]])
    rr = pa >= m
    out = []
    for sel in (rr, ~rr):
        v = d[:, :, sel].reshape(bsz, -1).min(axis=1, initial=np.inf)
        with np.errstate(over="ignore", under="ignore"):
            out.append(np.ldexp(v, e))
    ok = np.ones(bsz, dtype=bool)
    for sel, need in ((rr, 2 * Fraction(radius)),
                      (~rr, Fraction(radius) + Fraction(obstacle_radius))):
        if need == 0 or not sel.any():
            continue
        ok &= _at_least(wp, ws, e, exact, d[:, :, sel], A[:, :, sel], pa[sel], pb[sel], need)
    return out[0], out[1], ok


def _at_least(wp, ws, e, exact, d, A, pa, pb, need: Fraction) -> np.ndarray:
    """Whether every pair (pa, pb) keeps an exact distance >= ``need`` along every path (B,):
    the frame's float minima ``d`` (B, K-1, pairs) decide outside the band, the exact minima
    (on the frame's floats, or the original ones where the frame is not exact) inside it."""
    bsz = wp.shape[0]
    with np.errstate(over="ignore", under="ignore"):
        nf = np.ldexp(float(need), -e)[:, None, None]  # (inf: far above the scene)
    band = BAND_REL * (nf + A) + BAND_ABS
    with np.errstate(invalid="ignore"):
        sure = d > nf + band
        # (a waypoint that is not finite: not a path, it keeps no radius)
        fail = (d < nf - band) | (np.isinf(nf) & ~np.isnan(d)) | np.isnan(d)
    ok = ~fail.reshape(bsz, -1).any(axis=1)
    for bi, ki, qi in zip(*np.nonzero(~sure & ~fail)):
        if not ok[bi]:
            continue
        if exact[bi]:
            w, bound = ws[bi], need / (Fraction(2) ** int(e[bi]))
        else:
            w, bound = wp[bi], need
        if exact_segment_dist2(w[ki, pa[qi]], w[ki, pb[qi]], w[ki + 1, pa[qi]],
                                w[ki + 1, pb[qi]]) < bound * bound:
            ok[bi] = False
    return ok
