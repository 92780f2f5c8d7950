"""The numba kernel of the refinement map R (:mod:`pmplan.refine`), batch-first.

:func:`refine_batch` runs the whole schedule of :func:`pmplan.refine.reference.refine_paths` -- the
coarse-to-fine levels, per level the steps (a clearing then a shortening substep), then the
clearing-only steps -- with one compiled call per level (:func:`_level`, ``nogil``: the threads
of ``workers`` refine chunks in parallel). Its arithmetic is the reference's, operation for
operation and in the same order (sums over coordinates from 0, pushes pair after pair), so the
two give bitwise equal paths (tests/test_refine.py). The grid, the mobility and the chord
fractions are computed once per level by the numpy functions of :mod:`pmplan.refine.grid`,
which it shares with the reference (neither imports the other).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..kernels.common import OPTS, njit
from ..kernels.measure import minima, minima_scratch, pair_rel
from . import grid
from .grid import (
    chord_fraction,
    final_steps,
    hold_levels,
    levels,
    mobility,
    overshoot,
    pairs,
    subdivide,
)

__all__ = ["constants", "refine_batch"]

# the map's constants are passed as ``kp`` = (ALPHA, BETA, PHI, ETA, MARGIN, LAMBDA, OMEGA,
# SHARE, GAMMA, PHI_WAYPOINT, SLACK, WALL_SLIDE) and the overshoot ``eta`` of the level, read from
# pmplan.refine.grid at every call (a module global would be compiled in, and cached on disk,
# as a constant: a change of pmplan.refine.grid would not reach the kernel)


@njit(**OPTS)
def _caps(a, b, free, cap):  # pragma: no cover - compiled
    """Every point's cap at every waypoint (W, P): the minimum of ``free`` (W-1, pairs) over
    its pairs and the two adjacent pieces."""
    cap[:, :] = np.inf
    w1 = free.shape[0]
    for q in range(a.shape[0]):
        for pt in (a[q], b[q]):
            for j in range(w1):
                g = free[j, q]
                cap[j, pt] = min(cap[j, pt], g)
                cap[j + 1, pt] = min(cap[j + 1, pt], g)


@njit(**OPTS)
def _slack(x, slack):  # pragma: no cover - compiled
    """:func:`pmplan.refine.reference._slack` of one path: ``4 SLACK A``, A the largest norm of a point
    (summed as the reference's ``dot``)."""
    amax = 0.0
    w, p, dd = x.shape
    for j in range(w):
        for i in range(p):
            s = 0.0
            for k in range(dd):
                s = s + x[j, i, k] * x[j, i, k]
            amax = max(amax, math.sqrt(s))
    return (4.0 * slack) * amax


@njit(**OPTS)
def _shorten(x, m, a, b, c, tgt, frac, mob, dmin, free, cap, delta, rel_t, kp):  # pragma: no cover
    w, p, dd = x.shape
    minima(x, a, b, dmin, rel_t)
    sl = _slack(x, kp[10])
    for q in range(a.shape[0]):
        keep = tgt[q] * (1.0 + kp[4])
        for j in range(w - 1):
            free[j, q] = c[q] * max((dmin[j, q] - sl) - keep, 0.0)
    _caps(a, b, free, cap)
    for first in (1, 2):  # red-black, as the reference
        for j in range(first, w - 1, 2):
            f = frac[j - 1]
            wgt = kp[0] * mob[j]
            for i in range(m, p):
                s = 0.0
                for k in range(dd):
                    xm = x[j - 1, i, k]
                    chord = xm + f * (x[j + 1, i, k] - xm)
                    dk = wgt * (chord - x[j, i, k])
                    delta[j, i, k] = dk
                    s = s + dk * dk
                # the capped move of pmplan.refine.reference._apply, written out: a shared inlined helper
                # cost 10-20 % of a refined (2,4,2) batch (CPU time, 5 alternating pairs, 2,000
                # queries)
                nrm = math.sqrt(s)
                scale = cap[j, i] / nrm if nrm > cap[j, i] else 1.0
                for k in range(dd):
                    x[j, i, k] = x[j, i, k] + delta[j, i, k] * scale


@njit(**OPTS)
def _budget_at(r0, v, f2, den, al, be, start, err, t):  # pragma: no cover - compiled
    """``h(t) / g(t)`` of :func:`pmplan.refine.reference._budget` at one candidate t (inf where g <= 0)."""
    t = 0.0 if math.isnan(t) else min(max(t, 0.0), 1.0)
    g = ((1.0 - t) if start else t) * (al + t * be)
    if not g > 0:
        return np.inf
    s = 0.0
    for k in range(r0.shape[0]):
        rt = r0[k] + t * v[k]
        s = s + rt * rt
    return max((s - f2 * f2 - err) / den, 0.0) / g


@njit(**OPTS)
def _budget(r0, v, f2, nterms, al, be, start, err=0.0):  # pragma: no cover - compiled
    """:func:`pmplan.refine.reference._budget` of one term, same arithmetic."""
    if start:
        g0 = al
        g1 = be - al
        g2 = -be
    else:
        g0 = 0.0
        g1 = al
        g2 = be
    den = 2.0 * nterms
    rr = 0.0
    rv = 0.0
    vv = 0.0
    for k in range(r0.shape[0]):
        rr = rr + r0[k] * r0[k]
        rv = rv + r0[k] * v[k]
        vv = vv + v[k] * v[k]
    h0 = (rr - f2 * f2 - err) / den
    h1 = (2.0 * rv) / den
    h2 = vv / den
    qa = h2 * g1 - h1 * g2
    qb = h2 * g0 - h0 * g2
    qc = h1 * g0 - h0 * g1
    sq = math.sqrt(max(qb * qb - qa * qc, 0.0))
    qq = -(qb + sq) if qb >= 0 else -(qb - sq)
    s = min(1.0, _budget_at(r0, v, f2, den, al, be, start, err, 0.0))
    s = min(s, _budget_at(r0, v, f2, den, al, be, start, err, 1.0))
    if qa != 0:
        s = min(s, _budget_at(r0, v, f2, den, al, be, start, err, qq / qa))
    else:
        s = min(s, _budget_at(r0, v, f2, den, al, be, start, err, 0.0))
    if qq != 0:
        s = min(s, _budget_at(r0, v, f2, den, al, be, start, err, qc / qq))
    else:
        s = min(s, _budget_at(r0, v, f2, den, al, be, start, err, 0.0))
    if qa != 0:
        s = min(s, _budget_at(r0, v, f2, den, al, be, start, err, -qb / qa))
    return s


@njit(**OPTS)
def _room_at(r0, v, f2, al, be, t):  # pragma: no cover - compiled
    """The room of :func:`pmplan.refine.reference._room` at one candidate t."""
    t = 0.0 if math.isnan(t) else min(max(t, 0.0), 1.0)
    s = 0.0
    for k in range(r0.shape[0]):
        rt = r0[k] + t * v[k]
        s = s + rt * rt
    return (s - f2 * f2) + max(-(al + t * be), 0.0)


@njit(**OPTS)
def _room(r0, v, f2, al, be):  # pragma: no cover - compiled
    """:func:`pmplan.refine.reference._room` of one term, same arithmetic."""
    rv = 0.0
    vv = 0.0
    for k in range(r0.shape[0]):
        rv = rv + r0[k] * v[k]
        vv = vv + v[k] * v[k]
    a1 = 2.0 * rv
    a2 = vv
    s = min(_room_at(r0, v, f2, al, be, 0.0), _room_at(r0, v, f2, al, be, 1.0))
    s = min(s, _room_at(r0, v, f2, al, be, -al / be if be != 0 else 0.0))
    s = min(s, _room_at(r0, v, f2, al, be, -a1 / (2.0 * a2) if a2 > 0 else 0.0))
    s = min(s, _room_at(r0, v, f2, al, be, -(a1 - be) / (2.0 * a2) if a2 > 0 else 0.0))
    return s


@njit(**OPTS)
def _dir_scale(x, m, a, b, c, dmin, gap, delta, j, pt, nm, kp, r0, v, sl, start,
               members):  # pragma: no cover - compiled
    """The scale of point ``pt``'s clearing move at waypoint ``j`` beyond its isotropic cap
    (:func:`pmplan.refine.reference._clear_scale`, same arithmetic); ``r0``, ``v``: (d,) scratch;
    the pairs of ``pt`` are ``members[start[pt]:start[pt + 1]]`` (:func:`_members`)."""
    w, _, dd = x.shape
    share_k = kp[7]
    s = 1.0
    for u in range(start[pt], start[pt + 1]):
        q = members[u]
        pa, pb = a[q], b[q]
        sign = -1.0 if pb == pt else 1.0
        nterms = 4.0 if pa >= m else 2.0
        for jp in (j, j - 1):  # the piece starting at j, then the piece ending at j
            if jp < 0 or jp >= w - 1:
                continue
            gq = gap[jp, q]
            iso = (share_k * c[q]) * gq
            if not nm > iso:
                continue  # (the isotropic scale is 1 here: max(sd, 1) = 1 leaves s as it is)
            f2 = dmin[jp, q] - share_k * gq
            r0d = 0.0
            vd = 0.0
            rr = 0.0
            vv = 0.0
            for k in range(dd):
                r0[k] = x[jp, pa, k] - x[jp, pb, k]
                v[k] = (x[jp + 1, pa, k] - x[jp + 1, pb, k]) - r0[k]
                r0d = r0d + r0[k] * delta[j, pt, k]
                vd = vd + v[k] * delta[j, pt, k]
                rr = rr + r0[k] * r0[k]
                vv = vv + v[k] * v[k]
            e = (sl / kp[10] + (math.sqrt(rr) + math.sqrt(vv))) + nm
            err = (4.0 * kp[10]) * (e * e)
            al = -sign * r0d + (kp[10] * e) * nm
            be = -sign * vd
            dq = dmin[jp, q]
            room = dq * dq - f2 * f2
            if room < 8.0 * err:  # (beyond, the raised room is above 4 err too: the ramp is 1)
                room = _room(r0, v, f2, al, be)
            if room > 2.0 * err:  # (and the reference's continuous ramp above it)
                sd = _budget(r0, v, f2, nterms, al, be, jp == j, err) * min(
                    (room - 2.0 * err) / (2.0 * err), 1.0)
            else:
                sd = 0.0  # (the reference's: no room above F' beyond the rounding)
            si = iso / nm if nm > iso else 1.0
            s = min(s, max(sd, si))
    return s


@njit(**OPTS)
def _wall_scale(x, delta, walls, j, i, slide_k):  # pragma: no cover - compiled
    """:func:`pmplan.refine.reference._wall_scale` of point ``i`` at waypoint ``j``, same
    arithmetic."""
    big = 0.0
    for k in range(x.shape[2]):
        big = max(big, abs(delta[j, i, k]))
    slide = slide_k * big
    s = 1.0
    for k in range(x.shape[2]):
        dk = delta[j, i, k]
        xk = x[j, i, k]
        for side in range(2):
            if side == 0:
                out = -dk
                room = xk - walls[0, k]
            else:
                out = dk
                room = walls[1, k] - xk
            allow = max(room, 0.0) + slide
            if out > allow:
                s = min(s, allow / out)
    return s


@njit(**OPTS)
def _turned(rel, j, k, ein, eout):  # pragma: no cover - compiled
    """Coordinate k of the waypoint push direction ``u`` at waypoint j of
    :func:`pmplan.refine.reference._clear`: the relative position plus the turn of the relative path
    (interior waypoints only)."""
    if 0 < j < rel.shape[0] - 1:
        return rel[j, k] + eout * (rel[j + 1, k] - rel[j, k]) - ein * (rel[j, k] - rel[j - 1, k])
    return rel[j, k]


@njit(**OPTS)
def _clear(x, m, a, b, c, tgt, hold, mob, dmin, free, gap, cap, delta, rel, rel_t, kp, eta,
           at_waypoints, walls, has_walls, start, members):  # pragma: no cover - compiled
    """One clearing pass of :func:`pmplan.refine.reference._clear` (same arithmetic, same order;
    ``walls`` (2, d) of this query where ``has_walls``; ``start``, ``members``: every robot's
    pairs, :func:`_members`)."""
    w, p, dd = x.shape
    phi = kp[9] if at_waypoints else kp[2]
    delta[:, :, :] = 0.0  # the push
    share_k = kp[7]
    gamma = kp[8]
    minima(x, a, b, dmin, rel_t)
    sl = _slack(x, kp[10])
    for q in range(a.shape[0]):
        t = tgt[q]
        keep = t * (1.0 + kp[4])
        star = t * (1.0 + eta)
        low = phi * t
        slope = (keep - low) / (star - t)
        pa, pb, cq = a[q], b[q], c[q]
        near = False  # (a pair at least sq apart on every piece gets no push: skipped)
        for j in range(w - 1):
            dq = dmin[j, q]
            near = near or dq < star
            if dq <= t:
                floor = phi * dq
            elif dq >= star:
                floor = keep
            else:
                floor = low + (dq - t) * slope
            floor = max(floor, hold[q])
            g = max((dq - sl) - floor, 0.0)
            gap[j, q] = g
            free[j, q] = (share_k * cq) * g
        if not near:
            continue
        pair_rel(x, pa, pb, rel)
        sq = star
        for j in range(w if at_waypoints else 0):  # at the waypoints
            s = 0.0
            for k in range(dd):
                s = s + rel[j, k] * rel[j, k]
            dist = math.sqrt(s)
            if not sq - dist > 0.0:
                continue  # no push (the reference adds a zero)
            ein = 0.0
            eout = 0.0
            if 0 < j < w - 1:
                sin = 0.0
                sout = 0.0
                for k in range(dd):
                    vi = rel[j, k] - rel[j - 1, k]
                    vo = rel[j + 1, k] - rel[j, k]
                    sin = sin + vi * vi
                    sout = sout + vo * vo
                nin = math.sqrt(sin)
                nout = math.sqrt(sout)
                eps = gamma * min(nin, nout)
                ein = eps / nin if nin > 0 else 0.0
                eout = eps / nout if nout > 0 else 0.0
            su = 0.0
            for k in range(dd):
                uk = _turned(rel, j, k, ein, eout)
                su = su + uk * uk
            den = max(math.sqrt(su), dist)
            fw0 = (kp[6] * cq) * max(sq - dist, 0.0) / den if den > 0 else 0.0
            for k in range(dd):
                fw = fw0 * _turned(rel, j, k, ein, eout)
                delta[j, pb, k] = delta[j, pb, k] - fw
                if pa >= m:
                    delta[j, pa, k] = delta[j, pa, k] + fw
        for j in range(0 if at_waypoints else w - 1):  # at the push point of every piece
            if not dmin[j, q] < sq:
                continue  # no point of the piece is closer than sq: no push (exactly)
            r0v = 0.0
            vv = 0.0
            r00 = 0.0
            r11 = 0.0
            for k in range(dd):
                v = rel[j + 1, k] - rel[j, k]
                r0v = r0v + rel[j, k] * v
                vv = vv + v * v
                r00 = r00 + rel[j, k] * rel[j, k]
                r11 = r11 + rel[j + 1, k] * rel[j + 1, k]
            soft = min(max(-r0v / (vv + kp[5] * (r00 + r11)), 0.0), 1.0)
            # the push along the push point, in the soft point's weights
            # (pmplan.refine.grid.push_points, pmplan.refine.reference._clear)
            gram = max(r00 * vv - r0v * r0v, 0.0)
            den = vv * vv + kp[5] * gram
            qe = min(max((-r0v) * vv / den, 0.0), 1.0) if den > 0 else 0.0
            s = 0.0
            for k in range(dd):
                rm = rel[j, k] + qe * (rel[j + 1, k] - rel[j, k])
                s = s + rm * rm
            distm = math.sqrt(s)
            facm = cq * max(sq - distm, 0.0) / distm if distm > 0 else 0.0
            g1 = facm * soft
            g0 = facm - facm * soft
            for k in range(dd):
                rm = rel[j, k] + qe * (rel[j + 1, k] - rel[j, k])
                f1 = g1 * rm
                f0 = g0 * rm
                delta[j + 1, pb, k] = delta[j + 1, pb, k] - f1
                delta[j, pb, k] = delta[j, pb, k] - f0
                if pa >= m:
                    delta[j + 1, pa, k] = delta[j + 1, pa, k] + f1
                    delta[j, pa, k] = delta[j, pa, k] + f0
    if has_walls:  # pmplan.refine.reference._wall_push
        for j in range(w):
            for i in range(m, p):
                for k in range(dd):
                    xk = x[j, i, k]
                    delta[j, i, k] = delta[j, i, k] + max(walls[0, k] - xk, 0.0)
                    delta[j, i, k] = delta[j, i, k] - max(xk - walls[1, k], 0.0)
    _caps(a, b, free, cap)
    for j in range(w):
        wgt = kp[1] * mob[j]
        for i in range(p):
            for k in range(dd):
                delta[j, i, k] = wgt * delta[j, i, k]
    # the scales first (every one from the positions before the move), kept in ``cap``
    for j in range(w):
        for i in range(m, p):
            s = 0.0
            for k in range(dd):
                s = s + delta[j, i, k] * delta[j, i, k]
            nm = math.sqrt(s)
            cap[j, i] = _dir_scale(x, m, a, b, c, dmin, gap, delta, j, i, nm, kp, rel[0],
                                   rel[1], sl, start, members) if nm > cap[j, i] else 1.0
            if has_walls:
                cap[j, i] = min(cap[j, i], _wall_scale(x, delta, walls, j, i, kp[11]))
    for j in range(w):
        for i in range(m, p):
            sc = cap[j, i]
            for k in range(dd):
                x[j, i, k] = x[j, i, k] + delta[j, i, k] * sc


@njit(**OPTS)
def _level(x, m, a, b, c, tgt, hold, frac, mob, steps, clear_only, kp, eta,
           waypoint_pass, walls, has_walls, start, members):  # pragma: no cover - compiled
    """``steps`` steps (clear, shorten) then ``clear_only`` clearing steps on every query of
    the batch ``x`` (B, W, P, d), in place; ``frac`` (B, W-2), ``mob`` (B, W), ``tgt`` (B,
    pairs); ``waypoint_pass``: the steps' clearing begins with the waypoint pass (the coarsest
    level); ``walls`` (B, 2, d) where ``has_walls`` (else one unused row); ``start``,
    ``members``: every robot's pairs (:func:`_members`)."""
    bsz, w, p, dd = x.shape
    npair = a.shape[0]
    dmin = np.empty((w - 1, npair))
    free = np.empty((w - 1, npair))
    gap = np.empty((w - 1, npair))
    cap = np.empty((w, p))
    delta = np.empty((w, p, dd))
    rel = np.empty((w, dd))
    rel_t = minima_scratch(w, dd, npair)
    for i in range(bsz):
        xi = x[i]
        g = i if mob.shape[0] > 1 else 0  # shared times: one row of mobility and fractions
        wi = i if has_walls else 0
        for k in range(steps + clear_only):
            if waypoint_pass and k < steps:  # the clearing substep: the waypoint pass first
                _clear(xi, m, a, b, c, tgt[i], hold[i], mob[g], dmin, free, gap, cap, delta, rel,
                       rel_t, kp, eta, True, walls[wi], has_walls, start, members)
            _clear(xi, m, a, b, c, tgt[i], hold[i], mob[g], dmin, free, gap, cap, delta, rel,
                   rel_t, kp, eta, False, walls[wi], has_walls, start, members)
            if k < steps:
                _shorten(xi, m, a, b, c, tgt[i], frac[g], mob[g], dmin, free, cap, delta, rel_t,
                         kp)


@lru_cache(maxsize=256)
def _members(p: int, m: int) -> tuple[np.ndarray, np.ndarray]:
    """Every robot's pairs of :func:`~pmplan.refine.grid.pairs` ``(p, m)``, the ones whose
    clearing budget bounds its move (a robot is ``b`` of its pairs with an obstacle and ``a``
    or ``b`` of its pairs with another robot), in the order of the pairs: robot ``pt``'s are
    ``members[start[pt]:start[pt + 1]]`` (cached, as the pairs are: one per query shape)."""
    a, b, _ = pairs(p, m)
    lists = [[] for _ in range(p)]
    for q in range(a.shape[0]):  # (in the order of the pairs: every list ascends)
        lists[b[q]].append(q)
        if a[q] >= m:
            lists[a[q]].append(q)
    start = np.zeros(p + 1, dtype=np.int64)
    start[1:] = np.cumsum([len(x) for x in lists])
    members = np.array([q for x in lists for q in x], dtype=np.int64)
    return start, members


def constants() -> np.ndarray:
    """The map's constants (:mod:`pmplan.refine.grid`, the one source the reference imports
    too), as the kernel reads them at every call."""
    g = grid
    return np.array([g.ALPHA, g.BETA, g.PHI, g.ETA, g.MARGIN, g.LAMBDA, g.OMEGA, g.SHARE,
                     g.GAMMA, g.PHI_WAYPOINT, g.SLACK, g.WALL_SLIDE])


def _grids(times: np.ndarray, r: int, waypoints_per_piece: int, steps: int, b: int,
           still=None):
    """Per level ``(split, steps, times, mobility, chord fractions)`` (``split``: the pieces
    the level halves on its way in, :func:`~pmplan.refine.grid.split_mask`): shared
    breakpoints (K,) give one row (cached), per-query ones (b, K) one row per query."""
    key = None
    still = None if still is None else tuple(bool(v) for v in still)
    if times.ndim == 1:
        key = (times.tobytes(), r, waypoints_per_piece, steps, still)
        hit = _GRIDS.get(key)
        if hit is not None:
            return hit
    out = []
    for split, n_steps, t in levels(times, waypoints_per_piece, steps, still):
        tb = t[None] if t.ndim == 1 else t
        out.append((split, n_steps, t, np.ascontiguousarray(mobility(tb, r)),
                    np.ascontiguousarray(chord_fraction(tb))))
    if key is not None and len(_GRIDS) < 256:
        _GRIDS[key] = out
    return out


_GRIDS: dict = {}


def refine_batch(times: np.ndarray, waypoints: np.ndarray, m: int, r: int, target: np.ndarray,
                 waypoints_per_piece: int, steps: int,
                 walls: np.ndarray | None = None,
                 still=None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`pmplan.refine.reference.refine_paths` by the kernel: same arguments, same (bitwise) result."""
    times = np.asarray(times, dtype=float)
    x = np.array(waypoints, dtype=float)
    p = x.shape[2]
    a, b, c = pairs(p, m)
    tgt = np.ascontiguousarray(np.where(a >= m, target[:, :1], target[:, 1:2]))
    hold = np.ascontiguousarray(hold_levels(x, a, b, tgt))
    levels = _grids(times, r, waypoints_per_piece, steps, x.shape[0], still)
    kp = constants()
    start, members = _members(p, m)
    has_walls = walls is not None
    # (no walls: one unused row, numba compiles one signature)
    walls = np.ascontiguousarray(walls, dtype=float) if has_walls else np.zeros((1, 2, x.shape[3]))
    t = times
    for level, (split, n_steps, t, mob, frac) in enumerate(levels):
        if level:
            x = subdivide(x, split)
        if x.shape[0]:
            last = level == len(levels) - 1
            _level(x, m, a, b, c, tgt, hold, frac, mob, n_steps,
                   final_steps(steps, p - m, x.shape[3]) if last else 0, kp, overshoot(level),
                   level == 0, walls, has_walls, start, members)
    return t, x
