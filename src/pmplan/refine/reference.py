"""The numpy reference of the refinement map R (:func:`refine_paths`): vectorised over the
batch and the pieces, looping over pairs and coordinates in the kernel's order, so that the
numba kernel (:mod:`pmplan.refine.kernel`) gives the same paths bit for bit. Its grid,
schedule and constants are :mod:`pmplan.refine.grid`'s; the map and why it is continuous and
collision-free: :mod:`pmplan.refine` and ``docs/refinement.md``.
"""

from __future__ import annotations

import numpy as np

from .grid import (
    ALPHA,
    BETA,
    DEFAULT_STEPS,
    DEFAULT_WAYPOINTS,
    GAMMA,
    LAMBDA,
    MARGIN,
    OMEGA,
    PHI,
    PHI_WAYPOINT,
    SHARE,
    SLACK,
    WALL_SLIDE,
    chord_fraction,
    dot,
    final_steps,
    hold_levels,
    levels,
    mobility,
    overshoot,
    pairs,
    piece_minima,
    push_points,
    subdivide,
)

__all__ = ["clear_floor", "refine_paths"]


# --- one substep -----------------------------------------------------------------------------

def _caps(x, a, b, c, free) -> np.ndarray:
    """The cap of every point at every waypoint, (B, W, P): the minimum over its pairs and the
    two adjacent pieces of ``free`` (B, W-1, pairs), already multiplied by ``c``."""
    bsz, w, p = x.shape[:3]
    cap = np.full((bsz, w, p), np.inf)
    for q in range(a.shape[0]):
        g = free[:, :, q]
        for pt in (a[q], b[q]):
            cap[:, :-1, pt] = np.minimum(cap[:, :-1, pt], g)
            cap[:, 1:, pt] = np.minimum(cap[:, 1:, pt], g)
    return cap


def _apply(x, delta, cap, m, j=slice(None)) -> None:
    """Move the robots at the waypoints ``j`` by ``delta`` clipped to ``cap`` (both of those
    waypoints): ``x += delta min(1, cap/|delta|)``."""
    nrm = np.sqrt(dot(delta, delta))
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(nrm > cap, cap / nrm, 1.0)
    x[:, j, m:] = x[:, j, m:] + delta[:, :, m:] * scale[:, :, m:, None]


def _slack(x) -> np.ndarray:
    """``4 SLACK A`` per path (B,): the rounding slack of the caps (:data:`~pmplan.refine.grid.SLACK`), A the
    largest norm of a point of the path in the frame (1/2 <= A < 1 for the raw path; a norm,
    not the largest |coordinate|, and no absolute term: the map must commute with rotations
    and scalings, A sets where the directional allowance turns off)."""
    return (4.0 * SLACK) * np.sqrt(dot(x, x)).reshape(x.shape[0], -1).max(axis=1)


def _shorten(x, m, a, b, c, tgt, frac, mob) -> None:
    d = piece_minima(x, a, b)
    keep = tgt * (1.0 + MARGIN)
    sl = _slack(x)[:, None, None]
    free = c * np.maximum((d - sl) - keep[:, None, :], 0.0)
    cap = _caps(x, a, b, c, free)
    w = x.shape[1]
    # red-black: the odd waypoints toward the chords of the even ones, then the even ones
    # toward the chords of the moved odd ones; each move within its cap (of the positions at
    # the start of the substep, where the distances were measured)
    for first in (1, 2):
        j = slice(first, w - 1, 2)
        xm, xp = x[:, first - 1:w - 2:2], x[:, first + 1::2]
        chord = xm + frac[:, first - 1::2, None, None] * (xp - xm)
        delta = (ALPHA * mob[:, j])[..., None, None] * (chord - x[:, j])
        _apply(x, delta, cap[:, j], m, j)


