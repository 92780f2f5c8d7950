"""Only real numbers are accepted, at every entry point (issue 12, item 3).

The rule lives in :func:`pmplan.configuration.as_real` (coordinates) and
:func:`pmplan.configuration.as_lift` (``lift``); every entry point goes through it:
:func:`pmplan.plan` (its fast path and the general path), :func:`pmplan.plan_batch`,
:func:`pmplan.plan_sequence` (fast and general), :func:`pmplan.plan_sequence_batch`,
:func:`pmplan.plan_configurations`, :func:`pmplan.plan_query` and query files
(:func:`pmplan.io.parse_query`). What is checked, and how it could fail:

* refused -- bools, complex numbers, strings, bytes, object arrays (Fraction, Decimal, None),
  a bool hidden among the ints of a list, integers a double cannot hold exactly (2**53 + 1,
  10**400, uint64 2**64 - 1), long doubles that are not doubles -- with an ``InputError`` that
  names the argument (and the coordinate, when it can), the offending type and the fix; never
  a bare ``OverflowError``/``TypeError`` and no NumPy warning (``ComplexWarning``);
* accepted -- float16/32/64, signed and unsigned ints, lists of Python ints and floats, an
  integer that is a double (2**64) -- giving the plan of the same query as float64, bit for bit;
* ``lift`` -- a positive finite real number or ``"scene"``; bools, strings, complex, None,
  arrays, 10**400 are refused at every entry point, with the fast paths' rule the general one's.
"""

from __future__ import annotations

import json
import warnings
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import queries

import pmplan
from pmplan import single
from pmplan.configuration import as_lift, as_real
from pmplan.errors import InputError
from pmplan.io import parse_query, read_query

O = [[0.0, 0.0], [2.0, 0.0]]
S = [[0.0, 1.0]]
G = [[1.0, -1.0]]


def _entry_points(obstacles, start, goal, lift=1.0):
    """Every planning entry point applied to one query (as a batch of one where batched)."""
    return {
        "plan": lambda: pmplan.plan(obstacles, start, goal, lift=lift),
        "plan numpy": lambda: pmplan.plan(obstacles, start, goal, lift=lift, backend="numpy"),
        "plan_batch": lambda: pmplan.plan_batch([obstacles], [start], [goal], lift=lift),
        "plan_sequence": lambda: pmplan.plan_sequence(obstacles, [start, goal], lift=lift),
        "plan_sequence numpy": lambda: pmplan.plan_sequence(obstacles, [start, goal], lift=lift,
                                                            backend="numpy"),
        "plan_sequence_batch": lambda: pmplan.plan_sequence_batch([obstacles], [[start], [goal]],
                                                                  lift=lift),
        "plan_query": lambda: pmplan.plan_query({"obstacles": obstacles, "start": start,
                                                 "goal": goal, "lift": lift}),
    }


