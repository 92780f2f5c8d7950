"""Query generators: exact degenerate queries per stratum, random and nearly degenerate queries.

A *stratum* of the obstacle-line planner (Mathematics §4.2, paper Section 3 for m = 2) is fixed by the
numbers of distinct columns ``cp(C)``, ``cp(C')``, ``cp_o`` and, for odd d, the exact flag
``e == N`` (Mathematics §4.1); its label is ::

    l = cp(C) + cp(C') - cp_o + 2 - [e == N]

A finer notion is the *piece* (Mathematics §4.2): the partition of ``O u X`` and of ``O u X'`` by equal
columns, plus the flag ``e == N``. This module builds queries with prescribed strata **exactly**
(small integer or dyadic coordinates, so every column coincidence is an exact equality of the
floats), classifies queries exactly with :func:`pmplan.predicates.projection_classes`, and moves
queries inside their piece for continuity checks.

Everything takes a :class:`numpy.random.Generator`, so results are reproducible. Used by the
test-suite and by ``pmplan verify``.

Construction of exact degeneracies
----------------------------------
With an integer direction ``w`` (``o2 = o1 + L w``), a point ``o1 + c w + q`` with an integer
column index ``c`` and an integer offset ``q`` orthogonal to ``w`` (an integer combination of the
vectors ``w_j e_i - w_i e_j``) has column ``(y - o1) . w = c |w|^2``: two points share a column iff
their indices ``c`` are equal, exactly, in floating point.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .planar_strata import split_name
from .planners.planar_three import classify, parse_stratum
from .predicates import projection_classes

__all__ = [
    "Query",
    "Stratum",
    "strata",
    "stratum_of",
    "piece_of",
    "column_query",
    "column_sequence",
    "random_queries",
    "near_degenerate_queries",
    "perturb_within_stratum",
    "planar_stratum_queries",
    "perturb_planar_stratum",
]


class Query(NamedTuple):
    """A query: obstacles (m, d), start (n, d), goal (n, d) -- or a batch with a leading B axis."""

    obstacles: np.ndarray
    start: np.ndarray
    goal: np.ndarray


class Stratum(NamedTuple):
    """The stratum of a query (or of a sequence of r configurations) for the obstacle-line planner.

    Attributes
    ----------
    cps : tuple of int
        ``cp(C_k)`` for every configuration (two for an ordinary query).
    cp_o : int
        The number of distinct obstacle columns.
    pole : bool
        ``e == N`` exactly (odd d only, Mathematics §4.1); always False for even d.
    label : int
        ``sum_k cp(C_k) - (r-1) cp_o + 2 - [e == N]`` (Mathematics §4.2, §4.3).
    """

    cps: tuple
    cp_o: int
    pole: bool
    label: int

    @property
    def cp_start(self) -> int:
        """``cp(C)``."""
        return self.cps[0]

    @property
    def cp_goal(self) -> int:
        """``cp(C')`` (the last configuration)."""
        return self.cps[-1]

    def record(self) -> tuple:
        """The obstacle-line planner's stratum record ``(cp(C_1), ..., cp(C_r), cp_o, pole)``."""
        return (*self.cps, self.cp_o, int(self.pole))


# ------------------------------------------------------------------------------------------------
# exact classification


def _split(query):
    obstacles, *configs = (np.asarray(a, dtype=float) for a in query)
    if obstacles.ndim != 2 or not configs or any(c.ndim != 2 for c in configs):
        raise ValueError(
            "Expected a query (obstacles (m, d), config_1 (n, d), ..., config_r (n, d)), got "
            f"shapes {[np.shape(a) for a in query]}."
        )
    return obstacles, configs


def _is_pole(obstacles: np.ndarray) -> bool:
    """``e == N`` exactly: o2 - o1 is a positive multiple of e_d, d odd (float comparisons)."""
    d = obstacles.shape[1]
    o1, o2 = obstacles[0], obstacles[1]
    return bool(d % 2 == 1 and np.all(o1[:-1] == o2[:-1]) and o2[-1] > o1[-1])


def _canonical(labels: np.ndarray) -> tuple:
    """Relabel a partition by order of first occurrence."""
    seen: dict = {}
    return tuple(seen.setdefault(int(v), len(seen)) for v in labels)


def piece_of(query) -> tuple:
    """Return the *piece* of a query (Mathematics §4.2): column partitions of ``O u C_k`` and ``e == N``.

    Parameters
    ----------
    query : tuple
        ``(obstacles (m, d), config_1 (n, d), ..., config_r (n, d))``.

    Returns
    -------
    tuple
        ``(pole, partition_1, ..., partition_r)``; each partition is a tuple of m+n class
        indices (numbered by first occurrence). Two queries in the same piece have equal values.

    Examples
    --------
    >>> piece_of(([[0, 0], [2, 0]], [[0, 1]], [[1, 1]]))
    (False, (0, 1, 0), (0, 1, 2))
    """
    obstacles, configs = _split(query)
    pts = np.stack([np.concatenate([obstacles, c]) for c in configs])
    o1 = np.broadcast_to(obstacles[0], (len(configs), obstacles.shape[1]))
    o2 = np.broadcast_to(obstacles[1], (len(configs), obstacles.shape[1]))
    labels, _, _ = projection_classes(pts, o1, o2)
    return (_is_pole(obstacles), *(_canonical(row) for row in labels))


def stratum_of(query) -> Stratum:
    """Return the exact :class:`Stratum` of a query or of a sequence of configurations.

    Parameters
    ----------
    query : tuple
        ``(obstacles, start, goal)`` or ``(obstacles, config_1, ..., config_r)``, unbatched.

    Examples
    --------
    A robot in the column of o1 (cp(C) = 2) going to a generic goal (cp(C') = 3):

    >>> stratum_of(([[0, 0], [2, 0]], [[0, 1]], [[1, -1]]))
    Stratum(cps=(2, 3), cp_o=2, pole=False, label=5)

    In R^3 with ``o2 - o1`` along ``N = e_3`` the label drops by one:

    >>> stratum_of(([[0, 0, 0], [0, 0, 2]], [[1, 0, 1]], [[0, 1, 5]])).label
    5
    """
    obstacles, configs = _split(query)
    d, m = obstacles.shape[1], obstacles.shape[0]
    pts = np.stack([np.concatenate([obstacles, c]) for c in configs])
    r = len(configs)
    o1 = np.broadcast_to(obstacles[0], (r, d))
    o2 = np.broadcast_to(obstacles[1], (r, d))
    labels, counts, _ = projection_classes(pts, o1, o2)
    cp_o = len(set(labels[0, :m].tolist()))
    pole = _is_pole(obstacles)
    cps = tuple(int(c) for c in counts)
    return Stratum(cps, cp_o, pole, sum(cps) - (r - 1) * cp_o + 2 - int(pole))


def strata(d: int, n: int, m: int, r: int = 2) -> list[Stratum]:
    """Return every stratum ``(cps, cp_o, pole)`` that occurs for (d, n, m) and r configurations.

    ``cp_o`` runs over ``2..m``, each ``cp(C_k)`` over ``cp_o..cp_o + n`` and ``pole`` over
    {False, True} for odd d (only False for even d).

    Examples
    --------
    >>> len(strata(2, 1, 2)), len(strata(3, 1, 2)), len(strata(2, 2, 3))
    (4, 8, 18)
    >>> sorted({s.label for s in strata(2, 3, 4)}) == list(range(4, 2 * 3 + 4 + 3))
    True
    """
    import itertools

    out = []
    for pole in (False, True) if d % 2 == 1 else (False,):
        for cp_o in range(2, m + 1):
            for cps in itertools.product(range(cp_o, cp_o + n + 1), repeat=r):
                label = sum(cps) - (r - 1) * cp_o + 2 - int(pole)
                out.append(Stratum(tuple(cps), cp_o, pole, label))
    return out


# ------------------------------------------------------------------------------------------------
# exact constructions


def _direction(rng: np.random.Generator, d: int, pole: bool) -> np.ndarray:
    if pole:
        w = np.zeros(d, dtype=np.int64)
        w[-1] = rng.integers(1, 4)
        return w
    while True:
        if d % 2 == 1 and rng.random() < 0.15:  # e == -N: not the pole, but close to it in S^{d-1}
            w = np.zeros(d, dtype=np.int64)
            w[-1] = -rng.integers(1, 4)
            return w
        w = rng.integers(-3, 4, size=d)
        if rng.random() < 0.3:  # axis-aligned and sparse directions are frequent corner cases
            w[rng.random(d) < 0.5] = 0
        if not w.any():
            continue
        if d % 2 == 1 and not w[:-1].any() and w[-1] > 0:
            continue
        return w


def _perp_generators(w: np.ndarray) -> np.ndarray:
    """Integer vectors ``w_j e_i - w_i e_j`` (i < j), nonzero ones; they span ``w^perp``."""
    d = w.shape[0]
    gens = []
    for i in range(d):
        for j in range(i + 1, d):
            g = np.zeros(d, dtype=np.int64)
            g[i], g[j] = w[j], -w[i]
            if g.any():
                gens.append(g)
    return np.array(gens, dtype=np.int64).reshape(-1, d)


def _offset(rng, gens: np.ndarray, far: bool) -> np.ndarray:
    k = rng.integers(1, min(3, len(gens)) + 1)
    idx = rng.choice(len(gens), size=k, replace=False)
    coef = rng.integers(-3, 4, size=k)
    q = (coef[:, None] * gens[idx]).sum(0)
    if far:
        q = q * int(rng.integers(6, 20))
    return q


def _fresh(rng, used: set, count: int, lo: int, hi: int) -> list[int]:
    free = [c for c in range(lo, hi + 1) if c not in used]
    return [int(c) for c in rng.choice(free, size=count, replace=False)] if count else []


class _Frame(NamedTuple):
    o1: np.ndarray
    w: np.ndarray
    span: int  # o2 = o1 + span w
    gens: np.ndarray


def _new_frame(rng, d: int, pole: bool) -> _Frame:
    if pole and d % 2 == 0:
        raise ValueError(f"pole=True (e == N) needs an odd dimension d, got d = {d}")
    w = _direction(rng, d, pole)
    return _Frame(rng.integers(-5, 6, size=d), w, int(rng.integers(1, 4)), _perp_generators(w))


def _obstacles(rng, fr: _Frame, m: int, cp_o: int):
    """Obstacles with exactly cp_o distinct column indices; returns (points, indices)."""
    cols = [0, fr.span] + _fresh(rng, {0, fr.span}, cp_o - 2, -6, fr.span + 6)
    idx = [0, fr.span]
    rest = cols[2:] + [cols[int(rng.integers(len(cols)))] for _ in range(m - 2 - (cp_o - 2))]
    rest = [rest[i] for i in rng.permutation(len(rest))]
    idx += rest
    for _ in range(1000):
        offs = [np.zeros_like(fr.w), np.zeros_like(fr.w)]
        for c in idx[2:]:
            u = rng.random()
            if len(fr.gens) == 0 or u < 0.25:
                offs.append(np.zeros_like(fr.w))  # on the line L
            else:
                offs.append(_offset(rng, fr.gens, far=u > 0.75))  # far from L: lambda matters
        pts = np.array([fr.o1 + c * fr.w + q for c, q in zip(idx, offs)])
        if len({tuple(p) for p in pts.tolist()}) == m:
            return pts, idx
    raise RuntimeError("could not place distinct obstacles")  # pragma: no cover


def _robots(rng, fr: _Frame, obstacles: np.ndarray, obs_idx: list, n: int, cp: int):
    cp_o = len(set(obs_idx))
    u = cp - cp_o
    lo, hi = min(obs_idx) - 6, max(obs_idx) + 6
    new = _fresh(rng, set(obs_idx), u, lo, hi)
    pool = sorted(set(obs_idx)) + new
    cols = new + [pool[int(rng.integers(len(pool)))] for _ in range(n - u)]
    cols = [cols[i] for i in rng.permutation(n)]
    taken = {tuple(p) for p in obstacles.tolist()}
    out = []
    for c in cols:
        for _ in range(1000):
            q = _offset(rng, fr.gens, far=rng.random() < 0.1) if len(fr.gens) else 0 * fr.w
            if rng.random() < 0.15:
                q = 0 * fr.w  # on the line L
            p = fr.o1 + c * fr.w + q
            if tuple(p.tolist()) not in taken:
                break
        else:  # pragma: no cover
            raise RuntimeError("could not place distinct robots")
        taken.add(tuple(p.tolist()))
        out.append(p)
    return np.array(out).reshape(n, fr.w.shape[0])


def _check_counts(d: int, n: int, m: int, cp_o: int, cps) -> None:
    if d < 2 or n < 1 or m < 2:
        raise ValueError(f"need d >= 2, n >= 1, m >= 2, got (d, n, m) = ({d}, {n}, {m})")
    if not 2 <= cp_o <= m:
        raise ValueError(f"cp_o must lie in 2..m = 2..{m}, got {cp_o}")
    for cp in cps:
        if not cp_o <= cp <= cp_o + n:
            raise ValueError(f"cp must lie in cp_o..cp_o+n = {cp_o}..{cp_o + n}, got {cp}")


def _to_float(rng, arrays, integer: bool):
    arrays = [np.asarray(a, dtype=float) for a in arrays]
    if integer:
        return arrays
    # exact dyadic change of coordinates: scale by 2^-s and translate by a 20-bit dyadic vector.
    # Differences are scaled exactly, so every coincidence (y_r - y_s) . w == 0 is kept.
    s = 2.0 ** -int(rng.integers(0, 5))
    t = rng.integers(-(2**20), 2**20, size=arrays[0].shape[1]) * 2.0**-20
    return [a * s + t for a in arrays]


def column_sequence(rng: np.random.Generator, d: int, n: int, m: int, cps, *,
                    cp_o: int | None = None, pole: bool = False, integer: bool = True):
    """Return ``(obstacles, [config_1, ..., config_r])`` with exactly ``cp(C_k) = cps[k]``.

    Same construction and parameters as :func:`column_query` (which is the case r = 2).

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> obs, configs = column_sequence(rng, 3, 2, 3, [4, 2, 3], cp_o=2)
    >>> stratum_of((obs, *configs))
    Stratum(cps=(4, 2, 3), cp_o=2, pole=False, label=7)
    """
    cps = [int(c) for c in cps]
    if cp_o is None:
        lo = max(2, max(cps) - n)
        hi = min(m, min(cps))
        if lo > hi:
            raise ValueError(f"no cp_o in 2..{m} is compatible with cps = {cps} and n = {n}")
        cp_o = int(rng.integers(lo, hi + 1))
    _check_counts(d, n, m, cp_o, cps)
    fr = _new_frame(rng, d, pole)
    obstacles, idx = _obstacles(rng, fr, m, cp_o)
    configs = [_robots(rng, fr, obstacles, idx, n, cp) for cp in cps]
    obstacles, *configs = _to_float(rng, [obstacles, *configs], integer)
    got = stratum_of((obstacles, *configs))
    if got.cps != tuple(cps) or got.cp_o != cp_o or got.pole != bool(pole):  # pragma: no cover
        raise RuntimeError(f"internal error: built stratum {got}, wanted {cps}, {cp_o}, {pole}")
    return obstacles, configs


def column_query(rng: np.random.Generator, d: int, n: int, m: int, cp_start: int, cp_goal: int,
                 *, cp_o: int | None = None, pole: bool = False, integer: bool = True) -> Query:
    """Return a query with exactly the requested ``cp(C)``, ``cp(C')``, ``cp_o`` and ``e == N``.

    Parameters
    ----------
    rng : numpy.random.Generator
    d, n, m : int
        Dimension, number of robots, number of obstacles (m >= 2).
    cp_start, cp_goal : int
        ``cp(C)``, ``cp(C')``: numbers of distinct columns among the m+n points (Mathematics §4.2);
        each in ``cp_o..cp_o+n``.
    cp_o : int, optional
        Number of distinct obstacle columns, in ``2..m``; random (compatible) by default.
    pole : bool
        Odd d only: make ``o2 - o1`` a positive multiple of ``N = e_d`` (Mathematics §4.1, label - 1).
        With ``pole=False`` the direction is never ``N`` but is sometimes ``-N``.
    integer : bool
        True: integer coordinates. False: the same scene after an exact dyadic scaling and
        translation (non-integer floats, same exact coincidences).

    Returns
    -------
    Query
        ``(obstacles (m, d), start (n, d), goal (n, d))``, float arrays, all points of each
        configuration distinct.

    Notes
    -----
    The direction ``w`` is a random small integer vector and ``o2 = o1 + L w``; every other point
    is ``o1 + c w + q`` with an integer column index ``c`` and an integer ``q`` orthogonal to ``w``
    (so coincidences of columns are exact). Obstacles o3..om are put on L, off L, or far from L
    (where ``lambda = lift + max |r(o_k)|`` of Mathematics §4.2 matters), sharing columns with one another,
    with o1/o2, and with robots. The stratum is verified with :func:`stratum_of` before returning.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> q = column_query(rng, 4, 3, 5, 4, 6, cp_o=3)
    >>> q.obstacles.shape, q.start.shape, q.goal.shape
    ((5, 4), (3, 4), (3, 4))
    >>> stratum_of(q)
    Stratum(cps=(4, 6), cp_o=3, pole=False, label=9)
    >>> stratum_of(column_query(rng, 3, 1, 2, 2, 2, pole=True)).label  # T_{2,2} at the pole
    3
    """
    obstacles, (start, goal) = column_sequence(
        rng, d, n, m, [cp_start, cp_goal], cp_o=cp_o, pole=pole, integer=integer
    )
    return Query(obstacles, start, goal)


# ------------------------------------------------------------------------------------------------
# random and nearly degenerate batches


def random_queries(rng: np.random.Generator, d: int, n: int, m: int, count: int) -> Query:
    """Return ``count`` generic queries with standard normal coordinates, as a batch.

    Returns
    -------
    Query
        ``obstacles (count, m, d)``, ``start (count, n, d)``, ``goal (count, n, d)``.

    Examples
    --------
    >>> q = random_queries(np.random.default_rng(0), 3, 2, 4, 5)
    >>> q.obstacles.shape, q.start.shape
    ((5, 4, 3), (5, 2, 3))
    """
    return Query(rng.normal(size=(count, m, d)), rng.normal(size=(count, n, d)),
                 rng.normal(size=(count, n, d)))


def near_degenerate_queries(rng: np.random.Generator, d: int, n: int, m: int, count: int,
                            scale: float = 1e-9) -> Query:
    """Return ``count`` exact degenerate queries whose ties are broken by ``~scale`` (a batch).

    Each query is :func:`column_query` of a random stratum of :func:`strata`, after which every
    coordinate ``y`` becomes ``y + scale * (1 + |y|) * g`` with ``g`` standard normal (obstacles
    included): columns that coincided now differ by ``~scale`` of the scene, so ``eps(C)`` is tiny.
    For ``scale`` below ~1e-14 some queries cannot be planned in double precision and must end in
    :class:`~pmplan.errors.CertificationError` (Mathematics §6).

    Examples
    --------
    >>> q = near_degenerate_queries(np.random.default_rng(0), 2, 3, 3, 4)
    >>> q.start.shape
    (4, 3, 2)
    """
    table = strata(d, n, m)
    obs, st, go = [], [], []
    for _ in range(count):
        s = table[int(rng.integers(len(table)))]
        q = column_query(rng, d, n, m, s.cp_start, s.cp_goal, cp_o=s.cp_o, pole=s.pole)
        noisy = [a + scale * (1 + np.abs(a)) * rng.normal(size=a.shape) for a in q]
        obs.append(noisy[0])
        st.append(noisy[1])
        go.append(noisy[2])
    return Query(np.array(obs).reshape(count, m, d), np.array(st).reshape(count, n, d),
                 np.array(go).reshape(count, n, d))


# ------------------------------------------------------------------------------------------------
# perturbations inside a piece


def _pow2_at_most(x: float) -> float:
    return 2.0 ** np.floor(np.log2(x)) if x > 0 and np.isfinite(x) else 0.0


def _round_dyadic(v: np.ndarray, size: float) -> np.ndarray:
    """Round v to a multiple of a power of two ~ size/64 (few significant bits: exact sums)."""
    unit = _pow2_at_most(size / 64.0)
    return np.round(v / unit) * unit if unit > 0 else 0 * v


def perturb_within_stratum(rng: np.random.Generator, query, delta: float):
    """Return a query in the same *piece* (hence stratum) as ``query``, moved by at most ~delta.

    Up to six elementary moves are tried in turn, each of size at most ``delta / 6`` (per point):

    1. a near-rotation about o1, ``y -> o1 + (I + q S)(y - o1)`` with ``S`` skew-symmetric: for
       ``e != N``, ``S = v w^T - w v^T`` with ``v = w_j e_i - w_i e_j`` orthogonal to ``w``
       (a rotation in the 2-plane (w, v), exactly a scaled rotation for d = 2); at the pole
       ``e == N``, a rotation in a coordinate 2-plane orthogonal to N (so ``e`` stays N);
    2. a translation by a dyadic vector;
    3. a scaling about o1 by ``1 + q``;
    4. every robot alone in its column moved by a small dyadic vector (in start and goal);
    5. every other robot moved within its column, ``x -> x + q v``, ``v`` orthogonal to ``w``;
    6. every obstacle o_k (k >= 3) moved within its column.

    Exactness (floating-point rotations do not keep exact degeneracies!): ``q`` is a power of two
    and ``S``, ``v`` have entries that are (products of) coordinates of ``w``, so for the integer
    and dyadic queries of :func:`column_query` every operation is exact; and ``w`` is an
    eigenvector of ``(I + q S)^T (I + q S)``, so ``(y_r - y_s) . w == 0`` is preserved *exactly*.
    For other inputs rounding can break a coincidence: therefore every move is checked with
    :func:`piece_of` (exact) and distinctness of the points, and is **skipped** if it would leave
    the piece. The random choices do not depend on ``delta``: the same generator state gives the
    same direction of perturbation for every ``delta`` (so ``sup |path' - path| / delta`` can be
    compared across scales).

    Parameters
    ----------
    rng : numpy.random.Generator
    query : tuple
        ``(obstacles, start, goal)`` or ``(obstacles, config_1, ..., config_r)``, unbatched.
    delta : float
        Displacement budget: every point moves by at most about ``delta``.

    Returns
    -------
    Query or tuple
        Same shapes as ``query`` (a :class:`Query` for r = 2).

    Examples
    --------
    >>> rng = np.random.default_rng(3)
    >>> q = column_query(rng, 2, 3, 4, 4, 5, cp_o=3)
    >>> p = perturb_within_stratum(rng, q, 1e-6)
    >>> piece_of(p) == piece_of(q), 0 < max(float(np.abs(a - b).max()) for a, b in zip(p, q)) <= 1e-6
    (True, True)
    """
    obstacles, configs = _split(query)
    move = _PieceMoves(rng, query, obstacles, configs, delta / 6.0)
    pts = [obstacles.copy(), *[c.copy() for c in configs]]
    for make in (move.rotate, move.translate, move.scale, move.robots_alone,
                 move.robots_in_column, move.obstacles_in_column):
        cand = make(pts)
        if cand is not None and move.accept(cand):
            pts = cand
    if len(pts) == 3:
        return Query(*pts)
    return tuple(pts)


class _PieceMoves:
    """The six elementary moves of :func:`perturb_within_stratum`, each of size at most
    ``budget`` per point, and the exact test that a move stayed in the piece. Every random
    choice is drawn here, first, so that it does not depend on the size of the move."""

    def __init__(self, rng: np.random.Generator, query, obstacles, configs, budget: float):
        self.m, self.d = obstacles.shape
        self.target = piece_of(query)
        self.budget = budget
        self.pole = self.target[0]
        d, m = self.d, self.m
        self.pair = rng.choice(d - 1 if self.pole else d, size=2, replace=False)
        self.trans = rng.normal(size=d)
        self.sign = 1.0 if rng.random() < 0.5 else -1.0
        self.rob_dirs = [rng.normal(size=c.shape) for c in configs]
        self.rob_gen = [rng.integers(0, 1 << 30, size=c.shape[0]) for c in configs]
        self.rob_coef = [rng.choice([-1.0, 1.0], size=c.shape[0]) for c in configs]
        self.obs_gen = rng.integers(0, 1 << 30, size=m)
        self.obs_coef = rng.choice([-1.0, 1.0], size=m)

    def accept(self, candidate) -> bool:
        """Finite, distinct points, and the same piece, decided exactly."""
        if not all(np.isfinite(a).all() for a in candidate):
            return False
        for c in candidate[1:]:
            allp = np.concatenate([candidate[0], c])
            if len({tuple(p) for p in allp.tolist()}) != allp.shape[0]:
                return False
        return piece_of(candidate) == self.target

    @staticmethod
    def radius(cur) -> float:
        o1 = cur[0][0]
        return max(1e-300, max(float(np.abs(a - o1).max()) for a in cur))

    def perp(self, w: np.ndarray, k: int) -> np.ndarray:
        """A vector orthogonal to ``w`` with entries from ``w`` (exact), the k-th of them."""
        d = self.d
        gens = [(i, j) for i in range(d) for j in range(i + 1, d) if w[i] != 0 or w[j] != 0]
        if not gens:
            return np.zeros(d)
        i, j = gens[k % len(gens)]
        v = np.zeros(d)
        v[i], v[j] = w[j], -w[i]
        return v

    def rotate(self, cur):
        """1. A near-rotation about o1 (see :func:`perturb_within_stratum`)."""
        d = self.d
        o1, w = cur[0][0], cur[0][1] - cur[0][0]
        if self.pole:
            s = np.zeros((d, d))
            i, j = self.pair
            s[i, j], s[j, i] = -1.0, 1.0
        else:
            v = self.perp(w, int(self.pair[0] * d + self.pair[1]))
            s = np.outer(v, w) - np.outer(w, v)
        norm = np.linalg.norm(s, 2)
        q = self.sign * _pow2_at_most(self.budget / (norm * self.radius(cur))) \
            if norm > 0 else 0.0
        if q == 0.0:
            return None
        return [a + q * ((a - o1) @ s.T) for a in cur]

    def translate(self, cur):
        """2. A translation by a dyadic vector."""
        t = _round_dyadic(self.trans / np.linalg.norm(self.trans) * self.budget * 0.5,
                          self.budget)
        return [a + t for a in cur]

    def scale(self, cur):
        """3. A scaling about o1 by ``1 + q``."""
        o1 = cur[0][0]
        q = self.sign * _pow2_at_most(self.budget / self.radius(cur))
        return [o1 + (1.0 + q) * (a - o1) for a in cur]

    def robots_alone(self, cur):
        """4. Every robot alone in its column moved by a small dyadic vector."""
        out = [cur[0]]
        for k, c in enumerate(cur[1:]):
            part = self.target[1 + k]
            c = c.copy()
            for i in range(c.shape[0]):
                if part.count(part[self.m + i]) == 1:
                    dvec = self.rob_dirs[k][i] / np.linalg.norm(self.rob_dirs[k][i]) \
                        * self.budget * 0.5
                    c[i] = c[i] + _round_dyadic(dvec, self.budget)
            out.append(c)
        return out

    def _within_column(self, points, gen, coef, w):
        points = points.copy()
        for i in range(points.shape[0]):
            v = self.perp(w, int(gen[i]))
            nv = np.linalg.norm(v)
            if nv > 0:
                points[i] = points[i] + coef[i] * _pow2_at_most(self.budget / nv) * v
        return points

    def robots_in_column(self, cur):
        """5. Every other robot moved within its column, ``x -> x + q v``, ``v`` orthogonal to
        ``w``."""
        w = cur[0][1] - cur[0][0]
        out = [cur[0]]
        for k, c in enumerate(cur[1:]):
            part = self.target[1 + k]
            shared = [i for i in range(c.shape[0]) if part.count(part[self.m + i]) > 1]
            moved = self._within_column(c, self.rob_gen[k], self.rob_coef[k], w)
            c = c.copy()
            c[shared] = moved[shared]
            out.append(c)
        return out

    def obstacles_in_column(self, cur):
        """6. Every obstacle o_k (k >= 3) moved within its column."""
        if self.m < 3:
            return None
        w = cur[0][1] - cur[0][0]
        obs = cur[0].copy()
        obs[2:] = self._within_column(obs, self.obs_gen, self.obs_coef, w)[2:]
        return [obs, *cur[1:]]


# --------------------------------------------------------------------------------------------
# the strata of the planar_three planner (paper Section 4)


def _rejection(bad, draw, size: int) -> np.ndarray:
    """Draw ``size`` values with ``draw(k)``, redrawing entry i while ``bad(values, i)``."""
    out = draw(size)
    redo = bad(out, np.arange(size))
    while redo.any():
        idx = np.flatnonzero(redo)
        out[idx] = draw(idx.size)
        redo = np.zeros(size, dtype=bool)
        redo[idx] = bad(out[idx], idx)
    return out


def planar_stratum_queries(
    rng: np.random.Generator, stratum: str, count: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return ``count`` exact queries in one stratum of the ``planar_three`` planner (paper
    Section 4).

    Parameters
    ----------
    rng : numpy.random.Generator
    stratum : str
        ``"T22_23"`` (pmplan) or ``"T^{2,2}_{2,3}"`` (paper) style; see :data:`pmplan.planar_strata.STRATA`.
    count : int

    Returns
    -------
    obstacles : ndarray, shape (count, 3, 2)
    start, goal : ndarray, shape (count, 1, 2)

    Notes
    -----
    Points are ``o1 + U w + V rot90(w)`` with ``o1`` an integer point, ``w`` a random nonzero
    integer vector (random orientation of the line o1o2), ``o2 = o1 + k w`` (k in {1, 2, 3}),
    and U, V on the half-integer grid; ``u = U |w|``, ``h = V |w|``. Every coordinate is a small
    dyadic rational, exact in double precision, so the degeneracies of the stratum (equal
    columns, equal heights) are exact. o3 lies on either side of L_C; x = x' may occur.

    Examples
    --------
    >>> o, s, g = planar_stratum_queries(np.random.default_rng(1), "T23_34", 5)
    >>> o.shape, s.shape, g.shape
    ((5, 3, 2), (5, 1, 2), (5, 1, 2))
    >>> from pmplan.planners.planar_three import classify
    >>> classify(o, s, g).record[:, 0].tolist()
    [23, 23, 23, 23, 23]
    """
    name = parse_stratum(stratum)
    fam, i, j = split_name(name)
    n = int(count)

    def half_u(k):  # U on the half-integer grid in [-4, 8]
        return rng.integers(-8, 17, size=k) / 2.0

    def half_v(k):  # V on the half-integer grid in [-4, 4]
        return rng.integers(-8, 9, size=k) / 2.0

    def nonzero_v(k):  # V != 0, on either side of L_C
        return rng.integers(1, 9, size=k) / 2.0 * rng.choice([-1.0, 1.0], size=k)

    w = _rejection(lambda v, _: (v == 0).all(axis=1),
                   lambda k: rng.integers(-3, 4, size=(k, 2)).astype(float), n)
    o1 = rng.integers(-5, 6, size=(n, 2)).astype(float)
    u2 = rng.integers(1, 4, size=n).astype(float)
    if fam == 22:  # o3 on the column of o1 or o2, off L_C
        u3, v3 = np.where(rng.random(n) < 0.5, 0.0, u2), nonzero_v(n)
    else:  # o3 on its own column; on L_C (T1) or off it (T23)
        u3 = _rejection(lambda v, ix: (v == 0) | (v == u2[ix]), half_u, n)
        v3 = np.zeros(n) if fam == 1 else nonzero_v(n)
    obs_uv = np.stack([np.zeros((n, 2)), np.stack([u2, np.zeros(n)], 1), np.stack([u3, v3], 1)], 1)

    def on_obstacle(U, V, ix):
        return ((obs_uv[ix, :, 0] == U[:, None]) & (obs_uv[ix, :, 1] == V[:, None])).any(axis=1)

    def robot(c):
        if fam == 1 and c == 1:  # on L_C, off the obstacles
            U = _rejection(lambda v, ix: (v == 0) | (v == u2[ix]) | (v == u3[ix]), half_u, n)
            return U, np.zeros(n)
        if fam == 1:  # off L_C, any column
            return half_u(n), nonzero_v(n)
        on_col = (fam == 22 and c == 2) or (fam == 23 and c == 3)
        if on_col:  # on an obstacle column, off the obstacles
            cols = obs_uv[:, :, 0] if fam == 23 else obs_uv[:, :2, 0]
            pick = rng.integers(0, cols.shape[1], size=n)
            U = cols[np.arange(n), pick]
            V = _rejection(lambda v, ix: on_obstacle(U[ix], v, ix), half_v, n)
            return U, V
        U = _rejection(lambda v, ix: (v[:, None] == obs_uv[ix, :, 0]).any(axis=1), half_u, n)
        return U, half_v(n)

    (ux, vx), (ug, vg) = robot(i), robot(j)
    rot = np.stack([-w[:, 1], w[:, 0]], axis=1)

    def world(U, V):
        """o1 + U w + V rot90(w) for U, V of shape (n, P): points (n, P, 2), exact."""
        return o1[:, None, :] + U[..., None] * w[:, None, :] + V[..., None] * rot[:, None, :]

    obstacles = world(obs_uv[..., 0], obs_uv[..., 1])
    start = world(ux[:, None], vx[:, None])
    goal = world(ug[:, None], vg[:, None])
    return obstacles, start, goal


def perturb_planar_stratum(rng: np.random.Generator, q, delta: float):
    """Move one query of the planar three-obstacle planner inside its stratum by about delta.

    One of two exact moves, chosen at random:

    * a similarity about o1, ``y -> o1 + (I + a J)(y - o1) + t`` (J the rotation by 90 degrees,
      ``a`` a power of two, ``t`` dyadic): it keeps every equality of columns and of heights;
    * a dyadic translation of the whole scene, then every robot position and o3 moved by a
      power of two times a direction their stratum allows (with ``w = o2 - o1``): along ``w``
      for a point on L_C when o3 is on L_C (family T1), along ``rot90(w)`` for a point on an
      obstacle column (families T22, T23, and o3 there), anywhere otherwise.

    (Combining both in one move would need more than 53 bits.) The result is checked exactly
    with :func:`pmplan.planners.planar_three.classify` and for distinct points; None if it left
    the stratum (which does not happen for the dyadic queries of ``planar_stratum_queries``).
    """
    o, s, g = (np.array(a, dtype=float) for a in q)
    before = classify(o[None], s[None], g[None])
    budget = delta / 3.0
    o1 = o[0].copy()
    radius = max(np.abs(np.concatenate([o, s, g]) - o1).max(), 1e-300)
    tdir = rng.normal(size=2)
    unit = 2.0 ** np.floor(np.log2(budget / 64))
    t = np.round(tdir / np.abs(tdir).max() * budget / 2 / unit) * unit
    if rng.random() < 0.5:
        a = 2.0 ** np.floor(np.log2(budget / radius)) * rng.choice([-1.0, 1.0])

        def sim(y):
            rel = y - o1
            return o1 + rel + a * np.stack([-rel[..., 1], rel[..., 0]], axis=-1) + t

        o, s, g = sim(o), sim(s), sim(g)
    else:
        w = o[1] - o[0]
        fam = int(before.record[0, 0])
        cl, hl = before.col_labels[0], before.height_labels[0]
        step = 2.0 ** np.floor(np.log2(budget))
        o, s, g = o + t, s + t, g + t
        for arr, i, row in ((o, 2, 2), (s, 0, 3), (g, 0, 4)):
            if fam == 1 and hl[row] == hl[0]:  # on L_C (with o3 on it): stay on L_C
                v = w
            elif fam != 1 and cl[row] in cl[:3].tolist() and (row > 2 or fam == 22):
                v = np.array([-w[1], w[0]])  # on an obstacle column: stay on it
            else:  # free: any direction (dyadic, 6 bits)
                v = np.round(rng.normal(size=2) * 32) / 32
            if row == 2 and fam == 23:  # o3 alone in its column, but robots may share it
                v = np.array([-w[1], w[0]])
            size = np.abs(v).max()
            if size > 0:
                arr[i] = arr[i] + rng.choice([-1.0, 1.0]) * step / 2.0 ** np.ceil(np.log2(size)) * v
    after = classify(o[None], s[None], g[None])
    if not np.array_equal(after.record, before.record):
        return None
    for pts in (np.concatenate([o, s]), np.concatenate([o, g])):
        if len({tuple(r) for r in pts.tolist()}) != pts.shape[0]:
            return None
    return o, s, g
