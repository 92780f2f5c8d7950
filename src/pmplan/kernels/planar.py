"""Fused numba kernel of the planar three-obstacle planner (paper Section 4, Mathematics §5).

The numpy code of :mod:`pmplan.planners.planar_three` (with :mod:`pmplan.predicates`,
:mod:`pmplan.frame`, :mod:`pmplan.path` and :mod:`pmplan.certify`) is the *reference*. The
kernel computes, for every query of a chunk, in one pass and without any temporary larger than
a few scalars, exactly what that reference computes:

* the exact stratum (paper Section 4, Corollary 4.1): whether o3, x, x' lie on ``L_C``
  (heights ``(y - o1) . rot90(w)`` equal to 0) and which of x, x', o3 share a column with an
  obstacle (columns ``(y - o1) . w``), with the rigorous float filter of
  :func:`pmplan.predicates.projection_values` and, for what it cannot separate, the error-free
  stage (TwoSum / TwoProduct) of :func:`pmplan.predicates.exact_projection_difference_sign`;
  the exact order of the obstacle columns (T23, Figure 10);
* the frame ``e``, ``nu(e)`` of :class:`pmplan.frame.Frame`, the (u, h) coordinates, the
  polyline of the stratum (Figures 6, 7, 8, 9,
  10) mapped to the plane as ``_to_world`` does (start and goal set exactly, the second
  and second-to-last points as displacements from them, equal frame points made equal);
* the constant-speed breakpoints of
  :meth:`pmplan.path.PiecewiseLinearPath.arc_length_reparametrised` (same sums, same order),
  the reversal of the swapped query (T22_32, T23_43) and the padding to WAYPOINTS = 6;
* the certificate of Mathematics §6 (:func:`pmplan.certify.certify`): finite, and the
  clearance -- the closed-form minimum distance of the robot to each obstacle on every piece,
  and the obstacle pairs.

Every floating-point operation is done in the reference's order (sums of two products are
``a + b``, sums over legs are sequential, as numpy's below 8 terms) and no fused multiply-add
or fast-math reassociation is allowed, so waypoints, breakpoints and clearances are **bitwise
identical** to the reference (up to the sign of zero coordinates, which ``==`` does not see).

Two paths, one result. :func:`plan_chunk` (what the planner calls) first runs the SIMD path
:func:`_plan_lanes` (issue 17): the queries the float filter puts in the generic stratum
T23_44 -- every query of a random batch -- are planned :data:`LANES` = 64 at a time, lanes
innermost, with the same floating-point operations as selects (:func:`_lanes_generic`); every
other query goes to the scalar kernel :func:`plan_planar`, which is split into the steps above
(:func:`_classify`, :func:`_polyline`, :func:`_to_world`, :func:`_constant_speed`,
:func:`_reverse`, :func:`_clearance`). Both write the same bits, so which one plans a query
never shows (``tests/test_kernels_planar.py``).

What the kernel does not decide it *flags* (the bits of :mod:`pmplan.kernels.common`); the Python
caller re-decides:

``FALLBACK``
    a decision needs the exact rational stage of :mod:`pmplan.predicates` (the float filter
    and the error-free stage both fail), or something is not finite (``o2 - o1`` overflows, a
    projection or a waypoint is not finite), or ``o1 == o2``: the whole query is recomputed by
    the numpy reference and certified by :func:`pmplan.certify.certify`.
``SUSPECT``
    a float minimum distance is not above ``certify``'s threshold ``1e-9 * scale``: the
    clearance is recomputed by :func:`pmplan.certify.clearance` (exact on that pair).
``INVALID``
    (only when asked to validate) a coordinate is not finite or two points of a configuration
    coincide: nothing is computed, the caller's validation raises the error.
``BROKEN``
    the breakpoints or the endpoints read back from the outputs fail a clause of the
    certificate (never expected: a safety net, the certificate fails).

Numba compiles each kernel once for one signature (float64 C-contiguous arrays) and caches the
machine code on disk (``cache=True``); the kernels release the GIL (``nogil=True``).

References
----------
C. A. Ipanaque Zapata and J. Gonzalez, *Parametrised collision-free optimal motion planning
algorithms in Euclidean spaces*, Section 4.
"""

from __future__ import annotations

import math

import numpy as np

from ..planar_strata import DOMAIN_BY_CODE, FAMILIES, LUT, WAYPOINTS

# shared with the obstacle-line kernel: the error-free transformations, the numba import (with
# its no-numba fallback), the flag bits, the constants of the filter and the certificate, and
# the closed-form distance of a piece
from .common import (
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
    SUSPECT,
    segment_dist2_plane,
    two_prod,
    two_sum,
    njit,
)

__all__ = [
    "AVAILABLE",
    "BROKEN",
    "CODE_LUT",
    "FALLBACK",
    "INVALID",
    "LANES",
    "SUSPECT",
    "plan_chunk",
    "plan_planar",
    "plan_planar_one",
]


# (the waypoints of every path of a batch: one source, the planner's)


#: stratum code (index in planar_three.STRATA) of (family index, i, j); -1: no stratum.
#: Family index 0, 1, 2 = T1, T22, T23. One source: the planner's table (the kernel's branches
#: use the codes of planar_three.STRATA: 0 T1_11, ..., 11 T23_44).
CODE_LUT = LUT
#: the larger helpers :func:`plan_planar` and :func:`_lanes_generic` are split into (and every
#: one that takes an array): inlined by numba before typing (``inline="always"``), so that no
#: call passes an array (numba counts the references of every array argument of a call it does
#: not inline, atomic operations: measured 5-25 % of the scalar kernel) and the vector loop of
#: :func:`_lanes_generic` has no call left (LLVM does not inline the larger ones, and then does
#: not vectorise). The small ones are left to LLVM (:data:`INLINE`): inlining them here too
#: made the first compilation of :func:`plan_planar_one` (CPU time) about 60 % longer than the
#: one-function kernel's instead of about 25 %, for no speed (benchmarks/planar_bench.py
#: measures that compilation, old against new).
_INLINE_IR = {**OPTS, "inline": "always"}
#: rows of the scalar kernel's one scratch array W (WAYPOINTS columns): the polyline in the
#: frame (u, h), the robot's waypoints (x, y) and the breakpoints, before the reversal
_PU, _PH, _QX, _QY, _TM = range(5)
#: the domain W_a of every stratum code (paper (4.1)-(4.3)), the planner's
_DOMAIN = DOMAIN_BY_CODE
_FAMILY = np.array(FAMILIES, dtype=np.int64)



