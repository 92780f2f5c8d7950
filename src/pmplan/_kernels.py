"""Fused numba kernels: the obstacle-line planner and its certificate in one pass per query.

The numpy code of :mod:`pmplan.predicates`, :mod:`pmplan.frame`,
:mod:`pmplan.planners.obstacle_line` and :mod:`pmplan.certify` is the *reference*
implementation. The kernel :func:`plan_obstacle_line` computes, for every query of a chunk and
without any temporary larger than a few rows, exactly what that reference computes:

* the exact column classes of every configuration (SPEC section 1): the float filter of
  :func:`pmplan.predicates.projection_classes` with the same rigorous error bound -- one bound
  per configuration (the maximum over its points), so that comparing *neighbours in the sorted
  order* suffices -- and its error-free second stage (TwoSum / TwoProduct) for the pairs the
  filter cannot decide; ``cp(C)``, ``cp_o``, ``eps(C)``;
* the frame ``e``, ``nu(e)`` (paper Section 3 for even d, SPEC 4a for odd d with the exact
  ``e == N`` case) and ``lambda = lift + max_k |r(o_k)|`` (SPEC 4b);
* the ``7 (r - 1) + 1`` waypoints of paper Remark
  ``constructing-sections-via-deformations-higher-case`` -- desingularization ``(desin)``,
  projection ``(linear-transformation-obs)``, section ``(algorithm-gamma)`` -- written directly
  into the caller's output array (SPEC 4c for r > 2);
* the certificate of SPEC section 5: endpoints, obstacles fixed, finiteness, and the clearance
  (closed-form minimum distance per piece and pair, as :func:`pmplan.certify.clearance`).

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
    is recomputed with the numpy reference.
``SUSPECT``
    a float minimum distance is below ``certify``'s threshold ``1e-9 * scale``: the clearance of
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

try:
    from numba import njit

    AVAILABLE = True
except ImportError:  # pragma: no cover - numba is a dependency; keep the numpy path usable
    AVAILABLE = False

    def njit(*args, **kwargs):
        return lambda f: f

__all__ = [
    "AVAILABLE",
    "FALLBACK",
    "SUSPECT",
    "NONFINITE",
    "BROKEN",
    "INVALID",
    "MAX_D",
    "plan_obstacle_line",
    "plan_one",
    "first_coincident",
]

FALLBACK = 1
SUSPECT = 2
NONFINITE = 4
BROKEN = 8
INVALID = 16

#: numpy sums fewer than 8 terms sequentially (pairwise, with 8 accumulators, from 8 on): the
#: kernel reproduces the sequential order, so it handles d <= 7; larger d uses the reference
MAX_D = 7

_U = 2.0**-53  # unit roundoff (as in pmplan.predicates)
_TINY = 2.0**-1070
_REL = 1e-9  # as in pmplan.certify
_BIG = 2.0**900  # TwoProduct's split overflows beyond this (as in pmplan.predicates)
_SMALL = 2.0**-900  # below this TwoProduct's error term may underflow (as in pmplan.predicates)


_OPTS = {"cache": True, "nogil": True, "error_model": "numpy"}
_INLINE = {**_OPTS, "inline": "always"}


@njit(**_INLINE)
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
def _exact_sign(y, k, ia, ib, d):  # pragma: no cover - compiled
    """Stage 2 of ``predicates.exact_projection_difference_sign`` for points ia, ib of
    configuration ``y[k]`` (rows 0, 1 are o1, o2): returns (decided, sign of (y_a - y_b).w)."""
    ok = True
    s = 0.0
    for c in range(d):
        t, et = _two_sum(y[k, ia, c], -y[k, ib, c])
        w, ew = _two_sum(y[k, 1, c], -y[k, 0, c])
        p, ep = _two_prod(t, w)
        if et != 0.0 or ew != 0.0 or ep != 0.0:
            ok = False
        if not (abs(t) < _BIG and abs(w) < _BIG and math.isfinite(p)):
            ok = False
        # TwoProduct is error-free only without underflow: an exact zero (a zero factor) or a
        # product whose error term is a normal number
        if not ((p == 0 and (t == 0 or w == 0)) or abs(p) >= _SMALL):
            ok = False
        if c == 0:
            s = p
        else:
            s, es = _two_sum(s, p)
            if es != 0.0:
                ok = False
    if not math.isfinite(s):
        ok = False
    return ok, (s > 0) - (s < 0)


@njit(**_INLINE)
def _classes(y, k, p, m, d, w, vals, order, lab):  # pragma: no cover - compiled
    """Exact column classes of configuration ``y[k]`` (p points, obstacles first).

    Same semantics as :func:`pmplan.predicates.projection_classes`: float projections
    ``(y - o1).w`` with one error bound per configuration (the max over its points), stable
    sort, neighbours farther apart than the bound are distinct, the others are decided by the
    error-free stage (and must not be misordered). Returns ``(decided, cp, cp_o, gap)``; ``decided`` is False where the
    reference would need its exact rational stage (or its full exact pass).
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
    bound = (d + 2) * 1.01 * _U * absum + (d + 1) * _TINY
    if not (finite and math.isfinite(bound)):
        return False, 0, 0, 0.0
    thr = 2.0 * (2.0 * bound) * (1 + 4 * _U)
    # stable insertion sort (numpy's argsort(kind="stable") order)
    for i in range(p):
        order[i] = i
    for i in range(1, p):
        o = order[i]
        key = vals[o]
        j = i - 1
        while j >= 0 and vals[order[j]] > key:
            order[j + 1] = order[j]
            j -= 1
        order[j + 1] = o
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
                return False, 0, 0, 0.0
            eq = sgn == 0
            # a run of >= 2 undecided neighbours with an unequal pair, or a pair the float sort
            # put in the wrong order, needs the full exact pass
            if sgn > 0 or (prev_unc and not (prev_eq and eq)):
                return False, 0, 0, 0.0
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
    return True, label + 1, cp_o, gap


