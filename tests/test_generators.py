"""The query generators of :mod:`pmplan.generators`, checked against ``reference.py``'s
independent Fraction classification (not against ``stratum_of`` alone)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from reference import reference_plan

from pmplan.generators import (
    Query,
    column_query,
    column_sequence,
    near_degenerate_queries,
    perturb_within_stratum,
    piece_of,
    random_queries,
    strata,
    stratum_of,
)


def _distinct(obstacles, robots):
    pts = np.concatenate([obstacles, robots])
    return len({tuple(p) for p in pts.tolist()}) == pts.shape[0]


def _columns(q, k):
    """Exact columns (y - o1).w of obstacles + configuration k, as Fractions."""
    o1 = [Fraction(c) for c in q[0][0]]
    w = [Fraction(b) - a for a, b in zip(o1, q[0][1])]
    return [sum((Fraction(c) - a) * b for c, a, b in zip(y, o1, w))
            for y in np.concatenate([q[0], q[k]])]


@settings(max_examples=40)
@given(seed=st.integers(0, 2**32 - 1), d=st.integers(2, 5), n=st.integers(1, 8),
       m=st.integers(2, 5), integer=st.booleans())
def test_column_query_exact_stratum(seed, d, n, m, integer):
    rng = np.random.default_rng(seed)
    table = strata(d, n, m)
    s = table[int(rng.integers(len(table)))]
    q = column_query(rng, d, n, m, s.cp_start, s.cp_goal, cp_o=s.cp_o, pole=s.pole,
                     integer=integer)
    assert isinstance(q, Query)
    assert q.obstacles.shape == (m, d) and q.start.shape == q.goal.shape == (n, d)
    assert _distinct(q.obstacles, q.start) and _distinct(q.obstacles, q.goal)
    ref = reference_plan(*q)
    assert ref.record == s.record() and ref.label == s.label
    assert stratum_of(q) == s
    if integer:
        assert all((a == np.round(a)).all() for a in q)


def test_non_integer_coordinates_keep_exact_ties():
    rng = np.random.default_rng(3)
    q = column_query(rng, 3, 4, 4, 3, 5, cp_o=3, integer=False)
    assert any((a != np.round(a)).any() for a in q)
    cols = _columns(q, 1)
    assert len(set(cols)) == 3  # exact coincidences survive the dyadic change of coordinates


def test_pole_and_minus_pole():
    rng = np.random.default_rng(0)
    q = column_query(rng, 5, 2, 3, 4, 4, pole=True)
    w = q.obstacles[1] - q.obstacles[0]
    assert (w[:-1] == 0).all() and w[-1] > 0 and stratum_of(q).pole
    seen_minus = False
    for _ in range(60):
        q = column_query(rng, 3, 1, 2, 3, 3)
        w = q.obstacles[1] - q.obstacles[0]
        assert not stratum_of(q).pole
        seen_minus |= bool((w[:-1] == 0).all() and w[-1] < 0)
    assert seen_minus  # e == -N is generated (it is not the pole)


def test_obstacles_off_and_far_from_the_line():
    """Across many draws, o_k (k >= 3) appear on L, off L, far from L, and sharing columns."""
    rng = np.random.default_rng(11)
    on, far, shared = 0, 0, 0
    for _ in range(40):
        q = column_query(rng, 2, 1, 5, 4, 4, cp_o=3)
        o1, w = q.obstacles[0], q.obstacles[1] - q.obstacles[0]
        heights = [abs((o - o1) @ np.array([-w[1], w[0]])) / np.linalg.norm(w)
                   for o in q.obstacles[2:]]
        on += sum(h == 0 for h in heights)
        far += sum(h > 20 for h in heights)
        shared += len(set(_columns(q, 1)[:5])) < 5
    assert on > 0 and far > 0 and shared == 40


@pytest.mark.parametrize("kwargs, match", [
    (dict(d=2, n=1, m=2, cp_start=4, cp_goal=2, cp_o=2), "cp must lie"),
    (dict(d=2, n=1, m=2, cp_start=4, cp_goal=2), "no cp_o"),
    (dict(d=2, n=2, m=3, cp_start=3, cp_goal=3, cp_o=4), "cp_o must lie"),
    (dict(d=4, n=1, m=2, cp_start=2, cp_goal=2, pole=True), "odd dimension"),
    (dict(d=2, n=1, m=1, cp_start=2, cp_goal=2, cp_o=2), "m >= 2"),
])
def test_column_query_rejects_impossible_strata(kwargs, match):
    with pytest.raises(ValueError, match=match):
        column_query(np.random.default_rng(0), **kwargs)


def test_column_sequence():
    rng = np.random.default_rng(2)
    obstacles, configs = column_sequence(rng, 4, 3, 4, [5, 2, 4, 3], cp_o=2)
    assert stratum_of((obstacles, *configs)).record() == (5, 2, 4, 3, 2, 0)


def test_strata_table():
    for d, n, m in [(2, 1, 2), (3, 2, 4), (4, 3, 3)]:
        table = strata(d, n, m)
        poles = 2 if d % 2 else 1
        assert len(table) == poles * (m - 1) * (n + 1) ** 2
        assert len(set(table)) == len(table)
        assert len({s.label for s in table}) == (2 * n + m - 1 if d % 2 == 0 else 2 * n + m)


def test_random_and_near_degenerate():
    rng = np.random.default_rng(4)
    q = random_queries(rng, 3, 2, 4, 6)
    assert q.obstacles.shape == (6, 4, 3) and q.start.shape == q.goal.shape == (6, 2, 3)
    assert stratum_of([a[0] for a in q]).label == 2 + 2 + 4 + 2  # generic: all columns distinct
    nd = near_degenerate_queries(rng, 2, 3, 3, 20, scale=1e-9)
    assert nd.start.shape == (20, 3, 2)
    for b in range(20):
        qb = [a[b] for a in nd]
        cols = sorted(_columns(qb, 1))
        gaps = [float(y - x) for x, y in zip(cols, cols[1:])]
        assert min(gaps) > 0  # ties broken ...
    # ... and some by tiny amounts (relative to the scene)
    tiny = 0
    for b in range(20):
        qb = [a[b] for a in nd]
        cols = sorted(_columns(qb, 1))
        scale = float(max(abs(c) for c in cols))
        tiny += min(float(y - x) for x, y in zip(cols, cols[1:])) < 1e-6 * scale
    assert tiny >= 10


@settings(max_examples=30)
@given(seed=st.integers(0, 2**32 - 1), d=st.integers(2, 5), n=st.integers(1, 4),
       m=st.integers(2, 5), delta=st.sampled_from([1e-3, 1e-5, 1e-7]))
def test_perturb_within_stratum(seed, d, n, m, delta):
    rng = np.random.default_rng(seed)
    table = strata(d, n, m)
    s = table[int(rng.integers(len(table)))]
    q = column_query(rng, d, n, m, s.cp_start, s.cp_goal, cp_o=s.cp_o, pole=s.pole,
                     integer=bool(rng.integers(2)))
    st_seed = int(rng.integers(2**32))
    p = perturb_within_stratum(np.random.default_rng(st_seed), q, delta)
    assert piece_of(p) == piece_of(q)
    assert reference_plan(*p).record == reference_plan(*q).record  # independent check
    moved = max(float(np.abs(a - b).max()) for a, b in zip(p, q))
    assert 0 < moved <= delta
    # deterministic in the generator state
    p2 = perturb_within_stratum(np.random.default_rng(st_seed), q, delta)
    assert all(np.array_equal(a, b) for a, b in zip(p, p2))
    # the direction o2 - o1 turns (rotation applied), except at the pole where it is kept
    w = [Fraction(x) for x in q.obstacles[1] - q.obstacles[0]]
    w2 = [Fraction(x) for x in p.obstacles[1] - p.obstacles[0]]
    parallel = all(w[i] * w2[j] == w[j] * w2[i] for i in range(d) for j in range(d))
    assert parallel == s.pole


def test_perturb_sequence_and_generic():
    rng = np.random.default_rng(9)
    obstacles, configs = column_sequence(rng, 3, 2, 3, [3, 5, 4], cp_o=3)
    q = (obstacles, *configs)
    p = perturb_within_stratum(rng, q, 1e-6)
    assert len(p) == 4 and piece_of(p) == piece_of(q)
    g = [a[0] for a in random_queries(rng, 4, 2, 3, 1)]  # generic floats: still same piece
    pg = perturb_within_stratum(rng, g, 1e-6)
    assert piece_of(pg) == piece_of(g)
    assert 0 < max(float(np.abs(a - b).max()) for a, b in zip(pg, g)) <= 1e-6
