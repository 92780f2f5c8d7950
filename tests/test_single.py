"""The single-query fast paths of :func:`pmplan.plan` and :func:`pmplan.plan_sequence`.

Both functions first try a lean path (``pmplan.single._plan_fast`` / ``_plan_sequence_fast``: one
validating kernel call, no re-validation of the arrays the kernel wrote) and fall back to the
general path (validation of :mod:`pmplan.configuration`, :func:`pmplan.running.run_loop`, exact
re-decision of flagged queries) whenever the lean path returns None. The contract tested here:

* whenever the lean path answers, its :class:`pmplan.Plan` is the general path's, field by
  field and bit for bit (domain, stratum, clearance, times, waypoints, planner, dims), on
  generic float queries and on exactly degenerate integer-lattice ones;
* it does answer for plain valid queries (so the comparison is not vacuous), whatever the form
  of the input (lists, other dtypes, non-contiguous or read-only arrays, an int lift);
* bad input still raises the general path's errors, with the same types and messages.

The general path is forced by replacing the lean functions with ones that return None.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import queries

import pmplan
from pmplan import single
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
from pmplan.generators import column_sequence
from pmplan.path import PiecewiseLinearPath


def _general(fn, *args, **kwargs):
    """``fn(*args, **kwargs)`` with both lean paths disabled (the general path decides)."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(single, "_plan_fast", lambda *a, **k: None)
        mp.setattr(single, "_plan_sequence_fast", lambda *a, **k: None)
        return fn(*args, **kwargs)


def _lean(fn, *args, **kwargs):
    """``(plan, answered)``: ``fn(*args, **kwargs)`` and whether a lean path produced it."""
    answered = []
    with pytest.MonkeyPatch.context() as mp:
        for name in ("_plan_fast", "_plan_sequence_fast"):
            inner = getattr(single, name)

            def spy(*a, _inner=inner, **k):
                out = _inner(*a, **k)
                answered.append(out is not None)
                return out

            mp.setattr(single, name, spy)
        plan = fn(*args, **kwargs)
    return plan, any(answered)


def _outcome(fn, *args, **kwargs):
    """The Plan, or the (type, message) of the pmplan error raised."""
    try:
        return fn(*args, **kwargs)
    except PmplanError as exc:
        return type(exc), str(exc)


def _bits(a: np.ndarray) -> tuple:
    """Shape, dtype and raw bytes: equal only when the arrays are identical bit for bit
    (``-0.0`` and ``0.0`` differ)."""
    return a.shape, a.dtype, a.tobytes()


def assert_same_plan(a: pmplan.Plan, b: pmplan.Plan) -> None:
    assert type(a) is type(b) is pmplan.Plan
    assert type(a.domain) is type(b.domain) is int
    assert type(a.clearance) is type(b.clearance) is float
    assert type(a.stratum) is type(b.stratum) is str
    assert (a.domain, a.stratum, a.planner, a.dims) == (b.domain, b.stratum, b.planner, b.dims)
    assert math.copysign(1.0, a.clearance) == 1.0 and a.clearance.hex() == b.clearance.hex()
    assert isinstance(a.path, PiecewiseLinearPath) and isinstance(b.path, PiecewiseLinearPath)
    assert _bits(a.times) == _bits(b.times)
    assert _bits(a.waypoints) == _bits(b.waypoints)
    assert a.times.flags.writeable and a.waypoints.flags.writeable
    # a Plan owns its breakpoints: never the planner's shared (read-only) copy
    assert not np.shares_memory(a.times, b.times)


def check_plan(*args, **kwargs) -> bool:
    """The lean Plan equals the general one; return whether the lean path answered."""
    fast, answered = _lean(pmplan.plan, *args, **kwargs)
    assert_same_plan(fast, _general(pmplan.plan, *args, **kwargs))
    o, s, g = (np.asarray(x, dtype=float) for x in args)
    m = o.shape[0]
    # the plan's own endpoints: the query, exactly
    np.testing.assert_array_equal(fast.path(0.0), np.concatenate([o, s]))
    np.testing.assert_array_equal(fast.path(1.0), np.concatenate([o, g]))
    assert (np.diff(fast.times) > 0).all()  # compact, as the general path returns it
    assert fast.dims == (o.shape[1], s.shape[0], m)
    return answered


