"""Shared Hypothesis strategies for pmplan tests.

Every strategy returns numpy float arrays. Points of one configuration are always pairwise
distinct (configurations lie in F(R^d, m+n), Mathematics §1.1).

Grids (the ``grid`` argument of :func:`coords`):

* ``"int"``     small integers in [-4, 4]: exact ties (equal columns / heights) occur often;
* ``"dyadic"``  multiples of 1/8 in [-4, 4]: exact ties, non-integer;
* ``"float"``   generic doubles, uniform in [-10, 10] (drawn from a Hypothesis-chosen seed, so
  never subnormal and never pathologically close: well-conditioned generic queries);
* ``"nasty"``   raw Hypothesis floats in [-1e3, 1e3] (zeros, subnormals, neighbours, ...);
* ``"mixed"``   one of ``"int"``, ``"dyadic"``, ``"float"``.

``degenerate=True`` configurations and queries are drawn on the integer / dyadic grids; ``o2 - o1``
is sometimes exactly along an axis or the pole ``N = e_d`` (Mathematics §4.1); some obstacles o3.. and
robots are *moved onto the column* of an earlier point exactly (``x = y + k v`` with integer ``k``
and a vector ``v`` orthogonal to ``w = o2 - o1``) or onto its height (``x = y + k w``), and
the whole scene is scaled by a power of two and translated by a dyadic vector -- all exact in
double precision, so the degeneracies are exact. ``degenerate=False`` gives generic float scenes.
"""

from __future__ import annotations

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

__all__ = [
    "GRIDS",
    "scalars",
    "coords",
    "configurations",
    "queries",
    "orthogonal_integer_vector",
]

GRIDS = ("int", "dyadic", "float", "nasty", "mixed")


def _generic_floats(shape, low: float = -10.0, high: float = 10.0):
    """Strategy: a float array of ``shape`` uniform in [low, high] from a drawn seed."""
    return st.integers(0, 2**32 - 1).map(
        lambda seed: np.random.default_rng(seed).uniform(low, high, size=shape)
    )


def scalars(grid: str = "mixed"):
    """Strategy for one coordinate on ``grid`` (see the module docstring)."""
    if grid == "int":
        return st.integers(-4, 4).map(float)
    if grid == "dyadic":
        return st.integers(-32, 32).map(lambda k: k / 8.0)
    if grid == "float":
        return _generic_floats(()).map(float)
    if grid == "nasty":
        return st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)
    if grid == "mixed":
        return st.one_of(scalars("int"), scalars("dyadic"), scalars("float"))
    raise ValueError(f"unknown grid {grid!r}; choose one of {GRIDS}")


def coords(d: int, grid: str = "mixed"):
    """Strategy for one point of R^d, an array of shape (d,), coordinates on ``grid``."""
    if grid == "float":
        return _generic_floats((d,))
    return st.lists(scalars(grid), min_size=d, max_size=d).map(
        lambda xs: np.array(xs, dtype=float)
    )


def orthogonal_integer_vector(w: np.ndarray, choice: int) -> np.ndarray:
    """Return a nonzero vector orthogonal to ``w`` built exactly from its coordinates.

    ``v = (..., -w_j, ..., w_i, ...)`` at positions (i, j) chosen from ``choice``; for d > 2 it
    falls back to a unit axis vector orthogonal to ``w`` when that pair of coordinates is zero.
    Exact for integer / dyadic ``w`` (only sign changes). Returns None if none is found.
    """
    d = w.shape[0]
    pairs = [(i, j) for i in range(d) for j in range(i + 1, d)]
    order = pairs[choice % len(pairs):] + pairs[: choice % len(pairs)]
    for i, j in order:
        if w[i] != 0 or w[j] != 0:
            v = np.zeros(d)
            v[i], v[j] = -w[j], w[i]
            return v
    return None


def _distinct_rows(a: np.ndarray) -> bool:
    return len({tuple(r) for r in a.tolist()}) == a.shape[0]


@st.composite
def _grid_points(draw, k: int, d: int, grid: str, avoid: list[tuple]) -> list[np.ndarray]:
    """k distinct grid points of R^d (distinct from ``avoid`` too)."""
    seen = set(avoid)
    out = []
    for _ in range(k):
        p = draw(coords(d, grid).filter(lambda q: tuple(q.tolist()) not in seen))
        seen.add(tuple(p.tolist()))
        out.append(p)
    return out


