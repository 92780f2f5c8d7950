"""Exact predicates on projections (Mathematics §2) against an independent Fraction oracle.

The oracle below is written from the definition only: the column of ``y`` is
``(y - o1) . w`` with ``w = o2 - o1`` (``rot90(w) = (-w_2, w_1)`` for heights), evaluated in
rational arithmetic on the input floats (which are dyadic rationals, so ``Fraction(x)`` is exact).
"""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pmplan.predicates import (
    exact_projection_difference_sign,
    projection_classes,
    projection_values,
)

# --------------------------------------------------------------------------------------------
# independent oracle


def exact_direction(o1, o2, perpendicular=False):
    w = [Fraction(q) - Fraction(p) for p, q in zip(o1.tolist(), o2.tolist())]
    if perpendicular:
        w = [-w[1], w[0]]
    return w


def exact_projections(points, o1, o2, perpendicular=False):
    """Exact ``(y - o1) . w`` for points (P, d) of one configuration, as Fractions."""
    w = exact_direction(o1, o2, perpendicular)
    a = [Fraction(c) for c in o1.tolist()]
    return [sum((Fraction(c) - ac) * wc for c, ac, wc in zip(y, a, w)) for y in points.tolist()]


def exact_ranks(values):
    distinct = sorted(set(values))
    rank = {v: i for i, v in enumerate(distinct)}
    return np.array([rank[v] for v in values]), len(distinct)


def exact_sign(ya, yb, o1, o2, perpendicular=False):
    w = exact_direction(o1, o2, perpendicular)
    s = sum((Fraction(a) - Fraction(b)) * c for a, b, c in zip(ya.tolist(), yb.tolist(), w))
    return (s > 0) - (s < 0)


# --------------------------------------------------------------------------------------------
# scenes of many kinds, built from a drawn seed (deterministic under the ci profile)

KINDS = ["random", "integer", "dyadic", "near_tie", "mixed_scale", "huge", "tiny", "subnormal"]


def make_points(kind: str, rng: np.random.Generator, b: int, p: int, d: int) -> np.ndarray:
    """A batch (b, p, d) of points with o1 = points[:, 0] != o2 = points[:, 1]."""
    if kind == "random":
        pts = rng.normal(size=(b, p, d)) * 10.0 ** rng.integers(-3, 4)
    elif kind == "integer":
        pts = rng.integers(-3, 4, size=(b, p, d)).astype(float)
    elif kind == "dyadic":
        pts = rng.integers(-24, 25, size=(b, p, d)) / 8.0 + rng.integers(-4, 5) * 2.0**-30
    elif kind == "near_tie":
        base = rng.normal(size=(b, p, d))
        # every other point copies its predecessor and moves one coordinate by 0 or 1 ulp
        pts = base.copy()
        pts[:, 1::2] = base[:, 0:-1:2] if p % 2 == 0 else base[:, 0:-2:2]
        k = rng.integers(0, d, size=pts[:, 1::2].shape[:2])
        step = rng.choice([-np.inf, 0.0, np.inf], size=k.shape)
        sub = pts[:, 1::2]
        idx = np.indices(k.shape)
        sub[idx[0], idx[1], k] = np.nextafter(sub[idx[0], idx[1], k], step)
        pts[:, 1::2] = sub
        pts[:, 1] = rng.normal(size=(b, d))  # keep o2 generic
    elif kind == "mixed_scale":
        pts = rng.normal(size=(b, p, d)) * 10.0 ** rng.integers(-8, 9, size=(b, p, d))
    elif kind == "huge":
        pts = rng.integers(-3, 4, size=(b, p, d)) * 1e300 + rng.normal(size=(b, p, d)) * 1e299
    elif kind == "tiny":
        pts = rng.integers(-3, 4, size=(b, p, d)) * 1e-300
    elif kind == "subnormal":
        pts = rng.integers(-3, 4, size=(b, p, d)) * 5e-324
    else:  # pragma: no cover
        raise AssertionError(kind)
    same = (pts[:, 0] == pts[:, 1]).all(-1)
    pts[same, 1, 0] = pts[same, 0, 0] + (1e300 if kind == "huge" else 1.0)
    if kind in ("tiny", "subnormal"):
        pts[same, 1, 0] = pts[same, 0, 0] + (1e-300 if kind == "tiny" else 5e-324)
    assert not (pts[:, 0] == pts[:, 1]).all(-1).any()
    return pts


def same_partition(a, b) -> bool:
    return bool(((a[:, None] == a[None, :]) == (b[:, None] == b[None, :])).all())