def check_sequence(obstacles, configs, **kwargs) -> bool:
    """The lean sequential Plan equals the general one; return whether the lean path answered."""
    fast, answered = _lean(pmplan.plan_sequence, obstacles, configs, **kwargs)
    assert_same_plan(fast, _general(pmplan.plan_sequence, obstacles, configs, **kwargs))
    r = len(configs)
    o = np.asarray(obstacles, dtype=float)
    assert fast.planner == (kwargs.get("planner") or "obstacle_line_compact")
    assert fast.waypoints.shape[0] == 7 * (r - 1) + 1
    # the stratum names every configuration's cp(C_k) (paper notation T_{cp_1,...,cp_r})
    assert fast.stratum.startswith("T_{") and fast.stratum[3:].split("}")[0].count(",") == r - 1
    for k, c in enumerate(configs):  # through C_k at tau = k/(r-1), exactly
        np.testing.assert_array_equal(fast.path(k / (r - 1)),
                                      np.concatenate([o, np.asarray(c, dtype=float)]))
    return answered


# --- pmplan.plan ----------------------------------------------------------------------------
DNM = st.tuples(st.sampled_from([2, 3, 4]), st.sampled_from([1, 2, 4]), st.sampled_from([2, 3]))


@settings(max_examples=25)
@given(DNM.flatmap(lambda dnm: queries(dnm[0], dnm[2], dnm[1])))
def test_plan_generic_queries_take_the_fast_path_and_agree(q):
    assert check_plan(*q)


@settings(max_examples=40)
@given(DNM.flatmap(lambda dnm: queries(dnm[0], dnm[2], dnm[1], degenerate=True)))
def test_plan_lattice_queries_agree(q):
    """Exact ties on the integer / dyadic lattice: the kernel decides most of them (and
    flags the rest, which then take the general path)."""
    check_plan(*q)


@settings(max_examples=25)
@given(st.booleans().flatmap(lambda deg: queries(2, 3, 1, degenerate=deg)))
def test_planar_three_agrees(q):
    check_plan(*q)
    check_plan(*q, planner="obstacle_line")


@settings(max_examples=15)
@given(queries(2, 3, 1))
def test_planar_three_generic_takes_the_fast_path(q):
    assert check_plan(*q)
    assert pmplan.plan(*q).planner == "planar_three"


def test_lattice_queries_mostly_take_the_fast_path():
    """Integer-lattice queries with robots exactly in the columns of the obstacles (o2 - o1
    along e_1, so the column of a point is its first coordinate) are still decided by the
    kernel: the lean path answers for them."""
    rng = np.random.default_rng(5)
    answered = 0
    for _ in range(30):
        o1 = rng.integers(-3, 4, size=2).astype(float)
        o = np.stack([o1, o1 + [float(rng.integers(1, 4)), 0.0]])
        s = o + [[0.0, 1.0], [0.0, -2.0]]  # x1, x2 in the columns of o1, o2
        g = rng.integers(-3, 4, size=(2, 2)).astype(float)
        if len({tuple(p) for p in np.concatenate([o, g]).tolist()}) < 4:
            continue
        answered += check_plan(o, s, g)
    assert answered >= 15


FORMS = {
    "list": lambda a: a.tolist(),
    "tuple": lambda a: tuple(map(tuple, a.tolist())),
    "fortran": np.asfortranarray,
    "strided": lambda a: np.repeat(a, 2, axis=1)[:, ::2],
    "float32": lambda a: a.astype(np.float32),
    "int": lambda a: np.round(16 * a).astype(np.int64),
}


