"""Validation of queries: the configuration space F(R^d, m+n) and the fibre condition.

A configuration is an array of m+n pairwise distinct points of R^d, obstacles first (Mathematics §1).
A query is a pair of configurations with the same obstacles. Everything here raises a specific
:mod:`pmplan.errors` exception naming what was expected and what was received; nothing is
silently fixed.
"""

from __future__ import annotations

import numpy as np

from .backends import kernel_array, validation_kernels
from .errors import CollisionError, InputError, NonFiniteError, ObstacleMismatchError, ShapeError

__all__ = [
    "SCENE", "as_lift", "as_points", "as_real", "check_query", "coincident_pairs",
    "check_same_obstacles", "check_sequence", "as_config_list", "configuration_names",
    "kernel_array"]

#: the value of ``lift`` that makes the unit of every query its obstacles' radius
#: ``u(O) = max_{k >= 2} |o_k - o_1|`` (see :func:`pmplan.planners.base.unit`)
SCENE = "scene"

def configuration_names(r: int) -> list[str]:
    """How messages name the r configurations a motion passes through: ``start``,
    ``configuration 2`` .. ``configuration r-1``, ``goal``.

    >>> configuration_names(3)
    ['start', 'configuration 2', 'goal']
    """
    return ["start", *[f"configuration {k}" for k in range(2, r)], "goal"]


#: the fix every "not a real number" error names
_FIX = "pass real numbers, e.g. np.asarray(x, dtype=float)"
#: what a refused NumPy dtype kind is, in words
_KINDS = {"b": "bool", "c": "complex", "U": "str", "S": "bytes", "M": "datetime64",
          "m": "timedelta64", "V": "structured (void)", "O": "object"}
#: Python types that may hide among ints and floats in a list (np.asarray makes them numbers)
_HIDDEN = (bool, np.bool_)


def _where(name: str, index) -> str:
    """``name[i][j]`` for a flat index into an array of some shape, or ``name``."""
    if index is None:
        return f"`{name}`"
    return f"`{name}" + "".join(f"[{i}]" for i in index) + "`"


def _int_text(v: int) -> str:
    """A Python integer for a message: ``the integer 123``, or its digit count when it is long
    (``str`` refuses integers of more than 4300 digits)."""
    if v.bit_length() > 13000:
        return "an integer of more than 3900 digits"
    text = str(v)
    if len(text) <= 24:
        return f"the integer {text}"
    return f"an integer of {len(text.lstrip('-'))} digits"


def _inexact_int(v, name: str, index) -> InputError | None:
    """The error for an integer a double cannot hold exactly (None when it can): never rounded."""
    v = int(v)
    try:
        f = float(v)
    except OverflowError:
        why = "is too large for a double (beyond 1.8e308)"
    else:
        if int(f) == v:
            return None
        why = f"is not exactly representable as a double (it would be rounded to {f!r})"
    return InputError(
        f"{_where(name, index)} is {_int_text(v)}, which {why}; integers are not "
        "rounded silently: pass a float (e.g. float(v)) if rounding is acceptable"
        + (", or scale the scene down" if "too large" in why else "")
    )


def _not_real(name: str, what: str, index=None, fix: str | None = None) -> InputError:
    """The error for a value that is not a real number (``what`` names its type)."""
    if fix is None:
        fix = _FIX if "complex" not in what else \
            "pass real numbers, e.g. np.real(x) if the imaginary parts are zero"
    return InputError(f"{_where(name, index)} must hold real numbers, got {what}; {fix}")


def _type_name(v) -> str:
    t = type(v)
    return t.__name__ if t.__module__ == "builtins" else f"{t.__module__}.{t.__qualname__}"


_EXACT_INT = 2**53  # every integer of at most this magnitude is a double


def is_plain(v) -> bool:
    """True when every leaf of nested lists (tuples) is a float or an int of magnitude at most
    2**53 -- the common case, which then converts with one ``np.array(v, dtype=float)``."""
    for r in v:
        t = type(r)
        if t is list or t is tuple:
            for x in r:
                tx = type(x)
                if tx is float or (tx is int and -_EXACT_INT <= x <= _EXACT_INT):
                    continue
                if (tx is list or tx is tuple) and is_plain(x):
                    continue
                return False
        elif not (t is float or (t is int and -_EXACT_INT <= r <= _EXACT_INT)):
            return False
    return True