def check_against_oracle(pts: np.ndarray, perpendicular: bool, ordered: bool = True) -> None:
    """Classes (and, if ``ordered``, their numbering by increasing projection) are exact."""
    o1, o2 = pts[:, 0], pts[:, 1]
    labels, count, gap = projection_classes(pts, o1, o2, perpendicular=perpendicular)
    assert labels.shape == pts.shape[:2] and labels.dtype == np.int64
    assert count.shape == (pts.shape[0],)
    for b in range(pts.shape[0]):
        vals = exact_projections(pts[b], o1[b], o2[b], perpendicular)
        ranks, k = exact_ranks(vals)
        msg = f"query {b}: {pts[b].tolist()}"
        assert same_partition(labels[b], ranks), msg
        assert count[b] == k, msg
        assert sorted(set(labels[b].tolist())) == list(range(k)), msg
        if ordered:  # numbered in increasing order of projection
            np.testing.assert_array_equal(labels[b], ranks, err_msg=msg)


_KIND_PARAMS = [k for k in KINDS if k not in ("tiny", "subnormal")]


@pytest.mark.parametrize("kind", ["tiny", "subnormal"])
def test_tiny_scales_agree_with_fractions(kind):
    """Coordinates ~1e-300 and subnormal: same oracle (deterministic, no shrinking)."""
    for seed in range(3):
        pts = make_points(kind, np.random.default_rng(seed), 6, 5, 2)
        check_against_oracle(pts, perpendicular=False)


@pytest.mark.parametrize("kind", _KIND_PARAMS)
@settings(max_examples=15)
@given(seed=st.integers(0, 2**32 - 1), d=st.integers(2, 5), p=st.integers(2, 9))
def test_columns_agree_with_fractions(kind, seed, d, p):
    pts = make_points(kind, np.random.default_rng(seed), 6, p, d)
    check_against_oracle(pts, perpendicular=False, ordered=True)


@pytest.mark.parametrize("kind", _KIND_PARAMS)
@settings(max_examples=15)
@given(seed=st.integers(0, 2**32 - 1), p=st.integers(2, 9))
def test_heights_agree_with_fractions(kind, seed, p):
    pts = make_points(kind, np.random.default_rng(seed), 6, p, 2)
    check_against_oracle(pts, perpendicular=True, ordered=True)


_NEAR = np.nextafter(0.1, -1.0)
_NEAR_TIE = np.array([[[0.0, 0.0], [1.0, 1.0], [1.0, 0.1], [1.0, _NEAR]]])


def test_label_order_near_tie():
    check_against_oracle(_NEAR_TIE, perpendicular=False, ordered=True)


def test_near_tie_classes_are_distinct():
    check_against_oracle(_NEAR_TIE, perpendicular=False, ordered=False)


def test_gap_is_zero_below_float_resolution():
    """Documented: distinct classes whose float projections coincide give gap 0.0 (eps(C) = 0),
    and such a query cannot be planned in floats: the certificate fails (Mathematics §6)."""
    _, count, gap = projection_classes(_NEAR_TIE, _NEAR_TIE[:, 0], _NEAR_TIE[:, 1])
    assert count[0] == 4
    assert gap[0] == 0.0


@settings(max_examples=40)
@given(
    pts=st.lists(
        st.tuples(st.integers(-3, 3), st.integers(-3, 3), st.integers(-3, 3)), min_size=2,
        max_size=8,
    ).filter(lambda q: q[0] != q[1]),
    scale=st.sampled_from([1.0, 0.125, 2.0**40, 2.0**-40, 3.0]),
)
def test_exact_ties_on_integer_grid(pts, scale):
    """Degenerate integer scenes (scaled exactly or by 3): classes are the exact ones."""
    arr = np.array(pts, dtype=float)[None] * scale
    check_against_oracle(arr, perpendicular=False)
    if (arr[0, 0, :2] != arr[0, 1, :2]).any():
        check_against_oracle(arr[..., :2], perpendicular=True)


def test_underflow_minimal():
    """Minimal case: o1 = (0, 0), o2 = (1e-300, 0); the columns of (0, 0), (1e-300, 0) differ."""
    z = np.zeros((1, 2))
    o2 = np.array([[1e-300, 0.0]])
    ya = np.array([[1e-300, 0.0]])
    assert exact_sign(ya[0], z[0], z[0], o2[0]) == 1
    assert exact_projection_difference_sign(ya, z, z, o2)[0] == 1


def test_underflow_minimal_classes():
    z = np.zeros((1, 2))
    o2 = np.array([[1e-300, 0.0]])
    _, count, _ = projection_classes(np.array([[[0.0, 0.0], [1e-300, 0.0]]]), z, o2)
    assert count[0] == 2


