"""Bad input through the public API: every error is specific, a ValueError and a PmplanError."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pmplan
from pmplan.configuration import coincident_pairs
from pmplan.errors import (
    CertificationError,
    CollisionError,
    InputError,
    NonFiniteError,
    ObstacleMismatchError,
    PmplanError,
    ShapeError,
    UnsupportedError,
)

O = [[0.0, 0.0], [2.0, 0.0]]
S = [[1.0, 1.0], [0.0, 1.0]]
G = [[1.0, -1.0], [3.0, 3.0]]
NAMES = ("obstacles", "start", "goal")


def raises(exc, match):
    """pytest.raises that also checks the error hierarchy of pmplan.errors."""

    class _Ctx:
        def __enter__(self):
            self.cm = pytest.raises(exc, match=match)
            self.info = self.cm.__enter__()
            return self.info

        def __exit__(self, *a):
            out = self.cm.__exit__(*a)
            err = self.info.value
            assert isinstance(err, PmplanError)
            if not isinstance(err, CertificationError):
                assert isinstance(err, ValueError) and isinstance(err, InputError)
            return out

    return _Ctx()


def test_error_hierarchy():
    for cls in (InputError, ShapeError, NonFiniteError, CollisionError, ObstacleMismatchError,
                UnsupportedError):
        assert issubclass(cls, ValueError) and issubclass(cls, PmplanError)
    assert issubclass(CertificationError, PmplanError)
    assert not issubclass(CertificationError, ValueError)


def test_valid_query_plans():
    p = pmplan.plan(O, S, G)
    np.testing.assert_array_equal(p.path.waypoints[0], np.array(O + S))
    np.testing.assert_array_equal(p.path.waypoints[-1], np.array(O + G))
    assert p.clearance > 0


# --------------------------------------------------------------------------------------------
# shapes


def _with_ndim(a, ndim):
    a = np.asarray(a, dtype=float)
    while a.ndim > ndim:
        a = a[0]
    while a.ndim < ndim:
        a = a[None]
    return a


@pytest.mark.parametrize("which", range(3))
@pytest.mark.parametrize("ndim", [0, 1, 3, 4, 5])
def test_plan_wrong_ndim(which, ndim):
    args = [np.array(O), np.array(S), np.array(G)]
    args[which] = _with_ndim(args[which], ndim)
    with raises(ShapeError, match=rf"Expected `{NAMES[which]}` to have shape \(k, d\), got "
                                  rf"{re_shape(args[which].shape)}"):
        pmplan.plan(*args)


@pytest.mark.parametrize("which", range(3))
@pytest.mark.parametrize("ndim", [0, 1, 2, 4, 5])
def test_plan_batch_wrong_ndim(which, ndim):
    args = [np.array([O]), np.array([S]), np.array([G])]
    args[which] = _with_ndim(args[which], ndim)
    with raises(ShapeError, match=rf"Expected `{NAMES[which]}` to have shape \(B, k, d\), got "
                                  rf"{re_shape(args[which].shape)}"):
        pmplan.plan_batch(*args)


def re_shape(shape) -> str:
    import re

    return re.escape(str(tuple(shape)))


def test_mismatched_n():
    with raises(ShapeError, match=r"same shape \(n, d\), got \(1, 2\) and \(2, 2\)"):
        pmplan.plan(O, S[:1], G)


@pytest.mark.parametrize("d_robots", [1, 3])
def test_mismatched_d(d_robots):
    s = np.zeros((2, d_robots)) + [[1], [2]]
    with raises(ShapeError, match=rf"d = 2 coordinates .*start d = {d_robots}"):
        pmplan.plan(O, s, s + 1)
    with raises(ShapeError, match=r"d = 2 coordinates .*goal d = 3"):
        pmplan.plan(O, S, np.ones((2, 3)) + [[0], [1]])


@pytest.mark.parametrize("bs", [(1, 2, 2), (2, 1, 2), (2, 2, 1), (3, 2, 2)])
def test_mismatched_batch_size(bs):
    args = [np.array([O] * bs[0]), np.array([S] * bs[1]), np.array([G] * bs[2])]
    with raises(ShapeError, match=rf"same batch size B .*got {bs[0]}, {bs[1]} and {bs[2]}"):
        pmplan.plan_batch(*args)


# --------------------------------------------------------------------------------------------
# values


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
@pytest.mark.parametrize("which, index", [(0, (1, 0)), (1, (0, 1)), (2, (1, 1))])
def test_non_finite_single(bad, which, index):
    args = [np.array(O), np.array(S), np.array(G)]
    args[which][index] = bad
    with raises(NonFiniteError, match=rf"`{NAMES[which]}` has a NaN or infinite coordinate at "
                                      rf"index {re_shape(index)}"):
        pmplan.plan(*args)


def test_non_finite_batch_names_the_index():
    obstacles = np.array([O] * 4)
    start = np.array([S] * 4)
    start[2, 1, 0] = np.nan
    with raises(NonFiniteError, match=r"`start` .* index \(2, 1, 0\)"):
        pmplan.plan_batch(obstacles, start, np.array([G] * 4))


@pytest.mark.parametrize(
    "start, pair",
    [
        ([[1.0, 1.0], [1.0, 1.0]], ("x1", "x2")),
        ([[2.0, 0.0], [1.0, 1.0]], ("o2", "x1")),
        ([[1.0, 1.0], [0.0, 0.0]], ("o1", "x2")),
    ],
)
def test_coincident_points_single(start, pair):
    with raises(CollisionError, match=rf"points {pair[0]} and {pair[1]} of the start "
                                      r"configuration coincide") as info:
        pmplan.plan(O, start, G)
    assert info.value.pair == pair and info.value.index is None
    assert info.value.which == "start"
    with raises(CollisionError, match="goal configuration") as info:
        pmplan.plan(O, G, start)
    assert info.value.pair == pair and info.value.which == "goal"


def test_coincident_obstacles():
    with raises(CollisionError, match="o1 and o2") as info:
        pmplan.plan([[1.0, 1.0], [1.0, 1.0]], [[0.0, 0.0]], [[3.0, 0.0]])
    assert info.value.pair == ("o1", "o2")


def test_coincident_points_batch_names_index_and_count():
    obstacles = np.array([O] * 5)
    start = np.array([S] * 5)
    start[3, 1] = O[0]  # x2 == o1 in query 3
    start[4, 0] = start[4, 1]  # x1 == x2 in query 4
    with raises(CollisionError, match=r"o1 and x2 of the start configuration of query 3 .*"
                                      r"\(2 queries in all\)") as info:
        pmplan.plan_batch(obstacles, start, np.array([G] * 5))
    assert info.value.index == 3 and info.value.pair == ("o1", "x2")


@settings(max_examples=30)
@given(seed=st.integers(0, 2**32 - 1), p=st.integers(2, 9), d=st.integers(1, 4))
def test_coincident_pairs_mask(seed, p, d):
    rng = np.random.default_rng(seed)
    cfg = rng.integers(0, 3, size=(12, p, d)).astype(float)
    want = [len({tuple(r) for r in c.tolist()}) < p for c in cfg]
    np.testing.assert_array_equal(coincident_pairs(cfg), want)


def test_distinct_but_close_points_are_accepted():
    x = np.nextafter(1.0, 2.0)
    p = pmplan.plan(O, [[1.0, 1.0], [x, 1.0]], G)
    assert p.clearance > 0


@pytest.mark.parametrize(
    "obstacles, start, goal, match",
    [
        ([[0.0, 0.0]], [[1.0, 1.0]], [[2.0, 2.0]], r"m = 1: .*m >= 2 obstacles"),
        (O, np.zeros((0, 2)), np.zeros((0, 2)), r"n = 0: at least one robot"),
        ([[0.0], [1.0]], [[3.0]], [[4.0]], r"d = 1: planners need d >= 2"),
    ],
)
def test_unsupported_dimensions(obstacles, start, goal, match):
    with raises(UnsupportedError, match=match):
        pmplan.plan(obstacles, start, goal)
    b = [np.asarray(a, dtype=float)[None] for a in (obstacles, start, goal)]
    with raises(UnsupportedError, match=match):
        pmplan.plan_batch(*b)


def test_unknown_planner():
    with raises(UnsupportedError, match=r"unknown planner 'nope'; choose one of .*obstacle_line"):
        pmplan.plan(O, S, G, planner="nope")


def test_planner_that_does_not_apply():
    if "planar_three" not in pmplan.planner_names():
        pytest.skip("planar_three not registered")
    with raises(UnsupportedError, match=r"'planar_three' does not apply to \(d, n, m\) = "
                                        r"\(2, 2, 2\)"):
        pmplan.plan(O, S, G, planner="planar_three")


@pytest.mark.parametrize(
    "start",
    [[["a", "b"]], [[1.0, [2.0]]], [[1.0, 2.0], [3.0]], "abc", [[{}, 1.0]], None],
)
def test_non_numeric_input(start):
    with raises(InputError, match=r"`start(\[\d+\])*` must (be a numeric array|hold real numbers)"
                                  r"|Expected `start` to have"):
        pmplan.plan(O, start, G[:1])


@pytest.mark.parametrize("lift", [0, -1.0, np.nan, np.inf, -np.inf])
def test_bad_lift_value(lift):
    with raises(InputError, match=r"`lift` must be a positive finite number"):
        pmplan.plan(O, S, G, lift=lift)
    with raises(InputError, match=r"`lift` must be a positive finite number"):
        pmplan.plan_batch([O], [S], [G], lift=lift)
    with raises(InputError, match=r"`lift` must be a positive finite number"):
        pmplan.plan_sequence(O, [S, G], lift=lift)


@pytest.mark.parametrize("lift", ["x", [1.0, 2.0]])
def test_bad_lift_type(lift):
    with raises(InputError, match=r"`lift` must be a positive real number or 'scene'"):
        pmplan.plan(O, S, G, lift=lift)


# --------------------------------------------------------------------------------------------
# plan_configurations and plan_sequence


def test_plan_configurations_obstacle_mismatch():
    c = np.array(O + S)
    c2 = np.array(O + G)
    c2[1, 1] = np.nextafter(0.0, 1.0)  # o2 moved by the smallest subnormal
    with raises(ObstacleMismatchError, match=r"obstacles of the start and goal configurations "
                                             r"differ"):
        pmplan.plan_configurations(c, c2)
    p = pmplan.plan_configurations(c, np.array(O + G))
    np.testing.assert_array_equal(p.path.waypoints[-1], np.array(O + G))


def test_plan_configurations_shapes():
    with raises(ShapeError, match=r"same shape, got \(4, 2\) and \(3, 2\)"):
        pmplan.plan_configurations(np.array(O + S), np.array(O + G[:1]))
    with raises(ShapeError, match=r"`start configuration` to have shape \(k, d\)"):
        pmplan.plan_configurations(np.zeros(4), np.zeros(4))


def test_plan_configurations_m_one_is_unsupported():
    with raises(UnsupportedError, match=r"m = 1"):
        pmplan.plan_configurations(np.array(O + S), np.array([O[0], [5.0, 5.0]] + G), m=1)


def test_plan_configurations_m_zero_is_unsupported():
    with raises(UnsupportedError, match=r"m = 0"):
        pmplan.plan_configurations(np.array(O + S), np.array(O + G), m=0)


def test_plan_configurations_m_too_large():
    with raises(ShapeError, match=r"m = 4 obstacles leave no robot"):
        pmplan.plan_configurations(np.array(O + S), np.array(O + G), m=4)


def test_plan_sequence_errors():
    with raises(ShapeError, match=r"at least r = 2 configurations, got 1"):
        pmplan.plan_sequence(O, [S])
    with raises(ShapeError, match=r"configuration 2 has shape \(1, 2\), expected \(2, 2\)"):
        pmplan.plan_sequence(O, [S, [[5.0, 5.0]], G])
    with raises(InputError, match=r"`configs\[1\]\[0\]\[0\]` must hold real numbers, got str"):
        pmplan.plan_sequence(O, [S, [["a", "b"]], G])
    with raises(CollisionError, match="o2 and x1"):
        pmplan.plan_sequence(O, [S, [[2.0, 0.0], [5.0, 5.0]], G])
    with raises(NonFiniteError, match="NaN"):
        pmplan.plan_sequence(O, [S, [[np.nan, 0.0], [5.0, 5.0]], G])


def test_plan_sequence_names_the_bad_configuration():
    with raises(CollisionError, match=r"config(uration)? 2") as info:
        pmplan.plan_sequence(O, [S, [[2.0, 0.0], [5.0, 5.0]], G])
    assert info.value.which != "start"


# --------------------------------------------------------------------------------------------
# Mathematics §6: a query too nearly degenerate for double precision


PRECISION_OBSTACLES = [[0.0, 0.0], [1.0, 2.0]]
PRECISION_START = [[-1.0, 3.0], [3.0 + 2.0**-51, 1.0]]


def test_spec5_case_is_nearly_degenerate():
    """x1 and x2 have columns 5 and 5 + 2**-51 along w = (1, 2): eps(C) ~ 2**-51/4/sqrt(5),
    below the resolution of the coordinates (ulp(3) = 2**-51)."""
    from fractions import Fraction as F

    w = (F(1), F(2))
    cols = [sum(F(c) * wc for c, wc in zip(x, w)) for x in PRECISION_START]
    assert cols[0] != cols[1] and abs(cols[1] - cols[0]) == F(2) ** -51


@pytest.mark.parametrize("goal", [[[5.0, 5.0], [6.0, -7.0]], [[-3.0, 0.5], [2.5, 4.0]]])
def test_spec5_precision_case_raises_certification_error(goal):
    """The paper's projection puts x1 and x2 on the obstacle line in the same float point.
    (The compact lanes in the plane take the robots straight to their lanes, Mathematics §4.4,
    and plan this query: test_compact_lanes_plan_the_precision_case.)"""
    with pytest.raises(CertificationError, match="certificate") as info:
        pmplan.plan(PRECISION_OBSTACLES, PRECISION_START, goal, planner="obstacle_line")
    assert isinstance(info.value, PmplanError)
    with pytest.raises(CertificationError):
        pmplan.plan(PRECISION_OBSTACLES, goal, PRECISION_START, planner="obstacle_line")
    # in a batch: the offending index is named, nothing is returned
    obstacles = np.array([PRECISION_OBSTACLES] * 3)
    start = np.array([goal, PRECISION_START, goal])
    goal_b = np.array([[[7.0, 1.0], [-2.0, -2.0]], goal, PRECISION_START])
    with pytest.raises(CertificationError, match=r"queries \[1, 2\]") as info:
        pmplan.plan_batch(obstacles, start, goal_b, planner="obstacle_line")
    np.testing.assert_array_equal(info.value.indices, [1, 2])
