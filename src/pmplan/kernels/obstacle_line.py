"""Fused numba kernels: the obstacle-line planner and its certificate in one pass per query.

The numpy code of :mod:`pmplan.predicates`, :mod:`pmplan.frame`,
:mod:`pmplan.planners.obstacle_line` and :mod:`pmplan.certify` is the *reference*
implementation. The kernel :func:`plan_chunk` computes, for every query of a chunk and
without any temporary larger than a few rows, exactly what that reference computes:

* the exact column classes of every configuration (Mathematics §2): the float filter of
  :func:`pmplan.predicates.projection_classes` with the same rigorous error bound -- one bound
  per configuration (the maximum over its points), so that comparing *neighbours in the sorted
  order* suffices -- and its error-free second stage (TwoSum / TwoProduct) for the pairs the
  filter cannot decide; ``cp(C)``, ``cp_o``, ``eps(C)``;
* the frame ``e``, ``nu(e)`` (paper Section 3 for even d, Mathematics §4.1 for odd d with the exact
  ``e == N`` case) and ``lambda = lift + max_k |r(o_k)|`` (Mathematics §4.2), where ``lift`` is the
  unit, or for ``lift="scene"`` the obstacles' radius ``u(O) = max_k |o_k - o_1|`` of each query;
* the ``7 (r - 1) + 1`` waypoints of paper Remark 2.5 -- desingularization of paper (3.2),
  projection of paper (3.6) (for the compact lanes in d >= 3 keeping the robots' offsets,
  Mathematics §4.4), section of paper (3.8) -- written directly
  into the caller's output array (Mathematics §4.3 for r > 2);
* the certificate of Mathematics §6: endpoints, obstacles fixed, finiteness, and the clearance
  (closed-form minimum distance per piece and pair, as :func:`pmplan.certify.clearance`).

How the kernel is laid out for speed (every shortcut is exact, see the tests):

* a chunk is planned first by :func:`_plan_lanes`, which takes ``L`` (64) queries at a time
  with the lanes innermost, so that every loop is a vectorised loop over queries (AVX2: four
  at once) whatever (d, n, m, r) are. It decides the *generic* query -- every configuration in
  the top stratum, no pole, every minimum distance clearly positive: all of a random batch --
  with exactly the operations of the scalar kernel :func:`plan_queries`, and hands every other query
  to it (the scalar kernel also validates). Two layout rules matter for speed under numba: no
  array views in inner loops (each costs a reference count), and running minima kept in two
  alternating rows (a select written back into the row it reads becomes a masked store);
* the generic case of the column classes -- all projections pairwise farther apart than the
  filter bound -- is decided without sorting (then ``cp = m + n``, ``cp_o = m`` and the gap is
  the smallest pairwise difference, which rounding monotonicity makes the sorted neighbours'
  one); the stable sort (by ranks) and the error-free stage run only otherwise;
* the waypoints are gathered from one small vector of values through index tables
  (:func:`_build_tables`, built once per (r, m, n, d) and cached by :func:`tables`), written
  once, and *read back* for the certificate: the relative position of every pair at every
  waypoint is formed once from the written waypoints, and each piece takes two consecutive rows;
* the clearance is a branch-free pass over the pairs (vectorised); only when some squared
  minimum is small does the loop that decides as :func:`pmplan.certify.clearance` run. In the
  SIMD path in the plane, one loop takes a pair over a whole segment C_k -> C_k+1 (its
  stationary start and five moving pieces, :func:`_pair_plane`), forming the pair's relative
  position once per waypoint, with the running minimum in a register; from 16 points on
  (:data:`PRUNE_LANES`) every pair is first tested on float32 centres of its projections, for
  all lanes at once, and only the few that may reach the minimum are evaluated
  (:func:`_prune_plane`, exact).

Every floating-point operation is done in the reference's order -- sums over the d coordinates
are sequential, which is numpy's order below 8 terms, hence ``d <= MAX_D = 7`` (larger d is
planned by the numpy reference) -- and no fused multiply-add or fast-math reassociation is
allowed, so the waypoints and the clearance are **bitwise identical** to the reference (up to the
sign of zero coordinates, which ``==`` does not see).

What the kernel does not decide it *flags*, and the Python caller re-decides it with the exact
reference code:

``FALLBACK``
    a configuration needs the exact rational (``fractions.Fraction``) stage of
    ``projection_classes``: an undecided pair the error-free stage cannot settle, a run of
    undecided neighbours that is not all-equal, or a non-finite projection bound. The whole query
    is recomputed with the numpy reference. Also (only when asked to validate: the single-query
    paths) a coordinate beyond ``2**430``, where :mod:`pmplan.api` plans the query scaled by a
    power of two (:mod:`pmplan.magnitude`); nothing is computed.
``SUSPECT``
    a float minimum distance is below ``certify``'s threshold ``1e-9 * scale``, or the squared
    distance of two obstacles is below ``2**-1000`` (it may have underflowed): the clearance of
    the query is recomputed by :func:`pmplan.certify.clearance` (exact on that pair).
``NONFINITE``
    a waypoint is not finite: the certificate fails.
``BROKEN``
    endpoints, intermediate configurations or obstacle rows are not reproduced exactly (never
    expected: a safety net, the certificate fails).
``INVALID``
    (only when asked to validate) a coordinate is not finite or two points of a configuration
    coincide: nothing is computed, the caller's validation raises the error.

Numba compiles each kernel once for one signature (float64 C-contiguous arrays, always), and
caches the machine code on disk (``cache=True``).
"""

from __future__ import annotations

import math

import numpy as np

# the numba import, the flag bits, the thresholds and the shared primitives: one source
from .common import (
    DIRECT_AT,
    BIG,
    INLINE,
    MAXF,
    OBSTACLE_TINY2,
    OPTS,
    REL,
    SMALL,
    SURE,
    TINY,
    U,
    AVAILABLE,
    BROKEN,
    FALLBACK,
    INVALID,
    NONFINITE,
    SUSPECT,
    NoneType,
    read_lanes,
    segment_dist2_plane,
    segment_param,
    two_prod,
    two_sum,
    write_lanes,
    njit,
    overload,
)

__all__ = [
    "AVAILABLE",
    "BROKEN",
    "FALLBACK",
    "INVALID",
    "LANES_MIN",
    "MAX_D",
    "NONFINITE",
    "SUSPECT",
    "lanes",
    "plan_chunk",
    "plan_one",
    "tables",
]

#: numpy sums fewer than 8 terms sequentially (pairwise, with 8 accumulators, from 8 on): the
#: kernel reproduces the sequential order, so it handles d <= 7; larger d uses the reference
MAX_D = 7

#: (validating) a coordinate beyond this is flagged FALLBACK: such queries are planned scaled
#: by a power of two (2**pmplan.magnitude.LIMIT)
_EXTREME = 2.0**430


#: chunks smaller than this are planned query by query (:func:`plan_queries`), larger ones mostly
#: ``lanes(...)`` queries at a time (:func:`_plan_lanes`)
LANES_MIN = 16

#: from this many points (m + n) on, in the plane and in space, the clearance is the exact
#: pruned sweep of :func:`_sweep_min` (query by query; in :func:`_plan_lanes` lane by lane,
#: in the plane only from PRUNE_LANES[1] on);
#: below it every pair is evaluated, vectorised (over the pairs, or over the lanes). Measured
#: with ``benchmarks/cert_bench.py`` (one core, ratio to a copy of the output, brute / sweep):
#: (2,22,2) 6.9-12.2 / 9.9-14.0, (2,40,2) 11.5-14.2 / 10.8-12.3, (3,30,2) 11.6-15.0 / 9.3-10.7
SWEEP_MIN = (40, 24)
#: in the plane, the SIMD path (:func:`_certify_lanes`) prunes the pairs exactly without
#: sorting (:func:`_prune_plane`) for PRUNE_LANES[0] <= m + n < PRUNE_LANES[1] (below it every
#: pair is evaluated, from PRUNE_LANES[1] on the sweep runs lane by lane).
#: Where the time went before (issue 17; the kernel alone, CPU time, one process, with one
#: part removed at a time, B = 32,768 / 8,192, at 2e4589d): (2,16,2) 1.26 us per query -- the
#: brute-force pairs of the certificate 0.61 (48 %), writing the waypoints out lane by lane
#: 0.33 (26 %), the class test's pairs 0.04, the rest (configurations, frame, waypoints,
#: finiteness) 0.28; plan_batch adds about 6 % of per-chunk Python (magnitude check,
#: re-decision). (2,64,2) 7.3 us -- the sweep lane by lane with its gather of the lane 3.8
#: (51 %), the class test 0.73, the write-out 0.67. With the pruning (and the write-out eight
#: lanes at a time): (2,16,2) 0.83-0.98 us (certificate 0.31), (2,64,2) 3.5-3.9 us
#: (certificate 1.1-1.2). Tiling the lanes of the test for the first-level cache was slower
#: (+4 to +30 %), a guess of 1.05 instead of 1.25 times the gap no faster (1-2 %). The compact
#: lanes' direct lift made the gap a poor guess (about 40 % of lanes below their minimum, 16
#: pairs per lane); their guess is _guess_plane's estimate (about 3 pairs per lane; cert_bench,
#: alternating processes: (2,16,2) 0.93-1.0 us against 1.10-1.17, (2,30,2) 1.84-1.93 against
#: 2.0-2.3, (2,46,2) within the noise; its start side alone, (2,64,2) 4.1-4.2 against 4.6-4.7).
PRUNE_LANES = (16, 128)
#: the margins of the sweep's pruning, relative to the largest |coordinate| (see _sweep_min):
#: the distance of the closed form's float point to an exact point of the piece, a float
#: projection's error per coordinate, and a relative slack for every other rounding
_PRUNE_Q = 1e-14
_PRUNE_P = 1e-15
_PRUNE_REL = 1e-9
#: an offset below this times the largest |coordinate| is rounding (the paper's projection puts
#: every robot on the obstacle line): no direction of the offsets is taken from it (it would
#: prune nothing and cost its projections)
_OFFSET_MIN = 1e-9


@njit(**INLINE)
def _unit(w, n, out):  # pragma: no cover - compiled
    """``pmplan.frame.unit`` on ``w[:n]`` into ``out[:n]``."""
    scale = 0.0
    for c in range(n):
        a = abs(w[c])
        if a > scale:  # noqa: PLR1730 (explicit compare: NaN is never selected)
            scale = a
    ss = 0.0
    for c in range(n):
        x = w[c] / scale if scale > 0 else 0.0
        out[c] = x
        ss += x * x
    nn = math.sqrt(ss)
    for c in range(n):
        out[c] = out[c] / nn if nn > 0 else 0.0


@njit(**INLINE)
def _exact_sign(y, k, ia, ib, d):  # pragma: no cover - compiled
    """Stage 2 of ``predicates.exact_projection_difference_sign`` for points ia, ib of
    configuration ``y[k]`` (rows 0, 1 are o1, o2): returns (decided, sign of (y_a - y_b).w)."""
    ok = True
    s = 0.0
    for c in range(d):
        t, et = two_sum(y[k, ia, c], -y[k, ib, c])
        w, ew = two_sum(y[k, 1, c], -y[k, 0, c])
        p, ep = two_prod(t, w)
        if et != 0.0 or ew != 0.0 or ep != 0.0:
            ok = False
        if not (abs(t) < BIG and abs(w) < BIG and math.isfinite(p)):
            ok = False
        # TwoProduct is error-free only without underflow: an exact zero (a zero factor) or a
        # product whose error term is a normal number
        if not ((p == 0 and (t == 0 or w == 0)) or abs(p) >= SMALL):
            ok = False
        if c == 0:
            s = p
        else:
            s, es = two_sum(s, p)
            if es != 0.0:
                ok = False
    if not math.isfinite(s):
        ok = False
    return ok, (s > 0) - (s < 0)


@njit(**INLINE)
def _classes(y, k, p, m, d, w, vals, order, lab):  # pragma: no cover - compiled
    """Exact column classes of configuration ``y[k]`` (p points, obstacles first).

    Same semantics as :func:`pmplan.predicates.projection_classes`: float projections
    ``(y - o1).w`` with one error bound per configuration (the max over its points), stable
    sort, neighbours farther apart than the bound are distinct, the others are decided by the
    error-free stage (and must not be misordered). Returns ``(decided, cp, cp_o, gap,
    labelled)``; ``decided`` is False where the reference would need its exact rational stage
    (or its full exact pass); ``labelled`` is False in the generic case, every projection
    farther than the bound from every other (then ``lab`` is not written, and the float order
    of ``vals`` is the exact order), True where ``lab`` holds the exact classes.
    """
    absum = 0.0
    finite = True
    for i in range(p):
        v = 0.0
        a = 0.0
        for c in range(d):
            t = (y[k, i, c] - y[k, 0, c]) * w[c]
            v += t
            a += abs(t)
        vals[i] = v
        if not math.isfinite(v):
            finite = False
        if not a <= absum:
            absum = a
    bound = (d + 2) * 1.01 * U * absum + (d + 1) * TINY
    if not (finite and math.isfinite(bound)):
        return False, 0, 0, 0.0, False
    thr = 2.0 * (2.0 * bound) * (1 + 4 * U)
    # all projections pairwise farther apart than thr (the generic case): every point is its
    # own column, and the smallest gap between neighbours in the sorted order is the smallest
    # |vals[i] - vals[j]| (rounding is monotone, so no non-neighbour difference is smaller)
    mind = np.inf
    for i in range(1, p):
        vi = vals[i]
        for j in range(i):
            df = abs(vi - vals[j])
            mind = df if df < mind else mind  # noqa: FURB136 (branch-free, as below)
    if mind > thr:
        return True, p, m, mind, False
    # stable argsort (numpy's argsort(kind="stable") order) by ranks, branch-free: the rank of
    # point i is the number of points before it (smaller value, or equal value and index)
    for i in range(p):
        rk = 0
        vi = vals[i]
        for j in range(p):
            vj = vals[j]
            rk += (vj < vi) | ((vj == vi) & (j < i))
        order[rk] = i
    label = 0
    lab[order[0]] = 0
    gap = np.inf
    prev_unc = False
    prev_eq = False
    for i in range(p - 1):
        diff = vals[order[i + 1]] - vals[order[i]]
        unc = not (diff > thr)
        eq = False
        if unc:
            ok, sgn = _exact_sign(y, k, order[i], order[i + 1], d)
            if not ok:
                return False, 0, 0, 0.0, False
            eq = sgn == 0
            # a run of >= 2 undecided neighbours with an unequal pair, or a pair the float sort
            # put in the wrong order, needs the full exact pass
            if sgn > 0 or (prev_unc and not (prev_eq and eq)):
                return False, 0, 0, 0.0, False
        if not eq:
            label += 1
            if diff < gap:  # noqa: PLR1730 (explicit compare: NaN is never selected)
                gap = diff
        lab[order[i + 1]] = label
        prev_unc = unc
        prev_eq = eq
    cp_o = 0
    for i in range(m):
        new = True
        for j in range(i):
            if lab[j] == lab[i]:
                new = False
        if new:
            cp_o += 1
    return True, label + 1, cp_o, gap, True