def as_real(value, name: str, fix: str | None = None) -> np.ndarray:
    """``value`` as a float64 array, if it holds real numbers only; the one rule of pmplan.

    Accepted: arrays of a real dtype (float16, float32, float64; signed and unsigned
    integers) and (nested) lists of Python ints and floats. Refused with an
    :class:`~pmplan.errors.InputError` naming the argument, the offending type and the fix:
    bools, complex numbers, strings and bytes, object arrays of anything but ints and floats
    (``Fraction``, ``Decimal``, ``None``, ...), and any number a double cannot hold *exactly*
    (an integer beyond 2**53 that is not a double, 10**400, a long double): nothing is
    silently converted or rounded. A float64 ndarray is returned as it is (no copy).
    ``fix`` replaces the fix the message suggests (e.g. for a query file).

    Examples
    --------
    >>> as_real([[0, 1], [2.5, 3]], "start").dtype
    dtype('float64')
    >>> as_real([["0", "1"]], "start")
    Traceback (most recent call last):
    ...
    pmplan.errors.InputError: `start[0][0]` must hold real numbers, got str; pass real \
numbers, e.g. np.asarray(x, dtype=float)
    """
    if type(value) in (list, tuple) and is_plain(value):
        try:
            return np.array(value, dtype=np.float64)
        except ValueError:  # ragged: worded below
            pass
    if isinstance(value, np.ndarray):
        arr, from_list = value, False
    else:
        if isinstance(value, (str, bytes)):
            raise _not_real(name, _type_name(value), fix=fix)
        try:
            arr = np.asarray(value)
        except (TypeError, ValueError, OverflowError) as exc:
            raise InputError(
                f"`{name}` must be a numeric array (nested lists of numbers of equal lengths): "
                f"{exc}"
            ) from None
        from_list = True
    dt = arr.dtype
    kind = dt.kind
    if kind in "fiu":
        if from_list:  # a list: a bool (or an inexact int among floats) became a number
            objs = np.asarray(value, dtype=object)
            types = set(map(type, objs.ravel().tolist()))
            if any(t in types for t in _HIDDEN) or (kind == "f" and int in types):
                _object_reals(objs, name, fix)
        if dt == np.float64:
            return arr
        out = arr.astype(np.float64)
        if dt.itemsize >= 8:  # int64, uint64, long double: exactly representable?
            if kind == "f":
                bad = out.astype(dt) != arr
            else:
                top = 2.0**63 if kind == "i" else 2.0**64
                inside = out < top
                bad = ~inside | (np.where(inside, out, 0.0).astype(dt) != arr)
            if bad.any():
                index = tuple(int(i) for i in np.unravel_index(np.flatnonzero(bad)[0], arr.shape))
                if kind == "f":
                    raise InputError(
                        f"{_where(name, index)} is the {dt} value {arr[index]!r}, which is not "
                        "exactly representable as a double; values are not rounded silently: "
                        "pass float64 (np.asarray(x, dtype=float)) if rounding is acceptable"
                    )
                raise _inexact_int(arr[index], name, index)
        return out
    if kind == "O":
        out = _object_reals(arr, name, fix)
        if from_list:  # a list holding an int beyond 64 bits that a double holds exactly
            return out
        raise _not_real(name, "an object array (NumPy dtype object)", fix=fix)
    if from_list:  # name the first offending element (a str, a complex, a bool)
        _object_reals(np.asarray(value, dtype=object), name, fix)
    what = _KINDS.get(kind, str(dt))
    raise _not_real(name, f"{what} (NumPy dtype {dt})", fix=fix)


