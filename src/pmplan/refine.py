"""Refined motions: a planner's path shortened and cleared by a fixed continuous map R.

Definition. For a planner ``s`` with domains of continuity ``W_1..W_k`` and a map ``R`` from
paths to paths that is **continuous**, keeps the endpoints, the intermediate configurations and
the obstacles fixed and never creates a collision, ``R o s`` is again a planner, continuous on
every ``W_l``: it has the same domains, hence the same number of them, and is optimal whenever
``s`` is (paper Section 2: the sectional category counts domains of continuous sections, and a
continuous map of sections keeps their domains). The refined plan keeps the domain label and the
stratum of the unrefined one.

The map ``R`` (:func:`refine_paths`) is a FIXED number of steps of a continuous update of the
waypoints at FIXED times -- no accept/reject, no line search, no stop on convergence, no random
numbers, no discrete choice (only min, max and clip of continuous quantities):

1. *Coarse-to-fine grid.* Every piece of the raw path is cut into ``s = 1, 2, 4, .., S`` equal
   sub-pieces (``S = waypoints``); going from ``s`` to ``2 s`` inserts the midpoint of every
   piece, which keeps the path (and its collision-freeness) and is continuous in the query.
   Every raw breakpoint stays a breakpoint, so the intermediate configurations stay exactly at
   their times.
2. *Steps.* At each level, ``steps`` are split evenly; a step is a *clearing* substep followed
   by a *shortening* substep. At the coarsest level the clearing substep has two passes, the
   pushes at the waypoints then those at the soft closest points; at the finer levels and in
   the final clearing-only steps, the second only. Shortening moves every interior
   waypoint a fraction
   :data:`ALPHA` toward the point of the chord of its two neighbours at its time (red-black:
   the odd waypoints first, then the even ones toward the moved odd ones); clearing
   pushes the two points of a pair apart at the waypoints (weight :data:`OMEGA`) and at the
   *soft closest point* of every piece (the push shared by the two ends of the piece in
   proportion), by :data:`BETA` times the deficit ``max(T* - |x_a - x_b|, 0)`` below the push
   target
   ``T* = (1 + ETA) T``. Both moves are multiplied by a *mobility* in [0, 1], a continuous
   function of the times that is 0 at the fixed times (start, goal, intermediate
   configurations) and at zero-duration pieces.
3. *Collision-free by construction.* On a linear piece the relative position of two points is a
   convex combination of its values at the two ends, so if the ends of points a and b move by at
   most ``delta_a`` and ``delta_b`` the pair's distance anywhere on the piece changes by at most
   ``delta_a + delta_b``. Every move of point a at waypoint j is therefore scaled down (a
   continuous clip) to its *cap*: the minimum, over the pairs (a, b) and the two pieces adjacent
   to j, of ``c (D - F(D))`` where ``D`` is the exact closed-form minimum distance of the pair on
   that piece (the certificate's, :func:`pmplan.certify.segment_clearance`), ``F`` a floor below
   ``D`` and ``c = 1/2`` for two robots, ``1`` for a robot and an obstacle (which never moves).
   Then every distance stays above its floor: shortening uses ``F = min(T (1 + MARGIN), D)``
   (a pair at or above the target never goes below it), clearing uses ``F = PHI D`` below ``T``,
   rising continuously to ``T (1 + MARGIN)`` at ``T*``. The clearing spends half of that
   (:data:`SHARE`) isotropically, and may instead move a point further when the *inward* part
   of its move along the piece, ``max_t w(t) (-r(t).move)``, stays within its share of
   ``D^2 - F'^2`` (``|r + dr|^2 >= |r|^2 + 2 r.dr``; :func:`_clear_scale`): a pair that nearly
   touches is pushed out in steps that do not shrink with its distance.

The targets: ``T = 2 radius`` between robots and ``radius + obstacle_radius`` between a robot and
an obstacle; when a target is 0 (no radius asked), ``KAPPA`` times the raw plan's clearance, so
that the refined path keeps a clearance of the order of the raw one. Nothing here is an
absolute length: the map commutes with translations and rotations, and with scalings when the
radii scale too (bit for bit for powers of two).

The final path is certified exactly as every plan (:mod:`pmplan.certify`); the result also
reports the exact minimum robot-robot and robot-obstacle distances and whether the radii are
respected (:func:`radius_report`), decided exactly where the float value is close.

This module is the numpy reference of the kernel :mod:`pmplan.kernels.refine` (bitwise equal):
vectorised over the batch and the pieces, looping over pairs and coordinates in the kernel's
order.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from .backends import select
from .certify import (
    CLEARANCE,
    check_paths,
    clearance,
    describe,
    exact_segment_clearance,
    exact_segment_dist2,
    radius_report,
)
from .errors import CertificationError, CollisionError, InputError
from .planners.base import Stage
from .refine_grid import (  # noqa: F401 (the grid, its constants and the closed forms: re-exported)
    DECAY,
    ETA,
    FINAL,
    GROWTH,
    HOLD,
    MARGIN,
    MOBILITY,
    chord_fraction,
    dot,
    final_steps,
    hold_levels,
    mobility,
    overshoot,
    pairs,
    piece_minima,
    schedule,
    subdivide,
    subdivide_times,
)

__all__ = [
    "DEFAULT_STEPS",
    "DEFAULT_WAYPOINTS",
    "check_parameters",
    "check_radii",
    "radius_report",
    "refine_paths",
    "schedule",
]

#: default sub-pieces per raw piece at the finest level (a power of two): 7 raw pieces per leg
#: of the obstacle-line planner give 14 pieces per leg (measured: benchmarks/refine_bench.py)
DEFAULT_WAYPOINTS = 2
#: default number of steps (each a clearing and a shortening substep), split over the levels
DEFAULT_STEPS = 56
#: the largest ``waypoints`` accepted
MAX_WAYPOINTS = 64
#: the largest ``steps`` accepted
MAX_STEPS = 100_000
#: shortening gain: the fraction of the way to the chord point moved per step
ALPHA = 1.0
#: clearing gain: the fraction of the deficit pushed per step
BETA = 0.5
#: clearing floor: a pair below its target may lose at most 1 - PHI of its distance per step
#: (measured with the 1e-6 probe: 0.25 against 0.5, smaller largest probes and shorter paths)
PHI = 0.25
#: the soft closest point of a piece: ``clip(-r0.v / (|v|^2 + LAMBDA (|r0|^2 + |r1|^2)), 0,
#: 1)``, continuous where the exact one (LAMBDA = 0) jumps (v -> 0); its slope is of order
#: 1 / LAMBDA, so a larger LAMBDA keeps the continuity modulus small (measured: 2**-4 halves
#: the largest 1e-6 probe of n = 8 against 2**-12, at the same lengths)
LAMBDA = 2.0**-4
#: clearing floor of the waypoint pass (its pushes first, then the soft points' with PHI): a
#: pair below its target may lose at most 1 - PHI_WAYPOINT of its distance in that pass. Two
#: passes, so that the push at a waypoint where a pair nearly touches (along the path's turn,
#: outward on both pieces) is not held back by the soft points' pushes, nearly along the pieces
#: (measured on the n = 8 rows of benchmarks/refine_bench.py, three draws: 2 probes above 1e-4
#: of 400 against 4-13 in one pass; 0.9 keeps every path clear of 1e-2, 0.5 squeezes some to
#: 1e-9). The waypoint pass runs at the coarsest level only, where the raw path's
#: near-contacts are separated: at the finer levels and in the final steps it changed no probe
#: above 1e-5 and no length by 1e-3, and cost a fifth of the kernel's time
PHI_WAYPOINT = 0.9
#: the clearing's share of a pair's free distance ``D - F``: a move of a point within
#: ``SHARE c (D - F)`` (isotropic), or whose inward part along the piece stays within its share of
#: ``D^2 - F'^2`` (directional: a near-contact is pushed out, or slides, in large steps), keeps the
#: pair above ``F`` (1/2 makes the two kinds add up to at most ``D - F``; measured on the n = 8
#: rows of benchmarks/refine_bench.py: the largest 1e-6 probe 3-4e-4 against 0.7-4.9e-3 with the
#: isotropic cap alone, same lengths)
SHARE = 0.5
#: the push direction at an interior waypoint is ``r + GAMMA min(|v_in|, |v_out|) (v_out/|v_out|
#: - v_in/|v_in|)`` (r the relative position, v the relative path's pieces): where a pair nearly
#: touches at the end of a piece it follows the path's turn rather than ``r / |r|``
GAMMA = 0.25
#: the weight of the push at the waypoints (along the pair's relative position there) against
#: the push at the soft closest point of each piece (weight 1). Where a pair nearly touches at a
#: waypoint (clearance c) its direction turns by delta / c under a move delta of the query, so
#: it carries most of the continuity modulus; without it a pair pushed only at soft points,
#: nearly along the piece, can be squeezed to a clearance of 1e-17 (measured on the n = 8 rows
#: of benchmarks/refine_bench.py). 1/2: fewer 1e-6 probes above 1e-4 (9 against 22 of 640 for
#: 1), no squeezed path
OMEGA = 0.5
#: with no radius, the target clearance is KAPPA times the raw plan's clearance
KAPPA = 0.5
#: the kernel measures the refined paths for d below this (numpy sums fewer than 8 terms
#: sequentially, as the kernel does; beyond, numpy's pairwise sums round differently)
MAX_SEQUENTIAL_D = 8
#: the rounding slack of the caps, in the frame (extent in [1/2, 1)): every cap is measured
#: from ``D - 4 SLACK A`` (A the largest norm of a point of the path at the substep), every
#: directional budget from ``h - 4 SLACK e**2`` against an inward part raised by ``SLACK e
#: |move|`` (e = 4 A + |r0| + |v| + |move|), with a continuous ramp from 0 where the room above
#: F' is within 2 to 4 of that slack: the float piece minimum, the float inward part and the
#: rounded moves are within far less of the exact ones (about 2**-50 e), so every floor holds
#: for the floats computed, exactly (tests/test_refine_exact.py). Only norms and no absolute
#: term: the map commutes with rotations and scalings (to rounding)
SLACK = 2.0**-44
#: the largest target in the refinement's frame (:func:`to_frame`: the path's extent is below 1
#: there)
MAX_TARGET = 2.0**20

# the messages of the parameter checks (one source; the CLI prints them as they are)
_MSG_RADIUS = ("`{name}` must be a finite real number >= 0 (a length in the scene's units), "
               "got {value!r}")
_MSG_WAYPOINTS = ("`waypoints` must be a power of two from 1 to {max} (sub-pieces per piece of "
                  "the raw path), got {value!r}")
_MSG_STEPS = "`steps` must be an int from 1 to {max} (refinement steps), got {value!r}"
_MSG_REFINE = "`refine` must be True or False, got {value!r}"
MSG_PLAN = "refine() takes a Plan or a PlanBatch returned by pmplan, got {value}"
MSG_REFINED = ("this plan is already refined (radius {radius}); refine the unrefined plan "
                "(plan(..., refine=False)) with the radii you want")
MSG_REFINE_OUT = ("`out=` cannot be combined with refine=True (a refined batch has more "
                   "breakpoints): plan into `out`, then call pmplan.refine on it")
MSG_REFINE_DASK = ("refine() takes a computed batch, and this PlanBatch holds dask arrays: "
                    "plan it with refine=True (plan_batch on dask arrays then refines every "
                    "block lazily), or compute it first (pmplan.scale.compute)")
_MSG_RADII_UNREFINED = ("`radius` and `obstacle_radius` apply to refined motions: pass "
                        "refine=True (or call pmplan.refine on the plan)")
_MSG_TOO_CLOSE = ("{what}: {pair} are {dist:.6g} apart{where}, closer than {need} = "
                  "{value:.6g}; move them apart or use smaller radii")


def _is_real(x) -> bool:
    return isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(
        x, (bool, np.bool_))


def check_radius(value, name: str) -> float:
    """``value`` as a float if it is a finite real >= 0 (not a bool), else an InputError."""
    if not _is_real(value) or not math.isfinite(float(value)) or float(value) < 0:
        raise InputError(_MSG_RADIUS.format(name=name, value=value))
    return float(value)


def check_parameters(radius, obstacle_radius, waypoints, steps):
    """Validate the refinement parameters; return ``(radius, obstacle_radius, waypoints,
    steps)`` with the defaults filled in. Raises :class:`~pmplan.errors.InputError` naming the
    parameter and what it must be.

    Examples
    --------
    >>> check_parameters(0, 0.5, None, None)
    (0.0, 0.5, 2, 56)
    >>> check_parameters(-1.0, 0, None, None)
    Traceback (most recent call last):
    ...
    pmplan.errors.InputError: `radius` must be a finite real number >= 0 (a length in the scene's units), got -1.0
    """
    radius = check_radius(radius, "radius")
    obstacle_radius = check_radius(obstacle_radius, "obstacle_radius")
    if waypoints is None:
        waypoints = DEFAULT_WAYPOINTS
    elif (isinstance(waypoints, (bool, np.bool_)) or not isinstance(waypoints, (int, np.integer))
          or not 1 <= waypoints <= MAX_WAYPOINTS or waypoints & (waypoints - 1)):
        raise InputError(_MSG_WAYPOINTS.format(max=MAX_WAYPOINTS, value=waypoints))
    if steps is None:
        steps = DEFAULT_STEPS
    elif (isinstance(steps, (bool, np.bool_)) or not isinstance(steps, (int, np.integer))
          or not 1 <= steps <= MAX_STEPS):
        raise InputError(_MSG_STEPS.format(max=MAX_STEPS, value=steps))
    return radius, obstacle_radius, int(waypoints), int(steps)


def check_refine_flag(refine, radius, obstacle_radius) -> bool:
    """The ``refine=`` argument of the planning functions: a bool; radii without it are refused
    (they would be silently ignored)."""
    if not isinstance(refine, (bool, np.bool_)):
        raise InputError(_MSG_REFINE.format(value=refine))
    if not refine:
        check_radius(radius, "radius")
        check_radius(obstacle_radius, "obstacle_radius")
        if radius != 0 or obstacle_radius != 0:
            raise InputError(_MSG_RADII_UNREFINED)
    return bool(refine)


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
    """``4 SLACK A`` per path (B,): the rounding slack of the caps (:data:`SLACK`), A the
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
                sd = _budget(r0, v, f2, nterms, -sign * dot(r0, dl) + (SLACK * e) * nm,
                             -sign * dot(v, dl), start, err)
                # no directional allowance where the room above F' is within the rounding
                # anywhere on the piece (its budget would be empty there), and a continuous
                # ramp up to it (a switch would make the map jump there)
                dq = d[:, :, q]
                room = dq * dq - f2 * f2
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
    (:func:`hold_levels`)."""
    keep = tgt * (1.0 + MARGIN)  # (B, pairs)
    star = tgt * (1.0 + eta)
    low = phi * tgt
    slope = (keep - low) / (star - tgt)
    t_ = tgt[:, None, :]
    floor = np.where(d <= t_, phi * d,
                     np.where(d >= star[:, None, :], keep[:, None, :],
                              low[:, None, :] + (d - t_) * slope[:, None, :]))
    return np.maximum(floor, hold[:, None, :])


def _clear(x, m, a, b, c, tgt, mob, eta, at_waypoints: bool, hold=None) -> None:
    """One clearing pass: the pushes at the waypoints (``at_waypoints``, floor factor
    :data:`PHI_WAYPOINT`) or at the soft closest points of the pieces (floor factor
    :data:`PHI`), each point's move scaled by :func:`_clear_scale`; no pair below its floor
    (:func:`clear_floor`; ``hold``: (B, pairs), 0 when not given)."""
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
        # the soft closest point of the piece: continuous even where v -> 0
        soft = np.clip(-dot(r0, v) / (dot(v, v) + LAMBDA * (dot(r0, r0) + dot(r1, r1))),
                       0.0, 1.0)
        relm = r0 + soft[..., None] * v
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
    delta = (BETA * mob)[..., None, None] * push
    scale = _clear_scale(x, delta, m, a, b, c, d, gap, cap, sl)
    x[:, :, m:] = x[:, :, m:] + delta[:, :, m:] * scale[:, :, m:, None]


def refine_paths(times: np.ndarray, waypoints: np.ndarray, m: int, r: int, target: np.ndarray,
                 waypoints_per_piece: int = DEFAULT_WAYPOINTS, steps: int = DEFAULT_STEPS
                 ) -> tuple[np.ndarray, np.ndarray]:
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

    Returns
    -------
    times : ndarray, shape ((K-1) S + 1,) or (B, (K-1) S + 1)
    waypoints : ndarray, shape (B, (K-1) S + 1, P, d)
    """
    times = np.asarray(times, dtype=float)
    x = np.array(waypoints, dtype=float)
    p = x.shape[2]
    a, b, c = pairs(p, m)
    tgt = np.where(a >= m, target[:, :1], target[:, 1:2])  # (B, pairs)
    hold = hold_levels(x, a, b, tgt)
    t = times
    for level, (s, n_steps) in enumerate(schedule(waypoints_per_piece, steps)):
        if level:
            x = subdivide(x)
        t = subdivide_times(times, s)
        tb = np.broadcast_to(t, x.shape[:2])
        mob = mobility(tb, r)
        frac = chord_fraction(tb)
        eta = overshoot(level)
        for _ in range(n_steps):
            if level == 0:  # the waypoint pass: at the coarsest level (PHI_WAYPOINT)
                _clear(x, m, a, b, c, tgt, mob, eta, True, hold)
            _clear(x, m, a, b, c, tgt, mob, eta, False, hold)
            _shorten(x, m, a, b, c, tgt, frac, mob)
    for _ in range(final_steps(steps)):
        _clear(x, m, a, b, c, tgt, mob, eta, False, hold)
    return t, x


# --- the frame -------------------------------------------------------------------------------

def to_frame(raw: np.ndarray, target: np.ndarray):
    """The normalised frame of every raw path (B, K, P, d) and its targets (B, 2): ``(y, tgt,
    back)``. One rule for every query, no switch:

    1. ``z = raw 2**-e1``, e1 the exponent of the path's largest |coordinate| (``z`` depends
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


# --- the radii -------------------------------------------------------------------------------

def targets(radius: float, obstacle_radius: float, raw_clearance: np.ndarray) -> np.ndarray:
    """The target distances (B, 2): ``2 radius`` (robot-robot) and ``radius + obstacle_radius``
    (robot-obstacle), each replaced by ``KAPPA`` times the raw clearance when it is 0."""
    c = KAPPA * np.asarray(raw_clearance, dtype=float)
    rr = 2.0 * radius
    ro = radius + obstacle_radius
    return np.stack([c if rr == 0 else np.full(c.shape, rr),
                     c if ro == 0 else np.full(c.shape, ro)], axis=1)


def check_radii(obstacles: np.ndarray, configs: list, radius: float, obstacle_radius: float,
                batched: bool, backend=None) -> None:
    """Raise :class:`~pmplan.errors.CollisionError` (an InputError) if a configuration the path
    must pass through (start, goal, intermediate) violates the radii: two robots closer than
    ``2 radius`` or a robot closer than ``radius + obstacle_radius`` to an obstacle (exact)."""
    if radius == 0 and obstacle_radius == 0:
        return
    r = len(configs)
    names = ["start", *[f"configuration {k}" for k in range(2, r)], "goal"]
    m = obstacles.shape[1]
    full = np.concatenate([np.concatenate([obstacles, c], axis=1) for c in configs])
    wp = np.stack([full, full], axis=1)  # constant paths, (r B, 2, P, d)
    ok = None
    measured = None if backend is None else \
        backend.measure(wp, m, (2.0 * radius, radius + obstacle_radius))
    if measured is not None:  # the backend's measure; exact when close
        _, kept, close = measured
        if not close.any():
            ok = kept
    if ok is None:
        _, _, ok = radius_report(wp, m, radius, obstacle_radius)
    if ok.all():
        return
    k, i = divmod(int(np.flatnonzero(~ok)[0]), obstacles.shape[0])
    _raise_too_close(full[k * obstacles.shape[0] + i], m, radius, obstacle_radius, names[k],
                     i if batched else None)


def _raise_too_close(conf, m, radius, obstacle_radius, name, index) -> None:
    p = conf.shape[0]
    a, b, _ = pairs(p, m)
    label = [f"o{k + 1}" for k in range(m)] + [f"x{k + 1}" for k in range(p - m)]
    for pa, pb in zip(a, b):  # (check_radii's decision is exact: one pair is too close)
        need, value = (("2 * radius", 2 * Fraction(radius)) if pa >= m else
                       ("radius + obstacle_radius", Fraction(radius) + Fraction(obstacle_radius)))
        if exact_segment_dist2(conf[pa], conf[pb], conf[pa], conf[pb]) < value * value:
            break
    dist = exact_segment_clearance(conf[pa], conf[pb], conf[pa], conf[pb])
    pa, pb, value = label[pa], label[pb], float(value)
    where = f" in query {index}" if index is not None else ""
    raise CollisionError(
        _MSG_TOO_CLOSE.format(what=f"the {name} configuration" if name in ("start", "goal")
                              else name, pair=f"points {pa} and {pb}",
                              dist=dist, where=where, need=need, value=value),
        index=index, which=name, pair=(pa, pb))


# --- the stage: refine a batch chunk by chunk, certified ---------------------------------------

_MSG_FAILED = ("the refined path failed its certificate{where}: {what}; the query is too nearly "
               "degenerate for the refinement in double precision: use the unrefined plan "
               "(refine=False); nothing was returned")


class RefineStage(Stage):
    """The refinement of a batch of certified paths as a stage of the run loop
    (:func:`pmplan.running.run_stage`): per chunk, the kernel (:mod:`pmplan.kernels.refine`)
    or the numpy reference (:func:`refine_paths`), then the whole certificate (clauses 1-9 by
    :func:`pmplan.certify.check_paths`, the clearance by :func:`pmplan.certify.clearance` or the
    kernel's measurement in its arithmetic; never skipped) and the radii (:func:`radius_report`).

    Parameters
    ----------
    times : ndarray, shape (K,) or (B, K)
    waypoints : ndarray, shape (B, K, P, d)
        The certified raw paths (not modified).
    clearance : ndarray, shape (B,)
        Their clearance (the targets when a radius is 0, see :func:`targets`).
    m : int
        Obstacles (the first m points).
    fixed : sequence of int, length r
        The raw waypoints the path passes through its r configurations (start, intermediate
        ones at ``k / (r - 1)``, goal): :meth:`pmplan.planners.base.Planner.fixed_waypoints`.
        The refinement keeps them exactly (at refined waypoint ``fixed[k] * waypoints_per_piece``).
    radius, obstacle_radius : float
    waypoints_per_piece, steps : int
    backend : str or None
        ``"numpy"``: the reference; else the kernel.
    """

    chunk = 512
    label = "refining"

    def __init__(self, times, waypoints, clearance, m: int, fixed, radius: float,
                 obstacle_radius: float, waypoints_per_piece: int, steps: int, backend=None):
        self.raw_times = np.asarray(times, dtype=float)
        self.raw = waypoints
        self.size = waypoints.shape[0]
        self.fixed = [int(kj) for kj in fixed]
        self.m, self.r = m, len(self.fixed)
        self.radius, self.obstacle_radius = radius, obstacle_radius
        self.s, self.steps = waypoints_per_piece, steps
        self.backend = select(backend)
        self.target = targets(radius, obstacle_radius, clearance)
        k = self.raw_times.shape[-1]
        w = (k - 1) * self.s + 1
        b, _, p, d = waypoints.shape
        self.times = subdivide_times(self.raw_times, self.s)
        self.waypoints = np.empty((b, w, p, d))
        self.clearance = np.empty(b)
        self.robot_distance = np.empty(b)
        self.obstacle_distance = np.empty(b)
        self.respects = np.empty(b, dtype=bool)
        self.clause = np.zeros(b, np.uint8)

    def _refine(self, times, wp, target):
        """The map in the frame, by the backend (:func:`pmplan.backends.select`)."""
        return self.backend.refine(times, wp, self.m, self.r, target, self.s, self.steps)

    def run(self, lo: int, hi: int) -> np.ndarray:
        raw = self.raw[lo:hi]
        times = self.raw_times if self.raw_times.ndim == 1 else self.raw_times[lo:hi]
        y, tgt, back = to_frame(raw, self.target[lo:hi])
        out = self.waypoints[lo:hi]
        ref = self._refine(times, y, tgt)[1]
        out[...] = from_frame(ref, back)
        # the obstacles, and every raw waypoint the refinement left in place (the fixed
        # configurations, a padded row's repeated goal), exactly: the frame rounds them
        out[:, :, :self.m] = raw[:, :1, :self.m]
        same = (ref[:, ::self.s] == y).all(axis=-1)  # (B, K, P)
        out[:, ::self.s][same] = raw[same]
        for kj in self.fixed:
            out[:, kj * self.s] = raw[:, kj]
        self._certify(lo, hi, raw, out, np.zeros(hi - lo, dtype=bool))
        return self.clause[lo:hi] == 0

    def _certify(self, lo, hi, raw, out, exact) -> None:
        """The whole certificate of the refined rows (clauses 1-9 by
        :func:`pmplan.certify.check_paths`; the clearance, clause 10, and the radii by the
        kernel's measurement in the certificate's arithmetic, re-decided by
        :func:`pmplan.certify.clearance` and :func:`radius_report` where it flags a row --
        or by them alone)."""
        m, r = self.m, self.r
        tt = self.times if self.times.ndim == 1 else self.times[lo:hi]
        configs = [raw[:, kj] for kj in self.fixed]
        via = [(j / (r - 1), configs[j]) for j in range(1, r - 1)]
        with np.errstate(all="ignore"):
            clause = check_paths(tt, out, configs[0], configs[-1], m, via)
        clr = self.clearance[lo:hi]
        rd, od, ok = (self.robot_distance[lo:hi], self.obstacle_distance[lo:hi],
                      self.respects[lo:hi])
        measured = self.backend.measure(out, m, (2.0 * self.radius,
                                                 self.radius + self.obstacle_radius))
        if measured is not None:
            vals, kept, close = measured
            clr[:], rd[:], od[:] = vals[:, 0], vals[:, 1], vals[:, 2]
            ok[:] = kept
            redo = np.flatnonzero(exact | close)
        else:
            redo = np.arange(hi - lo)
        if redo.size:
            sub = out[redo]
            with np.errstate(all="ignore"):  # (clauses 1-9 are in ``clause`` already)
                clr[redo] = clearance(sub, m)
                rd[redo], od[redo], ok[redo] = radius_report(sub, m, self.radius,
                                                             self.obstacle_radius)
        clause[(clause == 0) & ~(clr > 0)] = CLEARANCE
        self.clause[lo:hi] = clause

    def fail(self, bad: np.ndarray) -> None:
        idx = np.flatnonzero(bad)
        where = f" for queries {idx[:10].tolist()}{'...' if idx.size > 10 else ''}" \
            if self.size > 1 else ""
        raise CertificationError(
            _MSG_FAILED.format(where=where, what=describe(int(self.clause[idx[0]]))),
            indices=idx)

    def extra(self) -> dict:
        """The refinement record of the batch (:attr:`pmplan.results.PlanBatch._extra`)."""
        b = self.size
        return {"radius": np.full(b, self.radius), "obstacle_radius": np.full(b, self.obstacle_radius),
                    "refined": np.ones(b, dtype=bool), "robot_distance": self.robot_distance,
                    "obstacle_distance": self.obstacle_distance, "respects_radius": self.respects}


def asks_refine(refine, radius, obstacle_radius, out=None) -> bool:
    """Whether a planning function was asked ``refine=True`` (the flag and the radii checked:
    :func:`pmplan.refine.check_refine_flag`; radii without the flag are refused, and so is
    ``out=`` with it: a refined batch has other shapes)."""
    if refine is False and type(radius) is float and type(obstacle_radius) is float \
            and radius == 0.0 and obstacle_radius == 0.0:
        return False
    if check_refine_flag(refine, radius, obstacle_radius):
        check_parameters(radius, obstacle_radius, None, None)
        if out is not None:
            raise InputError(MSG_REFINE_OUT)
        return True
    return False