def _budget(r0, v, f2, nterms: float, al, be, start: bool, err=0.0):
    """The directional scale of one end's move on one piece: ``min(1, min over t in [0, 1]
    with g(t) > 0 of h(t) / g(t))``, where ``g(t) = w(t) (al + t be)`` is the inward part of the
    move at the piece's parameter t (``w = 1 - t`` at the start, ``t`` at the end) and
    ``h(t) = (|r(t)|^2 - F'^2) / (2 terms)`` its share of the room above ``F'`` there. The
    minimum of the ratio of two quadratics is at t = 0, 1 or a root of ``h' g - h g'``, itself a
    quadratic (its cubic terms cancel); the candidates are clipped to [0, 1] (an extra one,
    the vertex ``-B / A``, only lowers the result)."""
    if start:  # (1 - t)(al + t be) = al + t (be - al) - t^2 be
        g0, g1, g2 = al, be - al, -be
    else:  # t (al + t be)
        g0, g1, g2 = np.zeros_like(al), al, be
    den = 2.0 * nterms
    h0 = (dot(r0, r0) - f2 * f2 - err) / den
    h1 = (2.0 * dot(r0, v)) / den
    h2 = dot(v, v) / den
    qa = h2 * g1 - h1 * g2
    qb = h2 * g0 - h0 * g2
    qc = h1 * g0 - h0 * g1
    sq = np.sqrt(np.maximum(qb * qb - qa * qc, 0.0))
    qq = np.where(qb >= 0, -(qb + sq), -(qb - sq))
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        cands = (np.zeros_like(al), np.ones_like(al),
                 np.where(qa != 0, qq / np.where(qa != 0, qa, 1.0), 0.0),
                 np.where(qq != 0, qc / np.where(qq != 0, qq, 1.0), 0.0),
                 np.where(qa != 0, -qb / np.where(qa != 0, qa, 1.0), 0.0))
    s = np.ones_like(al)
    for t in cands:
        t = np.clip(np.where(np.isnan(t), 0.0, t), 0.0, 1.0)
        g = ((1.0 - t) if start else t) * (al + t * be)
        rt = r0 + t[..., None] * v
        h = np.maximum((dot(rt, rt) - f2 * f2 - err) / den, 0.0)
        with np.errstate(invalid="ignore", divide="ignore"):
            s = np.where(g > 0, np.minimum(s, h / np.where(g > 0, g, 1.0)), s)
    return s


def _room(r0, v, f2, al, be):
    """The room of one end's move on one piece, ``min over t in [0, 1] of |r(t)|^2 - F'^2 +
    max(-(al + t be), 0)``: the room above ``F'`` where the move is not outward, raised by its
    outward part where it is (``al + t be`` the move's inward part at t, raised by its rounding
    bound). Convex in t (a convex quadratic plus a convex ramp): its minimum is at t = 0, 1, the
    zero of the inward part or the vertex of either quadratic, all evaluated (clipped to [0, 1])."""
    a1 = 2.0 * dot(r0, v)
    a2 = dot(v, v)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        cands = (np.zeros_like(al), np.ones_like(al),
                 np.where(be != 0, -al / np.where(be != 0, be, 1.0), 0.0),
                 np.where(a2 > 0, -a1 / np.where(a2 > 0, 2.0 * a2, 1.0), 0.0),
                 np.where(a2 > 0, -(a1 - be) / np.where(a2 > 0, 2.0 * a2, 1.0), 0.0))
    out = None
    for t in cands:
        t = np.clip(np.where(np.isnan(t), 0.0, t), 0.0, 1.0)
        rt = r0 + t[..., None] * v
        val = (dot(rt, rt) - f2 * f2) + np.maximum(-(al + t * be), 0.0)
        out = val if out is None else np.minimum(out, val)
    return out


