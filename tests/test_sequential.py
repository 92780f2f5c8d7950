"""Sequential planning through r >= 2 configurations (Mathematics §4.3) against ``reference.py``."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from reference import SHARING, reference_sequence

import pmplan
from pmplan.certify import clearance
from pmplan.generators import column_sequence, strata, stratum_of

ULPS = 16


def _check_one(obstacles, configs, plan, record, lift=1.0):
    r = len(configs)
    m = obstacles.shape[0]
    compact = plan.planner != "obstacle_line"
    label, ref_record, times, wps = reference_sequence(obstacles, configs, lift, compact,
                                                       SHARING.get(plan.planner, 0))
    assert plan.domain == label == stratum_of((obstacles, *configs)).label
    assert tuple(int(v) for v in record) == ref_record
    assert plan.waypoints.shape[0] == 7 * (r - 1) + 1
    assert np.abs(plan.times - np.array([float(t) for t in times])).max() <= 2.0**-52
    want = np.array(wps)
    assert np.abs(plan.waypoints - want).max() <= ULPS * np.spacing(np.abs(want).max())
    # through C_k at tau = (k-1)/(r-1), exactly
    for k, c in enumerate(configs):
        tk = k / (r - 1)
        np.testing.assert_array_equal(plan.path(tk), np.concatenate([obstacles, c]))
    assert plan.clearance > 0
    assert plan.clearance == clearance(plan.waypoints[None], m)[0]


@settings(max_examples=30)
@given(seed=st.integers(0, 2**32 - 1), d=st.sampled_from([2, 3, 4]),
       m=st.sampled_from([2, 3, 4]), n=st.sampled_from([1, 2, 3]), r=st.integers(2, 5),
       lift=st.sampled_from([1.0, 0.5, 2.0]),
       planner=st.sampled_from([None, "obstacle_line", "obstacle_line_compact",
                                "obstacle_line_shared", "obstacle_line_oneside"]))
def test_sequence_matches_reference(seed, d, m, n, r, lift, planner):
    rng = np.random.default_rng(seed)
    cp_o = int(rng.integers(2, m + 1))
    cps = rng.integers(cp_o, cp_o + n + 1, size=r)
    pole = bool(d % 2 and rng.integers(2))
    obstacles, configs = column_sequence(rng, d, n, m, cps, cp_o=cp_o, pole=pole,
                                         integer=bool(rng.integers(2)))
    p = pmplan.plan_sequence(obstacles, configs, lift=lift, planner=planner)
    b = pmplan.plan_sequence_batch(obstacles[None], [c[None] for c in configs], lift=lift,
                                   planner=planner)
    assert p.planner == b.planner == (planner or "obstacle_line_compact")
    _check_one(obstacles, configs, p, b.strata[0], lift)
    assert b.domain[0] == p.domain
    np.testing.assert_array_equal(b.waypoints[0], p.waypoints)


@pytest.mark.parametrize("d", [2, 3, 4, 5])
def test_r2_is_plan(d):
    """With r = 2 the sequential planner returns exactly pmplan.plan's path and label."""
    rng = np.random.default_rng(d)
    for s in strata(d, 2, 3)[::3]:
        obstacles, (c1, c2) = column_sequence(rng, d, 2, 3, s.cps, cp_o=s.cp_o, pole=s.pole)
        a = pmplan.plan_sequence(obstacles, [c1, c2])
        b = pmplan.plan(obstacles, c1, c2, planner="obstacle_line_compact")
        assert a.domain == b.domain
        np.testing.assert_array_equal(a.times, b.times)
        np.testing.assert_array_equal(a.waypoints, b.waypoints)
        assert a.clearance == b.clearance


@pytest.mark.parametrize("d, n, m, r", [(2, 1, 2, 3), (3, 1, 2, 3), (2, 2, 3, 3), (3, 1, 3, 4),
                                        (4, 1, 2, 4)])