@njit(**OPTS)
def _exact_product_ok(t, r, p, ep):  # pragma: no cover - compiled
    """The conditions of ``predicates.exact_projection_difference_sign`` on one product."""
    if ep != 0.0 or not math.isfinite(p):
        return False
    if not (abs(t) < BIG and abs(r) < BIG):
        return False
    # TwoProduct is error-free only without underflow: an exact zero or a large enough product
    return (p == 0 and (t == 0 or r == 0)) or abs(p) >= SMALL


@njit(**OPTS)
def _esign(ax, ay, bx, by, rx, ry):  # pragma: no cover - compiled
    """Error-free sign of ``(a - b) . r`` for an exactly known direction ``r`` (stage 2 of
    :func:`pmplan.predicates.exact_projection_difference_sign`): ``(decided, sign)``."""
    t0, e0 = two_sum(ax, -bx)
    t1, e1 = two_sum(ay, -by)
    p0, q0 = two_prod(t0, rx)
    p1, q1 = two_prod(t1, ry)
    ok = e0 == 0.0 and e1 == 0.0
    ok = ok and _exact_product_ok(t0, rx, p0, q0) and _exact_product_ok(t1, ry, p1, q1)
    s, es = two_sum(p0, p1)
    ok = ok and es == 0.0 and math.isfinite(s)
    return ok, (s > 0) - (s < 0)


@njit(**OPTS)
def _compare(vi, vj, thr, ax, ay, bx, by, rx, ry, rexact):  # pragma: no cover - compiled
    """Exact sign of ``(a - b) . r`` from float projections ``vi``, ``vj`` (error <= thr/4
    each, as in :func:`pmplan.predicates.projection_classes`), else the error-free stage.
    Returns ``(decided, sign)``."""
    diff = vi - vj
    if diff > thr:
        return True, 1
    if -diff > thr:
        return True, -1
    if not rexact:
        return False, 0
    return _esign(ax, ay, bx, by, rx, ry)


@njit(**OPTS)
def _radius(o1x, o1y, o2x, o2y, o3x, o3y):  # pragma: no cover - compiled
    """``u(O) = sqrt(max(|o2 - o1|^2, |o3 - o1|^2))``, the operations of
    :func:`pmplan.planners.base.scene_unit` (NaN propagates as numpy's maximum does)."""
    dx = o2x - o1x
    dy = o2y - o1y
    q2 = dx * dx + dy * dy
    dx = o3x - o1x
    dy = o3y - o1y
    q3 = dx * dx + dy * dy
    q = q3 if (q3 > q2 or math.isnan(q3)) and not math.isnan(q2) else q2
    return math.sqrt(q)


@njit(**_INLINE_IR)
def _invalid(o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy):  # pragma: no cover - compiled
    """Whether a coordinate is not finite or two points of a configuration coincide (the
    checks of :func:`pmplan.configuration.check_query`, which the caller then raises)."""
    bad = False
    for v in (o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy):
        if not math.isfinite(v):
            bad = True
    if ((o1x == o2x and o1y == o2y) or (o1x == o3x and o1y == o3y)
            or (o2x == o3x and o2y == o3y)):
        bad = True
    for px, py in ((xx, xy), (gx, gy)):
        if ((px == o1x and py == o1y) or (px == o2x and py == o2y)
                or (px == o3x and py == o3y)):
            bad = True
    return bad


@njit(**INLINE)
def _projection(px, py, o1x, o1y, r0, r1):  # pragma: no cover - compiled
    """``((p - o1) . r, |(p_0 - o1_0) r_0| + |(p_1 - o1_1) r_1|)``: a projection and what its
    error bound grows with (:func:`pmplan.predicates.projection_values`)."""
    t0 = (px - o1x) * r0
    t1 = (py - o1y) * r1
    return t0 + t1, abs(t0) + abs(t1)


@njit(**INLINE)
def _larger(a, b):  # pragma: no cover - compiled
    """``max(a, b)`` as a select (b when NaN: then the projection it bounds is not finite, and
    the query falls back either way)."""
    return a if a > b else b  # noqa: FURB136


@njit(**INLINE)
def _threshold(ab):  # pragma: no cover - compiled
    """The filter's error bound of projections whose terms are at most ``ab`` and the
    threshold two of them must differ by to be told apart (:func:`_compare`)."""
    bound = 4 * 1.01 * U * ab + 3 * TINY
    return bound, 2.0 * (2.0 * bound) * (1 + 4 * U)


@njit(**_INLINE_IR)
def _heights(o1x, o1y, o3x, o3y, xx, xy, gx, gy, w0, w1):  # pragma: no cover - compiled
    """The heights ``(y - o1) . rot90(w)`` of o3, x, x' (o1's is 0), their error bound and
    threshold: ``(h3, hx, hx', bound, threshold)``."""
    h3v, ab = _projection(o3x, o3y, o1x, o1y, -w1, w0)
    hxv, a = _projection(xx, xy, o1x, o1y, -w1, w0)
    ab = _larger(a, ab)
    hgv, a = _projection(gx, gy, o1x, o1y, -w1, w0)
    bound, thr = _threshold(_larger(a, ab))
    return h3v, hxv, hgv, bound, thr


@njit(**_INLINE_IR)
def _columns(o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy, w0, w1):  # pragma: no cover - compiled
    """The columns ``(y - o1) . w`` of o2, o3, x, x' (o1's is 0), their error bound and
    threshold: ``(c2, c3, cx, cx', bound, threshold)``."""
    c2v, ab = _projection(o2x, o2y, o1x, o1y, w0, w1)
    c3v, a = _projection(o3x, o3y, o1x, o1y, w0, w1)
    ab = _larger(a, ab)
    cxv, a = _projection(xx, xy, o1x, o1y, w0, w1)
    ab = _larger(a, ab)
    cgv, a = _projection(gx, gy, o1x, o1y, w0, w1)
    bound, thr = _threshold(_larger(a, ab))
    return c2v, c3v, cxv, cgv, bound, thr


@njit(**INLINE)
def _rank(s1, s2, s3, order):  # pragma: no cover - compiled
    """The rank (Figure 10) of the obstacle column a point lies on, -1 for none: ``s1``,
    ``s2``, ``s3`` are the exact signs of its column against those of o1, o2, o3, ``order``
    the obstacles' order (:func:`_classify_columns`)."""
    if s1 == 0:
        return 1 if order == 0 else 0
    if s2 == 0:
        return 2 if order < 2 else 1
    if s3 == 0:
        return order
    return -1