@njit(**INLINE)
def _before(kv, k, a, b):  # pragma: no cover - compiled
    """Whether robot ``a`` is before robot ``b`` in ``H(C_k, 1)``: by the key ``kv[k]`` (the
    exact class, or the projection where every one is its own), then by index (paper (3.2)
    moves robot j by j eps)."""
    return (kv[k, a] < kv[k, b]) | ((kv[k, a] == kv[k, b]) & (a < b))


@njit(**INLINE)
def _lane_chains(kv, r, n, order, lane, tail, sides):  # pragma: no cover - compiled
    """``lane[j]``: robot j's lane on its side, 1, 2, ...
    (:func:`pmplan.planners.obstacle_line.lane_chains` with ``sides`` 2, the odd robots and
    the even ones apart, or 1, every robot on one side: the robots of a side in the order of
    ``H(C_1, 1)``, ``order`` (a permutation, :func:`_bucket_sort`'s), each in the first chain
    whose last robot is before it in every ``H(C_k, 1)``). For r = 2 the chains' last robots
    are in decreasing order in ``H(C_2, 1)`` (a robot opens a chain only when it is before every
    last one, and replaces the first last one before it), so the first chain is found by
    bisection."""
    for side in range(sides):
        nch = 0
        for t in range(n):
            x = order[t]
            if sides == 2 and x % 2 != side:
                continue
            if r == 2:
                lo = 0
                hi = nch
                while lo < hi:
                    mid = (lo + hi) // 2
                    if _before(kv, 1, tail[mid], x):
                        hi = mid
                    else:
                        lo = mid + 1
                pick = lo
            else:
                pick = nch
                for c in range(nch):
                    ok = True
                    for k in range(1, r):
                        if not _before(kv, k, tail[c], x):
                            ok = False
                    if ok:
                        pick = c
                        break
            lane[x] = pick + 1
            tail[pick] = x
            if pick == nch:
                nch += 1


@njit(**INLINE)
def _row_min(best, npairs):  # pragma: no cover - compiled
    """The minimum of ``best[:npairs]`` (NaN is never selected)."""
    out = np.inf
    for k in range(npairs):
        if best[k] < out:  # noqa: PLR1730 (explicit compare: NaN is never selected)
            out = best[k]
    return out


@njit(**INLINE)
def _clearance_plane(dd, kk, npairs, best):  # pragma: no cover - compiled
    """Squared clearance in the plane (d = 2), branch-free over the pairs (vectorised).

    ``dd[t, c, k]`` is coordinate c of the relative position of pair k at waypoint t; the
    arithmetic is :func:`pmplan.certify.segment_clearance`'s, in its order, on every piece.
    Returns the minimum float squared distance; ``best`` is scratch (npairs,).
    """
    best[:npairs] = np.inf
    for t in range(kk - 1):
        for k in range(npairs):
            dist2 = segment_dist2_plane(dd[t, 0, k], dd[t, 1, k], dd[t + 1, 0, k],
                                         dd[t + 1, 1, k])
            best[k] = dist2 if dist2 < best[k] else best[k]  # noqa: FURB136
    return _row_min(best, npairs)


@njit(**INLINE)
def _clearance_any(dd, kk, npairs, d, best, vv, rv, tt, d2):  # pragma: no cover - compiled
    """:func:`_clearance_plane` for any d (coordinate loops outside the pair loops)."""
    best[:npairs] = np.inf
    for t in range(kk - 1):
        for k in range(npairs):
            vv[k] = 0.0
            rv[k] = 0.0
        for c in range(d):
            for k in range(npairs):
                r0 = dd[t, c, k]
                vc = dd[t + 1, c, k] - r0
                vv[k] += vc * vc
                rv[k] += r0 * vc
        for k in range(npairs):
            tt[k] = segment_param(-rv[k], vv[k])
            d2[k] = 0.0
        for c in range(d):
            for k in range(npairs):
                r0 = dd[t, c, k]
                vc = dd[t + 1, c, k] - r0
                qc = r0 + tt[k] * vc
                d2[k] += qc * qc
        for k in range(npairs):
            best[k] = d2[k] if d2[k] < best[k] else best[k]  # noqa: FURB136
    return _row_min(best, npairs)


@njit(**INLINE)
def _piece_dist2(w, t0, a, b, row, d):  # pragma: no cover - compiled
    """Float squared minimum distance of the points at offsets ``a`` < ``b`` of waypoint
    block ``t0`` of ``w`` over the piece to the next waypoint (``t0 + row``): the arithmetic of
    :func:`_clearance_any` (and of :func:`segment_dist2_plane` for d = 2) on the relative
    position ``w[t0 + a + c] - w[t0 + b + c]``, sums over c sequential."""
    vv = 0.0
    rv = 0.0
    for c in range(d):
        r0 = w[t0 + a + c] - w[t0 + b + c]
        vc = (w[t0 + row + a + c] - w[t0 + row + b + c]) - r0
        vv += vc * vc
        rv += r0 * vc
    q = segment_param(-rv, vv)
    dist2 = 0.0
    for c in range(d):
        r0 = w[t0 + a + c] - w[t0 + b + c]
        qc = r0 + q * ((w[t0 + row + a + c] - w[t0 + row + b + c]) - r0)
        dist2 += qc * qc
    return dist2


@njit(**INLINE)
def _directions(w, p, m, d, amax, aux):  # pragma: no cover - compiled
    """The two sweep directions of :func:`_sweep_min` and their pruning margins, into ``aux``.

    Direction 0 is the obstacle line ``o2 - o1`` (the columns: the projection, the lift and
    their inverses move the points across it, not along it), direction 1 the lift of robot 0
    (waypoint 3 minus waypoint 2: along the line the robots are lifted apart in it). Each is
    scaled to largest |component| 1 (a coordinate axis if it is zero or not finite: any
    direction gives a correct bound, these only make it tight). ``aux[2 d + k]`` is the norm of
    direction k, ``aux[2 d + 2 + k]`` its margin ``_PRUNE_Q amax |w| + 2 _PRUNE_P d amax |w|_1``
    (see :func:`_sweep_min`)."""
    row = p * d
    for c in range(d):
        aux[c] = w[d + c] - w[c]
        aux[d + c] = w[3 * row + m * d + c] - w[2 * row + m * d + c]
    for k in range(2):
        big = 0.0
        for c in range(d):
            a = abs(aux[k * d + c])
            big = a if a > big else big  # noqa: FURB136
        aux[2 * d + k], aux[2 * d + 2 + k] = _scaled(aux, k * d, d, amax, big,
                                                     big > 0 and big <= MAXF)


@njit(**INLINE)
def _scaled(aux, at, d, amax, big, ok):  # pragma: no cover - compiled
    """A direction of :func:`_sweep_min`: ``aux[at : at + d]`` divided by ``big``, its largest
    |component| (with ``ok`` False: the first coordinate axis instead); returns its norm and
    its pruning margin ``_PRUNE_Q amax |u| + 2 _PRUNE_P d amax |u|_1`` (see :func:`_sweep_min`)."""
    w1 = 0.0
    w2 = 0.0
    for c in range(d):
        x = aux[at + c] / big if ok else (1.0 if c == 0 else 0.0)
        aux[at + c] = x
        w1 += abs(x)
        w2 += x * x
    w2 = math.sqrt(w2)
    return w2, _PRUNE_Q * amax * w2 + 2.0 * _PRUNE_P * d * amax * w1 + 1e-300


@njit(**OPTS)
def _sweep_sizes(p, d):  # pragma: no cover - compiled
    """The sizes of the scratch ``lo`` (and ``hi``) and ``aux`` of :func:`_sweep_min` for p
    points in dimension d (:func:`_offset_direction`'s included)."""
    return 2 * p, 5 * d + 6


@njit(**OPTS)
def _offset_direction(w, p, m, d, amax, aux):  # pragma: no cover - compiled
    """The direction of the robots' offsets of :func:`_sweep_min` in space, after the two of
    :func:`_directions` in ``aux``: at ``aux[2 d + 4 : 3 d + 4]``, its norm at ``aux[3 d + 4]``
    and its margin at ``aux[3 d + 5]`` (as :func:`_directions`); ``aux[3 d + 6 : 5 d + 6]`` is
    scratch. Returns whether there is one.

    The compact lanes keep every robot's offset from the obstacle line, the part of its
    position orthogonal to the line and to ``nu`` (Mathematics §4.4): during the projection, the
    lift, the slide and their inverses a robot moves in the plane of ``e`` and ``nu``, so its
    offset is fixed there, and robots whose columns are close are apart along it. The direction
    is the largest offset at waypoint 2 (a robot's position minus ``o1``, its parts along the
    two directions of :func:`_directions` removed in floating point): any direction gives a
    correct bound, this one makes it tight. None in the plane, or where every offset is below
    ``_OFFSET_MIN amax`` (the paper's projection).

    One direction, though the offsets span d - 2: each costs a projection of every point in
    every group, what the sweep mostly spends. The sweep alone in a compiled loop over 2,000
    generic paths of the compact lanes (d, n, 2), us per path, two runs, one direction / d - 2
    of them / none: (4,30) 9.2-11.5 / 13.8-14.1 / 14.5-16.2, (7,24) 30.3-30.6 / 37.6 /
    50.0-51.9; (3,64) 11.7 / - / 10.8-12.3 (the pieces it saves, 187-574 to 4-22 on seeds
    4-8, cost about what its projections do there)."""
    if d < 3:
        return False
    fb = 2 * d + 4
    eh = 3 * d + 6  # unit vectors along the line and along the lift (its part off the line)
    nh = 4 * d + 6
    e2 = 0.0
    for c in range(d):
        e2 += aux[c] * aux[c]
    if not (e2 > 0 and e2 < np.inf):
        return False
    e1 = math.sqrt(e2)
    for c in range(d):
        aux[eh + c] = aux[c] / e1
    ed = 0.0
    for c in range(d):
        ed += aux[d + c] * aux[eh + c]
    n2 = 0.0
    for c in range(d):
        x = aux[d + c] - ed * aux[eh + c]
        aux[nh + c] = x
        n2 += x * x
    if not (n2 > 0 and n2 < np.inf):
        return False
    n1 = math.sqrt(n2)
    for c in range(d):
        aux[nh + c] /= n1
    row = p * d
    big = 0.0
    pick = -1
    for i in range(m, p):
        s2 = _offset(w, 2 * row + i * d, d, aux, eh, nh, fb)
        if s2 > big and s2 < np.inf:
            big = s2
            pick = i
    if pick < 0 or not big > (_OFFSET_MIN * amax) ** 2:
        return False
    _offset(w, 2 * row + pick * d, d, aux, eh, nh, fb)
    top = 0.0
    for c in range(d):
        a = abs(aux[fb + c])
        top = a if a > top else top  # noqa: FURB136
    aux[3 * d + 4], aux[3 * d + 5] = _scaled(aux, fb, d, amax, top, True)
    return True


@njit(**OPTS)
def _offset(w, at, d, aux, eh, nh, fb):  # pragma: no cover - compiled
    """Point ``w[at : at + d]`` minus ``o1`` without its parts along the unit vectors at
    ``eh`` and ``nh``, into ``aux[fb : fb + d]``; returns its squared norm (of the components:
    a difference of squares would keep the rounding of the parts removed)."""
    for c in range(d):
        aux[fb + c] = w[at + c] - w[c]
    for u in (eh, nh):
        dot = 0.0
        for c in range(d):
            dot += (w[at + c] - w[c]) * aux[u + c]
        for c in range(d):
            aux[fb + c] -= dot * aux[u + c]
    s2 = 0.0
    for c in range(d):
        s2 += aux[fb + c] * aux[fb + c]
    return s2


@njit(**INLINE)
def _sort_by(key, order, p):  # pragma: no cover - compiled
    """Insertion sort of ``order[:p]`` by ``key`` (ascending; fast when nearly sorted)."""
    for x in range(1, p):
        v = order[x]
        kv = key[v]
        y = x - 1
        while y >= 0 and key[order[y]] > kv:
            order[y + 1] = order[y]
            y -= 1
        order[y + 1] = v


@njit(**INLINE)
def _bucket_sort(key, order, p, bk, cnt):  # pragma: no cover - compiled
    """``order[:p]`` = the indices sorted by ``key`` (finite), in O(p) for spread keys: a
    counting sort into p buckets of equal width, then :func:`_sort_by` (which alone makes it
    correct). ``bk`` (p,), ``cnt`` (p + 1,) int64 scratch."""
    kmin = key[0]
    kmax = key[0]
    for i in range(1, p):
        kmin = key[i] if key[i] < kmin else kmin  # noqa: FURB136
        kmax = key[i] if key[i] > kmax else kmax  # noqa: FURB136
    span = kmax - kmin
    scale = (p - 1) / span if span > 0 else 0.0
    cnt[:] = 0
    for i in range(p):
        x = int((key[i] - kmin) * scale)
        x = min(max(x, 0), p - 1)
        bk[i] = x
        cnt[x + 1] += 1
    for x in range(p):
        cnt[x + 1] += cnt[x]
    for i in range(p):
        x = bk[i]
        order[cnt[x]] = i
        cnt[x] += 1
    _sort_by(key, order, p)