@st.composite
def _degenerate_points(draw, base: np.ndarray, k: int, grid: str, w: np.ndarray) -> np.ndarray:
    """k grid points distinct from ``base`` and each other, some moved exactly onto the column
    (``+ j v``, ``v . w = 0``) or the height (``+ j w``) of an earlier point."""
    d = base.shape[1]
    nb = base.shape[0]
    pts = np.array(
        draw(_grid_points(k, d, grid, [tuple(o) for o in base.tolist()])), dtype=float
    ).reshape(k, d)
    for i in range(k):
        kind = draw(st.sampled_from(["column", "keep", "column", "height", "column"]))
        if kind == "keep":
            continue
        earlier = np.concatenate([base, pts[:i]], axis=0)
        anchor = earlier[draw(st.integers(0, nb + i - 1))]
        j = float(draw(st.sampled_from([-2, -1, 1, 2, 3])))
        v = orthogonal_integer_vector(w, draw(st.integers(0, 20))) if kind == "column" else w
        cand = anchor + j * v
        others = np.concatenate([base, np.delete(pts, i, axis=0)], axis=0)
        if not any(np.array_equal(cand, q) for q in others):
            pts[i] = cand
    return pts


@st.composite
def _degenerate_obstacles(draw, m: int, d: int, grid: str) -> np.ndarray:
    """m distinct grid obstacles; o2 - o1 is sometimes exactly a positive multiple of e_d (the
    pole N of Mathematics §4.1) or of another axis, and o3.. sometimes share columns / heights."""
    o1 = draw(coords(d, grid))
    kind = draw(st.sampled_from(["free", "pole", "axis"]))
    if kind == "free":
        o2 = draw(coords(d, grid).filter(lambda q: not np.array_equal(q, o1)))
    else:
        c = float(draw(st.sampled_from([1, 2, 3, -1, -2] if kind == "axis" else [1, 2, 3])))
        axis = d - 1 if kind == "pole" else draw(st.integers(0, d - 1))
        o2 = o1.copy()
        o2[axis] += c
    base = np.stack([o1, o2])
    if m == 2:
        return base
    rest = draw(_degenerate_points(base, m - 2, grid, o2 - o1))
    return np.concatenate([base, rest], axis=0)


@st.composite
def _scale_translate(draw, d: int):
    """An exact similarity: a power of two and a dyadic translation."""
    s = 2.0 ** draw(st.integers(-3, 3))
    t = np.array(draw(st.lists(st.integers(-16, 16), min_size=d, max_size=d)), dtype=float) / 4.0
    return s, t


@st.composite
def queries(draw, d: int, m: int, n: int, degenerate: bool = False, grid: str | None = None):
    """Strategy for a query: ``(obstacles (m, d), start (n, d), goal (n, d))``.

    The obstacles are shared; ``obstacles ∪ start`` and ``obstacles ∪ goal`` each have pairwise
    distinct points. ``degenerate=True``: exact ties on grids (see module docstring);
    ``degenerate=False``: generic floats (or ``grid`` if given).
    """
    if not degenerate:
        grid = grid or "float"
        if grid == "float":
            arr = draw(_generic_floats((m + 2 * n, d)))
        else:
            arr = np.array(
                draw(st.lists(coords(d, grid), min_size=m + 2 * n, max_size=m + 2 * n)),
                dtype=float,
            ).reshape(m + 2 * n, d)
        obstacles, start, goal = arr[:m], arr[m:m + n], arr[m + n:]
        assume(_distinct_rows(np.concatenate([obstacles, start])))
        assume(_distinct_rows(np.concatenate([obstacles, goal])))
        return obstacles, start, goal
    grid = grid or draw(st.sampled_from(["int", "dyadic"]))
    obstacles = draw(_degenerate_obstacles(m, d, grid))
    w = obstacles[1] - obstacles[0]
    start = draw(_degenerate_points(obstacles, n, grid, w))
    goal = draw(_degenerate_points(obstacles, n, grid, w))
    s, t = draw(_scale_translate(d))
    obstacles, start, goal = obstacles * s + t, start * s + t, goal * s + t
    assert _distinct_rows(np.concatenate([obstacles, start]))
    assert _distinct_rows(np.concatenate([obstacles, goal]))
    return obstacles, start, goal


@st.composite
def configurations(draw, d: int, m: int, n: int, degenerate: bool = False,
                   grid: str | None = None):
    """Strategy for one configuration: an array (m + n, d) of distinct points, obstacles first."""
    obstacles, start, _ = draw(queries(d, m, n, degenerate, grid))
    return np.concatenate([obstacles, start], axis=0)


def spaced_points(rng: np.random.Generator, k: int, d: int, lo: float, hi: float,
                  gap: float) -> np.ndarray:
    """k points uniform in [lo, hi]^d, pairwise at least ``gap`` apart (rejection sampling with
    ``rng``: seeded draws for the tests that probe families of queries)."""
    while True:
        x = rng.uniform(lo, hi, (k, d))
        dist = np.linalg.norm(x[:, None] - x[None], axis=-1)
        if k < 2 or dist[np.triu_indices(k, 1)].min() >= gap:
            return x