@pytest.mark.parametrize("form", sorted(FORMS))
def test_plan_input_forms(form):
    rng = np.random.default_rng(7)
    for dnm in [(2, 4, 2), (3, 2, 3), (2, 1, 3)]:
        d, n, m = dnm
        o, s, g = rng.normal(size=(m, d)) * 3, rng.normal(size=(n, d)) * 3, \
            rng.normal(size=(n, d)) * 3
        args = [FORMS[form](x) for x in (o, s, g)]
        assert check_plan(*args)


def test_readonly_input_is_planned_by_the_fast_path():
    """Read-only arrays (copied once, so no second kernel specialisation is compiled) give the
    plan of their writeable copies. (Compared with the lean path only: the general path would
    compile read-only specialisations of the kernels, which other tests check never happen.)"""
    rng = np.random.default_rng(12)
    for m, n, d in [(2, 3, 2), (3, 1, 2)]:
        args = [rng.normal(size=shape) for shape in ((m, d), (n, d), (n, d))]
        frozen = [a.copy() for a in args]
        for a in frozen:
            a.flags.writeable = False
        fast, answered = _lean(pmplan.plan, *frozen)
        assert answered
        assert_same_plan(fast, pmplan.plan(*args))
        seq, answered = _lean(pmplan.plan_sequence, frozen[0], [frozen[1], frozen[2], frozen[1]])
        assert answered
        assert_same_plan(seq, pmplan.plan_sequence(args[0], [args[1], args[2], args[1]]))


@pytest.mark.parametrize("lift", [1, 2.5, np.float64(0.5), np.float32(0.25), np.int64(2), 3])
def test_plan_lift_forms(lift):
    rng = np.random.default_rng(11)
    o, s, g = rng.normal(size=(3, 3)), rng.normal(size=(2, 3)), rng.normal(size=(2, 3))
    check_plan(o, s, g, lift=lift)
    assert_same_plan(pmplan.plan(o, s, g, lift=lift), pmplan.plan(o, s, g, lift=float(lift)))


def test_large_d_takes_the_general_path():
    """d > MAX_D: no kernel, the general path (numpy reference) answers, identically."""
    rng = np.random.default_rng(3)
    o, s, g = rng.normal(size=(2, 8)), rng.normal(size=(2, 8)), rng.normal(size=(2, 8))
    assert not check_plan(o, s, g)


def test_plans_do_not_share_buffers():
    """Two lean plans of one shape own their arrays (writing one leaves the other alone)."""
    rng = np.random.default_rng(4)
    a = pmplan.plan(*(rng.normal(size=(k, 2)) for k in (2, 3, 3)))
    b = pmplan.plan(*(rng.normal(size=(k, 2)) for k in (2, 3, 3)))
    before = b.times.copy(), b.waypoints.copy()
    a.times[:] = -1.0
    a.waypoints[:] = np.nan
    np.testing.assert_array_equal(b.times, before[0])
    np.testing.assert_array_equal(b.waypoints, before[1])
    np.testing.assert_array_equal(pmplan.plan([[0, 0], [1, 0]], [[0, 1]], [[1, 1]]).times[[0, -1]],
                                  [0.0, 1.0])


FLAGGED = {
    # (0.3, -0.1) . (0.1, 0.3) == 0 exactly but not in floats: the kernel flags FALLBACK
    "fallback": ([[0.0, 0.0], [0.1, 0.3]], [[0.3, -0.1], [1.0, 1.0]], [[1.0, -1.0], [2.0, 2.0]]),
    # columns 1e-10 apart: a clearance below certify's float threshold, flagged SUSPECT
    "suspect": ([[0.0, 0.0], [1.0, 0.0]], [[0.0, 1.0], [1e-10, 5.0]], [[0.5, -1.0], [2.0, 2.0]]),
}