@njit(**_INLINE_IR)
def _classify_columns(o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy, w0, w1,
                      wexact):  # pragma: no cover - compiled
    """Families T22, T23 (o3 off ``L_C``): the exact order of the columns ``(y - o1) . w`` of
    o1 (0), o2, o3, x, x' (paper Section 4, Figure 10). Returns ``(decided, family
    index, i, j, rank of x, rank of x', order)``; ``order`` (T23) is the rank of o3 among the
    obstacle columns: 0 for o3 < o1 < o2, 1 for o1 < o3 < o2, 2 for o1 < o2 < o3."""
    c2v, c3v, cxv, cgv, bound, cthr = _columns(o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy,
                                               w0, w1)
    if not (math.isfinite(bound) and math.isfinite(c2v) and math.isfinite(c3v)
            and math.isfinite(cxv) and math.isfinite(cgv)):
        return False, 0, 0, 0, -1, -1, 0
    # o3 against o1 and o2 (o1 < o2 exactly: (o2 - o1) . w = |w|^2 > 0)
    ok1, s31 = _compare(c3v, 0.0, cthr, o3x, o3y, o1x, o1y, w0, w1, wexact)
    ok2, s32 = _compare(c3v, c2v, cthr, o3x, o3y, o2x, o2y, w0, w1, wexact)
    okx1, sx1 = _compare(cxv, 0.0, cthr, xx, xy, o1x, o1y, w0, w1, wexact)
    okx2, sx2 = _compare(cxv, c2v, cthr, xx, xy, o2x, o2y, w0, w1, wexact)
    okg1, sg1 = _compare(cgv, 0.0, cthr, gx, gy, o1x, o1y, w0, w1, wexact)
    okg2, sg2 = _compare(cgv, c2v, cthr, gx, gy, o2x, o2y, w0, w1, wexact)
    if not (ok1 and ok2 and okx1 and okx2 and okg1 and okg2):
        return False, 0, 0, 0, -1, -1, 0
    if s31 == 0 or s32 == 0:  # cp_o = 2: family T22
        ci = 2 if (sx1 == 0 or sx2 == 0) else 3
        cj = 2 if (sg1 == 0 or sg2 == 0) else 3
        return True, 1, ci, cj, -1, -1, 0
    # cp_o = 3: family T23, obstacle columns in exact order (Figure 10)
    okx3, sx3 = _compare(cxv, c3v, cthr, xx, xy, o3x, o3y, w0, w1, wexact)
    okg3, sg3 = _compare(cgv, c3v, cthr, gx, gy, o3x, o3y, w0, w1, wexact)
    if not (okx3 and okg3):
        return False, 0, 0, 0, -1, -1, 0
    order = 0 if s31 < 0 else (1 if s32 < 0 else 2)
    rank_x = _rank(sx1, sx2, sx3, order)
    rank_g = _rank(sg1, sg2, sg3, order)
    return True, 2, 3 if rank_x >= 0 else 4, 3 if rank_g >= 0 else 4, rank_x, rank_g, order


@njit(**_INLINE_IR)
def _classify(o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy, w0,
              w1):  # pragma: no cover - compiled
    """The exact stratum of a query with ``w = o2 - o1`` finite and nonzero (paper Section 4,
    Corollary 4.1; :func:`pmplan.planners.planar_three.classify`): first the heights
    ``(y - o1) . rot90(w)`` (is o3 on ``L_C``: family T1), then :func:`_classify_columns`.
    Returns ``(decided, family index, i, j, rank of x, rank of x', order)`` (see
    :func:`_classify_columns`); not decided: the exact rational stage is needed (``FALLBACK``)."""
    # w = o2 - o1 is exact (TwoSum errors zero): then the error-free stage applies
    _, ew0 = two_sum(o2x, -o1x)
    _, ew1 = two_sum(o2y, -o1y)
    wexact = ew0 == 0.0 and ew1 == 0.0
    h3v, hxv, hgv, bound, hthr = _heights(o1x, o1y, o3x, o3y, xx, xy, gx, gy, w0, w1)
    if not (math.isfinite(bound) and math.isfinite(h3v) and math.isfinite(hxv)
            and math.isfinite(hgv)):
        return False, 0, 0, 0, -1, -1, 0
    ok, s3 = _compare(h3v, 0.0, hthr, o3x, o3y, o1x, o1y, -w1, w0, wexact)
    if not ok:
        return False, 0, 0, 0, -1, -1, 0
    if s3 != 0:
        return _classify_columns(o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy, w0, w1, wexact)
    # cp_perp_o = 1: o3 on L_C, family T1
    ok1, sx = _compare(hxv, 0.0, hthr, xx, xy, o1x, o1y, -w1, w0, wexact)
    ok2, sg = _compare(hgv, 0.0, hthr, gx, gy, o1x, o1y, -w1, w0, wexact)
    if not (ok1 and ok2):
        return False, 0, 0, 0, -1, -1, 0
    return True, 0, 1 if sx == 0 else 2, 1 if sg == 0 else 2, -1, -1, 0


@njit(**INLINE)
def _frame(w0, w1):  # pragma: no cover - compiled
    """``e = w / |w|`` (scaled first, as :class:`pmplan.frame.Frame`), ``|w| = w . e`` and
    ``nu(e) = rot90(e)``: ``(e0, e1, norm, nu0, nu1)``; ``w`` finite and nonzero."""
    scale = abs(w0)
    if abs(w1) > scale:  # noqa: PLR1730 (w is finite here)
        scale = abs(w1)
    ws0 = w0 / scale
    ws1 = w1 / scale
    nn = math.sqrt(ws0 * ws0 + ws1 * ws1)
    e0 = ws0 / nn
    e1 = ws1 / nn
    return e0, e1, w0 * e0 + w1 * e1, -e1 + 0.0, e0 + 0.0


@njit(**INLINE)
def _coordinates(px, py, o1x, o1y, e0, e1, nu0, nu1):  # pragma: no cover - compiled
    """The frame coordinates ``(u, h) = ((p - o1) . e, (p - o1) . nu)`` of a point p."""
    r0 = px - o1x
    r1 = py - o1y
    return r0 * e0 + r1 * e1, r0 * nu0 + r1 * nu1


@njit(**INLINE)
def _vertical(r, order, norm, u3, unit):  # pragma: no cover - compiled
    """The column ``s_r`` of the vertical leg past the obstacle column of rank ``r`` (Figure
    10): ``s1 = (c1 + c2) / 2``, ``s2 = (c2 + c3) / 2``, ``s3 = c3 + unit`` for the
    obstacle columns c1 < c2 < c3 (0, ``norm``, ``u3`` in ``order``)."""
    c0 = u3 if order == 0 else 0.0
    c1 = 0.0 if order == 0 else (u3 if order == 1 else norm)
    c2 = u3 if order == 2 else norm
    if r == 0:
        return 0.5 * (c0 + c1)
    if r == 1:
        return 0.5 * (c1 + c2)
    return c2 + unit