def _clear_scale(x, delta, m, a, b, c, d, gap, cap, sl=None) -> np.ndarray:
    """The scale in [0, 1] of every point's clearing move, (B, W, P): 1 within the isotropic cap
    ``cap``; beyond it the smallest, over the point's pairs and the two adjacent pieces, of the
    larger of its isotropic scale ``SHARE c (D - F) / |move|`` and its *directional* scale
    (:func:`_budget`): at every t of the piece the inward part of the move stays within its share
    ``(|r(t)|^2 - F'^2) / (2 terms)``, ``F' = D - SHARE (D - F)``. Collision-free:
    ``|r + dr|^2 >= |r|^2 + 2 r.dr``, so the directional terms keep the pair above ``F'`` at every
    t and the isotropic ones take at most ``SHARE (D - F)`` more; with ``SHARE = 1/2`` the pair
    stays above ``F``."""
    bsz, w, p = x.shape[:3]
    nrm = np.sqrt(dot(delta, delta))
    s = np.ones((bsz, w, p))
    sl = _slack(x) if sl is None else sl
    for q in range(a.shape[0]):
        pa, pb = a[q], b[q]
        r = x[:, :, pa] - x[:, :, pb]
        r0, v = r[:, :-1], r[:, 1:] - r[:, :-1]
        ext = sl[:, None] / SLACK + (np.sqrt(dot(r0, r0)) + np.sqrt(dot(v, v)))
        gq = gap[:, :, q]
        f2 = d[:, :, q] - SHARE * gq
        nterms = 4.0 if pa >= m else 2.0
        iso = (SHARE * c[q]) * gq
        for pt, sign in ((pb, -1.0), (pa, 1.0)) if pa >= m else ((pb, -1.0),):
            for start in (True, False):
                sl_ = slice(None, -1) if start else slice(1, None)
                dl = delta[:, sl_, pt]
                big = nrm[:, sl_, pt] > cap[:, sl_, pt]  # only the moves beyond the cap
                nm = nrm[:, sl_, pt]
                e = ext + nm
                # (the inward part raised by its rounding bound, so that a move the floats see
                # as outward where the pair nearly touches is not taken as free)
                err = (4.0 * SLACK) * (e * e)
                al = -sign * dot(r0, dl) + (SLACK * e) * nm
                be = -sign * dot(v, dl)
                sd = _budget(r0, v, f2, nterms, al, be, start, err)
                # no directional allowance where the room above F' is within the rounding at
                # a point of the piece where the move is not outward (its budget would be empty
                # there), and a continuous ramp up to it (a switch would make the map jump
                # there); where the move is outward the room counts its outward part too
                # (computed where the room of the piece minimum is below 8 err: beyond, the
                # raised room is above 4 err too, where the ramp is 1)
                dq = d[:, :, q]
                room = dq * dq - f2 * f2
                low = room < 8.0 * err
                if low.any():
                    room = np.where(low, _room(r0, v, f2, al, be), room)
                with np.errstate(invalid="ignore", divide="ignore"):
                    ramp = np.minimum((room - 2.0 * err) / (2.0 * err), 1.0)
                sd = np.where(room > 2.0 * err, sd * ramp, 0.0)
                with np.errstate(invalid="ignore", divide="ignore"):
                    si = np.where(nm > iso, iso / np.where(nm > 0, nm, 1.0), 1.0)
                s[:, sl_, pt] = np.where(big, np.minimum(s[:, sl_, pt], np.maximum(sd, si)),
                                         s[:, sl_, pt])
    return s


def clear_floor(d, tgt, hold, phi, eta):
    """The clearing's floor of every pair on every piece (B, W-1, pairs) from its piece minimum
    ``d``: ``phi d`` below the target T, ``T (1 + MARGIN)`` from the push target ``T (1 +
    eta)`` on, linear between; never below ``hold`` (B, pairs), the pair's no-squeezing level
    (:func:`~pmplan.refine.grid.hold_levels`)."""
    keep = tgt * (1.0 + MARGIN)  # (B, pairs)
    star = tgt * (1.0 + eta)
    low = phi * tgt
    slope = (keep - low) / (star - tgt)
    t_ = tgt[:, None, :]
    floor = np.where(d <= t_, phi * d,
                     np.where(d >= star[:, None, :], keep[:, None, :],
                              low[:, None, :] + (d - t_) * slope[:, None, :]))
    return np.maximum(floor, hold[:, None, :])


def _wall_push(x, push, m, walls) -> None:
    """The walls' pushes, added to ``push`` (B, W, P, d) in place: a robot beyond a wall's
    limit (``walls`` (B, 2, d): the lowest and highest coordinates it should keep) is pushed
    back by how far it is beyond, coordinate by coordinate (continuous: a ramp). Only beyond: a
    push zone in front of the limits (the robots' radius times the overshoot, as the pairs')
    kept as many scene paths valid (311 against 312 of 384: rooms and swaps of 8 and 16
    robots, seeds 1, 2, 4) and amplified the modulus of continuity up to 2,140 against 212
    (room_walls n = 16, seed 1)."""
    for k in range(x.shape[-1]):
        xk = x[:, :, m:, k]
        lo = walls[:, 0, k][:, None, None]
        hi = walls[:, 1, k][:, None, None]
        push[:, :, m:, k] = push[:, :, m:, k] + np.maximum(lo - xk, 0.0)
        push[:, :, m:, k] = push[:, :, m:, k] - np.maximum(xk - hi, 0.0)