@pytest.mark.parametrize("name", sorted(FLAGGED))
def test_flagged_queries_are_re_decided_by_the_general_path(name):
    """Queries the kernel cannot decide alone: the lean paths decline, the general path
    answers (exactly as the numpy reference)."""
    o, s, g = (np.array(x) for x in FLAGGED[name])
    plan, answered = _lean(pmplan.plan, o, s, g)
    assert not answered
    ref = pmplan.plan(o, s, g, backend="numpy")
    assert (plan.domain, plan.stratum, plan.clearance) == (ref.domain, ref.stratum, ref.clearance)
    np.testing.assert_array_equal(plan.waypoints, ref.waypoints)
    seq, answered = _lean(pmplan.plan_sequence, o, [s, g, s])
    assert not answered
    ref = pmplan.plan_sequence(o, [s, g, s], backend="numpy")
    assert (seq.domain, seq.stratum, seq.clearance) == (ref.domain, ref.stratum, ref.clearance)
    np.testing.assert_array_equal(seq.waypoints, ref.waypoints)


def test_certificate_failure_raises_through_the_general_path():
    """An eps(C) below the resolution of the coordinates: no certified path, both entry
    points raise the general path's CertificationError."""
    o, s = [[0.0, 0.0], [1.0, 2.0]], [[-1.0, 3.0], [3.0 + 2.0**-51, 1.0]]
    g = [[1.0, -1.0], [2.0, 2.0]]
    for fn, args in ((pmplan.plan, (o, s, g)), (pmplan.plan_sequence, (o, [s, g, s]))):
        fast = _outcome(fn, *args, planner="obstacle_line")  # (Mathematics §6.2)
        assert isinstance(fast, tuple) and fast[0] is CertificationError
        assert fast == _outcome(_general, fn, *args, planner="obstacle_line")


# --- pmplan.plan_sequence -------------------------------------------------------------------
@settings(max_examples=30)
@given(seed=st.integers(0, 2**32 - 1), d=st.sampled_from([2, 3, 4]), m=st.sampled_from([2, 3]),
       n=st.sampled_from([1, 2, 3]), r=st.integers(2, 5), integer=st.booleans(),
       lift=st.sampled_from([1.0, 0.5, 2]))
def test_sequence_lattice_strata_agree(seed, d, m, n, r, integer, lift):
    """Exact column strata (generators.column_sequence): every cp(C_k), cp_o, e == N."""
    rng = np.random.default_rng(seed)
    cp_o = int(rng.integers(2, m + 1))
    cps = rng.integers(cp_o, cp_o + n + 1, size=r)
    pole = bool(d % 2 and rng.integers(2))
    obstacles, configs = column_sequence(rng, d, n, m, cps, cp_o=cp_o, pole=pole,
                                         integer=integer)
    check_sequence(obstacles, configs, lift=lift)
    want = "T_{" + ",".join(str(int(c)) for c in cps) + "}"
    assert pmplan.plan_sequence(obstacles, configs, lift=lift).stratum.startswith(want)


@settings(max_examples=25)
@given(seed=st.integers(0, 2**32 - 1), d=st.sampled_from([2, 3, 5]), m=st.sampled_from([2, 4]),
       n=st.sampled_from([1, 4]), r=st.integers(2, 6),
       form=st.sampled_from(["list", "tuple", "array", "lists"]))
def test_sequence_generic_takes_the_fast_path_and_agrees(seed, d, m, n, r, form):
    rng = np.random.default_rng(seed)
    obstacles = rng.normal(size=(m, d))
    stack = rng.normal(size=(r, n, d))
    configs = {"list": list(stack), "tuple": tuple(stack), "array": stack,
               "lists": stack.tolist()}[form]
    assert check_sequence(obstacles, configs)
    assert check_sequence(obstacles, configs, planner="obstacle_line")  # the paper's lanes