# values for `start` (shape (1, 2)) that are not real numbers: (value, regex of the message)
BAD_START = [
    ([["0", "1"]], r"`[^`]*\[0\]` must hold real numbers, got str; pass real numbers"),
    (np.array([["0", "1"]]), r"must hold real numbers, got str"),
    ([[b"0", b"1"]], r"got bytes"),
    (np.array([[True, False]]), r"got (numpy\.)?bool"),
    ([[True, 1]], r"\[0\]\[0\]` must hold real numbers, got bool"),
    ([[1.5, np.True_]], r"\[0\]\[1\]` must hold real numbers, got (numpy\.)?bool"),
    (np.array([[1 + 0j, 2]]), r"got (numpy\.)?complex.*np\.real\(x\)"),
    ([[1j, 2.0]], r"\[0\]\[0\]` must hold real numbers, got complex"),
    ([[Fraction(1, 2), 1]], r"\[0\]\[0\]` must hold real numbers, got fractions\.Fraction"),
    ([[1, Decimal("0.5")]], r"\[0\]\[1\]` must hold real numbers, got decimal\.Decimal"),
    ([[None, 1.0]], r"\[0\]\[0\]` must hold real numbers, got NoneType"),
    (np.array([[Fraction(1, 2), Fraction(1, 3)]], dtype=object), r"got fractions\.Fraction"),
    ([[0.5, 2**53 + 1]], r"\[0\]\[1\]` is the integer 9007199254740993"),  # among floats
    ([[10**400, 1]], r"\[0\]\[0\]` is an integer of 401 digits, which is too large for a double"),
    ([[1, 2**53 + 1]], r"\[0\]\[1\]` is the integer 9007199254740993, which is not exactly "
                       r"representable as a double \(it would be rounded to 9007199254740992\.0\); "
                       r"integers are not rounded silently: pass a float"),
    (np.array([[2**63 - 1, 0]], dtype=np.int64), r"is the integer 9223372036854775807"),
    (np.array([[0, 2**64 - 1]], dtype=np.uint64),
     r"\[0\]\[1\]` is the integer 18446744073709551615"),
    (np.array([[1, 3]], dtype=np.longdouble) / 3, r"not exactly representable as a double"),
    (np.array([["2020-01-01", "2020-01-02"]], dtype="datetime64[D]"),
     r"got (datetime64|datetime\.date)"),
    ("12", r"`[^`]*` must hold real numbers, got str"),
]
BAD_START = [v for v in BAD_START
             if not (isinstance(v[0], np.ndarray) and v[0].dtype == np.longdouble
                     and np.finfo(np.longdouble).nmant <= 52)]  # long double == double here


@pytest.mark.parametrize("bad, message", BAD_START)
def test_not_real_refused_everywhere(bad, message):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no ComplexWarning (or any other) may escape
        for name, call in _entry_points(O, bad, G).items():
            with pytest.raises(InputError, match=message):
                call()
        for name, call in _entry_points(O, G, bad).items():  # the goal too
            with pytest.raises(InputError, match=message.replace("start", "")):
                call()
        if isinstance(bad, list):
            with pytest.raises(InputError, match=r"^`goal configuration\[2\]\[\d\]` (must hold "
                                                 r"real numbers|is (the|an) integer)"):
                pmplan.plan_configurations(O + G, O + bad, m=2)


def test_object_array_refused():
    """An object array is refused even when it holds floats only (a list of them is not)."""
    bad = np.array([[1.0, 2.0]], dtype=object)
    for call in (lambda: pmplan.plan(O, bad, G), lambda: pmplan.plan(O, S, bad, backend="numpy"),
                 lambda: pmplan.plan_batch(np.array([O]), bad[None], np.array([G])),
                 lambda: pmplan.plan_sequence(O, [S, bad]),
                 lambda: pmplan.plan_configurations(np.array(O + G, dtype=object), O + G)):
        with pytest.raises(InputError, match=r"must hold real numbers, got an object array "
                                             r"\(NumPy dtype object\); pass real numbers"):
            call()
    _same(pmplan.plan(O, [list(bad[0])], G), pmplan.plan(O, [[1.0, 2.0]], G))


def test_messages_name_the_argument():
    with pytest.raises(InputError, match=r"^`obstacles\[1\]\[0\]` must hold real numbers, got str"):
        pmplan.plan([[0, 0], ["2", 0]], S, G)
    with pytest.raises(InputError, match=r"^`goal` must hold real numbers, got bool"):
        pmplan.plan(O, S, np.array([[True, False]]))
    with pytest.raises(InputError, match=r"^`configs\[1\]\[0\]\[1\]` must hold real numbers"):
        pmplan.plan_sequence(O, [S, [[1.0, "x"]], G])
    with pytest.raises(InputError, match=r"^`configs\[2\]\[0\]\[0\]\[0\]` is an integer of 401"):
        pmplan.plan_sequence_batch([O], [[S], [G], [[[10**400, 0]]]])
    with pytest.raises(InputError, match=r"^`start\[0\]\[0\]` is an integer of more than 3900"):
        pmplan.plan(O, [[-(10**5000), 0]], G)
    with pytest.raises(InputError, match=r"^`start configuration\[2\]\[1\]` must hold real"):
        pmplan.plan_configurations(O + [[1, "a"]], O + G)
    with pytest.raises(InputError, match=r"`m` \(the number of obstacles\) must be an int"):
        pmplan.plan_configurations(O + S, O + G, m=True)