# --------------------------------------------------------------------------------------------
# gap


@pytest.mark.parametrize("kind", ["random", "integer", "dyadic", "near_tie", "mixed_scale"])
@settings(max_examples=15)
@given(seed=st.integers(0, 2**32 - 1), d=st.integers(2, 4), p=st.integers(2, 8))
def test_gap_is_min_difference_of_distinct_projections(kind, seed, d, p):
    pts = make_points(kind, np.random.default_rng(seed), 5, p, d)
    o1, o2 = pts[:, 0], pts[:, 1]
    _, count, gap = projection_classes(pts, o1, o2)
    for b in range(pts.shape[0]):
        vals = sorted(set(exact_projections(pts[b], o1[b], o2[b])))
        if len(vals) == 1:
            assert gap[b] == np.inf
            continue
        true_gap = min(float(y - x) for x, y in zip(vals, vals[1:]))
        # gap is computed from float projections: allow their rounding error, nothing more
        rel = pts[b] - o1[b]
        w = o2[b] - o1[b]
        err = 4 * (d + 2) * 2.0**-53 * np.abs(rel * w).sum(-1).max() + 1e-320
        assert abs(gap[b] - true_gap) <= err, (gap[b], true_gap, err)
        assert gap[b] >= 0


def test_gap_doc_example_and_all_equal():
    pts = np.array([[[0, 0], [2, 0], [0, 1], [0, -3], [1, 7]]], dtype=float)
    labels, count, gap = projection_classes(pts, pts[:, 0], pts[:, 1])
    # columns x * 2: 0, 4, 0, 0, 2 -> classes {0,2,3} < {4} < {1}; gap = min(2, 2)
    assert labels[0, 0] == labels[0, 2] == labels[0, 3] < labels[0, 4] < labels[0, 1]
    assert count[0] == 3 and gap[0] == 2.0
    # all points on the perpendicular through o1 (heights of (1,0),(2,0) all 0): one class
    h = np.array([[[0, 0], [1, 0], [2, 0]]], dtype=float)
    labels, count, gap = projection_classes(h, h[:, 0], h[:, 1], perpendicular=True)
    assert count[0] == 1 and (labels == 0).all() and gap[0] == np.inf


def test_gap_when_projections_overflow():
    """Documented: classes stay exact when projections overflow; gap is then inf."""
    pts = np.array([[[0.0, 0.0], [1e300, 0.0], [-1e300, 5.0]]])
    _, count, gap = projection_classes(pts, pts[:, 0], pts[:, 1])
    assert count[0] == 3
    assert gap[0] == np.inf


# --------------------------------------------------------------------------------------------
# exact_projection_difference_sign


@pytest.mark.parametrize("kind", [k for k in KINDS if k not in ("tiny", "subnormal")])
@settings(max_examples=15)
@given(seed=st.integers(0, 2**32 - 1), d=st.integers(2, 5), q=st.integers(1, 12))
def test_sign_agrees_with_fractions(kind, seed, d, q):
    rng = np.random.default_rng(seed)
    pts = make_points(kind, rng, q, 4, d)
    ya, yb, o1, o2 = pts[:, 2], pts[:, 3], pts[:, 0], pts[:, 1]
    for perp in ([False, True] if d == 2 else [False]):
        got = exact_projection_difference_sign(ya, yb, o1, o2, perpendicular=perp)
        assert got.shape == (q,) and got.dtype == np.int8
        want = [exact_sign(ya[i], yb[i], o1[i], o2[i], perp) for i in range(q)]
        np.testing.assert_array_equal(got, want)


def _decimal_combinations():
    vals = [0.1, 0.3, 1.1, 3.3]
    rows = []
    for ya in itertools.product(vals, repeat=2):
        for yb in itertools.product(vals, repeat=2):
            for o2 in itertools.product([0.1, 0.3, 1.0, 2.0], repeat=2):
                rows.append((ya, yb, (0.0, 0.0), o2))
    a = np.array(rows, dtype=float)
    return a[:, 0], a[:, 1], a[:, 2], a[:, 3]