def _object_reals(arr: np.ndarray, name: str, fix: str | None = None) -> np.ndarray:
    """An object array as float64: only Python ints (exactly representable) and floats, and
    NumPy real scalars, are accepted (NumPy makes an object array of a list holding an integer
    beyond 64 bits, a Fraction, a Decimal, None, ...)."""
    flat = arr.ravel().tolist()
    out = np.empty(len(flat))
    for k, v in enumerate(flat):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.integer,
                                                                  np.floating)):
            index = tuple(int(i) for i in np.unravel_index(k, arr.shape))
            raise _not_real(name, _type_name(v), index, fix)
        if isinstance(v, (int, np.integer)):
            err = _inexact_int(v, name, tuple(int(i) for i in np.unravel_index(k, arr.shape)))
            if err is not None:
                raise err
        elif isinstance(v, np.floating) and np.dtype(type(v)).itemsize > 8 \
                and np.float64(v) != v:
            index = tuple(int(i) for i in np.unravel_index(k, arr.shape))
            raise InputError(
                f"{_where(name, index)} is the {type(v).__name__} value {v!r}, which is not "
                "exactly representable as a double; values are not rounded silently: pass "
                "float64 (np.asarray(x, dtype=float)) if rounding is acceptable"
            )
        out[k] = float(v)
    return out.reshape(arr.shape)


#: the paper's unit, the default ``lift`` of a raw plan (:func:`default_lift`)
PAPER_LIFT = 1.0


def default_lift(lift, radius=0.0, obstacle_radius=0.0, refining: bool = False):
    """The unit a planning function uses: ``lift`` itself when given; when it is None (the
    default), the robots' diameter ``max(2 radius, radius + obstacle_radius)`` for a refined
    plan with a positive radius -- the default planner's lanes are then exactly as far apart
    as the robots need (Mathematics §4.4), and the unit scales with the query, so the plan of
    a scaled query is the scaled plan -- and otherwise the paper's 1 (:data:`PAPER_LIFT`).

    The radii are already checked (:func:`pmplan.refine.stage.check_parameters`).
    """
    if lift is not None:
        return lift
    if refining:
        unit = max(2.0 * float(radius), float(radius) + float(obstacle_radius))
        if 0.0 < unit < float("inf"):
            return unit
    return PAPER_LIFT


def as_lift(lift) -> float | str:
    """Check ``lift``: a positive finite real number, or :data:`SCENE` (``"scene"``).

    The one rule for every entry point (:func:`pmplan.plan` and the other planning functions,
    their fast paths, query files). A real number is a Python ``int`` or ``float`` or a NumPy
    integer or floating scalar -- not a bool, a string, a complex number -- that a double holds
    exactly. Returns the float, or ``"scene"``.

    Raises
    ------
    InputError
        Naming what was given and what to pass instead.
    """
    if isinstance(lift, str) and lift == SCENE:
        return SCENE
    fix = ("pass a positive number (the unit of the motion: 1.0, the paper's) or "
           "lift='scene' (the obstacles' size)")
    if isinstance(lift, (bool, np.bool_)) or not isinstance(lift, (int, float, np.integer,
                                                                    np.floating)):
        raise InputError(f"`lift` must be a positive real number or 'scene', got "
                         f"{_type_name(lift)} {lift!r}; {fix}")
    if isinstance(lift, (int, np.integer)):
        err = _inexact_int(lift, "lift", None)
        if err is not None:
            raise err
    value = float(lift)
    if isinstance(lift, np.floating) and value != lift:
        raise InputError(f"`lift` is the {type(lift).__name__} value {lift!r}, which is not "
                         "exactly representable as a double; pass a float")
    if not 0.0 < value < np.inf:
        raise InputError(f"`lift` must be a positive finite number, got {lift!r}; {fix}")
    return value


def as_points(value, name: str, batched: bool) -> np.ndarray:
    """Convert to a float array of shape (k, d) (or (B, k, d) when ``batched``).

    The values must be real numbers (:func:`as_real`: no bools, strings, complex numbers,
    objects, nor integers a double cannot hold exactly).

    Raises
    ------
    InputError
        Ragged input, or values that are not real numbers.
    ShapeError
        Wrong number of axes.
    NonFiniteError
        NaN or infinite coordinates.
    """
    arr = as_real(value, name)
    want = 3 if batched else 2
    form = "(B, k, d)" if batched else "(k, d)"
    if arr.ndim != want:
        raise ShapeError(f"Expected `{name}` to have shape {form}, got {arr.shape}.")
    if not np.isfinite(arr).all():
        bad = np.argwhere(~np.isfinite(arr))[0].tolist()
        raise NonFiniteError(f"`{name}` has a NaN or infinite coordinate at index {tuple(bad)}.")
    return arr