def test_overflowing_integer_is_an_input_error_not_overflow():
    """The issue's case: the integer 10**400 raised a bare OverflowError."""
    for call in _entry_points([[0, 0], [10**400, 0]], S, G).values():
        with pytest.raises(InputError, match=r"`[^`]*\[1\]\[0\]` is an integer .* too "
                                             r"large for a double"):
            call()


# --- accepted forms -------------------------------------------------------------------------
def _same(p, q):
    assert (p.domain, p.stratum, p.planner, p.dims) == (q.domain, q.stratum, q.planner, q.dims)
    assert p.clearance == q.clearance
    assert np.array_equal(p.path.times, q.path.times)
    assert np.array_equal(p.path.waypoints, q.path.waypoints)


@pytest.mark.parametrize("dtype", [np.float16, np.float32, np.float64, np.int8, np.int16,
                                   np.int32, np.int64, np.uint8, np.uint16, np.uint32, np.uint64])
def test_real_dtypes_accepted(dtype):
    o = np.array([[0, 0], [4, 0], [1, 3]])
    s = np.array([[1, 1], [2, 5]])
    g = np.array([[3, 2], [0, 6]])
    want = pmplan.plan(o.astype(float), s.astype(float), g.astype(float))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for call in _entry_points(o.astype(dtype), s.astype(dtype), g.astype(dtype)).values():
            got = call()
            _same(got if isinstance(got, pmplan.Plan) else got[0], want)


def test_exact_big_integers_accepted():
    """An integer a double holds exactly is a real number like any other (2**64, -2**70)."""
    big = [[0, 0], [2**64, 0]]
    want = pmplan.plan([[0.0, 0.0], [2.0**64, 0.0]], [[-(2.0**70), 1.0]], [[3.0, 2.0**60]],
                       lift="scene")
    for call in _entry_points(big, [[-(2**70), 1]], [[3, 2**60]], lift="scene").values():
        got = call()
        _same(got if isinstance(got, pmplan.Plan) else got[0], want)


@settings(max_examples=40)
@given(queries(2, 2, 2, degenerate=True), st.sampled_from(["list", "int32", "float32"]))
def test_integer_queries_in_other_forms_same_plan(q, form):
    """Exactly degenerate integer/dyadic queries given as lists or other dtypes (where exact)
    get the float64 plan, bit for bit."""
    o, s, g = q
    if form == "list":
        args = [a.tolist() for a in q]
    else:
        dt = np.dtype(form)
        args = [a.astype(dt) for a in q]
        if not all(np.array_equal(a.astype(float), b) for a, b in zip(args, q)):
            args = [a.tolist() for a in q]
    _same(pmplan.plan(*args), pmplan.plan(o, s, g))
    _same(pmplan.plan_batch(*[[a] for a in args])[0], pmplan.plan(o, s, g))


def test_float64_arrays_pass_through_without_a_copy():
    a = np.array([[0.0, 1.0], [2.0, 3.0]])
    assert as_real(a, "x") is a
    assert single._fast_array(a) is a
    f32 = np.array([[0.5, 1.0]], dtype=np.float32)
    assert single._fast_array(f32).dtype == np.float64


# --- lift ------------------------------------------------------------------------------------
BAD_LIFT = [
    (True, r"`lift` must be a positive real number or 'scene', got bool True"),
    (np.True_, r"got (numpy\.)?bool"),
    ("2", r"got str '2'"),
    ("Scene", r"got str 'Scene'"),
    (1j, r"got complex"),
    (Fraction(1, 2), r"got fractions\.Fraction"),
    ([1.0], r"got list"),
    (np.array(1.0), r"got numpy\.ndarray"),
    (10**400, r"`lift` is an integer of 401 digits, which is too large for a double"),
    (2**53 + 1, r"`lift` is the integer 9007199254740993, which is not exactly representable"),
    (0, r"`lift` must be a positive finite number, got 0"),
    (-2.0, r"positive finite number"),
    (float("nan"), r"positive finite number"),
    (float("inf"), r"positive finite number"),
]