def _wall_scale(x, delta, m, walls) -> np.ndarray:
    """The walls' scale in [WALL_SLIDE, 1] of every robot's clearing move, (B, W, n): a move
    goes toward a wall's limit at most the room it has left there plus ``WALL_SLIDE`` times its
    largest coordinate, ``min(1, (max(room, 0) + WALL_SLIDE max_k |move_k|) / outward part)``
    (continuous: the allowance grows with the move, so the scale never switches between 0 and
    1; the largest coordinate, not the length, which would underflow for a tiny move). A smaller
    scale of a clearing move keeps it collision-free (every budget of :func:`_clear_scale` bounds
    the scale from above)."""
    dr = delta[:, :, m:]
    xr = x[:, :, m:]
    slide = WALL_SLIDE * np.abs(dr).max(axis=-1)
    s = np.ones(xr.shape[:3])
    for k in range(x.shape[-1]):
        for out, room in ((-dr[..., k], xr[..., k] - walls[:, 0, k][:, None, None]),
                          (dr[..., k], walls[:, 1, k][:, None, None] - xr[..., k])):
            allow = np.maximum(room, 0.0) + slide
            with np.errstate(invalid="ignore", divide="ignore"):
                s = np.where(out > allow, np.minimum(s, allow / np.where(out > allow, out, 1.0)),
                             s)
    return s


def _clear(x, m, a, b, c, tgt, mob, eta, at_waypoints: bool, hold=None, walls=None) -> None:
    """One clearing pass: the pushes at the waypoints (``at_waypoints``, floor factor
    :data:`~pmplan.refine.grid.PHI_WAYPOINT`) or at the push points of the pieces (floor factor
    :data:`~pmplan.refine.grid.PHI`), each point's move scaled by :func:`_clear_scale`; no pair below its floor
    (:func:`clear_floor`; ``hold``: (B, pairs), 0 when not given). With ``walls`` (B, 2, d) the
    robots beyond the walls' limits are pushed back too (:func:`_wall_push`) and their moves
    toward them held back (:func:`_wall_scale`)."""
    phi = PHI_WAYPOINT if at_waypoints else PHI
    d = piece_minima(x, a, b)
    star = tgt * (1.0 + eta)
    hold = np.zeros_like(tgt) if hold is None else hold
    floor = clear_floor(d, tgt, hold, phi, eta)
    sl = _slack(x)
    gap = np.maximum((d - sl[:, None, None]) - floor, 0.0)
    cap = _caps(x, a, b, c, (SHARE * c) * gap)
    push = np.zeros(x.shape)
    for q in range(a.shape[0]):
        pa, pb, cq, sq = a[q], b[q], c[q], star[:, q][:, None]
        rel = x[:, :, pa] - x[:, :, pb]  # (B, W, d)
        r0, r1 = rel[:, :-1], rel[:, 1:]
        v = r1 - r0
        if at_waypoints:
            dist = np.sqrt(dot(rel, rel))
            # the push direction at an interior waypoint: the relative position plus GAMMA
            # times the turn of the relative path there (continuous; it does not turn with
            # r / |r| where the pair nearly touches at the end of a piece)
            vn = np.sqrt(dot(v, v))
            nin, nout = vn[:, :-1], vn[:, 1:]
            eps = GAMMA * np.minimum(nin, nout)
            with np.errstate(invalid="ignore", divide="ignore"):
                ein = np.where(nin > 0, eps / np.where(nin > 0, nin, 1.0), 0.0)
                eout = np.where(nout > 0, eps / np.where(nout > 0, nout, 1.0), 0.0)
            u = rel.copy()
            u[:, 1:-1] = rel[:, 1:-1] + eout[..., None] * v[:, 1:] - ein[..., None] * v[:, :-1]
            den = np.maximum(np.sqrt(dot(u, u)), dist)
            with np.errstate(invalid="ignore", divide="ignore"):
                fac = np.where(den > 0, (OMEGA * cq) * np.maximum(sq - dist, 0.0) / den, 0.0)
            fw = fac[..., None] * u
            push[:, :, pb] = push[:, :, pb] - fw
            if pa >= m:
                push[:, :, pa] = push[:, :, pa] + fw
            continue
        # the push: along the piece's push point (its closest point where the line passes
        # close to the origin: outward along the piece; Lipschitz in the piece's ends,
        # grid.push_points), shared by its ends in the weights of its soft closest point
        # (continuous even where v -> 0, where the exact parameter jumps)
        soft = np.clip(-dot(r0, v) / (dot(v, v) + LAMBDA * (dot(r0, r0) + dot(r1, r1))),
                       0.0, 1.0)
        relm = push_points(r0, v)
        distm = np.sqrt(dot(relm, relm))
        with np.errstate(invalid="ignore", divide="ignore"):
            facm = np.where(distm > 0, cq * np.maximum(sq - distm, 0.0) / distm, 0.0)
        # no push on a piece whose every point is at least sq apart (d: its exact minimum)
        facm = np.where(d[:, :, q] < sq, facm, 0.0)
        f1 = (facm * soft)[..., None] * relm
        f0 = (facm - facm * soft)[..., None] * relm
        push[:, 1:, pb] = push[:, 1:, pb] - f1
        push[:, :-1, pb] = push[:, :-1, pb] - f0
        if pa >= m:
            push[:, 1:, pa] = push[:, 1:, pa] + f1
            push[:, :-1, pa] = push[:, :-1, pa] + f0
    if walls is not None:
        _wall_push(x, push, m, walls)
    delta = (BETA * mob)[..., None, None] * push
    scale = _clear_scale(x, delta, m, a, b, c, d, gap, cap, sl)
    if walls is not None:
        scale[:, :, m:] = np.minimum(scale[:, :, m:], _wall_scale(x, delta, m, walls))
    x[:, :, m:] = x[:, :, m:] + delta[:, :, m:] * scale[:, :, m:, None]


