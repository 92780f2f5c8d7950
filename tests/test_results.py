"""pmplan.results: Plan and PlanBatch, batch semantics (len, iteration, ``batch[i]``, slices,
masks, index arrays) as scipy's Rotation has them."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from test_contract import _assert_same_plan, _queries

import pmplan


@pytest.fixture(scope="module")
def batches():
    o, (s, g) = _queries((2, 3, 2), "integer", 24, seed=11)
    o3, (s3, g3) = _queries((2, 1, 3), "random", 10, seed=12)
    return {"line": (pmplan.plan_batch(o, s, g), (o, s, g)),
            "planar": (pmplan.plan_batch(o3, s3, g3), (o3, s3, g3))}


@pytest.mark.parametrize("which", ["line", "planar"])
def test_len_iteration_and_items_are_the_single_plans(batches, which):
    batch, (o, s, g) = batches[which]
    assert len(batch) == len(o) and len(list(batch)) == len(o)
    for i, plan in enumerate(batch):
        _assert_same_plan(plan, batch[i])
        _assert_same_plan(plan, pmplan.plan(o[i], s[i], g[i]))
        assert plan.stratum == batch.stratum[i]
        np.testing.assert_array_equal(plan.obstacles, o[i])
        np.testing.assert_array_equal(plan.start, s[i])
        np.testing.assert_array_equal(plan.goal, g[i])


@pytest.mark.parametrize("which", ["line", "planar"])
def test_slices_masks_and_index_arrays(batches, which):
    batch, _ = batches[which]
    idx = np.array([5, 0, 3])
    mask = batch.domain == batch.domain[0]
    for key, rows in ((slice(2, 7, 2), [2, 4, 6]), (idx, idx.tolist()),
                      (mask, np.flatnonzero(mask).tolist()), ([1, 1], [1, 1])):
        sub = batch[key]
        assert len(sub) == len(rows) and sub.planner == batch.planner and sub.dims == batch.dims
        for j, i in enumerate(rows):
            _assert_same_plan(sub[j], batch[i])
        if batch.times.ndim == 1:
            assert sub.times is batch.times  # shared breakpoints stay shared
    for bad in (np.zeros((2, 2), int), np.array([0.5]), "a"):
        with pytest.raises(IndexError, match="indexed by an int, a slice, a boolean mask"):
            batch[bad]
    with pytest.raises(IndexError):
        batch[len(batch)]


def test_unrefined_records_and_frozen_plans(batches):
    batch, _ = batches["line"]
    assert not batch.refined.any() and (batch.radius == 0).all()
    assert batch.respects_radius.all() and (batch.robot_distance > 0).all()
    plan = batch[0]
    assert plan.respects_radius and not plan.refined
    with pytest.raises(dataclasses.FrozenInstanceError):
        plan.domain = 3
    assert np.array_equal(batch.path.waypoints, batch.waypoints)