def test_sequence_r2_is_plan():
    rng = np.random.default_rng(8)
    o, s, g = rng.normal(size=(2, 2)), rng.normal(size=(3, 2)), rng.normal(size=(3, 2))
    a, b = pmplan.plan_sequence(o, [s, g]), pmplan.plan(o, s, g)
    assert (a.domain, a.stratum, a.clearance) == (b.domain, b.stratum, b.clearance)
    assert _bits(a.waypoints) == _bits(b.waypoints) and _bits(a.times) == _bits(b.times)


@pytest.mark.parametrize("form", sorted(FORMS))
def test_sequence_input_forms(form):
    rng = np.random.default_rng(9)
    o = rng.normal(size=(3, 2)) * 3
    configs = [FORMS[form](rng.normal(size=(2, 2)) * 3) for _ in range(4)]
    assert check_sequence(FORMS[form](o), configs)


def test_sequence_iterator_takes_the_general_path():
    """A one-shot iterable is left whole to the general path (which consumes it once)."""
    rng = np.random.default_rng(10)
    o = rng.normal(size=(2, 2))
    configs = list(rng.normal(size=(3, 2, 2)))
    p, answered = _lean(pmplan.plan_sequence, o, iter(configs))
    assert not answered
    assert_same_plan(p, pmplan.plan_sequence(o, configs))


# --- errors ---------------------------------------------------------------------------------
O = [[0.0, 0.0], [2.0, 0.0]]
S = [[1.0, 1.0], [0.0, 1.0]]
G = [[1.0, -1.0], [3.0, 3.0]]


@pytest.mark.parametrize("args, kwargs, error", [
    ((O, [[1.0, 1.0], [0.0, np.nan]], G), {}, NonFiniteError),
    ((O, S, [[1.0, -1.0], [np.inf, 3.0]]), {}, NonFiniteError),
    (([[0.0, np.nan], [2.0, 0.0]], S, G), {}, NonFiniteError),
    (([[0.0, 0.0], [0.0, 0.0]], S, G), {}, CollisionError),
    ((O, [[1.0, 1.0], [1.0, 1.0]], G), {}, CollisionError),
    ((O, S, [[1.0, -1.0], [2.0, 0.0]]), {}, CollisionError),
    ((O, [[1.0, 1.0]], G), {}, ShapeError),
    ((O, [[1.0, 1.0, 0.0], [0.0, 1.0, 0.0]], G), {}, ShapeError),
    (([0.0, 0.0], S, G), {}, ShapeError),
    ((np.zeros((2, 2, 2)), S, G), {}, ShapeError),
    ((O, [[1.0], [0.0, 1.0]], G), {}, InputError),
    ((O, [["a", 1.0], [0.0, 1.0]], G), {}, InputError),
    (([[0.0, 0.0]], S, G), {}, UnsupportedError),
    (([[0.0], [1.0]], [[2.0]], [[3.0]]), {}, UnsupportedError),
    ((O, S, G), {"planner": "nope"}, UnsupportedError),
    ((O, S, G), {"planner": "planar_three"}, UnsupportedError),
    ((O, S, G), {"lift": 0.0}, InputError),
    ((O, S, G), {"lift": -1}, InputError),
    ((O, S, G), {"lift": np.nan}, InputError),
    ((O, S, G), {"lift": math.inf}, InputError),
    ((O, S, G), {"lift": 10**400}, InputError),
    ((O, S, G), {"lift": "x"}, InputError),
    ((O, S, G), {"backend": "cuda"}, InputError),
    (([[0, 0], [4, 0], [2.5, 1.5]], [[2.5, 1.5]], [[6, 2.5]]), {}, CollisionError),
    (([[0, 0], [4, 0], [2.5, 1.5]], [[0, -2]], [[np.nan, 2.5]]), {}, NonFiniteError),
])
def test_plan_errors_are_the_general_errors(args, kwargs, error):
    fast = _outcome(pmplan.plan, *args, **kwargs)
    assert isinstance(fast, tuple) and issubclass(fast[0], error)
    assert fast == _outcome(_general, pmplan.plan, *args, **kwargs)
    assert issubclass(fast[0], ValueError)