def refine_paths(times: np.ndarray, waypoints: np.ndarray, m: int, r: int, target: np.ndarray,
                 waypoints_per_piece: int = DEFAULT_WAYPOINTS, steps: int = DEFAULT_STEPS,
                 walls: np.ndarray | None = None,
                 still=None) -> tuple[np.ndarray, np.ndarray]:
    """Apply the refinement map R to a batch of certified paths (the numpy reference).

    Parameters
    ----------
    times : ndarray, shape (K,) or (B, K)
        The raw breakpoints (the intermediate configurations at ``k / (r - 1)``).
    waypoints : ndarray, shape (B, K, P, d)
        The raw waypoints, obstacles first (rows ``< m``), in the normal float range.
    m, r : int
        Obstacles; configurations the path passes through (2: start and goal).
    target : ndarray, shape (B, 2)
        The target distances ``T`` between two robots and between a robot and an obstacle
        (positive).
    waypoints_per_piece, steps : int
        ``S`` (a power of two) and the number of steps (see the module docstring).
    walls : ndarray, shape (B, 2, d), optional
        A workspace: the lowest and highest coordinates the robots should keep (the clearing
        pushes them back from these limits and holds its moves toward them; the caller maps
        the result into the box). None: no walls.
    still : tuple of bool, length K - 1, optional
        The raw pieces that stand still for almost every query
        (:meth:`pmplan.planners.base.Planner.still_pieces`): one sub-piece at every level
        (:func:`~pmplan.refine.grid.subdivide_times`). None: every piece is cut.

    Returns
    -------
    times : ndarray, shape (W,) or (B, W)
        ``W = (K-1) S + 1``, less ``S - 1`` per piece that stands still.
    waypoints : ndarray, shape (B, W, P, d)
    """
    times = np.asarray(times, dtype=float)
    x = np.array(waypoints, dtype=float)
    p = x.shape[2]
    a, b, c = pairs(p, m)
    tgt = np.where(a >= m, target[:, :1], target[:, 1:2])  # (B, pairs)
    hold = hold_levels(x, a, b, tgt)
    t = times
    for level, (split, n_steps, t) in enumerate(levels(times, waypoints_per_piece, steps, still)):
        if level:
            x = subdivide(x, split)
        tb = np.broadcast_to(t, x.shape[:2])
        mob = mobility(tb, r)
        frac = chord_fraction(tb)
        eta = overshoot(level)
        for _ in range(n_steps):
            if level == 0:  # the waypoint pass: at the coarsest level (PHI_WAYPOINT)
                _clear(x, m, a, b, c, tgt, mob, eta, True, hold, walls)
            _clear(x, m, a, b, c, tgt, mob, eta, False, hold, walls)
            _shorten(x, m, a, b, c, tgt, frac, mob)
    for _ in range(final_steps(steps, x.shape[2] - m, x.shape[3])):
        _clear(x, m, a, b, c, tgt, mob, eta, False, hold, walls)
    return t, x