@njit(**_INLINE)
def _clearance_plane(s, kk, p, m, thr2, best):  # pragma: no cover - compiled
    """Squared clearance in the plane (d = 2), branch-free: the generic loop's arithmetic.

    Returns ``(min squared distance, undecided)``; ``undecided`` is True when some squared
    minimum is not above ``thr2``, and the caller then runs the generic loop, which decides
    those minima exactly as :func:`pmplan.certify.clearance` does. ``best`` is scratch (p,).
    """
    for j in range(p):
        best[j] = np.inf
    low = False
    for t in range(kk - 1):
        for i in range(p - 1):
            ax0 = s[t, 0, i]
            ay0 = s[t, 1, i]
            ax1 = s[t + 1, 0, i]
            ay1 = s[t + 1, 1, i]
            for j in range(max(i + 1, m), p):
                rx = ax0 - s[t, 0, j]
                ry = ay0 - s[t, 1, j]
                vx = (ax1 - s[t + 1, 0, j]) - rx
                vy = (ay1 - s[t + 1, 1, j]) - ry
                vv = (0.0 + vx * vx) + vy * vy
                num = -((0.0 + rx * vx) + ry * vy)
                q = num / vv
                q = 1.0 if num >= vv else q
                q = 0.0 if num <= 0 else q
                q = q if vv > 0 else 0.0
                qx = rx + q * vx
                qy = ry + q * vy
                dist2 = (0.0 + qx * qx) + qy * qy
                low |= not dist2 > thr2
                best[j] = dist2 if dist2 < best[j] else best[j]  # noqa: FURB136
    out = np.inf
    for j in range(p):
        if best[j] < out:  # noqa: PLR1730 (explicit compare: NaN is never selected)
            out = best[j]
    return out, low