@njit(**_INLINE_IR)
def _point(W, k, u, h):  # pragma: no cover - compiled
    """Point k of the polyline in the frame: (u, h)."""
    W[_PU, k] = u
    W[_PH, k] = h


@njit(**_INLINE_IR)
def _polyline(code, unit, ua, ha, ub, hb, ra, rb, u3, h3, norm, d13, order,
              W):  # pragma: no cover - compiled
    """The polyline of stratum ``code`` in (u, h) coordinates from a = (ua, ha) to
    b = (ub, hb) (Mathematics §5) into rows ``_PU``, ``_PH`` of ``W``; returns its number of
    points ``kk``.

    ``unit`` is the paper's 1 (``H = unit + max(0, h3)``, ``s3 = c3 + unit``), ``ra``, ``rb``
    the ranks of the obstacle columns a and b lie on and ``order`` the obstacles' (T23),
    ``d13 = |o3 - o1|`` (T1_22)."""
    _point(W, 0, ua, ha)
    if code == 0 or code == 7 or code == 11:  # W1, Figure 6
        big_h = unit + (h3 if h3 > 0.0 else 0.0)  # noqa: FURB136 (np.maximum(0, h3))
        kk = 4
        _point(W, 1, ua, big_h)
        _point(W, 2, ub, big_h)
    elif code == 1 or code == 2:  # T1_12, T1_21, Figure 7
        kk = 2
    elif code == 3 or code == 4:  # T1_22, T22_22, Figure 8
        if code == 3:
            delta = 0.5 * (norm if norm < d13 else d13)  # noqa: FURB136 (np.minimum)
        else:
            delta = 0.5 * norm
        kk = 4
        _point(W, 1, delta, ha)
        _point(W, 2, delta, hb)
    elif code == 5 or code == 6:  # T22_23 (T22_32 swapped), Figure 9
        mid = 0.5 * norm
        h_half = 0.5 * h3
        kk = 5
        _point(W, 1, mid, ha)
        _point(W, 2, mid, h_half)
        _point(W, 3, ub, h_half)
    else:  # T23_33, T23_34 (T23_43 swapped), Figure 10
        sa = _vertical(ra, order, norm, u3, unit)
        h_half = 0.5 * h3
        _point(W, 1, sa, ha)
        _point(W, 2, sa, h_half)
        if code == 8:
            sb = _vertical(rb, order, norm, u3, unit)
            kk = 6
            _point(W, 3, sb, h_half)
            _point(W, 4, sb, hb)
        else:
            kk = 5
            _point(W, 3, ub, h_half)
    _point(W, kk - 1, ub, hb)
    return kk


@njit(**INLINE)
def _displaced(px, py, du, dh, e0, e1, nu0, nu1):  # pragma: no cover - compiled
    """The point p moved by ``du e + dh nu`` (``planar_three._to_world``'s order)."""
    return (px + du * e0) + dh * nu0, (py + du * e1) + dh * nu1


@njit(**INLINE)
def _select(cond, ax, ay, bx, by):  # pragma: no cover - compiled
    """(ax, ay) where ``cond``, else (bx, by)."""
    return (ax if cond else bx), (ay if cond else by)


@njit(**INLINE)
def _length(x0, y0, x1, y1):  # pragma: no cover - compiled
    """The length of the piece (x0, y0) -> (x1, y1), as the reference computes it."""
    dx = x1 - x0
    dy = y1 - y0
    return math.sqrt(dx * dx + dy * dy)


@njit(**_INLINE_IR)
def _to_world(kk, W, o1x, o1y, e0, e1, nu0, nu1, ax, ay, ua, ha, bx, by, ub,
              hb):  # pragma: no cover - compiled
    """The polyline mapped to the plane as ``planar_three._to_world`` does: start and goal set
    exactly, the second and second-to-last points as displacements from them, equal frame
    points made equal."""
    for i in range(kk):
        W[_QX, i] = (o1x + W[_PU, i] * e0) + W[_PH, i] * nu0
        W[_QY, i] = (o1y + W[_PU, i] * e1) + W[_PH, i] * nu1
    if kk > 2:
        W[_QX, 1], W[_QY, 1] = _displaced(ax, ay, W[_PU, 1] - ua, W[_PH, 1] - ha, e0, e1, nu0,
                                          nu1)
        W[_QX, kk - 2], W[_QY, kk - 2] = _displaced(bx, by, W[_PU, kk - 2] - ub,
                                                    W[_PH, kk - 2] - hb, e0, e1, nu0, nu1)
    W[_QX, 0] = ax
    W[_QY, 0] = ay
    W[_QX, kk - 1] = bx
    W[_QY, kk - 1] = by
    for i in range(1, kk - 1):
        if W[_PU, i] == W[_PU, i - 1] and W[_PH, i] == W[_PH, i - 1]:
            W[_QX, i] = W[_QX, i - 1]
            W[_QY, i] = W[_QY, i - 1]
    for i in range(kk - 2, 0, -1):
        if W[_PU, i + 1] == W[_PU, i] and W[_PH, i + 1] == W[_PH, i]:
            W[_QX, i] = W[_QX, i + 1]
            W[_QY, i] = W[_QY, i + 1]


@njit(**_INLINE_IR)
def _constant_speed(kk, W, even):  # pragma: no cover - compiled
    """The constant-speed breakpoints of :meth:`pmplan.path.PiecewiseLinearPath.
    arc_length_reparametrised` (same sums, same order) into ``tm``; False when a waypoint or
    the length is not finite."""
    total = 0.0
    W[_TM, 0] = 0.0
    for i in range(kk - 1):
        total += _length(W[_QX, i], W[_QY, i], W[_QX, i + 1], W[_QY, i + 1])
        W[_TM, i + 1] = total
    for i in range(kk):
        if not (math.isfinite(W[_QX, i]) and math.isfinite(W[_QY, i])):
            return False
    if not math.isfinite(total):
        return False
    if total > 0:
        for i in range(kk):
            W[_TM, i] = W[_TM, i] / total
    else:
        for i in range(kk):
            W[_TM, i] = even[kk, i]
    W[_TM, kk - 1] = 1.0
    return True


