"""Fused numba kernel of the planar three-obstacle planner (paper Section 4, SPEC section 3).

The numpy code of :mod:`pmplan.planners.planar_three` (with :mod:`pmplan.predicates`,
:mod:`pmplan.frame`, :mod:`pmplan.path` and :mod:`pmplan.certify`) is the *reference*. The
kernel :func:`plan_planar` computes, for every query of a chunk, in one pass and without any
temporary larger than a few scalars, exactly what that reference computes:

* the exact stratum (paper Section 4, Corollary ``lapart``): whether o3, x, x' lie on ``L_C``
  (heights ``(y - o1) . rot90(w)`` equal to 0) and which of x, x', o3 share a column with an
  obstacle (columns ``(y - o1) . w``), with the rigorous float filter of
  :func:`pmplan.predicates.projection_values` and, for what it cannot separate, the error-free
  stage (TwoSum / TwoProduct) of :func:`pmplan.predicates.exact_projection_difference_sign`;
  the exact order of the obstacle columns (T23, Figure ``grid``);
* the frame ``e``, ``nu(e)`` of :class:`pmplan.frame.Frame`, the (u, h) coordinates, the
  polyline of the stratum (Figures ``T111``, ``Tstraight``, ``porenmedio``, ``t2223``,
  ``grid``) mapped to the plane as ``_to_world`` does (start and goal set exactly, the second
  and second-to-last points as displacements from them, equal frame points made equal);
* the constant-speed breakpoints of
  :meth:`pmplan.path.PiecewiseLinearPath.arc_length_reparametrised` (same sums, same order),
  the reversal of the swapped query (T22_32, T23_43) and the padding to WAYPOINTS = 6;
* the certificate of SPEC section 5 (:func:`pmplan.certify.certify`): finite, and the
  clearance -- the closed-form minimum distance of the robot to each obstacle on every piece,
  and the obstacle pairs.

Every floating-point operation is done in the reference's order (sums of two products are
``a + b``, sums over legs are sequential, as numpy's below 8 terms) and no fused multiply-add
or fast-math reassociation is allowed, so waypoints, breakpoints and clearances are **bitwise
identical** to the reference (up to the sign of zero coordinates, which ``==`` does not see).

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

from ..planners.planar_three import _DOMAIN_BY_CODE, _FAMILIES, _LUT, WAYPOINTS

# shared with the obstacle-line kernel: the error-free transformations, the numba import (with
# its no-numba fallback), the flag bits, the constants of the filter and the certificate, and
# the closed-form distance of a piece
from .common import (
    _BIG,
    _MAXF,
    _OBSTACLE_TINY2,
    _OPTS,
    _REL,
    _SMALL,
    _SURE,
    _TINY,
    _U,
    AVAILABLE,
    BROKEN,
    FALLBACK,
    INVALID,
    SUSPECT,
    _segment_dist2_plane,
    _two_prod,
    _two_sum,
    njit,
)

__all__ = [
    "AVAILABLE",
    "BROKEN",
    "CODE_LUT",
    "FALLBACK",
    "INVALID",
    "SUSPECT",
    "plan_planar",
    "plan_planar_one",
]


# (the waypoints of every path of a batch: one source, the planner's)


#: stratum code (index in planar_three.STRATA) of (family index, i, j); -1: no stratum.
#: Family index 0, 1, 2 = T1, T22, T23. One source: the planner's table (the kernel's branches
#: use the codes of planar_three.STRATA: 0 T1_11, ..., 11 T23_44).
CODE_LUT = _LUT
#: the domain W_a of every stratum code (paper (w2)-(w4)), the planner's
_DOMAIN = _DOMAIN_BY_CODE
_FAMILY = np.array(_FAMILIES, dtype=np.int64)



@njit(**_OPTS)
def _exact_product_ok(t, r, p, ep):  # pragma: no cover - compiled
    """The conditions of ``predicates.exact_projection_difference_sign`` on one product."""
    if ep != 0.0 or not math.isfinite(p):
        return False
    if not (abs(t) < _BIG and abs(r) < _BIG):
        return False
    # TwoProduct is error-free only without underflow: an exact zero or a large enough product
    return (p == 0 and (t == 0 or r == 0)) or abs(p) >= _SMALL


@njit(**_OPTS)
def _esign(ax, ay, bx, by, rx, ry):  # pragma: no cover - compiled
    """Error-free sign of ``(a - b) . r`` for an exactly known direction ``r`` (stage 2 of
    :func:`pmplan.predicates.exact_projection_difference_sign`): ``(decided, sign)``."""
    t0, e0 = _two_sum(ax, -bx)
    t1, e1 = _two_sum(ay, -by)
    p0, q0 = _two_prod(t0, rx)
    p1, q1 = _two_prod(t1, ry)
    ok = e0 == 0.0 and e1 == 0.0
    ok = ok and _exact_product_ok(t0, rx, p0, q0) and _exact_product_ok(t1, ry, p1, q1)
    s, es = _two_sum(p0, p1)
    ok = ok and es == 0.0 and math.isfinite(s)
    return ok, (s > 0) - (s < 0)


@njit(**_OPTS)
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


@njit(**_OPTS)
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


@njit(**_OPTS)
def plan_planar(obstacles, start, goal, even, lift, validate, times, wp, domain, strata,
                clearance, flags):  # pragma: no cover - compiled
    """Plan and certify a chunk of queries of the planar three-obstacle planner.

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
        Bit set of ``FALLBACK``, ``SUSPECT``, ``INVALID``.
    """
    nb = obstacles.shape[0]
    pu = np.empty(WAYPOINTS)  # frame polyline (u, h)
    ph = np.empty(WAYPOINTS)
    qx = np.empty(WAYPOINTS)  # the robot's waypoints (before reversal)
    qy = np.empty(WAYPOINTS)
    tm = np.empty(WAYPOINTS)  # breakpoints (before reversal)
    cols = np.empty(3)
    svert = np.empty(3)
    pos = np.empty(3, np.int64)
    for b in range(nb):
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
        if validate:
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
            if bad:
                flags[b] = INVALID
                continue
        # --- exact classification (pmplan.predicates, SPEC section 1) --------------------------
        w0 = o2x - o1x
        w1 = o2y - o1y
        if (w0 == 0.0 and w1 == 0.0) or not (math.isfinite(w0) and math.isfinite(w1)):
            flags[b] = FALLBACK
            continue
        # w = o2 - o1 is exact (TwoSum errors zero): then the error-free stage applies
        _, ew0 = _two_sum(o2x, -o1x)
        _, ew1 = _two_sum(o2y, -o1y)
        wexact = ew0 == 0.0 and ew1 == 0.0
        # heights (y - o1) . rot90(w) of o1 (0), o3, x, x' and their error bound
        t0 = (o3x - o1x) * -w1
        t1 = (o3y - o1y) * w0
        h3v = t0 + t1
        ab = abs(t0) + abs(t1)
        t0 = (xx - o1x) * -w1
        t1 = (xy - o1y) * w0
        hxv = t0 + t1
        ab = max(ab, abs(t0) + abs(t1))
        t0 = (gx - o1x) * -w1
        t1 = (gy - o1y) * w0
        hgv = t0 + t1
        ab = max(ab, abs(t0) + abs(t1))
        bound = 4 * 1.01 * _U * ab + 3 * _TINY
        if not (math.isfinite(bound) and math.isfinite(h3v) and math.isfinite(hxv)
                and math.isfinite(hgv)):
            flags[b] = FALLBACK
            continue
        hthr = 2.0 * (2.0 * bound) * (1 + 4 * _U)
        ok, s3 = _compare(h3v, 0.0, hthr, o3x, o3y, o1x, o1y, -w1, w0, wexact)
        if not ok:
            flags[b] = FALLBACK
            continue
        rank_x = -1
        rank_g = -1
        if s3 == 0:  # cp_perp_o = 1: o3 on L_C, family T1
            fam = 0
            ok1, sx = _compare(hxv, 0.0, hthr, xx, xy, o1x, o1y, -w1, w0, wexact)
            ok2, sg = _compare(hgv, 0.0, hthr, gx, gy, o1x, o1y, -w1, w0, wexact)
            if not (ok1 and ok2):
                flags[b] = FALLBACK
                continue
            ci = 1 if sx == 0 else 2
            cj = 1 if sg == 0 else 2
        else:  # columns (y - o1) . w of o1 (0), o2, o3, x, x'
            t0 = (o2x - o1x) * w0
            t1 = (o2y - o1y) * w1
            c2v = t0 + t1
            ab = abs(t0) + abs(t1)
            t0 = (o3x - o1x) * w0
            t1 = (o3y - o1y) * w1
            c3v = t0 + t1
            ab = max(ab, abs(t0) + abs(t1))
            t0 = (xx - o1x) * w0
            t1 = (xy - o1y) * w1
            cxv = t0 + t1
            ab = max(ab, abs(t0) + abs(t1))
            t0 = (gx - o1x) * w0
            t1 = (gy - o1y) * w1
            cgv = t0 + t1
            ab = max(ab, abs(t0) + abs(t1))
            bound = 4 * 1.01 * _U * ab + 3 * _TINY
            if not (math.isfinite(bound) and math.isfinite(c2v) and math.isfinite(c3v)
                    and math.isfinite(cxv) and math.isfinite(cgv)):
                flags[b] = FALLBACK
                continue
            cthr = 2.0 * (2.0 * bound) * (1 + 4 * _U)
            # o3 against o1 and o2 (o1 < o2 exactly: (o2 - o1) . w = |w|^2 > 0)
            ok1, s31 = _compare(c3v, 0.0, cthr, o3x, o3y, o1x, o1y, w0, w1, wexact)
            ok2, s32 = _compare(c3v, c2v, cthr, o3x, o3y, o2x, o2y, w0, w1, wexact)
            okx1, sx1 = _compare(cxv, 0.0, cthr, xx, xy, o1x, o1y, w0, w1, wexact)
            okx2, sx2 = _compare(cxv, c2v, cthr, xx, xy, o2x, o2y, w0, w1, wexact)
            okg1, sg1 = _compare(cgv, 0.0, cthr, gx, gy, o1x, o1y, w0, w1, wexact)
            okg2, sg2 = _compare(cgv, c2v, cthr, gx, gy, o2x, o2y, w0, w1, wexact)
            if not (ok1 and ok2 and okx1 and okx2 and okg1 and okg2):
                flags[b] = FALLBACK
                continue
            if s31 == 0 or s32 == 0:  # cp_o = 2: family T22
                fam = 1
                ci = 2 if (sx1 == 0 or sx2 == 0) else 3
                cj = 2 if (sg1 == 0 or sg2 == 0) else 3
            else:  # cp_o = 3: family T23, obstacle columns in exact order (Figure grid)
                fam = 2
                okx3, sx3 = _compare(cxv, c3v, cthr, xx, xy, o3x, o3y, w0, w1, wexact)
                okg3, sg3 = _compare(cgv, c3v, cthr, gx, gy, o3x, o3y, w0, w1, wexact)
                if not (okx3 and okg3):
                    flags[b] = FALLBACK
                    continue
                if s31 < 0:  # o3 < o1 < o2
                    pos[0] = 1
                    pos[1] = 2
                    pos[2] = 0
                elif s32 < 0:  # o1 < o3 < o2
                    pos[0] = 0
                    pos[1] = 2
                    pos[2] = 1
                else:  # o1 < o2 < o3
                    pos[0] = 0
                    pos[1] = 1
                    pos[2] = 2
                if sx1 == 0:
                    rank_x = pos[0]
                elif sx2 == 0:
                    rank_x = pos[1]
                elif sx3 == 0:
                    rank_x = pos[2]
                if sg1 == 0:
                    rank_g = pos[0]
                elif sg2 == 0:
                    rank_g = pos[1]
                elif sg3 == 0:
                    rank_g = pos[2]
                ci = 3 if rank_x >= 0 else 4
                cj = 3 if rank_g >= 0 else 4
        code = CODE_LUT[fam, ci, cj]
        # --- frame (pmplan.frame.Frame) and (u, h) coordinates --------------------------------
        scale = abs(w0)
        if abs(w1) > scale:  # noqa: PLR1730 (w is finite here)
            scale = abs(w1)
        ws0 = w0 / scale
        ws1 = w1 / scale
        nn = math.sqrt(ws0 * ws0 + ws1 * ws1)
        e0 = ws0 / nn
        e1 = ws1 / nn
        norm = w0 * e0 + w1 * e1
        nu0 = -e1 + 0.0
        nu1 = e0 + 0.0
        r0 = o3x - o1x
        r1 = o3y - o1y
        u3 = r0 * e0 + r1 * e1
        h3 = r0 * nu0 + r1 * nu1
        r0 = xx - o1x
        r1 = xy - o1y
        ux = r0 * e0 + r1 * e1
        hx = r0 * nu0 + r1 * nu1
        r0 = gx - o1x
        r1 = gy - o1y
        ug = r0 * e0 + r1 * e1
        hg = r0 * nu0 + r1 * nu1
        # --- the polyline of the stratum in (u, h) (SPEC section 3) ---------------------------
        swap = code == 6 or code == 10  # T22_32, T23_43: reverse of the swapped query's path
        if swap:
            ax, ay, ua, ha, ra = gx, gy, ug, hg, rank_g
            bx, by, ub, hb, rb = xx, xy, ux, hx, rank_x
        else:
            ax, ay, ua, ha, ra = xx, xy, ux, hx, rank_x
            bx, by, ub, hb, rb = gx, gy, ug, hg, rank_g
        pu[0] = ua
        ph[0] = ha
        unit = lift
        if (code == 0 or code == 7 or code >= 8) and not lift > 0:  # lift="scene": u(O)
            unit = _radius(o1x, o1y, o2x, o2y, o3x, o3y)
        if code == 0 or code == 7 or code == 11:  # W1, Figure T111
            big_h = unit + (h3 if h3 > 0.0 else 0.0)  # noqa: FURB136 (np.maximum(0, h3))
            kk = 4
            pu[1] = ua
            ph[1] = big_h
            pu[2] = ub
            ph[2] = big_h
        elif code == 1 or code == 2:  # T1_12, T1_21, Figure Tstraight
            kk = 2
        elif code == 3 or code == 4:  # T1_22, T22_22, Figure porenmedio
            if code == 3:
                d13 = math.hypot(o3x - o1x, o3y - o1y)
                delta = 0.5 * (norm if norm < d13 else d13)  # noqa: FURB136 (np.minimum)
            else:
                delta = 0.5 * norm
            kk = 4
            pu[1] = delta
            ph[1] = ha
            pu[2] = delta
            ph[2] = hb
        elif code == 5 or code == 6:  # T22_23 (T22_32 swapped), Figure t2223
            mid = 0.5 * norm
            h_half = 0.5 * h3
            kk = 5
            pu[1] = mid
            ph[1] = ha
            pu[2] = mid
            ph[2] = h_half
            pu[3] = ub
            ph[3] = h_half
        else:  # T23_33, T23_34 (T23_43 swapped), Figure grid
            cols[pos[0]] = 0.0
            cols[pos[1]] = norm
            cols[pos[2]] = u3
            svert[0] = 0.5 * (cols[0] + cols[1])
            svert[1] = 0.5 * (cols[1] + cols[2])
            svert[2] = cols[2] + unit
            sa = svert[ra]
            h_half = 0.5 * h3
            pu[1] = sa
            ph[1] = ha
            pu[2] = sa
            ph[2] = h_half
            if code == 8:
                sb = svert[rb]
                kk = 6
                pu[3] = sb
                ph[3] = h_half
                pu[4] = sb
                ph[4] = hb
            else:
                kk = 5
                pu[3] = ub
                ph[3] = h_half
        pu[kk - 1] = ub
        ph[kk - 1] = hb
        # --- to the plane (planar_three._to_world) --------------------------------------------
        for i in range(kk):
            qx[i] = (o1x + pu[i] * e0) + ph[i] * nu0
            qy[i] = (o1y + pu[i] * e1) + ph[i] * nu1
        if kk > 2:
            du = pu[1] - ua
            dh = ph[1] - ha
            qx[1] = (ax + du * e0) + dh * nu0
            qy[1] = (ay + du * e1) + dh * nu1
            du = pu[kk - 2] - ub
            dh = ph[kk - 2] - hb
            qx[kk - 2] = (bx + du * e0) + dh * nu0
            qy[kk - 2] = (by + du * e1) + dh * nu1
        qx[0] = ax
        qy[0] = ay
        qx[kk - 1] = bx
        qy[kk - 1] = by
        for i in range(1, kk - 1):
            if pu[i] == pu[i - 1] and ph[i] == ph[i - 1]:
                qx[i] = qx[i - 1]
                qy[i] = qy[i - 1]
        for i in range(kk - 2, 0, -1):
            if pu[i + 1] == pu[i] and ph[i + 1] == ph[i]:
                qx[i] = qx[i + 1]
                qy[i] = qy[i + 1]
        # --- constant speed (PiecewiseLinearPath.arc_length_reparametrised) -------------------
        total = 0.0
        tm[0] = 0.0
        finite = True
        for i in range(kk - 1):
            dx = qx[i + 1] - qx[i]
            dy = qy[i + 1] - qy[i]
            total += math.sqrt(dx * dx + dy * dy)
            tm[i + 1] = total
        for i in range(kk):
            if not (math.isfinite(qx[i]) and math.isfinite(qy[i])):
                finite = False
        if not (finite and math.isfinite(total)):
            flags[b] = FALLBACK
            continue
        if total > 0:
            for i in range(kk):
                tm[i] = tm[i] / total
        else:
            for i in range(kk):
                tm[i] = even[kk, i]
        tm[kk - 1] = 1.0
        # --- output: reversal, padding to WAYPOINTS, obstacles fixed -------------------------
        if swap:
            for t in range(kk // 2):
                u = kk - 1 - t
                qx[t], qx[u] = qx[u], qx[t]
                qy[t], qy[u] = qy[u], qy[t]
            for t in range(kk // 2):
                u = kk - 1 - t
                tm[t], tm[u] = 1.0 - tm[u], 1.0 - tm[t]
            if kk % 2 == 1:
                tm[kk // 2] = 1.0 - tm[kk // 2]
        amax = 0.0
        for v in (o1x, o1y, o2x, o2y, o3x, o3y):
            amax = max(amax, abs(v))
        for t in range(WAYPOINTS):
            src = t if t < kk else kk - 1
            times[b, t] = tm[t] if t < kk else 1.0
            wp[b, t, 0, 0] = o1x
            wp[b, t, 0, 1] = o1y
            wp[b, t, 1, 0] = o2x
            wp[b, t, 1, 1] = o2y
            wp[b, t, 2, 0] = o3x
            wp[b, t, 2, 1] = o3y
            wp[b, t, 3, 0] = qx[src]
            wp[b, t, 3, 1] = qy[src]
        for t in range(kk):
            amax = max(amax, abs(qx[t]), abs(qy[t]))
        # --- clauses 1-9 of the certificate (pmplan.certify.CLAUSES), read back from what was
        # written: finite times from 0 to 1 that never decrease, the start and the goal exactly
        # (the waypoints are finite: checked above; the obstacles are copied from the input)
        fl = 0
        brk = not (times[b, 0] == 0.0 and times[b, WAYPOINTS - 1] == 1.0)
        for t in range(WAYPOINTS):
            brk |= not abs(times[b, t]) <= _MAXF
            if t > 0:
                brk |= not times[b, t] >= times[b, t - 1]
        brk |= not (wp[b, 0, 3, 0] == xx and wp[b, 0, 3, 1] == xy
                    and wp[b, WAYPOINTS - 1, 3, 0] == gx and wp[b, WAYPOINTS - 1, 3, 1] == gy)
        if brk:
            fl = BROKEN
        domain[b] = _DOMAIN[code]
        strata[b, 0] = _FAMILY[fam]
        strata[b, 1] = ci
        strata[b, 2] = cj
        # --- clearance (pmplan.certify.clearance): robot against each obstacle, per piece ----
        # The padding pieces (t >= kk - 1) are constant: they all give the distance at the goal
        # (evaluated with q = 0, as certify does; not always bitwise the q = 1 end of the last
        # piece), so one evaluation (t = kk - 1) stands for all of them.
        # A float squared distance above thr2 is certainly above certify's threshold
        # 1e-9 max(scale, 1e-6 absval) <= 2.0000001e-9 amax; below it, test as certify does.
        thr2 = np.inf
        if 1e-130 < amax < 1e130:
            thr2 = (_SURE * amax) * (_SURE * amax)
        best = np.inf
        for t in range(kk if kk < WAYPOINTS else kk - 1):
            x0 = qx[t]
            y0 = qy[t]
            x1 = qx[t + 1] if t < kk - 1 else x0
            y1 = qy[t + 1] if t < kk - 1 else y0
            for i in range(3):
                ox = o1x if i == 0 else (o2x if i == 1 else o3x)
                oy = o1y if i == 0 else (o2y if i == 1 else o3y)
                rx = ox - x0
                ry = oy - y0
                r1x = ox - x1
                r1y = oy - y1
                dist2 = _segment_dist2_plane(rx, ry, r1x, r1y)
                if not dist2 > thr2:
                    sc = max(abs(rx), abs(ry), abs(r1x), abs(r1y))
                    av = max(abs(ox), abs(oy), abs(x0), abs(y0), abs(x1), abs(y1))
                    if not math.sqrt(dist2) > _REL * max(sc, av * 1e-6):
                        fl |= SUSPECT
                best = dist2 if dist2 < best else best  # noqa: FURB136
        for dx, dy in ((o1x - o2x, o1y - o2y), (o1x - o3x, o1y - o3y), (o2x - o3x, o2y - o3y)):
            dist2 = dx * dx + dy * dy
            if not dist2 >= _OBSTACLE_TINY2:  # the square may have underflowed
                fl |= SUSPECT
            best = dist2 if dist2 < best else best  # noqa: FURB136
        clearance[b] = math.sqrt(best)
        flags[b] = fl


@njit(**_OPTS)
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
    plan_planar(obstacles.reshape((1, 3, 2)), start.reshape((1, 1, 2)),
                goal.reshape((1, 1, 2)), even, lift, validate, times, wp, domain, strata,
                clearance, flags)
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
