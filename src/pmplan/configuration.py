"""Validation of queries: the configuration space F(R^d, m+n) and the fibre condition.

A configuration is an array of m+n pairwise distinct points of R^d, obstacles first (SPEC 0).
A query is a pair of configurations with the same obstacles. Everything here raises a specific
:mod:`pmplan.errors` exception naming what was expected and what was received; nothing is
silently fixed.
"""

from __future__ import annotations

import numpy as np

from .errors import CollisionError, InputError, NonFiniteError, ObstacleMismatchError, ShapeError

__all__ = [
    "as_points", "check_query", "coincident_pairs", "check_same_obstacles", "kernel_array"]


def as_points(value, name: str, batched: bool) -> np.ndarray:
    """Convert to a float array of shape (k, d) (or (B, k, d) when ``batched``).

    Raises
    ------
    InputError
        Ragged or non-numeric input.
    ShapeError
        Wrong number of axes.
    NonFiniteError
        NaN or infinite coordinates.
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(
            f"`{name}` must be a numeric array (nested lists of numbers of equal lengths): {exc}"
        ) from None
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

    A valid query takes the fast path (:func:`_valid_fast`: one numba pass, no temporary); any
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


def kernel_array(a) -> np.ndarray:
    """``a`` as a C-contiguous, writeable float64 array (copied only when it is not one).

    The numba kernels are compiled for exactly this array type: a read-only input (a memory
    map, a broadcast view) would otherwise make numba compile a second copy of every kernel.
    """
    a = np.ascontiguousarray(a, dtype=np.float64)
    return a if a.flags.writeable else a.copy()


def _valid_fast(obstacles, start, goal, batched: bool, deep: bool = True):
    """Return the arrays of :func:`check_query` when the query is valid, else None.

    Converts like :func:`as_points`, checks the axes and shapes, then (if ``deep``) asks
    :func:`pmplan._kernels.valid_queries` (finite, no two equal points in C or C') in one pass.
    It never raises: None means "let the reference checks decide (and word the error)".
    """
    from . import _kernels

    if not _kernels.AVAILABLE:  # pragma: no cover
        return None
    try:
        o = np.asarray(obstacles, dtype=float)
        s = np.asarray(start, dtype=float)
        g = np.asarray(goal, dtype=float)
    except (TypeError, ValueError):
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
    if deep and not _kernels.valid_queries(o, s, g):
        return None
    return o, s, g


def _check_distinct(obstacles: np.ndarray, robots: np.ndarray, m: int, which: str,
                    batched: bool) -> None:
    """Raise :class:`CollisionError` if two points of ``obstacles u robots`` coincide.

    The fast path is one pass of the numba kernel :func:`pmplan._kernels.first_coincident`
    (no temporary); only when it finds a coincidence (or numba is missing) does the numpy path
    :func:`check_configuration` run, and it raises with the full message.
    """
    from . import _kernels

    if _kernels.AVAILABLE and _kernels.first_coincident(obstacles, robots) < 0:
        return
    check_configuration(np.concatenate([obstacles, robots], axis=1), m, which, batched)


def check_same_obstacles(c_start: np.ndarray, c_goal: np.ndarray, m: int, batched: bool) -> None:
    """Raise :class:`ObstacleMismatchError` if the first m rows of C and C' differ."""
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