def test_sign_where_float_evaluation_is_wrong():
    """0.1/0.2/0.3 combinations: catastrophic cancellation makes naive floats lie."""
    ya, yb, o1, o2 = _decimal_combinations()
    want = np.array([exact_sign(ya[i], yb[i], o1[i], o2[i]) for i in range(len(ya))])
    naive = np.sign(((ya - yb) * (o2 - o1)).sum(-1))
    assert (naive != want).sum() >= 3  # the test set really contains cases floats get wrong
    assert ((naive == -want) & (want != 0)).any()  # even opposite signs
    got = exact_projection_difference_sign(ya, yb, o1, o2)
    np.testing.assert_array_equal(got, want)
    # and heights
    want_h = np.array([exact_sign(ya[i], yb[i], o1[i], o2[i], True) for i in range(len(ya))])
    got_h = exact_projection_difference_sign(ya, yb, o1, o2, perpendicular=True)
    np.testing.assert_array_equal(got_h, want_h)


def test_docstring_case_real_zero_is_float_positive():
    # 0.1 - 0.3 + 2 (0.2 - 0.1) is 0 over the reals, positive on the doubles nearest to them
    z = np.zeros((1, 2))
    o2 = np.array([[1.0, 2.0]])
    ya, yb = np.array([[0.1, 0.2]]), np.array([[0.3, 0.1]])
    assert exact_sign(ya[0], yb[0], z[0], o2[0]) == 1
    assert exact_projection_difference_sign(ya, yb, z, o2)[0] == 1


@pytest.mark.parametrize("x", [1.0, 0.1, 3.0e8, 1e-200, 123456.789, 2.0**52])
@pytest.mark.parametrize("direction", [np.inf, -np.inf])
def test_last_bit_differences(x, direction):
    """Points differing in the last bit of one coordinate have different columns, and the
    sign is that of the bit; a 1-ulp change of a coordinate orthogonal to w keeps the column."""
    y = np.nextafter(x, direction)
    ya = np.array([[x, 5.0], [x, 5.0], [1.0, x]])
    yb = np.array([[y, 5.0], [y, -7.0], [1.0, y]])
    o1 = np.array([[0.25, 3.0], [0.25, 3.0], [0.25, 3.0]])
    o2 = np.array([[1.25, 3.0], [1.25, 3.0], [1.25, 3.0]])  # w = (1, 0)
    want = [exact_sign(ya[i], yb[i], o1[i], o2[i]) for i in range(3)]
    assert want[0] == want[1] == (1 if x > y else -1) and want[2] == 0
    np.testing.assert_array_equal(exact_projection_difference_sign(ya, yb, o1, o2), want)


def test_sign_empty_batch():
    e = np.zeros((0, 3))
    out = exact_projection_difference_sign(e, e, e, e)
    assert out.shape == (0,)


def test_heights_need_the_plane():
    pts = np.zeros((1, 3, 3))
    pts[0, 1, 0] = 1.0
    with pytest.raises(ValueError, match="plane"):
        projection_classes(pts, pts[:, 0], pts[:, 1], perpendicular=True)


# --------------------------------------------------------------------------------------------
# projection_values bound, and batch == loop


@settings(max_examples=30)
@given(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(["random", "mixed_scale", "near_tie"]))
def test_projection_values_error_bound_holds(seed, kind):
    pts = make_points(kind, np.random.default_rng(seed), 4, 6, 3)
    values, bound = projection_values(pts, pts[:, 0], pts[:, 1])
    for b in range(4):
        exact = exact_projections(pts[b], pts[b, 0], pts[b, 1])
        for v, e in zip(values[b], exact):
            assert abs(Fraction(float(v)) - e) <= Fraction(float(bound[b]))


@settings(max_examples=20)
@given(seed=st.integers(0, 2**32 - 1), d=st.integers(2, 4),
       kinds=st.lists(st.sampled_from(["random", "integer", "dyadic", "near_tie", "huge"]),
                      min_size=1, max_size=4))
def test_batch_equals_loop(seed, d, kinds):
    rng = np.random.default_rng(seed)
    pts = np.concatenate([make_points(k, rng, 5, 6, d) for k in kinds])
    rng.shuffle(pts)
    o1, o2 = pts[:, 0], pts[:, 1]
    labels, count, gap = projection_classes(pts, o1, o2)
    sign = exact_projection_difference_sign(pts[:, 2], pts[:, 3], o1, o2)
    for b in range(pts.shape[0]):
        lb, cb, gb = projection_classes(pts[b:b + 1], o1[b:b + 1], o2[b:b + 1])
        np.testing.assert_array_equal(labels[b], lb[0])
        assert count[b] == cb[0]
        np.testing.assert_array_equal(gap[b], gb[0])
        sb = exact_projection_difference_sign(pts[b:b + 1, 2], pts[b:b + 1, 3], o1[b:b + 1],
                                              o2[b:b + 1])
        assert sign[b] == sb[0]