def test_none_is_the_default_unit_but_not_a_json_value():
    """``lift=None`` is the default of every entry point (pmplan.configuration.default_lift);
    a query file says so by leaving "lift" out, not with null."""
    for call in _entry_points(O, S, G, lift=None).values():
        assert call() is not None
    obj = {"obstacles": O, "start": S, "goal": G, "lift": None}
    with pytest.raises(InputError, match="got NoneType"):
        parse_query(json.loads(json.dumps(obj)))


@pytest.mark.parametrize("lift, message", BAD_LIFT)
def test_bad_lift_refused_everywhere(lift, message):
    for name, call in _entry_points(O, S, G, lift=lift).items():
        with pytest.raises(InputError, match=message):
            call()
    # the planar planner, which used to ignore lift
    with pytest.raises(InputError, match=message):
        pmplan.plan([[0, 0], [4, 0], [5, 1.5]], [[1.5, -3]], [[7, -1.5]], lift=lift)
    # the fast paths' rule is the general one's
    assert single._fast_lift(lift) is None
    obj = {"obstacles": O, "start": S, "goal": G, "lift": lift}
    if isinstance(lift, (bool, int, float, str)) or lift is None:  # what JSON can hold
        with pytest.raises(InputError, match=message):
            parse_query(json.loads(json.dumps(obj)))


@pytest.mark.parametrize("lift", [1, 2.5, np.float64(0.5), np.float32(0.25), np.float16(2),
                                  np.int64(3), np.uint8(2), 2**60])
def test_real_lift_forms_accepted(lift):
    assert as_lift(lift) == float(lift)
    assert single._fast_lift(lift) == float(lift)
    for call in _entry_points(O, S, G, lift=lift).values():
        got = call()
        want = pmplan.plan(O, S, G, lift=float(lift))
        _same(got if isinstance(got, pmplan.Plan) else got[0], want)


def test_scene_lift_in_query_files():
    q = parse_query({"obstacles": O, "start": S, "goal": G, "lift": "scene"})
    assert q["lift"] == "scene"
    _same(pmplan.plan_query(q), pmplan.plan(O, S, G, lift="scene"))


def test_json_numbers():
    """JSON numbers follow the API's rule; the message names the coordinate."""
    text = '{"obstacles": [[0, 0], [2, 0]], "start": [[0, %s]], "goal": [[1, -1]]}'
    with pytest.raises(InputError, match=r"^`start\[0\]\[1\]` is an integer of 401 digits, "
                                         r"which is too large for a double"):
        parse_query(json.loads(text % ("1" + "0" * 400)))
    with pytest.raises(InputError, match=r"^`start\[0\]\[1\]` is the integer 9007199254740993"):
        parse_query(json.loads(text % (2**53 + 1)))
    for bad, kind in (("true", "bool"), ('"1"', "str"), ("null", "NoneType")):
        with pytest.raises(InputError, match=rf"^`start\[0\]\[1\]` must hold real numbers, got "
                                             rf"{kind}; write plain numbers in the query"):
            parse_query(json.loads(text % bad))
    q = parse_query(json.loads(text % (2**64)))
    assert q["start"][0, 1] == 2.0**64
    assert q["start"][0, 1] == 2.0**64
    with pytest.raises(InputError, match=r"`start` must be a list nested 2 deep"):
        parse_query(json.loads(text % "[1]"))


def test_json_integer_beyond_python_str_limit(tmp_path):
    """A JSON integer of 5000 digits (beyond Python's str -> int limit) is an InputError naming
    the coordinate, not a ValueError from the JSON decoder."""
    path = tmp_path / "q.json"
    path.write_text('{"obstacles": [[0, 0], [2, 0]], "start": [[0, -%s]], "goal": [[1, -1]]}'
                    % ("9" * 5000))
    with pytest.raises(InputError, match=r"^`start\[0\]\[1\]` is an integer of more than 3900 "
                                         r"digits, which is too large for a double"):
        read_query(path)