def _point_name(i: int, m: int) -> str:
    return f"o{i + 1}" if i < m else f"x{i - m + 1}"


def coincident_pairs(config: np.ndarray) -> np.ndarray:
    """Return a bool mask (B,) of configurations (B, P, d) with two exactly equal points.

    Lexicographic sort of the points of each configuration (stable argsorts, last coordinate
    first), then comparison of neighbours: O(B P log P).
    """
    b, p, d = config.shape
    order = np.broadcast_to(np.arange(p), (b, p)).copy()
    for k in reversed(range(d)):
        key = np.take_along_axis(config[:, :, k], order, axis=1)
        order = np.take_along_axis(order, np.argsort(key, axis=1, kind="stable"), axis=1)
    srt = np.take_along_axis(config, order[:, :, None], axis=1)
    return (srt[:, 1:] == srt[:, :-1]).all(axis=2).any(axis=1)


def _first_pair(config: np.ndarray) -> tuple[int, int]:
    p = config.shape[0]
    for i in range(p):
        for j in range(i + 1, p):
            if np.array_equal(config[i], config[j]):
                return i, j
    raise AssertionError("no coincident pair")


def check_configuration(config: np.ndarray, m: int, which: str, batched: bool) -> None:
    """Raise :class:`CollisionError` if two points of a configuration (B, P, d) coincide."""
    bad = coincident_pairs(config)
    if bad.any():
        b = int(np.flatnonzero(bad)[0])
        i, j = _first_pair(config[b])
        pair = (_point_name(i, m), _point_name(j, m))
        where = f" of query {b}" if batched else ""
        more = f" ({int(bad.sum())} queries in all)" if batched and bad.sum() > 1 else ""
        phrase = f"the {which} configuration" if which in ("start", "goal") else which
        raise CollisionError(
            f"points {pair[0]} and {pair[1]} of {phrase}{where} coincide "
            f"at {config[b, i].tolist()}{more}",
            index=b if batched else None,
            which=which,
            pair=pair,
        )


def check_query(obstacles, start, goal, *, batched: bool, names: tuple[str, str] = ("start", "goal"),
                deep: bool = True):
    """Validate a query (or a batch) and return float arrays (B, m, d), (B, n, d), (B, n, d).

    A single query is returned as a batch of one. ``names`` label the two robot arrays in error
    messages (e.g. ``("configuration 1", "configuration 3")`` for sequential queries).

    A valid query takes the fast path (``_valid_fast``: one numba pass, no temporary); any
    problem sends it through the checks below, which raise the error. ``deep=False`` checks the
    types, axes and shapes only, for a caller whose kernel validates every query itself (and
    calls this again with ``deep=True`` to raise the error when it finds an invalid one).
    """
    fast = _valid_fast(obstacles, start, goal, batched, deep)
    if fast is not None:
        return fast
    obstacles = as_points(obstacles, "obstacles", batched)
    start = as_points(start, names[0], batched)
    goal = as_points(goal, names[1], batched)
    if not batched:
        obstacles, start, goal = obstacles[None], start[None], goal[None]
    b, m, d = obstacles.shape
    if start.shape[0] != b or goal.shape[0] != b:
        raise ShapeError(
            f"Expected the same batch size B for obstacles, start and goal, got "
            f"{obstacles.shape[0]}, {start.shape[0]} and {goal.shape[0]}."
        )
    if start.shape[2] != d or goal.shape[2] != d:
        raise ShapeError(
            f"Expected every point to have d = {d} coordinates (from `obstacles`), got "
            f"start d = {start.shape[2]}, goal d = {goal.shape[2]}."
        )
    if start.shape != goal.shape:
        raise ShapeError(
            f"Expected `start` and `goal` to have the same shape (n, d), got "
            f"{start.shape[1:]} and {goal.shape[1:]}."
        )
    obstacles = np.ascontiguousarray(obstacles)
    start = np.ascontiguousarray(start)
    goal = start if goal is start else np.ascontiguousarray(goal)
    for which, robots in zip(names, (start, goal)):
        if robots is goal and goal is start and which == names[1]:
            break
        _check_distinct(obstacles, robots, m, which, batched)
    return obstacles, start, goal