@njit(**_INLINE)
def _clearance_any(s, kk, p, m, d, thr2, best, vv, rv, tt):  # pragma: no cover - compiled
    """:func:`_clearance_plane` for any d (coordinate loops); scratch arrays of length p."""
    for j in range(p):
        best[j] = np.inf
    low = False
    for t in range(kk - 1):
        for i in range(p - 1):
            j0 = max(i + 1, m)
            for j in range(j0, p):
                vv[j] = 0.0
                rv[j] = 0.0
            for c in range(d):
                a0 = s[t, c, i]
                a1 = s[t + 1, c, i]
                for j in range(j0, p):
                    r0 = a0 - s[t, c, j]
                    vc = (a1 - s[t + 1, c, j]) - r0
                    vv[j] += vc * vc
                    rv[j] += r0 * vc
            for j in range(j0, p):
                num = -rv[j]
                q = num / vv[j]
                q = 1.0 if num >= vv[j] else q
                q = 0.0 if num <= 0 else q
                tt[j] = q if vv[j] > 0 else 0.0
                vv[j] = 0.0  # now the squared distance
            for c in range(d):
                a0 = s[t, c, i]
                a1 = s[t + 1, c, i]
                for j in range(j0, p):
                    r0 = a0 - s[t, c, j]
                    vc = (a1 - s[t + 1, c, j]) - r0
                    qc = r0 + tt[j] * vc
                    vv[j] += qc * qc
            for j in range(j0, p):
                dist2 = vv[j]
                low |= not dist2 > thr2
                best[j] = dist2 if dist2 < best[j] else best[j]  # noqa: FURB136
    out = np.inf
    for j in range(p):
        if best[j] < out:  # noqa: PLR1730 (explicit compare: NaN is never selected)
            out = best[j]
    return out, low