def test_sequence_labels_cover_tc(d, n, m, r):
    """All strata (cps, cp_o, pole) built exactly as one batch: labels
    sum cp - (r-1) cp_o + 2 (- pole) and exactly rn+m-1 (even d) / rn+m (odd d) of them."""
    rng = np.random.default_rng(d + 10 * n + 100 * m + 1000 * r)
    table = strata(d, n, m, r)
    built = [column_sequence(rng, d, n, m, s.cps, cp_o=s.cp_o, pole=s.pole) for s in table]
    obstacles = np.stack([b[0] for b in built])
    configs = [np.stack([b[1][k] for b in built]) for k in range(r)]
    batch = pmplan.plan_sequence_batch(obstacles, configs)
    want = [sum(s.cps) - (r - 1) * s.cp_o + 2 - int(s.pole) for s in table]
    assert list(batch.domain) == want
    assert [tuple(x) for x in batch.strata] == [s.record() for s in table]
    labels = sorted(set(want))
    count = r * n + m - 1 if d % 2 == 0 else r * n + m
    assert len(labels) == count == pmplan.parametrised_tc(d, n, m, r)
    assert labels == list(range(4 if d % 2 == 0 else 3, r * n + m + 3))
    info = pmplan.info(d, n, m, r)
    assert info.domains == count and tuple(labels) == info.labels and info.optimal
    assert (batch.clearance > 0).all()
    assert batch.clearance.tolist() == clearance(batch.waypoints, m).tolist()
    # batch == single on a few
    for i in range(0, len(table), max(1, len(table) // 5)):
        single = pmplan.plan_sequence(obstacles[i], [c[i] for c in configs])
        assert single.domain == batch.domain[i]
        np.testing.assert_array_equal(single.waypoints, batch.waypoints[i])
        _check_one(obstacles[i], [c[i] for c in configs], single, batch.strata[i])


def test_sequence_generic_floats_batch():
    rng = np.random.default_rng(5)
    b, d, n, m, r = 12, 3, 2, 4, 4
    obstacles = rng.normal(size=(b, m, d))
    configs = [rng.normal(size=(b, n, d)) for _ in range(r)]
    batch = pmplan.plan_sequence_batch(obstacles, configs, lift=0.75)
    for i in range(b):
        single = pmplan.plan_sequence(obstacles[i], [c[i] for c in configs], lift=0.75)
        np.testing.assert_array_equal(single.waypoints, batch.waypoints[i])
        _check_one(obstacles[i], [c[i] for c in configs], single, batch.strata[i], lift=0.75)
        assert batch.domain[i] == r * n + m + 2  # generic: every cp = n + m, cp_o = m


def test_sequence_repeated_configuration():
    """C_1 = C_2 = C_3 is allowed: a motion that returns through the same configuration."""
    obstacles = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    c = np.array([[0.0, -1.0], [3.0, 1.0]])
    p = pmplan.plan_sequence(obstacles, [c, c, c])
    _check_one(obstacles, [c, c, c], p, pmplan.plan_sequence_batch(
        obstacles[None], [c[None]] * 3).strata[0])


def test_a_named_planner_reaches_every_sequence_entry(tmp_path):
    """``planner=`` (or a query's "planner") is honoured for sequences: the API, plan_query
    with "via", and a Zarr store run all plan with the paper's lanes when asked."""
    from pmplan.io import parse_query
    from pmplan.scale import plan_store

    o = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 1.5]])
    configs = [np.array([[0.5, 1.0], [1.5, -1.0]]), np.array([[3.0, 2.0], [-1.0, 1.0]]),
               np.array([[1.2, -2.0], [2.5, 0.7]])]
    paper = pmplan.plan_sequence(o, configs, planner="obstacle_line")
    compact = pmplan.plan_sequence(o, configs)
    assert (paper.planner, compact.planner) == ("obstacle_line", "obstacle_line_compact")
    assert not np.array_equal(paper.waypoints, compact.waypoints)
    q = parse_query({"obstacles": o.tolist(), "start": configs[0].tolist(),
                     "via": [configs[1].tolist()], "goal": configs[2].tolist(),
                     "planner": "obstacle_line"})
    np.testing.assert_array_equal(pmplan.plan_query(q).waypoints, paper.waypoints)
    arrays = {"obstacles": o[None], "start": configs[0][None], "via": configs[1][None, None],
              "goal": configs[2][None]}
    plan_store(arrays, tmp_path / "p.zarr", planner="obstacle_line")
    import zarr
    grp = zarr.open_group(str(tmp_path / "p.zarr"), mode="r")
    assert grp.attrs["planner"] == "obstacle_line"
    np.testing.assert_array_equal(grp["waypoints"][0], paper.waypoints)