@njit(**OPTS)
def _sweep_min(w, kk, p, m, d, amax, lo, hi, order, aux, cap):  # pragma: no cover - compiled
    """The clearance's minimum over the pieces and pairs, pruned exactly: a sweep per group.

    ``w`` (kk p d,) are the waypoints of one obstacle-line path (obstacles first; kk = 7 (r - 1)
    + 1), ``amax`` their largest |coordinate|, in ``(1e-130, 1e130)`` (the caller's range: no
    square overflows, no margin underflows). Returns exactly the minimum over every piece and
    every pair with a moving point of the float squared distance :func:`_piece_dist2` (the
    arithmetic of :func:`pmplan.certify.segment_clearance`), computing it only for the pairs
    that may reach the minimum found so far. Scratch: ``lo``, ``hi``, ``order`` int64 (4 p +
    1,) and ``aux`` of the sizes :func:`_sweep_sizes` gives. With ``cap`` finite, every pair
    that may be at most ``cap`` is computed too, and decided as :func:`_clearance_exact`
    decides it: returns ``(minimum, suspect)``, ``suspect`` True when some float minimum at
    most ``cap`` is not above certify's threshold (``cap = -inf``: only the minimum).

    The pieces of a leg C_k -> C_k+1 come in three groups: 7k -> 7k + 3 (desingularization,
    projection onto the obstacle line, lift: the points move across the line's direction u0,
    not along it), 7k + 3 -> 7k + 4 (along the line, the robots lifted apart along the lift's
    direction u1) and 7k + 4 -> 7k + 7 (as the first, at C_k+1's columns) (:func:`_directions`).
    In a group, every point's projection on its direction spans ``[lo, hi]`` over the group's
    waypoints; the points are sorted by ``lo`` (:func:`_bucket_sort` at a new configuration's
    columns, otherwise the previous order fixed by :func:`_sort_by`), and for each point the
    later ones are visited until the gap ``lo_b - hi_a`` exceeds
    ``(sqrt(best) |u| + margin) (1 + _PRUNE_REL)``: every later point is at least that far along
    u on all the group's pieces, and its float distance is above ``best``. In space a visited
    pair is skipped too where the same holds along the direction of the robots' offsets
    (:func:`_offset_direction`; spans ``[lo[p + i], hi[p + i]]``): the compact lanes keep them
    apart there, however close their columns.

    Why the margin is rigorous (``eps = 2**-53``): a float projection is within
    ``1.0001 d eps amax |u|_1`` of the exact one (``_PRUNE_P d amax |u|_1``, ``_PRUNE_P = 1e-15``,
    covers it 9 times), so the exact gap of the moving points along u, hence their exact
    distance times |u|, is above ``(sqrt(best) + _PRUNE_Q amax) |u| (1 + _PRUNE_REL) / (1 + 9
    eps)``; the float vector ``q`` of the closed form is within ``17 sqrt(d) eps amax < 5e-15
    amax`` (d <= 7) of an exact point of the piece, so ``|q| > sqrt(best) (1 + _PRUNE_REL - 10
    eps)``, and the float sum of its squares is at least ``|q|^2 (1 - eps)^d > best``. A pair
    skipped is never below the minimum: the result is bitwise the unpruned one.

    ``best`` starts as the float distance on the piece 1 -> 2 of the neighbours in the first
    group's order closest at waypoint 2, where the robots lie on the obstacle line (the compact
    lanes in d >= 3: in its hyperplane orthogonal to ``nu``) and the columns' gaps make it
    small.
    """
    row = p * d
    _directions(w, p, m, d, amax, aux)
    off = _offset_direction(w, p, m, d, amax, aux)  # (in space: the offsets prune too)
    nf = aux[3 * d + 4]
    mf = np.inf
    suspect = False
    oe = order[:p]
    on = order[p:2 * p]
    bk = order[2 * p:3 * p]
    cnt = order[3 * p:]
    best = np.inf
    for g in range(3 * ((kk - 1) // 7)):
        k = g // 3
        u = g % 3 == 1
        ts = 7 * k + (0 if g % 3 == 0 else (3 if u else 4))
        te = ts + (1 if u else 3)  # the group's pieces: ts -> ts + 1, ..., te - 1 -> te
        o = on if u else oe
        dr = d if u else 0
        ok = _spans(w, ts, te, p, d, aux, dr, lo, hi, 0)
        if g < 2 or g % 3 == 2:  # C_0's columns, the first lift, C_k+1's columns
            _bucket_sort(lo, o, p, bk, cnt)
        else:
            _sort_by(lo, o, p)
        wn = aux[2 * d + int(u)]
        mg = aux[2 * d + 2 + int(u)]
        if not ok:  # (never with amax in range)
            mg = np.inf  # every pair of the group is visited
        if off:
            mf = _offset_spans(w, ts, te, p, d, aux, lo, hi)
        if g == 0:  # the seed
            near = np.inf
            ia = 0
            ib = 0
            for x in range(p - 1):
                a = min(o[x], o[x + 1])
                b = max(o[x], o[x + 1])
                s2 = 0.0
                for c in range(d):
                    rc = w[2 * row + a * d + c] - w[2 * row + b * d + c]
                    s2 += rc * rc
                if b >= m and s2 < near:
                    near = s2
                    ia = a * d
                    ib = b * d
            if ib:
                best = _piece_dist2(w, row, ia, ib, row, d)
        reach = math.sqrt(max(best, cap))
        thr = (reach * wn + mg) * (1.0 + _PRUNE_REL)
        thf = (reach * nf + mf) * (1.0 + _PRUNE_REL)
        for x in range(p - 1):
            a = o[x]
            ha = hi[a]
            for y in range(x + 1, p):
                b = o[y]
                if lo[b] - ha > thr:
                    break
                if a < m and b < m:
                    continue
                if off and (lo[p + b] - hi[p + a] > thf or lo[p + a] - hi[p + b] > thf):
                    continue
                ia = min(a, b) * d
                ib = max(a, b) * d
                for t in range(ts, te):
                    dist2 = _piece_dist2(w, t * row, ia, ib, row, d)
                    if dist2 <= cap:
                        suspect |= _suspect(w, t * row, ia, ib, row, d, dist2)
                    if dist2 < best:
                        best = dist2
                        reach = math.sqrt(max(best, cap))
                        thr = (reach * wn + mg) * (1.0 + _PRUNE_REL)
                        thf = (reach * nf + mf) * (1.0 + _PRUNE_REL)
    return best, suspect


@njit(**INLINE)
def _spans(w, ts, te, p, d, aux, f, lo, hi, at):  # pragma: no cover - compiled
    """For :func:`_sweep_min`: every point's span along the direction ``aux[f : f + d]`` over
    the waypoints ts..te, into ``lo[at : at + p]`` and ``hi[at : at + p]`` (NaN: lo > hi);
    returns whether every ``|lo| + |hi|`` is at most MAXF (False for NaN: the margins hold)."""
    row = p * d
    ok = True
    for i in range(p):
        a0 = np.inf
        a1 = -np.inf
        for t in range(ts, te + 1):
            v = 0.0
            for c in range(d):
                v += w[t * row + i * d + c] * aux[f + c]
            a0 = v if v < a0 else a0  # noqa: FURB136 (NaN: then a0 > a1)
            a1 = v if v > a1 else a1  # noqa: FURB136
        lo[at + i] = a0
        hi[at + i] = a1
        ok &= abs(a0) + abs(a1) <= MAXF
    return ok


@njit(**OPTS)
def _offset_spans(w, ts, te, p, d, aux, lo, hi):  # pragma: no cover - compiled
    """For :func:`_sweep_min`: every point's span along the direction of the offsets
    (:func:`_offset_direction`) over the waypoints ts..te, into ``lo[p:]``/``hi[p:]``; returns
    the direction's margin (infinite where a span is not finite or too large: it prunes
    nothing)."""
    return aux[3 * d + 5] if _spans(w, ts, te, p, d, aux, 2 * d + 4, lo, hi, p) else np.inf


@njit(**INLINE)
def _suspect(w, t0, a, b, row, d, dist2):  # pragma: no cover - compiled
    """Whether the float minimum ``dist2`` of the pair at offsets a, b on the piece from
    waypoint block ``t0`` is not above certify's threshold ``1e-9 max(scale, 1e-6 absval)``
    (then :func:`pmplan.certify.clearance` decides it exactly)."""
    scale = 0.0
    absval = 0.0
    for c in range(d):
        r0 = w[t0 + a + c] - w[t0 + b + c]
        r1 = w[t0 + row + a + c] - w[t0 + row + b + c]
        scale = max(scale, abs(r0), abs(r1))
        absval = max(absval, abs(w[t0 + a + c]), abs(w[t0 + b + c]),
                     abs(w[t0 + row + a + c]), abs(w[t0 + row + b + c]))
    return not math.sqrt(dist2) > REL * max(scale, absval * 1e-6)


@njit(**INLINE)
def _clearance_exact(wf, b, kk, p, m, d, thr2):  # pragma: no cover - compiled
    """The clearance loop deciding small minima as :func:`pmplan.certify.clearance` does.

    Every piece and pair with a moving point of the waypoints ``wf[b]``. Returns ``(min
    squared distance, suspect)``: ``suspect`` is True when some pair's float minimum is not
    above certify's threshold ``1e-9 max(scale, 1e-6 absval)``.
    """
    row = p * d
    w = wf[b]
    best = np.inf
    suspect = False
    for t in range(kk - 1):
        t0 = t * row
        for i in range(p - 1):
            for j in range(max(i + 1, m), p):
                dist2 = _piece_dist2(w, t0, i * d, j * d, row, d)
                if not dist2 > thr2:
                    suspect |= _suspect(w, t0, i * d, j * d, row, d, dist2)
                if dist2 < best:  # noqa: PLR1730 (explicit compare: NaN is never selected)
                    best = dist2
    return best, suspect


@njit(**OPTS)
def _certify_one(wf, b, ddf, dd, ia, ja, kk, p, m, d, npairs, amax, best_k, vv, rv, tt,
                 d2):  # pragma: no cover - compiled
    """The clearance of query ``b`` of :func:`plan_queries` from its waypoints ``wf[b]`` (Mathematics §6).

    ``amax`` is the largest |coordinate| of the waypoints (finite); ``ddf``/``dd`` and
    ``best_k``, ``vv``, ``rv``, ``tt``, ``d2`` are scratch, ``ia``, ``ja`` the index tables
    (empty from ``SWEEP_MIN`` points on: then the pruned sweep :func:`_sweep_min`). Returns
    ``(clearance, flags)``: flags is ``SUSPECT`` where :func:`pmplan.certify.clearance` must
    re-decide the query, else 0.
    """
    fl = 0
    # A float squared distance above thr2 is certainly above certify's suspect threshold
    # 1e-9 max(scale, 1e-6 absval) <= 2.0000001e-9 amax; below it, decide as certify does.
    # (outside that range every minimum is decided as certify does)
    best = 0.0
    thr2 = np.inf
    if 1e-130 < amax < 1e130:
        thr2 = (SURE * amax) * (SURE * amax)
        # a fast pass; if some minimum is small, the exact loop decides as certify
        if _sweeps(p, d):
            nlo, naux = _sweep_sizes(p, d)
            lo = np.empty(nlo)
            hi = np.empty(nlo)
            order = np.empty(4 * p + 1, np.int64)
            aux = np.empty(naux)
            best, _ = _sweep_min(wf[b], kk, p, m, d, amax, lo, hi, order, aux, -np.inf)
            if not best > thr2:  # the pairs that may be below thr2, as _clearance_exact
                best, suspect = _sweep_min(wf[b], kk, p, m, d, amax, lo, hi, order, aux, thr2)
                fl |= SUSPECT if suspect else 0
                thr2 = -1.0  # (decided)
        else:
            for x in range(ddf.shape[0]):
                ddf[x] = wf[b, ia[x]] - wf[b, ja[x]]
            if d == 2:
                best = _clearance_plane(dd, kk, npairs, best_k)
            else:
                best = _clearance_any(dd, kk, npairs, d, best_k, vv, rv, tt, d2)
    if not best > thr2:
        best, suspect = _clearance_exact(wf, b, kk, p, m, d, thr2)
        if suspect:
            fl |= SUSPECT
    for i in range(m):
        for j in range(i + 1, m):
            dist2 = 0.0
            for c in range(d):
                dc = wf[b, i * d + c] - wf[b, j * d + c]
                dist2 += dc * dc
            if not dist2 >= OBSTACLE_TINY2:  # the square may have underflowed
                fl |= SUSPECT
            if dist2 < best:  # noqa: PLR1730 (explicit compare: NaN is never selected)
                best = dist2
    return math.sqrt(best), fl


@njit(**INLINE)
def _sweeps(p, d):  # pragma: no cover - compiled
    """Whether the clearance of p points in dimension d is the sweep (:data:`SWEEP_MIN`)."""
    return p >= (SWEEP_MIN[0] if d == 2 else SWEEP_MIN[1])


@njit(**INLINE)
def _brute_pairs(p, m, d):  # pragma: no cover - compiled
    """The number of pairs with a moving point that the tables list for the brute-force
    passes over the pairs (0 where the sweep needs none, :func:`_sweeps`)."""
    return 0 if _sweeps(p, d) else (p * (p - 1)) // 2 - (m * (m - 1)) // 2


def _build_tables(r, m, n, d):
    """The index tables of :func:`plan_queries` for queries through r configurations of (d, n, m).

    One int64 vector: ``g1, g2, add`` (size ``K (m + n) d`` each: waypoint element x is
    ``src[g1[x]]``, plus ``src[g2[x]]`` where ``add[x]``), the pairs ``pi, pj`` with a moving
    point, and ``ia, ja``: the positions in a waypoint block of the two coordinates whose
    difference is ``dd[t, c, k]``.

    Plain Python (built once per shape by :func:`tables`; under a millisecond for the usual
    shapes): compiling it would cost more than it ever saves.
    """
    p = m + n
    kk = 7 * (r - 1) + 1
    row = p * d
    size = kk * row
    y0 = 1
    x10 = y0 + r * p * d
    x20 = x10 + r * n * d
    of0 = x20 + r * n * d
    # waypoint element x is src[g1[x]] (+ src[g2[x]] where add[x]): paper Remark
    # Remark 2.5, one leg C_k -> C_{k+1} per 7 waypoints
    g1 = np.zeros(size, np.int64)
    g2 = np.zeros(size, np.int64)
    add = np.zeros(size, np.int64)
    for k in range(r - 1):
        for s in range(7):
            for i in range(p):
                for c in range(d):
                    x = (7 * k + s) * row + i * d + c
                    if i < m:
                        g1[x] = y0 + i * d + c
                        # (the reference adds the zero lift to the obstacles too)
                        add[x] = 1 if s == 3 or s == 4 else 0
                        continue
                    j = i - m
                    a0 = (k * n + j) * d + c
                    a1 = a0 + n * d
                    if s == 0:
                        g1[x] = y0 + (k * p + i) * d + c
                    elif s == 1:
                        g1[x] = x10 + a0
                    elif s in (2, 3):
                        g1[x] = x20 + a0
                    elif s in (4, 5):
                        g1[x] = x20 + a1
                    else:
                        g1[x] = x10 + a1
                    if s == 3 or s == 4:
                        g2[x] = of0 + j * d + c
                        add[x] = 1
    for i in range(p * d):
        g1[(kk - 1) * row + i] = y0 + (r - 1) * p * d + i
    # the pairs with a moving point (i < j, j >= m), and the positions of their coordinates
    npairs = _brute_pairs(p, m, d)
    pi = np.empty(npairs, np.int64)
    pj = np.empty(npairs, np.int64)
    k = 0
    for i in range(p - 1 if npairs else 0):
        for j in range(max(i + 1, m), p):
            pi[k] = i
            pj[k] = j
            k += 1
    ndd = kk * d * npairs
    ia = np.empty(ndd, np.int64)
    ja = np.empty(ndd, np.int64)
    for t in range(kk):
        for c in range(d):
            for k in range(npairs):
                x = (t * d + c) * npairs + k
                ia[x] = t * row + pi[k] * d + c
                ja[x] = t * row + pj[k] * d + c
    return np.concatenate((g1, g2, add, pi, pj, ia, ja))


@njit(**OPTS)
def lanes(r, m, n, d):  # pragma: no cover - compiled
    """How many queries :func:`_plan_lanes` plans at once: 64, fewer when its scratch (the
    waypoints and configurations of every lane) would exceed 1 MiB."""
    rows = (7 * (r - 1) + 1 + 3 * r) * (m + n) * d
    L = 64
    while L > 8 and rows * L * 8 > 2**20:
        L //= 2
    return L


# plan_queries and _plan_lanes stay one function each (issue 13 item 3: over 150 lines, because
# splitting costs more than 5 %). Split into named helpers (frame, column classes, lift,
# waypoints...: commit 924b6d3), measured in one process, the variants alternating, CPU time
# (time.thread_time, immune to the other jobs of this shared machine), 16,384 / 32,768 generic
# queries per call, best of 30-60 (benchmarks/kernel_ab.py):
#   plan_queries (every query scalar): (2,1,2) +17 % (7.85 -> 9.27 ms), (2,4,2) +10 %, (3,4,2) +8 %;
#     with numba's inline="always" on the helpers still +7 to +9 %;
#   _plan_lanes: (2,1,2) +14 to +19 % (3.02 -> 3.55 ms), (2,4,2), (3,4,2), (2,16,2) unchanged;
#     with inline="always" +4 to +8 % on (2,1,2).
@njit(**OPTS)
def plan_queries(obstacles, first, last, middle, lift, validate, wp, domain, strata, clearance, flags,
          tab, sel, nsel, compact, shared):  # pragma: no cover - compiled
    """Plan and certify a chunk of queries of the obstacle-line planner (Mathematics §3, §4.1-§4.3).

    Parameters
    ----------
    obstacles : float64 (B, m, d), C-contiguous, d <= MAX_D
    first, last : float64 (B, n, d)
        Robots of the first and last configuration.
    middle : float64 (r - 2, B, n, d)
        Robots of the intermediate configurations (shape (0, B, n, d) when r = 2).
    lift : float
        The unit of the lift when positive; otherwise (``SCENE_CODE`` of
        :mod:`pmplan.planners.base`, ``lift="scene"``) the unit of every query is its
        obstacles' radius ``u(O) = max_k |o_k - o_1|``, computed here as the reference does.
    validate : bool
        Check the input first: a query with a non-finite coordinate or two equal points in one
        of its configurations gets the flag ``INVALID`` and nothing else is computed for it.
    wp : float64 (B, 7 (r - 1) + 1, m + n, d), C-contiguous, output
        The waypoints (bitwise those of the numpy reference).
    domain : int64 (B,), output
        ``l = sum_k cp(C_k) - (r - 1) cp_o + 2 - [e == N]``.
    strata : int64 (B, r + 2), output
        ``cp(C_1), ..., cp(C_r), cp_o, [e == N]``.
    clearance : float64 (B,), output
        The certified clearance where ``flags == 0``.
    flags : uint8 (B,), output
        Bit set of ``FALLBACK``, ``SUSPECT``, ``NONFINITE``, ``BROKEN``, ``INVALID``.
    tab : int64 (:func:`_build_tables`)
    sel, nsel : int64 (>= nsel,), int
        The queries to plan: ``sel[:nsel]`` (the others are not touched).
    compact : bool
        The compact lanes of Mathematics §4.4 (the planner ``obstacle_line_compact``) instead of
        the paper's ``i lambda`` (:func:`pmplan.planners.obstacle_line.lane_heights`).
    shared : int
        With ``compact``, the shared lanes of Mathematics §4.4
        (:func:`pmplan.planners.obstacle_line.lane_chains`): 0, every robot its own lane; 2
        (the planner ``obstacle_line_shared``), the robots of a side that keep their order
        share a lane; 1 (``obstacle_line_oneside``), every robot on the side of ``nu``, the
        robots that keep their order sharing a lane.

    Notes
    -----
    The certificate is computed from the waypoints as written into ``wp`` (read back), not from
    the construction: the relative position of every pair at every waypoint is formed once
    (``dd``), and the closed-form minimum of every piece is taken from two consecutive rows.
    """
    nb, m, d = obstacles.shape
    n = first.shape[1]
    r = middle.shape[0] + 2
    p = m + n
    kk = wp.shape[1]
    row = p * d
    size = kk * row
    wf = wp.reshape((nb, size))
    w = np.empty(d)
    e = np.empty(d)
    nu = np.empty(d)
    h = np.empty(d)
    vals = np.empty(p)
    order = np.empty(p, np.int64)
    lab = np.empty(p, np.int64)
    cps = np.empty(r, np.int64)
    kv = np.empty((r, n))  # the compact lanes' chains (obstacle_line.lane_chains): keys,
    lane = np.empty(n, np.int64)  # lanes, the last robot of every chain, the order in C_1
    tail = np.empty(n, np.int64)
    rorder = np.empty(n, np.int64)
    bk = np.empty(n, np.int64)
    cnt = np.empty(n + 1, np.int64)
    # the values the waypoints are made of, in one vector: 0.0, then the configurations C_k
    # (waypoints 7k), the desingularized robots F(C_k, 1), the projected robots
    # phi(F(C_k, 1), 1), and the lift i lambda nu(e) of robot i
    y0 = 1
    x10 = y0 + r * p * d
    x20 = x10 + r * n * d
    of0 = x20 + r * n * d
    src = np.zeros(of0 + n * d)
    y = src[y0:x10].reshape((r, p, d))
    x1 = src[x10:x20].reshape((r, n, d))
    x2 = src[x20:of0].reshape((r, n, d))
    off = src[of0:].reshape((n, d))
    size3 = 3 * size
    npairs = _brute_pairs(p, m, d)  # pairs with a moving point (0: the sweep, no tables)
    ndd = kk * d * npairs
    g1 = tab[0:size]
    g2 = tab[size:2 * size]
    add = tab[2 * size:size3]
    ia = tab[size3 + 2 * npairs:size3 + 2 * npairs + ndd]
    ja = tab[size3 + 2 * npairs + ndd:size3 + 2 * npairs + 2 * ndd]
    ddf = np.empty(ndd)
    dd = ddf.reshape((kk, d, npairs))  # relative positions of the pairs at every waypoint
    best_k = np.empty(npairs)
    vv = np.empty(npairs)
    rv = np.empty(npairs)
    tt = np.empty(npairs)
    d2 = np.empty(npairs)
    nfl = float(n + m)
    odd = d % 2 == 1
    for ii in range(nsel):
        b = sel[ii]
        fl = 0
        for k in range(r):
            for i in range(m):
                for c in range(d):
                    y[k, i, c] = obstacles[b, i, c]
        for j in range(n):
            for c in range(d):
                y[0, m + j, c] = first[b, j, c]
                y[r - 1, m + j, c] = last[b, j, c]
        for k in range(1, r - 1):
            for j in range(n):
                for c in range(d):
                    y[k, m + j, c] = middle[k - 1, b, j, c]
        if validate:
            extreme = False
            for k in range(r):
                for i in range(p):
                    for c in range(d):
                        if not math.isfinite(y[k, i, c]):
                            fl = INVALID
                        elif not abs(y[k, i, c]) < _EXTREME:
                            extreme = True
                    for j in range(i):
                        same = True
                        for c in range(d):
                            if y[k, i, c] != y[k, j, c]:
                                same = False
                        if same:
                            fl = INVALID
            if fl:
                flags[b] = fl
                continue
            if extreme:  # planned scaled by a power of two by the caller (pmplan.magnitude)
                flags[b] = FALLBACK
                continue
        # --- frame (pmplan.frame): w = o2 - o1, e, |w|, nu(e), e == N ------------------------
        for c in range(d):
            w[c] = y[0, 1, c] - y[0, 0, c]
        _unit(w, d, e)
        norm = 0.0
        for c in range(d):
            norm += w[c] * e[c]
        pole = 0
        if not odd:  # paper Section 3: nu(a1, b1, ...) = (-b1, a1, ...)
            for c in range(0, d, 2):
                nu[c] = -e[c + 1] + 0.0
                nu[c + 1] = e[c] + 0.0
        else:  # Mathematics §4.1
            pole = 1 if w[d - 1] > 0 else 0
            for c in range(d - 1):
                if w[c] != 0:
                    pole = 0
            if pole == 1:
                for c in range(d):
                    nu[c] = 0.0
                nu[0] = 1.0
            else:
                _unit(w, d - 1, h)
                for c in range(d - 1):
                    nu[c] = -(h[0] * h[c]) * (1.0 + e[d - 1])
                nu[0] += 1.0
                nu[d - 1] = e[0]
                for c in range(d):
                    nu[c] = nu[c] + 0.0
        # --- columns, desingularization of paper (3.2), projection of paper (3.6) -------
        cp_o = 0
        for k in range(r):
            ok, cp, cpo_k, gap, labelled = _classes(y, k, p, m, d, w, vals, order, lab)
            if not ok:
                fl |= FALLBACK
                break
            if shared:  # the exact class, or where each is its own the projection
                for j in range(n):
                    kv[k, j] = float(lab[m + j]) if labelled else vals[m + j]
            cps[k] = cp
            cp_o = cpo_k
            eps = gap / norm / nfl
            sh = eps if cp < cpo_k + n else 0.0
            for j in range(n):
                shj = sh * float(j + 1)
                s1 = 0.0
                for c in range(d):
                    xc = y[k, m + j, c] + shj * e[c]
                    x1[k, j, c] = xc
                    s1 += (xc - y[k, 0, c]) * e[c]
                for c in range(d):
                    x2[k, j, c] = y[k, 0, c] + s1 * e[c]
                if compact and d > 2:  # the offsets (obstacle_line.offset, Mathematics §4.4)
                    tn = 0.0
                    for c in range(d):
                        tn += (x1[k, j, c] - x2[k, j, c]) * nu[c]
                    for c in range(d):
                        x2[k, j, c] = x2[k, j, c] + ((x1[k, j, c] - x2[k, j, c]) - tn * nu[c])
        if fl:
            flags[b] = fl
            continue
        # --- the unit: lift, or for lift="scene" (lift <= 0, planners.base.SCENE_CODE) the
        # obstacles' radius u(O) = sqrt(max_k sum_c (o_k,c - o_1,c)^2) (planners.base.scene_unit)
        unit = lift
        if not lift > 0:
            q = 0.0
            for i in range(1, m):
                sq = 0.0
                for c in range(d):
                    dc = y[0, i, c] - y[0, 0, c]
                    sq += dc * dc
                if sq > q or i == 1 or math.isnan(sq):
                    q = sq
            unit = math.sqrt(q)
        # --- the lanes of the section of paper (3.8): the compact ones (Mathematics §4.4,
        # obstacle_line.lane_heights) or the paper's i lambda (§4.2) ------------------------
        if compact:
            hp = 0.0
            hm = 0.0
            for i in range(2, m):
                t = 0.0
                for c in range(d):
                    t += (y[0, i, c] - y[0, 0, c]) * nu[c]
                if t > hp:
                    hp = t
                if -t > hm:
                    hm = -t
            if shared:
                _bucket_sort(kv[0], rorder, n, bk, cnt)  # (stable: ties by index)
                _lane_chains(kv, r, n, rorder, lane, tail, shared)
            for j in range(n):
                kq = float(lane[j]) if shared else float(j // 2 + 1)
                li = hp + unit * kq if j % 2 == 0 or shared == 1 else -(hm + unit * kq)
                for c in range(d):
                    off[j, c] = li * nu[c]
        else:
            lam = unit
            if m > 2:
                mx = 0.0
                for i in range(2, m):
                    sc = 0.0
                    for c in range(d):
                        sc += (y[0, i, c] - y[0, 0, c]) * e[c]
                    q = 0.0
                    for c in range(d):
                        rc = (y[0, i, c] - y[0, 0, c]) - sc * e[c]
                        q += rc * rc
                    q = math.sqrt(q)
                    if q > mx or i == 2 or math.isnan(q):
                        mx = q
                lam = unit + mx
            for j in range(n):
                li = lam * float(j + 1)
                for c in range(d):
                    off[j, c] = li * nu[c]
        # --- the waypoints, written into wp; the certificate (pmplan.certify) reads them back:
        # finite, obstacles fixed, the configurations C_k at waypoints 7k -------------------
        for x in range(size):
            v1 = src[g1[x]]
            v2 = v1 + src[g2[x]]
            wf[b, x] = v2 if add[x] else v1
        if compact and d == 2:  # the direct lift (obstacle_line.two_configuration_path)
            for k in range(r - 1):
                t0 = 7 * k * row
                for x in range(m * d, row):
                    for s_, a_, b_ in ((2, 1, 3), (5, 6, 4)):
                        va = wf[b, t0 + a_ * row + x]
                        wf[b, t0 + s_ * row + x] = va + DIRECT_AT * (wf[b, t0 + b_ * row + x] - va)
        # the largest |coordinate| of the waypoints as returned (certify's scale: not of the
        # projections the direct lift replaced) and their finiteness
        amax = 0.0
        finite = True
        for x in range(size):
            a = abs(wf[b, x])
            finite &= a <= MAXF  # False for inf and NaN
            amax = a if a > amax else amax  # noqa: FURB136 (NaN is caught by `finite`)
        if not finite:
            fl |= NONFINITE
        for t in range(1, kk):
            for x in range(m * d):
                if wf[b, t * row + x] != wf[b, x]:
                    fl |= BROKEN
        for k in range(r):
            for x in range(row):
                if wf[b, 7 * k * row + x] != src[y0 + k * row + x]:
                    fl |= BROKEN
        dom = 2 - pole - (r - 1) * cp_o
        for k in range(r):
            dom += cps[k]
            strata[b, k] = cps[k]
        strata[b, r] = cp_o
        strata[b, r + 1] = pole
        domain[b] = dom
        if fl & NONFINITE:
            clearance[b] = np.nan
            flags[b] = fl
            continue
        # --- clearance: closed-form minimum per piece and pair ------------------------------
        clr, fl_c = _certify_one(wf, b, ddf, dd, ia, ja, kk, p, m, d, npairs, amax, best_k,
                                 vv, rv, tt, d2)
        clearance[b] = clr
        flags[b] = fl | fl_c


@njit(**OPTS)
def _unit_rows(w, n, out, t):  # pragma: no cover - compiled
    """``_unit`` lane by lane on rows: ``w[:n]`` into ``out[:n]`` (rows of L lanes);
    ``t`` is scratch (>= 3 rows)."""
    L = w.shape[1]
    src = 0
    dst = 1
    for l in range(L):
        t[src, l] = 0.0
        t[2, l] = 0.0
    for c in range(n):
        for l in range(L):
            a = abs(w[c, l])
            s = t[src, l]
            t[dst, l] = a if a > s else s  # noqa: FURB136 (a select: NaN never chosen)
        src, dst = dst, src
    for c in range(n):
        for l in range(L):
            s = t[src, l]
            x = w[c, l] / s
            x = x if s > 0 else 0.0
            out[c, l] = x
            t[2, l] += x * x
    for l in range(L):
        t[2, l] = math.sqrt(t[2, l])
    for c in range(n):
        for l in range(L):
            s = t[2, l]
            x = out[c, l] / s
            out[c, l] = x if s > 0 else 0.0


@njit(**INLINE)
def _fold_min(T, a, src, dst):  # pragma: no cover - compiled
    """Row ``dst`` of T = min(row ``src``, row ``a``), every lane, as a select (NaN is never
    chosen); the caller then swaps ``src`` and ``dst`` (running minima in alternating rows)."""
    for l in range(T.shape[1]):
        v = T[a, l]
        z = T[src, l]
        T[dst, l] = v if v < z else z  # noqa: FURB136


@njit(**INLINE)
def _dist2_lanes(rx, ry, r1x, r1y):  # pragma: no cover - compiled
    """:func:`segment_dist2_plane` for :func:`_plan_lanes`, without its three ``0.0 +``.

    The value is the same: a sum of squares never is -0, so ``0.0 + x * x`` is ``x * x``;
    ``num = -(rx vx + ry vy)`` may differ only in the sign of a zero, and both signs of zero give
    the parameter 0 (:func:`segment_param`)."""
    vx = r1x - rx
    vy = r1y - ry
    vv = vx * vx + vy * vy
    q = segment_param(-(rx * vx + ry * vy), vv)
    qx = rx + q * vx
    qy = ry + q * vy
    return qx * qx + qy * qy


@njit(**INLINE)
def _pair_lane(S, w0, a, b, row, l, z):  # pragma: no cover - compiled
    """One pair over one segment of the path in the plane, lane l: min(``z``, the squared
    distance at waypoint w0 -- the piece w0 -> w0 + 1 does not move -- and the squared
    minimum distance of the five moving pieces w0 + 1 -> ... -> w0 + 6). The pair's points
    start at rows ``a`` and ``b`` of a waypoint (coordinates 0, 1); the segment is the
    waypoints ``w0 .. w0 + 6 row`` (row = one waypoint). The relative position at each
    waypoint is formed once. The loop of :func:`_pair_plane` over the lanes, written out:
    :func:`_prune_pass` evaluates a pair lane by lane. (:func:`_pair_plane` calling this, or a
    lane range in :func:`_pair_plane`, ran (2,4,2) 1.5-1.7 times slower -- kernel_ab, with or
    without numba's ``inline="always"``: the loop was no longer one vectorised loop -- so the
    arithmetic is written twice, in the same order.)"""
    x0 = S[w0 + a, l] - S[w0 + b, l]
    y0 = S[w0 + a + 1, l] - S[w0 + b + 1, l]
    best = x0 * x0 + y0 * y0
    best = best if best < z else z  # noqa: FURB136 (a select: NaN never chosen)
    w = w0 + row
    x1 = S[w + a, l] - S[w + b, l]
    y1 = S[w + a + 1, l] - S[w + b + 1, l]
    for _ in range(5):
        w += row
        x2 = S[w + a, l] - S[w + b, l]
        y2 = S[w + a + 1, l] - S[w + b + 1, l]
        dist2 = _dist2_lanes(x1, y1, x2, y2)
        best = dist2 if dist2 < best else best  # noqa: FURB136
        x1 = x2
        y1 = y2
    return best


@njit(**OPTS)
def _pair_plane(S, w0, a, b, row, T, src, dst):  # pragma: no cover - compiled
    """One pair over one segment of the path in the plane, every lane.

    The pair's points start at rows ``a`` and ``b`` of a waypoint (coordinates 0, 1); the
    segment is the waypoints ``w0 .. w0 + 6 row`` (row = one waypoint). Row ``dst`` of T =
    min(row ``src``, the squared distance at waypoint w0 -- the piece w0 -> w0 + 1 does not
    move -- and the squared minimum distance of the five moving pieces w0 + 1 -> ... -> w0 + 6).
    The relative position at each waypoint is formed once."""
    for l in range(S.shape[1]):
        x0 = S[w0 + a, l] - S[w0 + b, l]
        y0 = S[w0 + a + 1, l] - S[w0 + b + 1, l]
        best = x0 * x0 + y0 * y0
        z = T[src, l]
        best = best if best < z else z  # noqa: FURB136 (a select: NaN never chosen)
        w = w0 + row
        x1 = S[w + a, l] - S[w + b, l]
        y1 = S[w + a + 1, l] - S[w + b + 1, l]
        for _ in range(5):
            w += row
            x2 = S[w + a, l] - S[w + b, l]
            y2 = S[w + a + 1, l] - S[w + b + 1, l]
            dist2 = _dist2_lanes(x1, y1, x2, y2)
            best = dist2 if dist2 < best else best  # noqa: FURB136
            x1 = x2
            y1 = y2
        T[dst, l] = best


@njit(**INLINE)
def _lane_thresholds(D, EW, T32, nseg, l, ng):  # pragma: no cover - compiled
    """Lane l's float32 thresholds of :func:`_prune_pass` (rows of ``T32``, ``ng`` per segment:
    one per group) from its ``s = sqrt(min(best, guess))`` (rows BEST, GUESS of ``D``; ``-inf``:
    the lane is left out): ``(thr + EW) (1 + 2**-21)`` rounded to float32, ``thr = (s |u| +
    margin) (1 + _PRUNE_REL)`` as in :func:`_sweep_min` (u1 for group B, u0 for the others)."""
    z = D[_BEST, l]
    g = D[_GUESS, l]
    sq = math.sqrt(z if z < g else g)  # noqa: FURB136 (a select, as elsewhere)
    sq = sq if D[_OUT, l] == 0 else -np.inf
    t0 = (sq * D[_WN0, l] + D[_MG0, l]) * (1.0 + _PRUNE_REL)
    t1 = (sq * D[_WN1, l] + D[_MG1, l]) * (1.0 + _PRUNE_REL)
    for x in range(ng * nseg):
        t = t1 if x % ng == 1 else t0
        T32[x, l] = np.float32((t + EW[x, l]) * _UP32)


@njit(**OPTS)
def _prune_pass(S, C32, T32, D, EW, NEED, r, m, p, row, kk, shared):  # pragma: no cover - compiled
    """One pass of :func:`_prune_plane` over every pair with a moving point: a pair is
    evaluated (:func:`_pair_lane` over the segment, and at the last configuration) in a lane
    where the float32 distance of its centres along ``u0`` (groups A, C) or ``u1`` (group B) is
    not above the lane's threshold for that group (``T32``); row BEST of ``D`` takes the minima,
    and the thresholds follow it down. The test runs over every lane at once (one vectorised
    loop on float32 rows: the test reads the bytes of a few rows per pair, so that their size
    bounds its speed), its verdict in ``NEED``, counted; the few lanes that need a pair evaluate
    it one by one (a block of lanes would evaluate it where it is not needed, and numba leaves
    a loop over a few lanes scalar anyway).

    With ``shared`` (the shared lanes, Mathematics §4.4, whose robots of one lane keep one
    height along the whole slide, so that their spans along u1 meet) the slide also passes a
    pair whose float32 positions along u0 at its two ends (groups 3 and 4, single waypoints:
    no span) are above their thresholds with the same sign: the exact relative position along
    u0 is then above ``thr`` at both ends, with one sign, and it moves linearly on the piece,
    so it is above ``thr`` on the whole piece -- the premise of :func:`_sweep_min`'s argument
    (there from disjoint spans), whose conclusion follows word for word."""
    L = S.shape[1]
    r0 = (kk - 1) * row
    ng = 5 if shared else 3
    for k in range(r - 1):
        w0 = 7 * k * row
        ga = ng * k * p  # the rows of C32 of groups A, B, C (and the slide's ends) of segment k
        gb = ga + p
        gc = gb + p
        g3 = gc + p
        g4 = g3 + p
        ta = ng * k  # their rows of T32
        for i in range(p - 1):
            for j in range(max(i + 1, m), p):
                cnt = 0
                if shared:  # (a loop of its own: the compact lanes' loop stays as it was)
                    for l in range(L):
                        xa = abs(C32[ga + j, l] - C32[ga + i, l])
                        xb = abs(C32[gb + j, l] - C32[gb + i, l])
                        xc = abs(C32[gc + j, l] - C32[gc + i, l])
                        y3 = C32[g3 + j, l] - C32[g3 + i, l]
                        y4 = C32[g4 + j, l] - C32[g4 + i, l]
                        fb = (xb > T32[ta + 1, l]) | ((abs(y3) > T32[ta + 3, l])
                                                      & (abs(y4) > T32[ta + 4, l])
                                                      & ((y3 > 0) == (y4 > 0)))
                        nd = not ((xa > T32[ta, l]) & fb & (xc > T32[ta + 2, l]))
                        NEED[l] = nd
                        cnt += nd
                else:
                    for l in range(L):
                        xa = abs(C32[ga + j, l] - C32[ga + i, l])
                        xb = abs(C32[gb + j, l] - C32[gb + i, l])
                        xc = abs(C32[gc + j, l] - C32[gc + i, l])
                        # (NaN is never above: then the pair is evaluated)
                        nd = not ((xa > T32[ta, l]) & (xb > T32[ta + 1, l])
                                  & (xc > T32[ta + 2, l]))
                        NEED[l] = nd
                        cnt += nd
                if cnt == 0:
                    continue
                for l in range(L):  # the lanes that need the pair, one by one
                    if not NEED[l]:
                        continue
                    D[_BEST, l] = _pair_lane(S, w0, 2 * i, 2 * j, row, l, D[_BEST, l])
                    if k == r - 2:  # the last configuration (as the brute-force pass)
                        x0 = S[r0 + 2 * i, l] - S[r0 + 2 * j, l]
                        y0 = S[r0 + 2 * i + 1, l] - S[r0 + 2 * j + 1, l]
                        a = x0 * x0 + y0 * y0
                        z = D[_BEST, l]
                        D[_BEST, l] = a if a < z else z  # noqa: FURB136
                    _lane_thresholds(D, EW, T32, r - 1, l, ng)


# the rows of D in _prune_plane / _prune_pass: the directions u0, u1 and their norms and
# margins (as _directions writes them for d = 2), the running minimum, the guess, the lanes
# left out of a second pass
_WN0 = 4
_WN1 = 5
_MG0 = 6
_MG1 = 7
_BEST = 8
_GUESS = 9
_OUT = 10
#: (1 + 2**-21): the float32 thresholds of _prune_pass are rounded up past every rounding
_UP32 = 1.0 + 2.0**-21


@njit(**OPTS)
def _guess_plane(S, D, T, mx, r, m, p, row):  # pragma: no cover - compiled
    """Row GUESS of ``D`` for the compact lanes (Mathematics §4.4): every lane's estimate of the
    squared minimum distance of the pairs with a moving point, from the pieces 7k + 1 -> 7k + 2
    of the direct lift (the start side's lift), where the minimum of random queries often lies.

    In the frame of ``u0`` (rows 0, 1 of ``D``: the obstacle line, scaled) and ``u0`` turned by
    a right angle, a pair's relative position on such a piece goes from ``(a0, b0)`` to
    ``(a1, b1)``; the points move along the normal ``nu`` of the line, so ``a1 = a0`` up to
    rounding and, where ``b0 b1 <= 0`` (the pair crosses ``b = 0``), the pair's minimum is
    ``|a0|``. The estimate is the least such ``|a0|`` over the crossing pairs (float32, every lane
    at once), times ``1 + 2**-20`` plus ``2**-20`` times the largest |coordinate| ``amax``
    (the float32 ``a`` are within ``2**-23 amax``, their differences within ``2**-21 amax``),
    over ``|u0|``; ``inf`` when no pair crosses. It is never below the lane's minimum, only
    :func:`_prune_plane`'s guess, which is exact whatever the guess: a lane whose guess is below
    its minimum takes the second pass. The goal side's lift (pieces 7k + 5 -> 7k + 6) holds the
    minimum in about half of the lanes; reading it too made the estimate that minimum in
    nearly every lane, but saved few pairs (random (2,64,2) lanes evaluated 2.4 pairs each,
    against 2.9 from the start side alone) and cost more than it saved (cert_bench, alternating
    processes, (2,64,2): 4.6-4.7 us per query against 4.1-4.2; (2,16,2) alike). On 64 lanes of random (2,16,2) and of (2,64,2)
    queries of the default planner no lane took the second pass
    (``tests/test_prune_lanes.py::test_prune_prunes``)."""
    L = S.shape[1]
    A = np.empty((3 * p, L), np.float32)  # a, b at the piece's start, b at its end
    E = np.empty((2, L), np.float32)
    e0 = 0
    e1 = 1
    for l in range(L):
        E[e0, l] = np.float32(np.inf)
    for k in range(r - 1):
        t0 = (7 * k + 1) * row
        t1 = t0 + row
        for i in range(p):
            x = t0 + 2 * i
            z = t1 + 2 * i
            for l in range(L):
                ux = D[0, l]
                uy = D[1, l]
                A[i, l] = np.float32(S[x, l] * ux + S[x + 1, l] * uy)
                A[p + i, l] = np.float32(S[x + 1, l] * ux - S[x, l] * uy)
                A[2 * p + i, l] = np.float32(S[z + 1, l] * ux - S[z, l] * uy)
        for i in range(p - 1):
            for j in range(max(i + 1, m), p):
                for l in range(L):
                    a0 = abs(A[j, l] - A[i, l])
                    b0 = A[p + j, l] - A[p + i, l]
                    b1 = A[2 * p + j, l] - A[2 * p + i, l]
                    e = a0 if b0 * b1 <= np.float32(0.0) else np.float32(np.inf)
                    z = E[e0, l]
                    E[e1, l] = e if e < z else z  # noqa: FURB136 (NaN never chosen)
                e0, e1 = e1, e0
    for l in range(L):
        e = (np.float64(E[e0, l]) * (1.0 + 2.0**-20) + 2.0**-20 * T[mx, l]) / D[_WN0, l]
        D[_GUESS, l] = e * e


@njit(**OPTS)
def _prune_plane(S, T, wf, b0, r, m, p, row, kk, mx, mn, BAD, THR2, GAP,
                 NORM, compact, shared):  # pragma: no cover - compiled
    """Row ``mn`` of T = every lane's minimum over the pairs with a moving point of the plane
    (d = 2), exactly that of the brute-force pass of :func:`_certify_lanes` (bitwise), the
    pairs pruned as :func:`_sweep_min` prunes them, without sorting.

    In each segment C_k -> C_k+1 the pieces form :func:`_sweep_min`'s three groups -- A: the
    waypoints 7k .. 7k + 3 (C_k, desingularization, projection, lift: the points move across
    the obstacle line's direction u0), B: 7k + 3 -> 7k + 4 (the slide; u1, the lift's
    direction), C: 7k + 4 .. 7k + 7 (as A, at C_k+1's columns; with the last configuration).
    Every point's projection on the group's direction spans ``[lo, hi]`` over the group's
    waypoints, and a pair with ``lo_b - hi_a > thr = (s |u| + margin) (1 + _PRUNE_REL)`` has
    every float squared distance of the group's pieces above ``s^2`` (:func:`_sweep_min` proves
    it; the directions and margins are :func:`_directions`'s). A lane evaluates a pair over the
    whole segment (:func:`_pair_lane`) unless that holds in all three groups.

    The test reads float32 centres ``c32 = f32((lo + hi) / 2)``: with ``C`` the group's largest
    ``|(lo + hi) / 2|`` and ``W`` its largest ``hi - lo`` (float64, per lane), the float32
    ``|c32_b - c32_a|`` is within ``E = 2**-20 C + 2**-120`` of the exact difference of the
    centres (two float32 roundings, one float32 subtraction, relative 2**-24 each, plus the
    subnormal spacing; float64's own roundings are far below), so ``|c32_b - c32_a| > f32((thr
    + E + W) (1 + 2**-21))`` (rounded up past the float64 sum's and float32's rounding) gives
    ``lo_b - hi_a > thr`` exactly, a stronger premise than :func:`_sweep_min`'s float test. A
    group whose ``C`` is not below 2**120 (a centre could overflow float32) has ``E = inf``:
    its test never skips.

    ``s`` starts as a guess: on the paper's lanes 1.25 times the smallest gap of the
    column-class test (row ``GAP``, divided by ``|w|``, row ``NORM``), near the true minimum on
    random queries of the paper's projection, where the closest columns meet on the line; on
    the compact lanes (``compact``), whose direct lift (Mathematics §4.4) keeps them apart, the
    estimate of :func:`_guess_plane`; then ``min(best, guess)``. A pair skipped is above ``min
    (best, guess)`` at that time; so where the final ``best <= guess`` it is the minimum, and
    every other lane (a poor guess) takes a second pass from its ``best`` (inf if none: every
    pair). Lanes that go to the scalar kernel anyway (row ``BAD``, or ``THR2`` infinite) are
    left out of the second pass."""
    L = S.shape[1]
    D = np.empty((11, L))
    aux = np.empty(8)
    for l in range(L):
        _directions(wf[b0 + l], p, m, 2, T[mx, l], aux)
        for x in range(8):
            D[x, l] = aux[x]
    nseg = r - 1
    ng = 5 if shared else 3  # groups A, B, C (and the slide's two ends along u0, _prune_pass)
    C32 = np.empty((ng * nseg * p, L), np.float32)
    EW = np.empty((ng * nseg, L))
    T32 = np.empty((ng * nseg, L), np.float32)
    NEED = np.empty(L, np.bool_)
    LO = np.empty((2, L))
    for k in range(nseg):
        for g in range(ng):
            ts = 7 * k + (0 if g == 0 else (3 if g == 1 or g == 3 else 4))
            te = ts + (1 if g == 1 else (3 if g < 3 else 0))
            dr = 2 if g == 1 else 0
            y = (ng * k + g) * p
            ew = ng * k + g
            for l in range(L):
                D[_BEST, l] = 0.0  # (scratch here) the group's C
                EW[ew, l] = 0.0  # its W
            for i in range(p):
                # the span [lo, hi] of point i on the group's direction (as _sweep_min)
                for l in range(L):
                    LO[0, l] = np.inf
                    LO[1, l] = -np.inf
                for t in range(ts, te + 1):
                    x = t * row + 2 * i
                    for l in range(L):
                        v = 0.0
                        v += S[x, l] * D[dr, l]
                        v += S[x + 1, l] * D[dr + 1, l]
                        a0 = LO[0, l]
                        a1 = LO[1, l]
                        LO[0, l] = v if v < a0 else a0  # noqa: FURB136
                        LO[1, l] = v if v > a1 else a1  # noqa: FURB136
                for l in range(L):
                    c = 0.5 * (LO[0, l] + LO[1, l])
                    wd = LO[1, l] - LO[0, l]
                    C32[y + i, l] = np.float32(c)
                    z = D[_BEST, l]
                    ac = abs(c)
                    D[_BEST, l] = ac if not ac <= z else z  # (NaN is kept: E is NaN, no skip)
                    z = EW[ew, l]
                    EW[ew, l] = wd if not wd <= z else z
            for l in range(L):
                cc = D[_BEST, l]
                e = 2.0**-20 * cc + 2.0**-120 if cc < 2.0**120 else np.inf
                EW[ew, l] = e + EW[ew, l]
    if compact:
        _guess_plane(S, D, T, mx, r, m, p, row)
    else:
        for l in range(L):
            sq = 1.25 * T[GAP, l] / T[NORM, l]
            D[_GUESS, l] = sq * sq
    for l in range(L):
        D[_BEST, l] = np.inf
        D[_OUT, l] = 0.0
        _lane_thresholds(D, EW, T32, nseg, l, ng)
    _prune_pass(S, C32, T32, D, EW, NEED, r, m, p, row, kk, shared)
    again = False
    for l in range(L):  # a lane whose guess was too small: a second pass from its best
        poor = (T[BAD, l] == 0) & (T[THR2, l] < np.inf) & (not D[_BEST, l] <= D[_GUESS, l])
        again |= poor
        D[_GUESS, l] = np.inf
        D[_OUT, l] = 0.0 if poor else 1.0
        _lane_thresholds(D, EW, T32, nseg, l, ng)
    if again:
        _prune_pass(S, C32, T32, D, EW, NEED, r, m, p, row, kk, shared)
    for l in range(L):
        T[mn, l] = D[_BEST, l]
    return mn


@njit(**INLINE)
def _rel4(S, w, a, b, a3, b3, l):  # pragma: no cover - compiled
    """The relative position of a pair at waypoint block ``w``, lane l (see :func:`_pair_space`):
    coordinates 0-2 at rows ``a``, ``b`` (+ 0, 1, 2), and with ``a3`` not None (d = 4) the
    fourth at rows ``a3``, ``b3`` (:func:`_fourth`: the d = 3 specialisation has 3-tuples)."""
    return (S[w + a, l] - S[w + b, l], S[w + a + 1, l] - S[w + b + 1, l],
            S[w + a + 2, l] - S[w + b + 2, l]) + _fourth(S, w, a3, b3, l)


def _fourth(S, w, a3, b3, l):  # pragma: no cover - only its compiled overload runs
    """The fourth coordinate of :func:`_rel4` as a tuple: ``()`` when ``a3`` is None (d = 3),
    else ``(S[w + a3, l] - S[w + b3, l],)``; chosen by the type of ``a3`` when numba compiles."""
    raise NotImplementedError("compiled only")


@overload(_fourth)
def _fourth_typed(S, w, a3, b3, l):  # pragma: no cover - compiled
    if isinstance(a3, NoneType):
        return lambda S, w, a3, b3, l: ()
    return lambda S, w, a3, b3, l: (S[w + a3, l] - S[w + b3, l],)


@njit(**INLINE)
def _norm2(r):  # pragma: no cover - compiled
    """The squared norm of the tuple ``r``, summed in order (``r[0]**2`` first, no ``0.0 +``:
    a sum of squares is never -0, so the value is that of certify's sum)."""
    s = r[0] * r[0]
    for c in range(1, len(r)):
        s += r[c] * r[c]
    return s


@njit(**INLINE)
def _dist2_space(r1, r2):  # pragma: no cover - compiled
    """:func:`_dist2_lanes` for 3 or 4 coordinates (the tuples ``r1`` -> ``r2``): the sums
    sequential; without the ``0.0 +`` (no value changes, see :func:`_dist2_lanes`). The loops
    over the coordinates have a length numba knows (the tuples'), so LLVM unrolls them."""
    v = r2[0] - r1[0]
    vv = v * v
    num = r1[0] * v
    for c in range(1, len(r1)):
        v = r2[c] - r1[c]
        vv += v * v
        num += r1[c] * v
    q = segment_param(-num, vv)
    qc = r1[0] + q * (r2[0] - r1[0])
    s = qc * qc
    for c in range(1, len(r1)):
        qc = r1[c] + q * (r2[c] - r1[c])
        s += qc * qc
    return s


@njit(**INLINE)
def _step_space(S, w, a, b, a3, b3, l, r1, best):  # pragma: no cover - compiled
    """One piece of :func:`_pair_space`: the relative position ``r2`` at waypoint block ``w``,
    and ``(r2, min(best, the squared minimum distance of the piece r1 -> r2))``."""
    r2 = _rel4(S, w, a, b, a3, b3, l)
    x = _dist2_space(r1, r2)
    return r2, (x if x < best else best)  # noqa: FURB136 (a select: NaN never chosen)


@njit(**OPTS)
def _pair_space(S, w0, a, b, a3, b3, row, T, src, dst):  # pragma: no cover - compiled
    """:func:`_pair_plane` in space, d = 3 or 4: one pair over one segment, every lane.

    Coordinates 0-2 of the pair's points are at rows ``a``, ``b`` (+ 0, 1, 2) of a waypoint,
    the fourth (d = 4) at rows ``a3``, ``b3`` (``a + 3``, ``b + 3``); d = 3 passes
    ``a3 = b3 = None`` and gets its own specialisation with three coordinates (a zero fourth
    coordinate, as before, cost (3,4,2) about 4 % of the kernel). The sums over the coordinates
    are sequential, in certify's order. Written out piece by piece (no inner loop over the
    pieces), so that the loop over the lanes vectorises.
    """
    for l in range(S.shape[1]):
        r0 = _rel4(S, w0, a, b, a3, b3, l)
        best = _norm2(r0)
        z = T[src, l]
        best = best if best < z else z  # noqa: FURB136 (a select: NaN never chosen)
        r1 = _rel4(S, w0 + row, a, b, a3, b3, l)
        r1, best = _step_space(S, w0 + 2 * row, a, b, a3, b3, l, r1, best)
        r1, best = _step_space(S, w0 + 3 * row, a, b, a3, b3, l, r1, best)
        r1, best = _step_space(S, w0 + 4 * row, a, b, a3, b3, l, r1, best)
        r1, best = _step_space(S, w0 + 5 * row, a, b, a3, b3, l, r1, best)
        r1, best = _step_space(S, w0 + 6 * row, a, b, a3, b3, l, r1, best)
        T[dst, l] = best


@njit(**OPTS)
def _sweep_lanes(wf, b0, T, mx, mn, THR2, BAD, kk, p, m, d):  # pragma: no cover - compiled
    """Row ``mn`` of T = :func:`_sweep_min` of every lane whose waypoints (already written,
    ``wf[b0 + l]``: read there, contiguous, not gathered from the lanes' rows) are finite
    (row ``BAD`` zero) with the largest |coordinate| (row ``mx``) in range (row ``THR2``
    finite); the other lanes go to the scalar kernel anyway (inf: not above THR2)."""
    L = T.shape[1]
    nlo, naux = _sweep_sizes(p, d)
    lo = np.empty(nlo)
    hi = np.empty(nlo)
    order = np.empty(4 * p + 1, np.int64)
    aux = np.empty(naux)
    for l in range(L):
        T[mn, l] = np.inf
        if T[BAD, l] == 0 and T[THR2, l] < np.inf:
            T[mn, l] = _sweep_min(wf[b0 + l], kk, p, m, d, T[mx, l], lo, hi, order, aux,
                                  -np.inf)[0]


@njit(**OPTS)
def _max_finite(S, T, x0, x1, mx, mx2, BAD):  # pragma: no cover - compiled
    """Rows ``x0 .. x1`` of ``S`` into the running maximum of |value| of every lane (row ``mx``
    of T, alternating with ``mx2``: returns the new pair) and the finiteness test (adds to row
    ``BAD``: ``v - v`` is NaN unless v is finite). Four rows per pass."""
    L = S.shape[1]
    quads = x1 - (x1 - x0) % 4
    for x in range(x0, quads, 4):
        for l in range(L):
            v0 = S[x, l]
            v1 = S[x + 1, l]
            v2 = S[x + 2, l]
            v3 = S[x + 3, l]
            T[BAD, l] += ((v0 - v0) + (v1 - v1)) + ((v2 - v2) + (v3 - v3))
            a0 = abs(v0)
            a1 = abs(v1)
            a2 = abs(v2)
            a3 = abs(v3)
            a0 = a1 if a1 > a0 else a0  # noqa: FURB136 (selects: NaN is caught by BAD)
            a2 = a3 if a3 > a2 else a2  # noqa: FURB136
            a0 = a2 if a2 > a0 else a0  # noqa: FURB136
            z = T[mx, l]
            T[mx2, l] = a0 if a0 > z else z  # noqa: FURB136
        mx, mx2 = mx2, mx
    for x in range(quads, x1):
        for l in range(L):
            v = S[x, l]
            av = abs(v)
            T[BAD, l] += v - v
            z = T[mx, l]
            T[mx2, l] = av if av > z else z  # noqa: FURB136 (a select: NaN never chosen)
        mx, mx2 = mx2, mx
    return mx, mx2


@njit(**OPTS)
def _certify_lanes(S, T, size, r, m, p, d, row, kk, mx, mx2, BAD, ACC, ACC2, Q, THR2, wf,
                   b0, GAP, NORM, compact, shared):  # pragma: no cover - compiled
    """The certificate of :func:`_plan_lanes` for one block of L queries (Mathematics §6).

    ``S`` holds the waypoints of the block (row x: coordinate x of every lane), ``T`` the
    lanes' scratch rows (``mx``, ``mx2``: the alternating running maximum; ``BAD``, ``ACC``,
    ``ACC2``, ``Q``, ``THR2``: the rows of :func:`_plan_lanes`); ``wf[b0 + l]`` are the
    waypoints of lane l as already written to the output; rows ``GAP``, ``NORM``: the smallest
    gap of the column-class test and ``|w|`` (:func:`_prune_plane`'s guess). Adds to row ``BAD`` (a lane
    that is not finite, or whose minimum is not clearly above certify's threshold, goes to the
    scalar kernel) and returns the row of T holding every lane's squared clearance.
    """
    L = S.shape[1]
    # --- certificate: finite, clearance --------------------------------------------------
    # (the obstacle rows, the endpoints and the configurations C_k are copies of the input
    # here -- F(C_k, 1) = C_k + 0 e as values for finite e -- so the scalar kernel's BROKEN
    # checks hold for every lane with finite waypoints, and the pieces 7k -> 7k + 1,
    # 7k + 6 -> 7k + 7 do not move). The largest |coordinate| (certify's scale) and the
    # finiteness test over the rows that hold every value of the waypoints: the
    # configurations (waypoints 7k and the last) and the robots of waypoints 7k + 2 .. 7k + 5.
    # The others are copies, up to the sign of a zero, of these: the obstacles (+ 0.0 at
    # 7k + 3, 7k + 4) and F(C_k, 1) = C_k + 0 e at 7k + 1, 7k + 6 -- unless e has a NaN (e is
    # never infinite), and then the projected robots at 7k + 2 are NaN too. (Every row:
    # 7-9 % of the (3,4,2) and (4,4,2) kernels; these rows are 84 of (3,4,2)'s 144.)
    for l in range(L):
        T[mx, l] = 0.0
    md = m * d
    for k in range(r - 1):
        t0 = 7 * k * row
        mx, mx2 = _max_finite(S, T, t0, t0 + row, mx, mx2, BAD)
        for s in range(2, 6):
            mx, mx2 = _max_finite(S, T, t0 + s * row + md, t0 + (s + 1) * row, mx, mx2, BAD)
    mx, mx2 = _max_finite(S, T, (kk - 1) * row, kk * row, mx, mx2, BAD)
    mn = np.int64(13)  # not the literal 13: numba would compile _pair_plane for it too
    mn2 = np.int64(14)
    for l in range(L):
        z = SURE * T[mx, l]
        T[THR2, l] = z * z if (T[mx, l] > 1e-130) & (T[mx, l] < 1e130) else np.inf
        T[mn, l] = np.inf
    if d == 2 and PRUNE_LANES[0] <= p < PRUNE_LANES[1]:
        # the plane, many points: every pair tested, the few that may reach the minimum
        # evaluated (exactly pruned, blocks of eight lanes)
        mn = _prune_plane(S, T, wf, b0, r, m, p, row, kk, mx, mn, BAD, THR2, GAP, NORM,
                          compact, shared)
    elif _sweeps(p, d):
        # many points: the exact pruned sweep, lane by lane (each lane has its own order)
        _sweep_lanes(wf, b0, T, mx, mn, THR2, BAD, kk, p, m, d)
    elif d == 2:
        # every segment C_k -> C_k+1 (its stationary start and five moving pieces) per pair
        for k in range(r - 1):
            for i in range(p - 1):
                for j in range(max(i + 1, m), p):
                    _pair_plane(S, 7 * k * row, 2 * i, 2 * j, row, T, mn, mn2)
                    mn, mn2 = mn2, mn
        r0 = (kk - 1) * row
        for i in range(p - 1):
            for j in range(max(i + 1, m), p):
                for l in range(L):
                    x0 = S[r0 + 2 * i, l] - S[r0 + 2 * j, l]
                    y0 = S[r0 + 2 * i + 1, l] - S[r0 + 2 * j + 1, l]
                    a = x0 * x0 + y0 * y0
                    z = T[mn, l]
                    T[mn2, l] = a if a < z else z  # noqa: FURB136 (a select: NaN never chosen)
                mn, mn2 = mn2, mn
    else:
        # the pieces that do not move: the squared distance at their start, once per C_k
        # (certify's arithmetic with v = 0 gives exactly this); for d <= 4 _pair_space takes
        # every segment C_k -> C_k+1, this only the last configuration
        for k in range(r - 1 if d <= 4 else 0, r):
            r0 = 7 * k * row
            for i in range(p - 1):
                for j in range(max(i + 1, m), p):
                    for l in range(L):
                        T[ACC, l] = 0.0
                    for c in range(d):
                        for l in range(L):
                            rc = S[r0 + i * d + c, l] - S[r0 + j * d + c, l]
                            T[ACC, l] += rc * rc
                    _fold_min(T, ACC, mn, mn2)
                    mn, mn2 = mn2, mn
        for k in range(r - 1 if d <= 4 else 0):
            for i in range(p - 1):
                for j in range(max(i + 1, m), p):
                    if d == 3:
                        _pair_space(S, 7 * k * row, i * d, j * d, None, None, row, T, mn, mn2)
                    else:
                        _pair_space(S, 7 * k * row, i * d, j * d, i * d + 3, j * d + 3, row,
                                    T, mn, mn2)
                    mn, mn2 = mn2, mn
        R = np.empty((2 * d, L))  # d > 4: the relative position and motion of a pair
        for t in range(kk - 1 if d > 4 else 0):
            if t % 7 == 0 or t % 7 == 6:
                continue
            r0 = t * row
            for i in range(p - 1):
                for j in range(max(i + 1, m), p):
                    for l in range(L):
                        T[ACC, l] = 0.0
                        T[ACC2, l] = 0.0
                    for c in range(d):
                        si = r0 + i * d + c
                        sj = r0 + j * d + c
                        for l in range(L):
                            rc = S[si, l] - S[sj, l]
                            vc = (S[si + row, l] - S[sj + row, l]) - rc
                            R[c, l] = rc
                            R[d + c, l] = vc
                            T[ACC, l] += vc * vc
                            T[ACC2, l] += rc * vc
                    for l in range(L):
                        T[Q, l] = segment_param(-T[ACC2, l], T[ACC, l])
                        T[ACC, l] = 0.0
                    for c in range(d):
                        for l in range(L):
                            qc = R[c, l] + T[Q, l] * R[d + c, l]
                            T[ACC, l] += qc * qc
                    _fold_min(T, ACC, mn, mn2)
                    mn, mn2 = mn2, mn
    for l in range(L):
        T[BAD, l] += 0.0 if T[mn, l] > T[THR2, l] else 1.0
    for i in range(m):
        for j in range(i + 1, m):
            for l in range(L):
                T[ACC, l] = 0.0
            for c in range(d):
                for l in range(L):
                    dc = S[i * d + c, l] - S[j * d + c, l]
                    T[ACC, l] += dc * dc
            for l in range(L):  # a square that may have underflowed: the scalar path
                T[BAD, l] += 0.0 if T[ACC, l] >= OBSTACLE_TINY2 else 1.0
            _fold_min(T, ACC, mn, mn2)
            mn, mn2 = mn2, mn
    return mn


# Where the time of _plan_lanes goes (issue 17 item 3), measured by removing one part at a time
# in throwaway variants (kernel code only, CPU time in one process, 32,768 generic queries, best
# of 20 alternating rounds; a share is the time the variant saves, +-3 % noise):
#   at 2e4589d, the waypoints written to the output element by element: 43 % of (2,4,2),
#     43 % of (3,4,2), 47 % of (4,4,2); the certificate 26 / 33 / 30 %, its pair minima
#     21 / 22 / 23 %. The strided reads of the lanes' rows made the write cost twice a copy.
#   then (the write in 8 x 8 blocks transposed in registers, common.write_lanes; d = 3
#     pairs with three coordinates; before the blocked read, read_lanes): the write
#     36 / 35 / 35 % -- about one copy of the output: memory-bound --, the certificate
#     30 / 34 / 35 % (pair minima 23 / 25 / 25 %: arithmetic, one division per piece and
#     lane), reading the queries 11 / 15 / 10 %, building the waypoint rows 5 / 2 / 7 %, the
#     rest (frame, column classes, projection, lift) about 15 %. Per output float (3,4,2)
#     costs what (2,4,2) does.
#   since: the queries read in blocks too (read_lanes), the next block's output rows
#     prefetched (write_lanes), the scale and finiteness from 84 of (3,4,2)'s 144 rows
#     (_max_finite: every row was 7-9 %). Kernel against 2e4589d, CPU time, one process,
#     best of 30 (benchmarks/kernel_ab.py): (2,4,2) 0.84, (3,4,2) 0.81, (4,4,2) 0.84; against
#     8632269: 0.85, 0.66, 0.68.
@njit(**OPTS)
def _plan_lanes(obstacles, first, last, middle, lift, wp, domain, strata, clearance, flags, todo,
               L, compact, shared):  # pragma: no cover - compiled
    """Plan and certify the *generic* queries of a chunk, ``L`` queries at a time (SIMD).

    The same computation as :func:`plan_queries`, operation for operation (so the results are bitwise
    the same), restricted to the case every query of a random batch is in: every configuration
    in the top stratum (all projections pairwise farther apart than the filter bound, so
    ``cp(C_k) = m + n``, ``cp_o = m`` and the desingularization of paper (3.2) moves nothing), not
    at the pole ``e == N`` (odd d), finite waypoints, every float minimum distance above
    certify's suspect threshold. The data are laid out lanes-innermost -- row ``x`` of the
    scratch ``S`` holds coordinate x of the waypoints of L queries -- so that every loop over
    the lanes is one vectorised loop without branches (selects only, minima and maxima in two
    alternating rows, the "undecided" test accumulated as a float: ``v - v`` is NaN unless v is
    finite). The waypoints are then written query after query into ``wp``.

    Queries that are not generic -- and the last ``B mod L`` -- are listed in ``todo`` (their
    count is returned) for :func:`plan_queries`, which decides them exactly (and validates them:
    a query with a non-finite coordinate or two equal points is never generic). Arguments as
    :func:`plan_queries` (without ``validate``, ``tab``) plus ``todo`` int64 (B,) and ``L``.
    """
    nb, m, d = obstacles.shape
    n = first.shape[1]
    r = middle.shape[0] + 2
    p = m + n
    kk = wp.shape[1]
    row = p * d
    size = kk * row
    md = m * d
    nd = n * d
    of = obstacles.reshape((nb, md))
    ff = first.reshape((nb, nd))
    lf = last.reshape((nb, nd))
    mf = middle.reshape((r - 2, nb, nd))
    wf = wp.reshape((nb, size))
    odd = d % 2 == 1
    Y = np.empty((r * row, L))  # configuration k, point i, coordinate c: row (k p + i) d + c
    S = np.empty((size, L))  # waypoint t, point i, coordinate c: row (t p + i) d + c
    X1 = np.empty((r * nd, L))  # robot j of F(C_k, 1): row (k n + j) d + c
    X2 = np.empty((r * nd, L))  # robot j of phi(F(C_k, 1), 1)
    OFF = np.empty((nd, L))  # the lift of robot j: row j d + c
    CV = np.empty((r * n, L))  # robot j's projection in C_k (row k n + j), for the chains
    KQ = np.empty((n, L))  # robot j's lane on its side
    kv = np.empty((r, n))
    lane = np.empty(n, np.int64)
    rorder = np.empty(n, np.int64)
    tail = np.empty(n, np.int64)
    bk = np.empty(n, np.int64)
    cnt = np.empty(n + 1, np.int64)
    W = np.empty((d, L))
    E = np.empty((d, L))
    NU = np.empty((d, L))
    H = np.empty((d, L))
    V = np.empty((p, L))
    T = np.empty((19, L))
    HP = 17  # the compact lanes' obstacle heights H_+, H_- (Mathematics §4.4)
    HM = 18
    BAD = 3
    NORM = 4
    ACC = 5
    ACC2 = 6
    THR = 7
    SC = 8
    Q = 9
    THR2 = 10
    GAP = 16  # the smallest gap of the column-class test over the configurations
    # (_prune_plane's guess on the paper's lanes: the column-class test's gap)
    gap_guess = d == 2 and PRUNE_LANES[0] <= p < PRUNE_LANES[1] and not compact
    nt = 0
    nfull = nb // L
    dom = 2 - (r - 1) * m + r * p
    for blk in range(nfull):
        b0 = blk * L
        # --- the configurations, lanes innermost (8 x 8 blocks transposed in registers; read
        # element by element, this was 10-15 % of the kernel's time: blocked, (4,4,2) is 4 %
        # faster, (2,4,2) 2 %; (3,4,2), whose rows are 6 and 12 long, unchanged) ------------
        read_lanes(of, b0, L, md, Y, 0)
        read_lanes(ff, b0, L, nd, Y, md)
        read_lanes(lf, b0, L, nd, Y, (r - 1) * row + md)
        for k in range(1, r - 1):
            read_lanes(mf[k - 1], b0, L, nd, Y, k * row + md)
        for k in range(1, r):
            for x in range(md):
                for l in range(L):
                    Y[k * row + x, l] = Y[x, l]
        for l in range(L):
            T[BAD, l] = 0.0
        # --- the frame: w = o2 - o1, e, |w|, nu(e) ------------------------------------------
        for c in range(d):
            for l in range(L):
                W[c, l] = Y[d + c, l] - Y[c, l]
        _unit_rows(W, d, E, T)
        for l in range(L):
            T[NORM, l] = 0.0
        for c in range(d):
            for l in range(L):
                T[NORM, l] += W[c, l] * E[c, l]
        if not odd:
            for c in range(0, d, 2):
                for l in range(L):
                    NU[c, l] = -E[c + 1, l] + 0.0
                    NU[c + 1, l] = E[c, l] + 0.0
        else:
            # the pole e == N is left to the scalar kernel
            for l in range(L):
                T[ACC, l] = 1.0 if W[d - 1, l] > 0 else 0.0
            for c in range(d - 1):
                for l in range(L):
                    T[ACC, l] = 0.0 if W[c, l] != 0 else T[ACC, l]
            for l in range(L):
                T[BAD, l] += T[ACC, l]
            _unit_rows(W, d - 1, H, T)
            for c in range(d - 1):
                for l in range(L):
                    NU[c, l] = -(H[0, l] * H[c, l]) * (1.0 + E[d - 1, l])
            for l in range(L):
                NU[0, l] += 1.0
                NU[d - 1, l] = E[0, l]
            for c in range(d):
                for l in range(L):
                    NU[c, l] = NU[c, l] + 0.0
        # --- column classes: only the generic case, every point its own column --------------
        mx = 11
        mx2 = 12
        if gap_guess:
            for l in range(L):
                T[GAP, l] = np.inf
        for k in range(r):
            yk = k * row
            for l in range(L):
                T[mx, l] = 0.0
            for i in range(p):
                for l in range(L):
                    T[ACC, l] = 0.0
                    T[ACC2, l] = 0.0
                for c in range(d):
                    for l in range(L):
                        t = (Y[yk + i * d + c, l] - Y[yk + c, l]) * W[c, l]
                        T[ACC, l] += t
                        T[ACC2, l] += abs(t)
                for l in range(L):
                    v = T[ACC, l]
                    V[i, l] = v
                    T[BAD, l] += v - v  # NaN unless finite
                    a = T[ACC2, l]
                    z = T[mx, l]
                    T[mx2, l] = z if a <= z else a  # noqa: FURB136 (a select: NaN never chosen)
                mx, mx2 = mx2, mx
            mn = 13
            mn2 = 14
            for l in range(L):
                bound = (d + 2) * 1.01 * U * T[mx, l] + (d + 1) * TINY
                T[BAD, l] += bound - bound
                T[THR, l] = 2.0 * (2.0 * bound) * (1 + 4 * U)
                T[mn, l] = np.inf
            for i in range(1, p):
                for j in range(i):
                    for l in range(L):
                        df = abs(V[i, l] - V[j, l])
                        z = T[mn, l]
                        T[mn2, l] = df if df < z else z  # noqa: FURB136 (a select: NaN never chosen)
                    mn, mn2 = mn2, mn
            for l in range(L):
                T[BAD, l] += 0.0 if T[mn, l] > T[THR, l] else 1.0
            if shared:  # generic: the float order of the projections is exact
                for j in range(n):
                    for l in range(L):
                        CV[k * n + j, l] = V[m + j, l]
            if gap_guess:  # (own loop: a select written back into its row costs (2,1,2) 5 %)
                for l in range(L):
                    z = T[GAP, l]
                    T[GAP, l] = T[mn, l] if T[mn, l] < z else z  # noqa: FURB136
            # desingularization of paper (3.2) moves nothing here (cp = cp_o + n), projection
            # paper (3.6)
            for j in range(n):
                for l in range(L):
                    T[ACC, l] = 0.0
                for c in range(d):
                    yj = yk + (m + j) * d + c
                    x1 = (k * n + j) * d + c
                    for l in range(L):
                        xc = Y[yj, l] + 0.0 * E[c, l]
                        X1[x1, l] = xc
                        T[ACC, l] += (xc - Y[yk + c, l]) * E[c, l]
                for c in range(d):
                    x2 = (k * n + j) * d + c
                    for l in range(L):
                        X2[x2, l] = Y[yk + c, l] + T[ACC, l] * E[c, l]
                if compact and d > 2:  # the offsets (plan_queries, operation for operation)
                    for l in range(L):
                        T[ACC, l] = 0.0
                    for c in range(d):
                        x2 = (k * n + j) * d + c
                        for l in range(L):
                            T[ACC, l] += (X1[x2, l] - X2[x2, l]) * NU[c, l]
                    for c in range(d):
                        x2 = (k * n + j) * d + c
                        for l in range(L):
                            X2[x2, l] = X2[x2, l] + ((X1[x2, l] - X2[x2, l]) - T[ACC, l] * NU[c, l])
        # a block with few generic queries (a degenerate batch) goes to the scalar kernel at
        # once: finishing the block costs about what the scalar kernel takes for L / 3 queries
        ngood = 0
        for l in range(L):
            ngood += T[BAD, l] == 0
        if 3 * ngood < L:
            for l in range(L):
                todo[nt] = b0 + l
                nt += 1
            continue
        # --- lambda (Mathematics §4.2), for the paper's lanes only (the rows mx, mx2 are the
        # certificate's scratch after this, which sets them first) ------------------------------
        if not compact:
            for l in range(L):
                T[mx, l] = 0.0
            for i in range(2, m):
                for l in range(L):
                    T[SC, l] = 0.0
                    T[Q, l] = 0.0
                for c in range(d):
                    for l in range(L):
                        T[SC, l] += (Y[i * d + c, l] - Y[c, l]) * E[c, l]
                for c in range(d):
                    for l in range(L):
                        rc = (Y[i * d + c, l] - Y[c, l]) - T[SC, l] * E[c, l]
                        T[Q, l] += rc * rc
                for l in range(L):
                    qq = math.sqrt(T[Q, l])
                    z = T[mx, l]
                    T[mx2, l] = qq if (qq > z) | (i == 2) | math.isnan(qq) else z
                mx, mx2 = mx2, mx
        # the unit: lift, or the obstacles' radius u(O) of every lane (lift="scene", see plan_queries)
        UNIT = 15
        if lift > 0:
            for l in range(L):
                T[UNIT, l] = lift
        else:
            for i in range(1, m):
                for l in range(L):
                    T[ACC, l] = 0.0
                for c in range(d):
                    for l in range(L):
                        dc = Y[i * d + c, l] - Y[c, l]
                        T[ACC, l] += dc * dc
                for l in range(L):
                    sq = T[ACC, l]
                    z = T[UNIT, l]
                    T[UNIT, l] = sq if (sq > z) | (i == 1) | math.isnan(sq) else z
            for l in range(L):
                T[UNIT, l] = math.sqrt(T[UNIT, l])
        if compact:  # (plan_queries, operation for operation)
            for l in range(L):
                T[HP, l] = 0.0
                T[HM, l] = 0.0
            for i in range(2, m):
                for l in range(L):
                    T[SC, l] = 0.0
                for c in range(d):
                    for l in range(L):
                        T[SC, l] += (Y[i * d + c, l] - Y[c, l]) * NU[c, l]
                for l in range(L):
                    t = T[SC, l]
                    z = T[HP, l]
                    T[HP, l] = t if t > z else z
                    z = T[HM, l]
                    T[HM, l] = -t if -t > z else z
            # the shared lanes' chains (plan_queries' _lane_chains), lane by lane (generic:
            # the projections are distinct and their float order is exact)
            if shared:
                for l in range(L):
                    for k in range(r):
                        for j in range(n):
                            kv[k, j] = CV[k * n + j, l]
                    _bucket_sort(kv[0], rorder, n, bk, cnt)
                    _lane_chains(kv, r, n, rorder, lane, tail, shared)
                    for j in range(n):
                        KQ[j, l] = float(lane[j])
            else:
                for j in range(n):
                    for l in range(L):
                        KQ[j, l] = float(j // 2 + 1)
            for j in range(n):
                if j % 2 == 0 or shared == 1:
                    for c in range(d):
                        for l in range(L):
                            OFF[j * d + c, l] = (T[HP, l] + T[UNIT, l] * KQ[j, l]) * NU[c, l]
                else:
                    for c in range(d):
                        for l in range(L):
                            OFF[j * d + c, l] = (-(T[HM, l] + T[UNIT, l] * KQ[j, l])) * NU[c, l]
        else:
            for j in range(n):
                for c in range(d):
                    for l in range(L):
                        OFF[j * d + c, l] = ((T[UNIT, l] + T[mx, l]) * float(j + 1)) * NU[c, l]
        # --- the waypoints (Remark 2.5) ------------------
        direct = compact and d == 2  # the direct lift (obstacle_line.two_configuration_path)
        for k in range(r - 1):
            for s in range(7):
                t0 = (7 * k + s) * row
                lifted = s == 3 or s == 4
                for x in range(md):
                    if lifted:
                        for l in range(L):
                            S[t0 + x, l] = Y[x, l] + 0.0
                    else:
                        for l in range(L):
                            S[t0 + x, l] = Y[x, l]
                for x in range(nd):
                    if s == 0:
                        for l in range(L):
                            S[t0 + md + x, l] = Y[k * row + md + x, l]
                    elif s == 1:
                        for l in range(L):
                            S[t0 + md + x, l] = X1[k * nd + x, l]
                    elif s == 2 and direct:  # (plan_queries: the direct lift)
                        x1 = k * nd + x
                        for l in range(L):
                            S[t0 + md + x, l] = X1[x1, l] + DIRECT_AT * (
                                (X2[x1, l] + OFF[x, l]) - X1[x1, l])
                    elif s == 2:
                        for l in range(L):
                            S[t0 + md + x, l] = X2[k * nd + x, l]
                    elif s == 3:
                        for l in range(L):
                            S[t0 + md + x, l] = X2[k * nd + x, l] + OFF[x, l]
                    elif s == 4:
                        for l in range(L):
                            S[t0 + md + x, l] = X2[(k + 1) * nd + x, l] + OFF[x, l]
                    elif s == 5 and direct:
                        x1 = (k + 1) * nd + x
                        for l in range(L):
                            S[t0 + md + x, l] = X1[x1, l] + DIRECT_AT * (
                                (X2[x1, l] + OFF[x, l]) - X1[x1, l])
                    elif s == 5:
                        for l in range(L):
                            S[t0 + md + x, l] = X2[(k + 1) * nd + x, l]
                    else:
                        for l in range(L):
                            S[t0 + md + x, l] = X1[(k + 1) * nd + x, l]
        for x in range(row):
            for l in range(L):
                S[(kk - 1) * row + x, l] = Y[(r - 1) * row + x, l]
        # --- write the waypoints (query after query), before the certificate: the lane sweeps
        # read them there. 8 x 8 blocks transposed in registers (common.write_lanes): element
        # by element, this write was 43-47 % of the kernel's time for (2,4,2), (3,4,2),
        # (4,4,2); blocked, the kernel is 10-13 % faster. (Eight lanes at a time element by
        # element, from 256 values per query, had made (2,16,2) 8-15 % and (2,64,2) 13 %
        # faster than lane by lane, (2,1,2) 26-34 % and (2,4,2) 8 % slower.)
        write_lanes(S, wf, b0, L, size)
        # --- certificate: finite, clearance (:func:`_certify_lanes`) -------------------------
        mn = _certify_lanes(S, T, size, r, m, p, d, row, kk, mx, mx2, BAD, ACC, ACC2, Q, THR2,
                            wf, b0, GAP, NORM, compact, shared)
        # --- the decided queries' records ----------------------------------------------------
        for l in range(L):
            b = b0 + l
            if T[BAD, l] == 0:
                domain[b] = dom
                for k in range(r):
                    strata[b, k] = p
                strata[b, r] = m
                strata[b, r + 1] = 0
                clearance[b] = math.sqrt(T[mn, l])
                flags[b] = 0
            else:
                todo[nt] = b
                nt += 1
    for b in range(nfull * L, nb):
        todo[nt] = b
        nt += 1
    return nt


def plan_chunk(obstacles, first, last, middle, lift, validate, wp, domain, strata, clearance,
               flags, tab, compact=False, shared=0):
    """Plan and certify a chunk of queries of the obstacle-line planner (Mathematics §3, §4.1-§4.3), with
    the index tables ``tab`` of :func:`tables`.

    Parameters and outputs as :func:`plan_queries`. The generic queries are planned by
    :func:`_plan_lanes`, many at a time; :func:`plan_queries` decides the others, and every query of a
    chunk smaller than ``LANES_MIN``. Both compute the same floating-point operations, so which
    one plans a query never shows in the result.

    Plain Python on purpose, as :func:`_build_tables`: a jitted
    caller would have numba link :func:`_plan_lanes` and :func:`plan_queries` into its own module and
    optimise and generate their machine code a second time -- about a quarter of the first
    run's compile time -- for a saving of a few microseconds per chunk (see docs/install.md, "The first
    run compiles the kernels").
    """
    nb, m, d = obstacles.shape
    n = first.shape[1]
    r = middle.shape[0] + 2
    todo = np.empty(nb, np.int64)
    nt = nb
    if nb >= LANES_MIN:
        nt = _plan_lanes(obstacles, first, last, middle, lift, wp, domain, strata, clearance,
                         flags, todo, lanes(r, m, n, d), compact, shared)
    else:
        for b in range(nb):
            todo[b] = b
    if nt:  # (so that a run whose every query is generic never compiles plan_queries)
        plan_queries(obstacles, first, last, middle, lift, validate, wp, domain, strata, clearance,
              flags, tab, todo, nt, compact, shared)


_TABLES: dict = {}


def tables(r: int, m: int, n: int, d: int) -> np.ndarray:
    """The index tables of :func:`plan_queries` for (r, m, n, d), cached (never to be written)."""
    key = (r, m, n, d)
    tab = _TABLES.get(key)
    if tab is None:
        tab = _build_tables(r, m, n, d)
        if len(_TABLES) < 256:
            _TABLES[key] = tab
    return tab


@njit(**OPTS)
def plan_one(obstacles, start, goal, lift, tab, compact, shared):  # pragma: no cover - compiled
    """One query, validated, planned and certified: the lean path of ``pmplan.plan``.

    ``obstacles`` (m, d), ``start``, ``goal`` (n, d), C-contiguous float64; ``tab`` is
    :func:`tables` ``(2, m, n, d)``; ``compact``, ``shared`` as in :func:`plan_queries`. Returns
    ``(waypoints (8, m+n, d), domain, cp(C), cp(C'), cp_o, [e == N], clearance, flags)`` (see
    :func:`plan_queries`, called with ``validate=True``).
    """
    m, d = obstacles.shape
    n = start.shape[0]
    wp = np.empty((1, 8, m + n, d))
    domain = np.empty(1, np.int64)
    strata = np.empty((1, 4), np.int64)
    clearance = np.empty(1)
    flags = np.empty(1, np.uint8)
    validate = m >= 0  # a run-time True: the batch kernel's own specialisation is reused
    sel = np.zeros(1, np.int64)  # (and a run-time count, not the literal 1, for the same reason)
    plan_queries(obstacles.reshape((1, m, d)), start.reshape((1, n, d)), goal.reshape((1, n, d)),
          np.empty((0, 1, n, d)), lift, validate, wp, domain, strata, clearance, flags, tab,
          sel, sel.shape[0], compact, shared)
    return (wp[0], domain[0], strata[0, 0], strata[0, 1], strata[0, 2], strata[0, 3],
            clearance[0], flags[0])