def _valid_fast(obstacles, start, goal, batched: bool, deep: bool = True):
    """Return the arrays of :func:`check_query` when the query is valid, else None.

    Converts like :func:`as_points` (:func:`as_real`), checks the axes and shapes, then (if
    ``deep``) asks :func:`pmplan.kernels.validation.valid_queries` (finite, no two equal points
    in C or C') in one pass.
    It never raises: None means "let the reference checks decide (and word the error)".
    """
    kern = validation_kernels()
    if not kern.AVAILABLE:  # pragma: no cover
        return None
    try:
        o = as_real(obstacles, "obstacles")
        s = as_real(start, "start")
        g = as_real(goal, "goal")
    except InputError:
        return None
    want = 3 if batched else 2
    if o.ndim != want or s.ndim != want or g.ndim != want:
        return None
    if not batched:
        o, s, g = o[None], s[None], g[None]
    if s.shape != g.shape or s.shape[0] != o.shape[0] or s.shape[2] != o.shape[2]:
        return None
    o = kernel_array(o)
    s = kernel_array(s)
    g = s if g is s else kernel_array(g)
    if deep and not kern.valid_queries(o, s, g):
        return None
    return o, s, g


def _check_distinct(obstacles: np.ndarray, robots: np.ndarray, m: int, which: str,
                    batched: bool) -> None:
    """Raise :class:`CollisionError` if two points of ``obstacles u robots`` coincide.

    The fast path is one pass of the numba kernel
    :func:`pmplan.kernels.validation.first_coincident` (no temporary); only when it finds a
    coincidence (or numba is missing) does the numpy path :func:`check_configuration` run, and
    it raises with the full message.
    """
    kern = validation_kernels()
    if kern.AVAILABLE and kern.first_coincident(obstacles, robots) < 0:
        return
    check_configuration(np.concatenate([obstacles, robots], axis=1), m, which, batched)


def check_same_obstacles(c_start: np.ndarray, c_goal: np.ndarray, m: int, batched: bool) -> None:
    """Raise :class:`~pmplan.ObstacleMismatchError` if the first m rows of C and C' differ."""
    same = (c_start[..., :m, :] == c_goal[..., :m, :]).all(axis=(-1, -2))
    if not np.all(same):
        if batched:
            b = int(np.flatnonzero(~np.asarray(same))[0])
            raise ObstacleMismatchError(
                f"the obstacles of the start and goal configurations of query {b} differ: "
                f"{c_start[b, :m].tolist()} != {c_goal[b, :m].tolist()} "
                "(obstacles are fixed along a motion)"
            )
        raise ObstacleMismatchError(
            f"the obstacles of the start and goal configurations differ: "
            f"{c_start[:m].tolist()} != {c_goal[:m].tolist()} (obstacles are fixed along a motion)"
        )


def check_sequence(obstacles, configs, batched: bool):
    """``obstacles`` and the r >= 2 configurations ``configs`` of a query through intermediate
    configurations, checked (:func:`check_query` for each, one shape for all) and converted."""
    configs = as_config_list(configs)
    configs = [as_real(c, f"configs[{k}]") for k, c in enumerate(configs)]
    if len(configs) < 2:
        raise ShapeError(f"Expected at least r = 2 configurations, got {len(configs)}.")
    r = len(configs)
    obstacles_b, first, _ = check_query(
        obstacles, configs[0], configs[-1], batched=batched,
        names=("configuration 1 (start)", f"configuration {r} (goal)"),
    )
    out = [first]
    for k, c in enumerate(configs[1:], start=2):
        _, ck, _ = check_query(obstacles, c, c, batched=batched,
                               names=(f"configuration {k}", f"configuration {k}"))
        if ck.shape != first.shape:
            raise ShapeError(f"configuration {k} has shape {ck.shape[1:]}, expected {first.shape[1:]}")
        out.append(ck)
    return obstacles_b, out


def as_config_list(configs) -> list:
    """``configs`` (the configurations of a sequential query) as a list, or the InputError
    saying what it must be."""
    try:
        if isinstance(configs, (str, bytes)):
            raise TypeError
        return list(configs)
    except TypeError:
        raise InputError(f"`configs` must be a list of r >= 2 arrays of real numbers, got "
                         f"{type(configs).__name__}") from None
