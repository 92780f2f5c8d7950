"""Exact predicates on projections: the only decisions a planner takes.

For a configuration with obstacles ``o1, o2`` put ``w = o2 - o1``. The *column* of a point ``y``
is the scalar ``(y - o1) . w`` (a positive multiple of the paper's ``p_C(y)`` coordinate along
``e_C = w/|w|``) and, in the plane, its *height* is ``(y - o1) . rot90(w)`` with
``rot90(w) = (-w_2, w_1)``. Two points share a column iff ``(y_r - y_s) . w == 0``
(Mathematics §2). These equalities decide every stratum, so they are decided **exactly** on the
input floats (which are dyadic rationals); no tolerance is used anywhere.

The fast way (Mathematics §2) is a floating-point filter with a rigorous error bound, in three
stages, all vectorised over a batch:

1. Float filter. Projections are computed in double precision together with a bound on their
   rounding error; after sorting, two neighbouring projections whose difference exceeds the bound
   are certainly distinct. Almost every pair of a generic query is decided here.
2. Error-free evaluation. For the undecided pairs the dot product is re-evaluated with
   error-free transformations (Dekker's TwoProduct, Knuth's TwoSum); when every rounding error
   is exactly zero (always the case for small integer or dyadic coordinates, where degeneracies
   are exact) the float result *is* the exact value.
3. Exact arithmetic. What remains is decided with :class:`fractions.Fraction`.

Nothing here knows about planners.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

__all__ = [
    "projection_values",
    "exact_projection_difference_sign",
    "projection_classes",
]

U = 2.0**-53  # unit roundoff of IEEE double
TINY = 2.0**-1070  # bound on absolute error from gradual underflow of one product


def _direction(o1: np.ndarray, o2: np.ndarray, perpendicular: bool) -> np.ndarray:
    w = o2 - o1
    if perpendicular:
        if w.shape[-1] != 2:
            raise ValueError("heights (perpendicular projections) are defined in the plane only")
        w = np.stack([-w[..., 1], w[..., 0]], axis=-1)
    return w


def projection_values(points, o1, o2, *, perpendicular: bool = False):
    """Return approximate projections ``(y - o1) . w`` and a bound on their rounding error.

    Parameters
    ----------
    points : array_like, shape (B, P, d)
    o1, o2 : array_like, shape (B, d)
    perpendicular : bool
        If True use ``rot90(w)`` (heights, d = 2 only) instead of ``w`` (columns).

    Returns
    -------
    values : ndarray, shape (B, P)
        Floating-point projections.
    bound : ndarray, shape (B,)
        For every query, a number ``E`` with ``|values - exact| <= E`` for all its points
        (``inf`` when an intermediate overflowed).

    Examples
    --------
    >>> v, e = projection_values(np.array([[[0., 0.], [2., 0.], [1., 5.]]]),
    ...                          np.array([[0., 0.]]), np.array([[2., 0.]]))
    >>> v
    array([[0., 4., 2.]])
    >>> bool(e[0] < 1e-14)
    True
    """
    points = np.asarray(points, dtype=float)
    o1 = np.asarray(o1, dtype=float)
    w = _direction(o1, np.asarray(o2, dtype=float), perpendicular)
    rel = points - o1[:, None, :]
    terms = rel * w[:, None, :]
    values = terms.sum(axis=-1)
    d = points.shape[-1]
    absum = np.abs(terms).sum(axis=-1).max(axis=-1, initial=0.0)
    bound = (d + 2) * 1.01 * U * absum + (d + 1) * TINY
    bound = np.where(np.isfinite(bound) & np.isfinite(values).all(axis=-1), bound, np.inf)
    return values, bound


def two_sum(a, b):
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def _split(a):
    c = 134217729.0 * a
    hi = c - (c - a)
    return hi, a - hi


def two_prod(a, b):
    p = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _fraction_dot_sign(ya, yb, o1, o2, perpendicular: bool) -> int:
    w = [Fraction(q) - Fraction(p) for p, q in zip(o1.tolist(), o2.tolist())]
    if perpendicular:
        w = [-w[1], w[0]]
    total = sum((Fraction(a) - Fraction(b)) * c for a, b, c in zip(ya.tolist(), yb.tolist(), w))
    return (total > 0) - (total < 0)


def exact_projection_difference_sign(ya, yb, o1, o2, *, perpendicular: bool = False) -> np.ndarray:
    """Return the exact sign of ``(ya - yb) . w`` (``w = o2 - o1``, or ``rot90(w)``).

    All arguments have shape (Q, d); the result has shape (Q,) and dtype int8 with values in
    {-1, 0, 1}. Decided exactly: stage 2 (error-free evaluation) then stage 3 (fractions).

    Examples
    --------
    The second pair would be 0 in real arithmetic (0.1 - 0.3 + 2 (0.2 - 0.1)), but the
    doubles nearest to 0.1, 0.2, 0.3 give a tiny positive value, and that is what is decided:

    >>> z = np.zeros((2, 2)); o2 = np.array([[1., 2.], [1., 2.]])
    >>> exact_projection_difference_sign(np.array([[-2., 1.], [0.1, 0.2]]),
    ...                                  np.array([[0., 0.], [0.3, 0.1]]), z, o2)
    array([0, 1], dtype=int8)
    """
    ya = np.asarray(ya, dtype=float)
    yb = np.asarray(yb, dtype=float)
    o1 = np.asarray(o1, dtype=float)
    o2 = np.asarray(o2, dtype=float)
    q = ya.shape[0]
    out = np.zeros(q, dtype=np.int8)
    if q == 0:
        return out
    with np.errstate(over="ignore", invalid="ignore"):
        t, et = two_sum(ya, -yb)
        w, ew = two_sum(o2, -o1)
        if perpendicular:
            w = np.stack([-w[:, 1], w[:, 0]], axis=-1)
            ew = np.stack([-ew[:, 1], ew[:, 0]], axis=-1)
        p, ep = two_prod(t, w)
        ok = (et == 0).all(-1) & (ew == 0).all(-1) & (ep == 0).all(-1)
        s = p[:, 0]
        for k in range(1, p.shape[1]):
            s, es = two_sum(s, p[:, k])
            ok &= es == 0
        ok &= np.isfinite(p).all(-1) & np.isfinite(s)
        # the split in TwoProduct overflows for |x| > 2**996: require moderate magnitudes
        ok &= (np.abs(t) < 2.0**900).all(-1) & (np.abs(w) < 2.0**900).all(-1)
        # TwoProduct is error-free only without underflow: a product must be an exact zero
        # (a zero factor) or large enough that its error term is a normal number
        exact_zero = (p == 0) & ((t == 0) | (w == 0))
        ok &= (exact_zero | (np.abs(p) >= 2.0**-900)).all(-1)
    out[ok] = np.sign(s[ok]).astype(np.int8)
    for i in np.flatnonzero(~ok):
        out[i] = _fraction_dot_sign(ya[i], yb[i], o1[i], o2[i], perpendicular)
    return out


def _exact_classes_one(points, o1, o2, perpendicular):
    """Exact equivalence classes of projections of one configuration (fraction arithmetic)."""
    w = [Fraction(q) - Fraction(p) for p, q in zip(o1.tolist(), o2.tolist())]
    if perpendicular:
        w = [-w[1], w[0]]
    fo1 = [Fraction(c) for c in o1.tolist()]
    vals = [sum((Fraction(c) - a) * b for c, a, b in zip(y, fo1, w)) for y in points.tolist()]
    distinct = sorted(set(vals))
    rank = {v: i for i, v in enumerate(distinct)}
    return np.array([rank[v] for v in vals], dtype=np.int64), len(distinct)


def projection_classes(points, o1, o2, *, perpendicular: bool = False):
    """Classify the points of each query by exact equality of their projections.

    Parameters
    ----------
    points : array_like, shape (B, P, d)
        The points of each query (e.g. the m+n points of a configuration).
    o1, o2 : array_like, shape (B, d)
        The obstacles that define the direction ``w = o2 - o1`` (``o2 != o1``).
    perpendicular : bool
        Classify heights ``(y - o1) . rot90(w)`` instead of columns (d = 2 only).

    Returns
    -------
    labels : ndarray of int64, shape (B, P)
        ``labels[b, i] == labels[b, j]`` iff points i and j of query b have exactly the same
        projection. Labels are 0..count-1, numbered in increasing order of projection.
    count : ndarray of int64, shape (B,)
        The number of distinct projections (the paper's cp for columns).
    gap : ndarray of float, shape (B,)
        The smallest difference between two distinct projections (in units of ``|w|``-scaled
        projections: divide by ``|w|`` to get a length), evaluated in floating point: it is
        ``0.0`` when two exactly distinct projections are closer than the float resolution
        (no float path can then separate them: the certificate fails, Mathematics §6), and
        ``inf`` when all projections coincide or when the projections overflow.

    Examples
    --------
    Three collinear robots on the vertical line through o1 share its column (degenerate, exact):

    >>> pts = np.array([[[0, 0], [2, 0], [0, 1], [0, -3], [1, 7]]], dtype=float)
    >>> labels, count, gap = projection_classes(pts, pts[:, 0], pts[:, 1])
    >>> labels, count, gap
    (array([[0, 2, 0, 0, 1]]), array([3]), array([2.]))
    """
    points = np.asarray(points, dtype=float)
    o1 = np.asarray(o1, dtype=float)
    o2 = np.asarray(o2, dtype=float)
    bsz, npts = points.shape[:2]
    with np.errstate(over="ignore", invalid="ignore"):
        values, bound = projection_values(points, o1, o2, perpendicular=perpendicular)
        order = np.argsort(values, axis=1, kind="stable")
        sv = np.take_along_axis(values, order, axis=1)
        diff = sv[:, 1:] - sv[:, :-1]
        certain = diff > 2.0 * (2.0 * bound[:, None]) * (1 + 4 * U)
    uncertain = ~certain
    equal_adj = np.zeros_like(certain)
    bi, ki = np.nonzero(uncertain)
    if bi.size:
        ia = order[bi, ki]
        ib = order[bi, ki + 1]
        sgn = exact_projection_difference_sign(
            points[bi, ia], points[bi, ib], o1[bi], o2[bi], perpendicular=perpendicular
        )
        equal_adj[bi, ki] = sgn == 0
    # a run of >= 2 undecided neighbours containing an unequal pair needs a full exact pass, and
    # so does a pair that the float sort put in the wrong order (labels follow exact order)
    ambiguous = uncertain[:, 1:] & uncertain[:, :-1] & ~(equal_adj[:, 1:] & equal_adj[:, :-1])
    full = ambiguous.any(axis=1) | ~np.isfinite(bound)
    if bi.size:
        misordered = np.zeros(bsz, dtype=bool)
        misordered[bi[sgn > 0]] = True
        full |= misordered
    step = (~equal_adj).astype(np.int64)
    sorted_labels = np.concatenate([np.zeros((bsz, 1), np.int64), np.cumsum(step, axis=1)], axis=1)
    labels = np.empty((bsz, npts), dtype=np.int64)
    np.put_along_axis(labels, order, sorted_labels, axis=1)
    count = sorted_labels[:, -1] + 1 if npts else np.zeros(bsz, np.int64)
    with np.errstate(invalid="ignore"):
        gap = np.where(equal_adj, np.inf, diff).min(axis=1, initial=np.inf)
    for b in np.flatnonzero(full):
        labels[b], count[b] = _exact_classes_one(points[b], o1[b], o2[b], perpendicular)
        vals = values[b]
        with np.errstate(invalid="ignore"):
            dv = np.abs(vals[:, None] - vals[None, :])
            dl = labels[b][:, None] != labels[b][None, :]
            gap[b] = dv[dl].min(initial=np.inf)
    return labels, count, gap