@njit(**_OPTS)
def plan_obstacle_line(obstacles, first, last, middle, lift, validate, wp, domain, strata,
                       clearance, flags):  # pragma: no cover - compiled
    """Plan and certify a chunk of queries of the obstacle-line planner (SPEC 2, 4a-4c).

    Parameters
    ----------
    obstacles : float64 (B, m, d), C-contiguous, d <= MAX_D
    first, last : float64 (B, n, d)
        Robots of the first and last configuration.
    middle : float64 (r - 2, B, n, d)
        Robots of the intermediate configurations (shape (0, B, n, d) when r = 2).
    lift : float
    validate : bool
        Check the input first: a query with a non-finite coordinate or two equal points in one
        of its configurations gets the flag ``INVALID`` and nothing else is computed for it.
    wp : float64 (B, 7 (r - 1) + 1, m + n, d), output
        The waypoints (bitwise those of the numpy reference).
    domain : int64 (B,), output
        ``l = sum_k cp(C_k) - (r - 1) cp_o + 2 - [e == N]``.
    strata : int64 (B, r + 2), output
        ``cp(C_1), ..., cp(C_r), cp_o, [e == N]``.
    clearance : float64 (B,), output
        The certified clearance where ``flags == 0``.
    flags : uint8 (B,), output
        Bit set of ``FALLBACK``, ``SUSPECT``, ``NONFINITE``, ``BROKEN``, ``INVALID``.
    """
    nb, m, d = obstacles.shape
    n = first.shape[1]
    r = middle.shape[0] + 2
    p = m + n
    kk = wp.shape[1]
    w = np.empty(d)
    e = np.empty(d)
    nu = np.empty(d)
    h = np.empty(d)
    vals = np.empty(p)
    order = np.empty(p, np.int64)
    lab = np.empty(p, np.int64)
    cps = np.empty(r, np.int64)
    y = np.empty((r, p, d))  # the configurations C_k (waypoints 7k)
    x1 = np.empty((r, n, d))  # desingularized robots F(C_k, 1)
    x2 = np.empty((r, n, d))  # projected robots phi(F(C_k, 1), 1)
    off = np.empty((n, d))  # the lift i lambda nu(e) of robot i
    s = np.empty((kk, d, p))  # this query's waypoints, coordinate-major (for the clearance)
    vv = np.empty(p)
    rv = np.empty(p)
    tt = np.empty(p)
    d2 = np.empty(p)
    nfl = float(n + m)
    odd = d % 2 == 1
    for b in range(nb):
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
            for k in range(r):
                for i in range(p):
                    for c in range(d):
                        if not math.isfinite(y[k, i, c]):
                            fl = INVALID
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
        else:  # SPEC 4a
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
        # --- columns, desingularization (desin), projection (linear-transformation-obs) -------
        cp_o = 0
        for k in range(r):
            ok, cp, cpo_k, gap = _classes(y, k, p, m, d, w, vals, order, lab)
            if not ok:
                fl |= FALLBACK
                break
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
        if fl:
            flags[b] = fl
            continue
        # --- lambda (SPEC 4b) and the lift of the section (algorithm-gamma) -----------------
        lam = lift
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
            lam = lift + mx
        for j in range(n):
            li = lam * float(j + 1)
            for c in range(d):
                off[j, c] = li * nu[c]
        # --- the waypoints (paper Remark constructing-sections-via-deformations) -----------
        for k in range(r - 1):
            t0 = 7 * k
            for c in range(d):
                for i in range(m):
                    oc = y[0, i, c]
                    s[t0, c, i] = oc
                    s[t0 + 1, c, i] = oc
                    s[t0 + 2, c, i] = oc
                    s[t0 + 3, c, i] = oc + 0.0
                    s[t0 + 4, c, i] = oc + 0.0
                    s[t0 + 5, c, i] = oc
                    s[t0 + 6, c, i] = oc
                for j in range(n):
                    s[t0, c, m + j] = y[k, m + j, c]
                    s[t0 + 1, c, m + j] = x1[k, j, c]
                    s[t0 + 2, c, m + j] = x2[k, j, c]
                    s[t0 + 3, c, m + j] = x2[k, j, c] + off[j, c]
                    s[t0 + 4, c, m + j] = x2[k + 1, j, c] + off[j, c]
                    s[t0 + 5, c, m + j] = x2[k + 1, j, c]
                    s[t0 + 6, c, m + j] = x1[k + 1, j, c]
        for c in range(d):
            for i in range(p):
                s[kk - 1, c, i] = y[r - 1, i, c]
        amax = 0.0
        for t in range(kk):
            for i in range(p):
                for c in range(d):
                    x = s[t, c, i]
                    wp[b, t, i, c] = x
                    a = abs(x)
                    if not a <= amax:
                        amax = a
        # --- certificate (pmplan.certify): finite, obstacles fixed, endpoints ---------------
        if not math.isfinite(amax):
            fl |= NONFINITE
        for t in range(1, kk):
            for c in range(d):
                for i in range(m):
                    if s[t, c, i] != s[0, c, i]:
                        fl |= BROKEN
        for k in range(r):
            for c in range(d):
                for i in range(p):
                    if s[7 * k, c, i] != y[k, i, c]:
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
        # A float squared distance above thr2 is certainly above certify's suspect threshold
        # 1e-9 max(scale, 1e-6 absval) <= 2.0000001e-9 amax; below it, decide as certify does.
        thr2 = np.inf  # (outside that range every minimum is decided as certify does)
        if 1e-130 < amax < 1e130:
            thr2 = (2.1e-9 * amax) * (2.1e-9 * amax)
        best = np.inf
        # a fast branch-free pass; if some minimum is small, the loop below decides as certify
        if d == 2:
            best, check = _clearance_plane(s, kk, p, m, thr2, d2)
        else:
            best, check = _clearance_any(s, kk, p, m, d, thr2, d2, vv, rv, tt)
        if check:
            best = np.inf
            for t in range(kk - 1):
                for i in range(p - 1):
                    j0 = max(i + 1, m)
                    for j in range(j0, p):
                        vv[j] = 0.0
                        rv[j] = 0.0
                    for c in range(d):
                        a0 = s[t, c, i]
                        a1 = s[t + 1, c, i]
                        for j in range(j0, p):
                            r0 = a0 - s[t, c, j]
                            vc = (a1 - s[t + 1, c, j]) - r0
                            vv[j] += vc * vc
                            rv[j] += r0 * vc
                    for j in range(j0, p):
                        num = -rv[j]
                        q = num / vv[j]
                        if num <= 0:
                            q = 0.0
                        elif num >= vv[j]:
                            q = 1.0
                        if not vv[j] > 0:
                            q = 0.0
                        tt[j] = q
                        d2[j] = 0.0
                    for c in range(d):
                        a0 = s[t, c, i]
                        a1 = s[t + 1, c, i]
                        for j in range(j0, p):
                            r0 = a0 - s[t, c, j]
                            vc = (a1 - s[t + 1, c, j]) - r0
                            qc = r0 + tt[j] * vc
                            d2[j] += qc * qc
                    for j in range(j0, p):
                        dist2 = d2[j]
                        if not dist2 > thr2:
                            dist = math.sqrt(dist2)
                            scale = 0.0
                            absval = 0.0
                            for c in range(d):
                                scale = max(scale, abs(s[t, c, i] - s[t, c, j]),
                                            abs(s[t + 1, c, i] - s[t + 1, c, j]))
                                absval = max(absval, abs(s[t, c, i]), abs(s[t, c, j]),
                                             abs(s[t + 1, c, i]), abs(s[t + 1, c, j]))
                            if not dist > _REL * max(scale, absval * 1e-6):
                                fl |= SUSPECT
                        if dist2 < best:  # noqa: PLR1730 (explicit compare: NaN is never selected)
                            best = dist2

        for i in range(m):
            for j in range(i + 1, m):
                dist2 = 0.0
                for c in range(d):
                    dc = s[0, c, i] - s[0, c, j]
                    dist2 += dc * dc
                if dist2 < best:  # noqa: PLR1730 (explicit compare: NaN is never selected)
                    best = dist2
        clearance[b] = math.sqrt(best)
        flags[b] = fl