@njit(**_INLINE_IR)
def _reverse(kk, W):  # pragma: no cover - compiled
    """The reversed path (of the swapped query: T22_32, T23_43): points in reverse order,
    breakpoints ``1 - t`` in reverse order, as :meth:`pmplan.path.PiecewiseLinearPath.reversed`."""
    for t in range(kk // 2):
        u = kk - 1 - t
        W[_QX, t], W[_QX, u] = W[_QX, u], W[_QX, t]
        W[_QY, t], W[_QY, u] = W[_QY, u], W[_QY, t]
    for t in range(kk // 2):
        u = kk - 1 - t
        W[_TM, t], W[_TM, u] = 1.0 - W[_TM, u], 1.0 - W[_TM, t]
    if kk % 2 == 1:
        W[_TM, kk // 2] = 1.0 - W[_TM, kk // 2]


@njit(**_INLINE_IR)
def _clearance(kk, W, o1x, o1y, o2x, o2y, o3x, o3y):  # pragma: no cover - compiled
    """The clearance of :func:`pmplan.certify.clearance` (robot against each obstacle, per
    piece, and the obstacle pairs) and ``SUSPECT`` when a float minimum is not certainly above
    certify's threshold: ``(clearance, flag)``.

    The padding pieces (t >= kk - 1) are constant: they all give the distance at the goal
    (evaluated with q = 0, as certify does; not always bitwise the q = 1 end of the last
    piece), so one evaluation (t = kk - 1) stands for all of them. A float squared distance
    above thr2 is certainly above certify's threshold 1e-9 max(scale, 1e-6 absval) <=
    2.0000001e-9 amax; below it, test as certify does."""
    amax = 0.0
    for v in (o1x, o1y, o2x, o2y, o3x, o3y):
        amax = max(amax, abs(v))
    for t in range(kk):
        amax = max(amax, abs(W[_QX, t]), abs(W[_QY, t]))
    thr2 = np.inf
    if 1e-130 < amax < 1e130:
        thr2 = (SURE * amax) * (SURE * amax)
    fl = 0
    best = np.inf
    for t in range(kk if kk < WAYPOINTS else kk - 1):
        x0 = W[_QX, t]
        y0 = W[_QY, t]
        x1 = W[_QX, t + 1] if t < kk - 1 else x0
        y1 = W[_QY, t + 1] if t < kk - 1 else y0
        for i in range(3):
            ox = o1x if i == 0 else (o2x if i == 1 else o3x)
            oy = o1y if i == 0 else (o2y if i == 1 else o3y)
            rx = ox - x0
            ry = oy - y0
            r1x = ox - x1
            r1y = oy - y1
            dist2 = segment_dist2_plane(rx, ry, r1x, r1y)
            if not dist2 > thr2:
                sc = max(abs(rx), abs(ry), abs(r1x), abs(r1y))
                av = max(abs(ox), abs(oy), abs(x0), abs(y0), abs(x1), abs(y1))
                if not math.sqrt(dist2) > REL * max(sc, av * 1e-6):
                    fl |= SUSPECT
            best = dist2 if dist2 < best else best  # noqa: FURB136
    for dx, dy in ((o1x - o2x, o1y - o2y), (o1x - o3x, o1y - o3y), (o2x - o3x, o2y - o3y)):
        dist2 = dx * dx + dy * dy
        if not dist2 >= OBSTACLE_TINY2:  # the square may have underflowed
            fl |= SUSPECT
        best = dist2 if dist2 < best else best  # noqa: FURB136
    return math.sqrt(best), fl


@njit(**OPTS)
def plan_planar(obstacles, start, goal, even, lift, validate, times, wp, domain, strata,
                clearance, flags, sel, nsel):  # pragma: no cover - compiled
    """Plan and certify the queries ``sel[:nsel]`` of a chunk, one at a time (the scalar
    kernel: every query, exactly; :func:`plan_chunk` hands it what the SIMD path leaves).

    Split into helpers (issue 13 item 3). Measured against the one-function kernel it was, in
    the same process (``benchmarks/planar_bench.py``, RESULTS.md "Planar kernel"): 1.06-1.18
    times its time on generic queries (which a batch of 64 or more plans on the SIMD path),
    0.96-1.10 on the strata mix; the output loop stays inline (as a helper it cost 5-9 %).

    Parameters
    ----------
    obstacles : float64 (B, 3, 2), C-contiguous
    start, goal : float64 (B, 1, 2)
    even : float64 (WAYPOINTS + 1, WAYPOINTS)
        ``even[k, :k] = numpy.linspace(0, 1, k)``: the breakpoints of a path of length 0
        (:meth:`~pmplan.path.PiecewiseLinearPath.arc_length_reparametrised`).
    lift : float
        The paper's unit (the 1 in ``H = 1 + max(0, h3)`` and ``s3 = c3 + 1``) when positive;
        otherwise (``SCENE_CODE`` of :mod:`pmplan.planners.base`, ``lift="scene"``) the
        obstacles' radius ``u(O) = max(|o2 - o1|, |o3 - o1|)`` of each query, computed as
        :func:`pmplan.planners.base.scene_unit` does.
    validate : bool
        Check the input first: a query with a non-finite coordinate or two equal points in
        one of its configurations gets the flag ``INVALID`` and nothing else is computed.
    times : float64 (B, WAYPOINTS), output
        Constant-speed breakpoints, padded with 1.0.
    wp : float64 (B, WAYPOINTS, 4, 2), output
        Waypoints (obstacles in rows 0..2, the robot in row 3), padded with the goal.
    domain : int64 (B,), output
        The domain W_a, a in {1, 2, 3, 4}.
    strata : int64 (B, 3), output
        ``(family, i, j)`` of the stratum T^{family}_{ij}.
    clearance : float64 (B,), output
        The certified clearance where ``flags == 0``.
    flags : uint8 (B,), output
        Bit set of ``FALLBACK``, ``SUSPECT``, ``INVALID``, ``BROKEN``.
    sel : int64 (>= nsel,)
        The rows to plan; the other rows are not touched.
    nsel : int
    """
    W = np.empty((_TM + 1, WAYPOINTS))  # one scratch array: one reference count per call
    for k in range(nsel):
        b = sel[k]
        o1x = obstacles[b, 0, 0]
        o1y = obstacles[b, 0, 1]
        o2x = obstacles[b, 1, 0]
        o2y = obstacles[b, 1, 1]
        o3x = obstacles[b, 2, 0]
        o3y = obstacles[b, 2, 1]
        xx = start[b, 0, 0]
        xy = start[b, 0, 1]
        gx = goal[b, 0, 0]
        gy = goal[b, 0, 1]
        if validate and _invalid(o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy):
            flags[b] = INVALID
            continue
        # --- exact classification (pmplan.predicates, Mathematics §2) ----------------------
        w0 = o2x - o1x
        w1 = o2y - o1y
        if (w0 == 0.0 and w1 == 0.0) or not (math.isfinite(w0) and math.isfinite(w1)):
            flags[b] = FALLBACK
            continue
        ok, fam, ci, cj, rank_x, rank_g, order = _classify(o1x, o1y, o2x, o2y, o3x, o3y, xx,
                                                           xy, gx, gy, w0, w1)
        if not ok:
            flags[b] = FALLBACK
            continue
        code = CODE_LUT[fam, ci, cj]
        # --- frame (pmplan.frame.Frame), (u, h) coordinates, the polyline (Mathematics §5) --
        e0, e1, norm, nu0, nu1 = _frame(w0, w1)
        u3, h3 = _coordinates(o3x, o3y, o1x, o1y, e0, e1, nu0, nu1)
        ux, hx = _coordinates(xx, xy, o1x, o1y, e0, e1, nu0, nu1)
        ug, hg = _coordinates(gx, gy, o1x, o1y, e0, e1, nu0, nu1)
        swap = code == 6 or code == 10  # T22_32, T23_43: reverse of the swapped query's path
        if swap:
            ax, ay, ua, ha, ra = gx, gy, ug, hg, rank_g
            bx, by, ub, hb, rb = xx, xy, ux, hx, rank_x
        else:
            ax, ay, ua, ha, ra = xx, xy, ux, hx, rank_x
            bx, by, ub, hb, rb = gx, gy, ug, hg, rank_g
        unit = lift
        if (code == 0 or code == 7 or code >= 8) and not lift > 0:  # lift="scene": u(O)
            unit = _radius(o1x, o1y, o2x, o2y, o3x, o3y)
        d13 = math.hypot(o3x - o1x, o3y - o1y) if code == 3 else 0.0
        kk = _polyline(code, unit, ua, ha, ub, hb, ra, rb, u3, h3, norm, d13, order, W)
        # --- to the plane, constant speed, reversal -------------------------------------------
        _to_world(kk, W, o1x, o1y, e0, e1, nu0, nu1, ax, ay, ua, ha, bx, by, ub, hb)
        if not _constant_speed(kk, W, even):
            flags[b] = FALLBACK
            continue
        if swap:
            _reverse(kk, W)
        # output: padded to WAYPOINTS (with 1.0 and the goal), obstacles fixed; then clauses
        # 1-9 of the certificate (pmplan.certify.CLAUSES) read back from what was written:
        # finite times from 0 to 1 that never decrease, the start and the goal exactly (the
        # waypoints are finite: checked above; the obstacles are copies). Not a helper: passing
        # times and wp to one cost 5-9 % of the scalar kernel (benchmarks/planar_bench.py).
        for t in range(WAYPOINTS):
            src = t if t < kk else kk - 1
            times[b, t] = W[_TM, t] if t < kk else 1.0
            wp[b, t, 0, 0] = o1x
            wp[b, t, 0, 1] = o1y
            wp[b, t, 1, 0] = o2x
            wp[b, t, 1, 1] = o2y
            wp[b, t, 2, 0] = o3x
            wp[b, t, 2, 1] = o3y
            wp[b, t, 3, 0] = W[_QX, src]
            wp[b, t, 3, 1] = W[_QY, src]
        brk = not (times[b, 0] == 0.0 and times[b, WAYPOINTS - 1] == 1.0)
        for t in range(WAYPOINTS):
            brk |= not abs(times[b, t]) <= MAXF
            if t > 0:
                brk |= not times[b, t] >= times[b, t - 1]
        brk |= not (wp[b, 0, 3, 0] == xx and wp[b, 0, 3, 1] == xy
                    and wp[b, WAYPOINTS - 1, 3, 0] == gx and wp[b, WAYPOINTS - 1, 3, 1] == gy)
        fl = BROKEN if brk else 0  # (a safety net: never expected)
        domain[b] = _DOMAIN[code]
        strata[b, 0] = _FAMILY[fam]
        strata[b, 1] = ci
        strata[b, 2] = cj
        clearance[b], suspect = _clearance(kk, W, o1x, o1y, o2x, o2y, o3x, o3y)
        flags[b] = fl | suspect


#: how many queries :func:`_plan_lanes` plans at once (the lanes of its vector loops); a
#: chunk of fewer queries goes to the scalar kernel whole
LANES = 64
#: the stratum every lane of :func:`_plan_lanes` is in: T23_44 (code 11, Figure 6, domain W1)
_GENERIC = int(CODE_LUT[2, 4, 4])
#: at most this many blocks in a row are handed to the scalar kernel untried (_plan_lanes)
_MAX_SKIP = 32
#: rows of the lanes' scratch: the ten input coordinates, then what the vector loop computes
_O1X, _O1Y, _O2X, _O2Y, _O3X, _O3Y, _XX, _XY, _GX, _GY = range(10)
_Q1X, _Q1Y, _Q2X, _Q2Y, _T1, _T2, _CLR, _BAD = range(10, 18)


@njit(**INLINE)
def _decided(v, thr):  # pragma: no cover - compiled
    """1.0 unless the float filter of :func:`_compare` decides ``v`` (a difference of two
    projections) to be nonzero (``v > thr`` or ``-v > thr``), else 0.0; NaN gives 1.0."""
    return 0.0 if (v > thr) | (-v > thr) else 1.0


@njit(**_INLINE_IR)
def _lane_classes(o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy):  # pragma: no cover - compiled
    """0.0 when the float filter puts the query in T23_44 -- o3 off ``L_C`` and the columns
    of o1, o2, o3, x, x' pairwise apart except x against x' -- with every value finite;
    otherwise a nonzero (or NaN) number. The operations of :func:`_classify` and
    :func:`_classify_columns`, branch-free (what they do not need there is not computed)."""
    w0 = o2x - o1x
    w1 = o2y - o1y
    bad = (w0 - w0) + (w1 - w1)  # NaN unless finite
    bad += 1.0 if (w0 == 0.0) & (w1 == 0.0) else 0.0
    h3v, hxv, hgv, bound, hthr = _heights(o1x, o1y, o3x, o3y, xx, xy, gx, gy, w0, w1)
    bad += (bound - bound) + (h3v - h3v) + (hxv - hxv) + (hgv - hgv)
    bad += _decided(h3v - 0.0, hthr)
    c2v, c3v, cxv, cgv, bound, cthr = _columns(o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy,
                                               w0, w1)
    bad += (bound - bound) + (c2v - c2v) + (c3v - c3v) + (cxv - cxv) + (cgv - cgv)
    bad += _decided(c3v - 0.0, cthr) + _decided(c3v - c2v, cthr)
    bad += _decided(cxv - 0.0, cthr) + _decided(cxv - c2v, cthr) + _decided(cxv - c3v, cthr)
    bad += _decided(cgv - 0.0, cthr) + _decided(cgv - c2v, cthr) + _decided(cgv - c3v, cthr)
    return bad


@njit(**_INLINE_IR)
def _lane_dist2(ox, oy, x0, y0, x1, y1, best, thr2):  # pragma: no cover - compiled
    """``(min(best, d2), 0.0 if d2 > thr2 else 1.0)`` for the squared distance d2 of obstacle
    (ox, oy) to the piece (x0, y0) -> (x1, y1), as :func:`_clearance` computes it."""
    d2 = segment_dist2_plane(ox - x0, oy - y0, ox - x1, oy - y1)
    return (d2 if d2 < best else best), (0.0 if d2 > thr2 else 1.0)  # noqa: FURB136


@njit(**OPTS)
def _lanes_generic(S, even, lift):  # pragma: no cover - compiled
    """The vector loop of :func:`_plan_lanes`: every lane (column) of the scratch ``S`` from
    its ten input rows to its waypoints 1 and 2, breakpoints 1 and 2, clearance and the row
    ``_BAD`` (0.0: the lane is decided here; see :func:`_plan_lanes`).

    The operations of :func:`plan_planar` for stratum T23_44 (W1, Figure 6: the path
    x -> x + (H - hx) nu -> x' + (H - hx') nu -> x', H = unit + max(0, h3)), in its order, as
    selects: :func:`_to_world`'s merging of equal frame points, :func:`_constant_speed`,
    :func:`_clearance` (every float minimum distance certainly above certify's threshold)."""
    for l in range(S.shape[1]):
        o1x = S[_O1X, l]
        o1y = S[_O1Y, l]
        o2x = S[_O2X, l]
        o2y = S[_O2Y, l]
        o3x = S[_O3X, l]
        o3y = S[_O3Y, l]
        xx = S[_XX, l]
        xy = S[_XY, l]
        gx = S[_GX, l]
        gy = S[_GY, l]
        bad = _lane_classes(o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, gx, gy)
        e0, e1, _, nu0, nu1 = _frame(o2x - o1x, o2y - o1y)
        _, h3 = _coordinates(o3x, o3y, o1x, o1y, e0, e1, nu0, nu1)
        ux, hx = _coordinates(xx, xy, o1x, o1y, e0, e1, nu0, nu1)
        ug, hg = _coordinates(gx, gy, o1x, o1y, e0, e1, nu0, nu1)
        unit = lift if lift > 0 else _radius(o1x, o1y, o2x, o2y, o3x, o3y)
        big_h = unit + (h3 if h3 > 0.0 else 0.0)  # noqa: FURB136 (np.maximum(0, h3))
        # _to_world: frame points (ux, hx), (ux, H), (ug, H), (ug, hg)
        q1x, q1y = _displaced(xx, xy, ux - ux, big_h - hx, e0, e1, nu0, nu1)
        q2x, q2y = _displaced(gx, gy, ug - ug, big_h - hg, e0, e1, nu0, nu1)
        # (the merging of equal frame points; a comparison of a value with itself is True in
        # every lane that is decided here, where every value is finite, so it is left out)
        q1x, q1y = _select(big_h == hx, xx, xy, q1x, q1y)
        q2x, q2y = _select(ug == ux, q1x, q1y, q2x, q2y)
        q2x, q2y = _select(hg == big_h, gx, gy, q2x, q2y)
        q1x, q1y = _select(ug == ux, q2x, q2y, q1x, q1y)
        # _constant_speed
        t1 = 0.0 + _length(xx, xy, q1x, q1y)
        t2 = t1 + _length(q1x, q1y, q2x, q2y)
        total = t2 + _length(q2x, q2y, gx, gy)
        bad += ((q1x - q1x) + (q1y - q1y)) + ((q2x - q2x) + (q2y - q2y)) + (total - total)
        pos = total > 0
        t1 = t1 / total if pos else even[4, 1]
        t2 = t2 / total if pos else even[4, 2]
        # _clearance: certify's scale, the pieces 0-1, 1-2, 2-3 and the goal, obstacle pairs
        amax = 0.0
        for v in (o1x, o1y, o2x, o2y, o3x, o3y, xx, xy, q1x, q1y, q2x, q2y, gx, gy):
            a = abs(v)
            amax = a if a > amax else amax  # noqa: FURB136 (finite when accepted)
        z = SURE * amax
        thr2 = z * z if (amax > 1e-130) & (amax < 1e130) else np.inf
        best = np.inf
        for ox, oy in ((o1x, o1y), (o2x, o2y), (o3x, o3y)):
            best, f = _lane_dist2(ox, oy, xx, xy, q1x, q1y, best, thr2)
            bad += f
            best, f = _lane_dist2(ox, oy, q1x, q1y, q2x, q2y, best, thr2)
            bad += f
            best, f = _lane_dist2(ox, oy, q2x, q2y, gx, gy, best, thr2)
            bad += f
            best, f = _lane_dist2(ox, oy, gx, gy, gx, gy, best, thr2)
            bad += f
        for dx, dy in ((o1x - o2x, o1y - o2y), (o1x - o3x, o1y - o3y), (o2x - o3x, o2y - o3y)):
            d2 = dx * dx + dy * dy
            bad += 0.0 if d2 >= OBSTACLE_TINY2 else 1.0  # (may have underflowed)
            best = d2 if d2 < best else best  # noqa: FURB136
        S[_Q1X, l] = q1x
        S[_Q1Y, l] = q1y
        S[_Q2X, l] = q2x
        S[_Q2Y, l] = q2y
        S[_T1, l] = t1
        S[_T2, l] = t2
        S[_CLR, l] = math.sqrt(best)
        S[_BAD, l] = bad


@njit(**OPTS)
def _plan_lanes(obstacles, start, goal, even, lift, times, wp, domain, strata, clearance, flags,
                todo):  # pragma: no cover - compiled
    """Plan and certify the *generic* queries of a chunk, :data:`LANES` at a time (SIMD).

    The same computation as :func:`plan_planar`, operation for operation (so the results are
    bitwise the same), restricted to the stratum every query of a random batch is in: T23_44
    (o3 off ``L_C``, x and x' on no obstacle's column), decided by the float filter alone,
    finite waypoints, every float minimum distance above certify's suspect threshold. The
    queries are copied lanes-innermost into a scratch (row = one coordinate of L queries), the
    vector loop :func:`_lanes_generic` runs over the lanes without branches, and the decided
    queries are written out query after query. The certificate's clauses 1-9 hold for every
    decided lane by construction: the breakpoints are 0, d01 / total, (d01 + d12) / total, 1
    (or ``even``), the end points are copies of the input. Such a query is also valid (finite,
    no two equal points: every column is apart from the others), so ``validate`` changes
    nothing here.

    The other queries of the full blocks of L are listed in ``todo`` (their count is
    returned) for :func:`plan_planar`; :func:`plan_chunk` adds the last ``B mod L``. A batch
    with few generic queries (the strata mix, a degenerate batch) is not tried block after
    block: after a block with fewer than L / 4 decided lanes the next 1, 2, 4, ...,
    :data:`_MAX_SKIP` blocks go to the scalar kernel untried (which plans them the same way:
    only the speed depends on it). Arguments as :func:`plan_planar` (without ``validate``,
    ``sel``, ``nsel``) plus ``todo`` int64 (B,).
    """
    nb = obstacles.shape[0]
    S = np.empty((_BAD + 1, LANES))
    dom = _DOMAIN[_GENERIC]
    fam = _FAMILY[2]
    nt = 0
    nfull = nb // LANES
    skip = 0  # blocks still to hand to the scalar kernel untried
    wait = 1  # blocks to skip after the next poor one
    for blk in range(nfull):
        b0 = blk * LANES
        if skip:
            skip -= 1
            for l in range(LANES):
                todo[nt] = b0 + l
                nt += 1
            continue
        for l in range(LANES):
            b = b0 + l
            S[_O1X, l] = obstacles[b, 0, 0]
            S[_O1Y, l] = obstacles[b, 0, 1]
            S[_O2X, l] = obstacles[b, 1, 0]
            S[_O2Y, l] = obstacles[b, 1, 1]
            S[_O3X, l] = obstacles[b, 2, 0]
            S[_O3Y, l] = obstacles[b, 2, 1]
            S[_XX, l] = start[b, 0, 0]
            S[_XY, l] = start[b, 0, 1]
            S[_GX, l] = goal[b, 0, 0]
            S[_GY, l] = goal[b, 0, 1]
        _lanes_generic(S, even, lift)
        ngood = 0
        for l in range(LANES):
            ngood += S[_BAD, l] == 0.0
        if 4 * ngood < LANES:  # a poor block: skip the next blocks, twice as many each time
            skip = wait
            wait = min(2 * wait, _MAX_SKIP)
        else:
            wait = 1
        for l in range(LANES):
            b = b0 + l
            if S[_BAD, l] != 0.0:
                todo[nt] = b
                nt += 1
                continue
            times[b, 0] = 0.0
            times[b, 1] = S[_T1, l]
            times[b, 2] = S[_T2, l]
            for t in range(3, WAYPOINTS):
                times[b, t] = 1.0
            for t in range(WAYPOINTS):
                for x in range(6):
                    wp[b, t, x // 2, x % 2] = S[x, l]
                r = _XX if t == 0 else (_Q1X if t == 1 else (_Q2X if t == 2 else _GX))
                wp[b, t, 3, 0] = S[r, l]
                wp[b, t, 3, 1] = S[r + 1, l]
            domain[b] = dom
            strata[b, 0] = fam
            strata[b, 1] = 4
            strata[b, 2] = 4
            clearance[b] = S[_CLR, l]
            flags[b] = 0
    return nt


def plan_chunk(obstacles, start, goal, even, lift, validate, times, wp, domain, strata,
               clearance, flags):
    """Plan and certify a chunk of queries of the planar three-obstacle planner.

    Arguments as :func:`plan_planar` without ``sel``, ``nsel`` (every query is planned). The
    generic queries are planned by :func:`_plan_lanes`, :data:`LANES` at a time; the scalar
    kernel :func:`plan_planar` decides the others, and every query of a chunk smaller than
    :data:`LANES`. Both compute the same floating-point operations, so which one plans a query
    never shows in the result.

    Plain Python on purpose (as :func:`pmplan.kernels.obstacle_line.plan_chunk`): a jitted
    caller would have numba compile both kernels into its own module a second time.
    """
    nb = obstacles.shape[0]
    todo = np.arange(nb, dtype=np.int64)
    nt = nb
    if nb >= LANES:
        nt = _plan_lanes(obstacles, start, goal, even, lift, times, wp, domain, strata,
                         clearance, flags, todo)
        rest = nb % LANES  # the last B mod L queries: after the undecided ones
        todo[nt:nt + rest] = np.arange(nb - rest, nb)
        nt += rest
    if nt:  # (so that a run whose every query is generic never compiles plan_planar)
        plan_planar(obstacles, start, goal, even, lift, validate, times, wp, domain, strata,
                    clearance, flags, todo, nt)


@njit(**OPTS)
def plan_planar_one(obstacles, start, goal, even, lift):  # pragma: no cover - compiled
    """One query, validated, planned and certified: the lean path of ``pmplan.plan``.

    ``obstacles`` (3, 2), ``start``, ``goal`` (1, 2), C-contiguous float64; ``lift`` as in
    :func:`plan_planar`. Returns
    ``(times (k,), waypoints (k, 4, 2), domain, family, i, j, clearance, flags)`` where the
    path is already compacted as :meth:`pmplan.path.PiecewiseLinearPath.compact` does (only
    breakpoints strictly after the previous one are kept).
    """
    times = np.empty((1, WAYPOINTS))
    wp = np.empty((1, WAYPOINTS, 4, 2))
    domain = np.empty(1, np.int64)
    strata = np.empty((1, 3), np.int64)
    clearance = np.empty(1)
    flags = np.empty(1, np.uint8)
    validate = obstacles.shape[0] >= 0  # a run-time True: the batch kernel's specialisation
    sel = np.zeros(1, np.int64)  # (and a run-time count, not the literal 1, for the same reason)
    plan_planar(obstacles.reshape((1, 3, 2)), start.reshape((1, 1, 2)),
                goal.reshape((1, 1, 2)), even, lift, validate, times, wp, domain, strata,
                clearance, flags, sel, sel.shape[0])
    keep = np.empty(WAYPOINTS, np.int64)
    kc = 0
    if flags[0] == 0:
        for t in range(WAYPOINTS):
            if t == 0 or times[0, t] - times[0, t - 1] > 0:
                keep[kc] = t
                kc += 1
    tout = np.empty(kc)
    wout = np.empty((kc, 4, 2))
    for q in range(kc):
        tout[q] = times[0, keep[q]]
        for i in range(4):
            for c in range(2):
                wout[q, i, c] = wp[0, keep[q], i, c]
    return (tout, wout, domain[0], strata[0, 0], strata[0, 1], strata[0, 2], clearance[0],
            flags[0])
