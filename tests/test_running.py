"""pmplan.running: the run loop, and the one entry below the facade (plan_arrays,
refine_plans)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_contract import _assert_same_batch, _queries

import pmplan
from pmplan import running
from pmplan.errors import InputError, UnsupportedError


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 10**7), st.integers(1, 10**6), st.integers(1, 8))
def test_chunk_size(b, row_bytes, workers):
    c = running.chunk_size(b, row_bytes, workers)
    assert 1 <= c <= running.CHUNK
    if workers == 1:
        assert c == min(running.CHUNK, max(running.MIN_CHUNK, running.CHUNK_BYTES // row_bytes))
    elif b >= running.CHUNKS_PER_WORKER * workers * running.MIN_CHUNK:
        assert -(-b // c) >= running.CHUNKS_PER_WORKER * workers or c == running.MIN_CHUNK


@pytest.mark.parametrize("kind", ["random", "integer"])
def test_plan_arrays_is_plan_batch_and_plan_sequence_batch(kind):
    o, (s, g) = _queries((2, 3, 2), kind, 30, seed=3)
    _assert_same_batch(running.plan_arrays(o, [s, g]), pmplan.plan_batch(o, s, g))
    _assert_same_batch(running.plan_arrays(o, [s, g], backend="numpy", workers=2),
                       pmplan.plan_batch(o, s, g))
    o, cs = _queries((2, 2, 3), kind, 20, seed=4, r=3)
    _assert_same_batch(running.plan_arrays(o, cs), pmplan.plan_sequence_batch(o, cs))
    # r = 2 through the sequential route: the sequential default planner, the sequence checks
    o, (s, g) = _queries((2, 1, 3), kind, 10, seed=5)
    assert running.plan_arrays(o, [s, g]).planner == "planar_three"
    seq = running.plan_arrays(o, [s, g], sequential=True)
    assert seq.planner == "obstacle_line_compact"
    _assert_same_batch(seq, pmplan.plan_sequence_batch(o, [s, g]))


def test_plan_arrays_checks():
    o, (s, g) = _queries((2, 2, 2), "random", 4, seed=6)
    with pytest.raises(InputError, match="lift"):
        running.plan_arrays(o, [s, g], lift=-1)
    with pytest.raises(InputError, match="workers"):
        running.plan_arrays(o, [s, g], workers=0)
    with pytest.raises(InputError, match="unknown backend"):
        running.plan_arrays(o, [s, g], backend="cuda")
    with pytest.raises(UnsupportedError, match="via"):
        running.plan_arrays(o, [s, s, g], planner="planar_three")
    bad = s.copy()
    bad[2, 1, 0] = np.nan  # an invalid query is reported before an unknown planner
    with pytest.raises(InputError, match="NaN"):
        running.plan_arrays(o, [bad, g], planner="nope")


def test_refine_plans_is_pmplan_refine():
    o, (s, g) = _queries((2, 2, 2), "integer", 12, seed=7)
    raw = pmplan.plan_batch(o, s, g)
    a = running.refine_plans(raw, radius=0.05)
    b = pmplan.refine(raw, radius=0.05)
    _assert_same_batch(a, b)
    assert np.array_equal(a.domain, raw.domain) and a.refined.all()
    with pytest.raises(InputError, match="already refined"):
        running.refine_plans(a)
    with pytest.raises(InputError, match="takes a Plan or a PlanBatch"):
        running.refine_plans(o)