@njit(**_OPTS)
def plan_one(obstacles, start, goal, lift):  # pragma: no cover - compiled
    """One query, validated, planned and certified: the lean path of ``pmplan.plan``.

    ``obstacles`` (m, d), ``start``, ``goal`` (n, d), C-contiguous float64. Returns
    ``(waypoints (8, m+n, d), domain, cp(C), cp(C'), cp_o, [e == N], clearance, flags)``
    (see :func:`plan_obstacle_line`, called with ``validate=True``).
    """
    m, d = obstacles.shape
    n = start.shape[0]
    wp = np.empty((1, 8, m + n, d))
    domain = np.empty(1, np.int64)
    strata = np.empty((1, 4), np.int64)
    clearance = np.empty(1)
    flags = np.empty(1, np.uint8)
    validate = m >= 0  # a run-time True: the batch kernel's own specialisation is reused
    plan_obstacle_line(obstacles.reshape((1, m, d)), start.reshape((1, n, d)),
                       goal.reshape((1, n, d)), np.empty((0, 1, n, d)), lift, validate, wp,
                       domain, strata, clearance, flags)
    return (wp[0], domain[0], strata[0, 0], strata[0, 1], strata[0, 2], strata[0, 3],
            clearance[0], flags[0])


@njit(**_OPTS)
def first_coincident(obstacles, robots):  # pragma: no cover - compiled
    """Return the first query b whose configuration ``obstacles[b] u robots[b]`` has two equal
    points (compared with ``==``), or -1; shapes (B, m, d) and (B, n, d), C-contiguous."""
    nb, m, d = obstacles.shape
    n = robots.shape[1]
    p = m + n
    for b in range(nb):
        for i in range(p):
            for j in range(i + 1, p):
                same = True
                for c in range(d):
                    a = obstacles[b, i, c] if i < m else robots[b, i - m, c]
                    z = obstacles[b, j, c] if j < m else robots[b, j - m, c]
                    if a != z:
                        same = False
                        break
                if same:
                    return b
    return -1
