"""Planning into an existing batch: the ``out=`` argument of plan_batch / plan_sequence_batch.

The contract tested here:

* ``plan_batch(q2, out=plan_batch(q1))`` returns the very object ``out``, and its arrays then
  equal those of a fresh ``plan_batch(q2)`` bit for bit -- for generic and exactly degenerate
  queries, both planners, both backends, several chunks and several threads, whatever ``out``
  held before (including the answers to another batch whose queries took other code paths);
* ``out`` is written in place (no array of it is replaced), so its memory is reused;
* an ``out`` that does not fit the batch (another type, planner, (d, n, m), length, r, dtype,
  a read-only or non-contiguous array, memory shared with the query) is refused with an
  :class:`~pmplan.errors.InputError` naming the problem, before anything is written;
* a bad query raises the same error with or without ``out``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import queries

import pmplan
from pmplan import running
from pmplan.errors import CollisionError, InputError, NonFiniteError
from pmplan.generators import random_queries

FIELDS = ("domain", "strata", "clearance", "times", "waypoints")


def _stack(qs):
    return tuple(np.stack([q[i] for q in qs]) for i in range(3))


@st.composite
def two_batches(draw, ds=(2, 3, 4), ms=(2, 3), ns=(1, 2, 4)):
    """Two batches of the same (d, m, n) and length, each generic or exactly degenerate."""
    d, m, n = (draw(st.sampled_from(x)) for x in (ds, ms, ns))
    size = draw(st.integers(1, 20))
    out = []
    for _ in range(2):
        degenerate = draw(st.booleans())
        qs = draw(st.lists(queries(d, m, n, degenerate=degenerate), min_size=size,
                           max_size=size))
        out.append(_stack(qs))
    return out


def _assert_same(a, b):
    for k in FIELDS:
        x, y = getattr(a, k), getattr(b, k)
        assert x.shape == y.shape and x.dtype == y.dtype, k
        assert np.array_equal(x, y), k
    assert (a.planner, a.dims) == (b.planner, b.dims)


def _arrays(batch):
    return {k: getattr(batch, k) for k in FIELDS}


@settings(max_examples=40, deadline=None)
@given(two_batches(), st.sampled_from(["numba", "numpy"]))
def test_out_equals_fresh_batch(case, backend):
    q1, q2 = case
    out = pmplan.plan_batch(*q1, backend=backend)
    before = _arrays(out)
    got = pmplan.plan_batch(*q2, backend=backend, out=out)
    assert got is out
    assert all(getattr(out, k) is before[k] for k in FIELDS)  # written in place
    _assert_same(got, pmplan.plan_batch(*q2, backend=backend))


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([1, 2]))
def test_out_many_chunks_and_threads(seed, workers):
    rng = np.random.default_rng(seed)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(running, "CHUNK", 64)  # several chunks, the SIMD path in each
        q1 = random_queries(rng, 2, 4, 2, 300)
        q2 = random_queries(rng, 2, 4, 2, 300)
        out = pmplan.plan_batch(*q1)
        got = pmplan.plan_batch(*q2, out=out, workers=workers)
        _assert_same(got, pmplan.plan_batch(*q2))


def test_out_planar_three():
    rng = np.random.default_rng(5)
    qs = [(rng.normal(size=(300, 3, 2)), rng.normal(size=(300, 1, 2)),
           rng.normal(size=(300, 1, 2))) for _ in range(2)]
    out = pmplan.plan_batch(*qs[0], planner="planar_three")
    times = out.times
    got = pmplan.plan_batch(*qs[1], planner="planar_three", out=out)
    assert got is out and got.times is times  # per-query breakpoints, rewritten in place
    _assert_same(got, pmplan.plan_batch(*qs[1], planner="planar_three"))


@pytest.mark.parametrize("r", [2, 3, 5])
def test_out_sequence(r):
    rng = np.random.default_rng(r)
    obstacles = rng.normal(size=(50, 2, 3))
    first = [rng.normal(size=(50, 2, 3)) for _ in range(r)]
    second = [rng.normal(size=(50, 2, 3)) for _ in range(r)]
    out = pmplan.plan_sequence_batch(obstacles, first)
    out.times[...] = -1.0  # shared breakpoints are rewritten too
    got = pmplan.plan_sequence_batch(obstacles, second, out=out)
    assert got is out
    _assert_same(got, pmplan.plan_sequence_batch(obstacles, second))


def _batch(b=10, d=2, n=2, m=2, seed=0):
    return random_queries(np.random.default_rng(seed), d, n, m, b)


def _refused(q, out, match, **kw):
    saved = {k: getattr(out, k).copy() for k in FIELDS} if hasattr(out, "domain") else None
    with pytest.raises(InputError, match=match):
        pmplan.plan_batch(*q, out=out, **kw)
    if saved is not None:  # refused before anything is written
        for k in FIELDS:
            assert np.array_equal(getattr(out, k), saved[k])


def test_out_refuses_what_does_not_fit():
    q = _batch()
    good = pmplan.plan_batch(*q)
    _refused(q, good.waypoints, "must be a PlanBatch")
    _refused(q, pmplan.plan_batch(*_batch(b=11)), "needs 10 of the obstacle_line_compact planner")
    _refused(q, pmplan.plan_batch(*_batch(n=3)), r"for \(2, 2, 2\)")
    _refused(q, pmplan.plan_batch(*_batch(d=3)), r"for \(2, 2, 2\)")
    rng = np.random.default_rng(1)
    seq = pmplan.plan_sequence_batch(q[0], [q[1], rng.normal(size=q[1].shape), q[2]])
    _refused(q, seq, r"`out.strata` has shape \(10, 5\)")
    planar = pmplan.plan_batch(rng.normal(size=(10, 3, 2)), rng.normal(size=(10, 1, 2)),
                               rng.normal(size=(10, 1, 2)), planner="planar_three")
    q3 = (planar.waypoints[:, 0, :3].copy(), rng.normal(size=(10, 1, 2)),
          rng.normal(size=(10, 1, 2)))
    _refused(q3, pmplan.plan_batch(*q3, planner="obstacle_line"), "planar_three planner",
             planner="planar_three")


@pytest.mark.parametrize(
    ("field", "change", "match"),
    [
        ("clearance", lambda a: a.astype(np.float32), "dtype float32"),
        ("domain", lambda a: a.astype(np.int32), "dtype int32"),
        ("waypoints", np.asfortranarray, "C-contiguous"),
        ("clearance", lambda a: np.broadcast_to(a[:1], a.shape), "writeable"),
    ],
)
def test_out_refuses_bad_arrays(field, change, match):
    q = _batch()
    good = pmplan.plan_batch(*q)
    bad = dataclasses.replace(good, **{field: change(getattr(good, field))})
    _refused(q, bad, f"out.{field}.*{match}")


def test_out_refuses_memory_shared_with_the_query():
    q = _batch()
    out = pmplan.plan_batch(*q)
    alias = out.waypoints.reshape(-1, 2, 2)[:10]  # C-contiguous, float64: used as given
    _refused((alias, q[1], q[2]), out, "shares memory with the query")


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_out_bad_query_raises_the_same_error(backend):
    q = [a.copy() for a in _batch(b=100)]
    out = pmplan.plan_batch(*q)
    q[1][70, 1] = np.nan
    with pytest.raises(NonFiniteError) as fresh:
        pmplan.plan_batch(*q, backend=backend)
    with pytest.raises(NonFiniteError) as into:
        pmplan.plan_batch(*q, backend=backend, out=out)
    assert str(into.value) == str(fresh.value)
    q[1][70, 1] = q[0][70, 0]  # robot 2 on obstacle 1
    with pytest.raises(CollisionError) as into:
        pmplan.plan_batch(*q, backend=backend, out=out)
    with pytest.raises(CollisionError) as fresh:
        pmplan.plan_batch(*q, backend=backend)
    assert str(into.value) == str(fresh.value)