C1, C2, C3 = [[0.0, 1.0]], [[1.0, -1.0]], [[3.0, 3.0]]


@pytest.mark.parametrize("obstacles, configs, kwargs, error", [
    (O, [C1, [[np.nan, 1.0]], C3], {}, NonFiniteError),
    (O, [C1, C2, [[3.0, -np.inf]]], {}, NonFiniteError),
    ([[0.0, 0.0], [np.nan, 0.0]], [C1, C2, C3], {}, NonFiniteError),
    (O, [C1, [[0.0, 0.0]], C3], {}, CollisionError),
    (O, [[[0.0, 0.0]], C2, C3], {}, CollisionError),
    (O, [C1, C2, [[2.0, 0.0]]], {}, CollisionError),
    (O, [S, [[5.0, 5.0], [5.0, 5.0]], G], {}, CollisionError),
    ([[0.0, 0.0], [0.0, 0.0]], [C1, C2, C3], {}, CollisionError),
    (O, [C1, [[1.0, 1.0, 1.0]], C3], {}, ShapeError),
    (O, [S, C2, G], {}, ShapeError),
    (O, [C1], {}, ShapeError),
    (O, [], {}, ShapeError),
    ([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], [C1, C2, C3], {}, ShapeError),
    ([0.0, 0.0], [C1, C2, C3], {}, ShapeError),
    (O, [C1, [[1.0], [2.0, 3.0]], C3], {}, InputError),
    ([[0.0, 0.0]], [C1, C2, C3], {}, UnsupportedError),
    (O, np.array(1.0), {}, InputError),
    (O, np.zeros((3, 2)), {}, ShapeError),
    (O, [C1, C2, C3], {"lift": 0}, InputError),
    (O, [C1, C2, C3], {"lift": np.nan}, InputError),
    (O, [C1, C2, C3], {"lift": 10**400}, InputError),
    (O, [C1, C2, C3], {"backend": "cuda"}, InputError),
])
def test_sequence_errors_are_the_general_errors(obstacles, configs, kwargs, error):
    fast = _outcome(pmplan.plan_sequence, obstacles, configs, **kwargs)
    assert isinstance(fast, tuple) and issubclass(fast[0], error)
    assert fast == _outcome(_general, pmplan.plan_sequence, obstacles, configs, **kwargs)
    assert issubclass(fast[0], ValueError)


def test_mismatched_obstacles_raise():
    """plan_configurations: the obstacles of C and C' must agree (then the lean plan)."""
    c = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
    c2 = np.array([[0.0, 0.0], [2.0, 0.5], [1.0, -1.0]])
    for fn in (pmplan.plan_configurations, lambda *a: _general(pmplan.plan_configurations, *a)):
        with pytest.raises(ObstacleMismatchError):
            fn(c, c2)
    c2[1] = c[1]
    assert_same_plan(pmplan.plan_configurations(c, c2),
                     _general(pmplan.plan_configurations, c, c2))


def test_input_forms_compile_no_new_specialisation():
    """Whatever the form of the input, the lean paths call the kernels with C-contiguous
    float64 arrays: no second specialisation is compiled (that would take seconds)."""
    from pmplan.kernels import obstacle_line as kernels_line

    rng = np.random.default_rng(13)
    o, s, g = rng.normal(size=(3, 3)), rng.normal(size=(2, 3)), rng.normal(size=(2, 3))
    pmplan.plan(o, s, g)
    pmplan.plan_sequence(o, [s, g, s, g])
    before = len(kernels_line.plan_one.signatures), len(kernels_line.plan_queries.signatures)
    for form in FORMS.values():
        pmplan.plan(form(o), form(s), form(g), lift=2)
        for r in (2, 3, 5):
            pmplan.plan_sequence(form(o), [form(c) for c in (s, g, s, g, s)[:r]])
    assert (len(kernels_line.plan_one.signatures), len(kernels_line.plan_queries.signatures)) == before
