"""The planner contract, over every registered planner (``pmplan.planners.base.REGISTRY``).

A new planner registered in ``pmplan.planners`` is held to all of it without a new test:

* its domain labels are as many as the parametrised topological complexity (optimal) and every
  plan's domain is one of them; ``info`` says so;
* batch == single (``plan_batch`` row i is ``plan`` of query i, bit for bit), for both backends;
* kernel == reference: the numba backend gives the numpy reference's plans bit for bit;
* every returned path passes the whole certificate (``pmplan.certify.certificate``), on random
  queries and on exactly degenerate ones (small integer coordinates: equal columns, equal
  heights, points on the line L_C happen often);
* sequential planning (r = 3) where the planner supports it: the same, through the middle
  configuration.

Then the protocol itself: a test planner of a few lines (a mirror image of the obstacle-line
planner, with a fast path) is registered and runs through every entry point, fast path
included; ``PlanBatch`` slicing and indexing.
"""

from __future__ import annotations

import zlib

import numpy as np
import pytest

import pmplan
from pmplan import api, backends, single
from pmplan.certify import certificate
from pmplan.planners import OBSTACLE_LINE
from pmplan.planners.base import REGISTRY, Planner, RawPlan, default_planner
from pmplan.path import PiecewiseLinearPath

#: the (d, n, m) the contract runs on; each planner takes those it supports
DIMS = [(2, 1, 2), (2, 2, 2), (3, 1, 2), (2, 1, 3), (3, 2, 3), (4, 2, 2), (8, 1, 2), (9, 2, 2)]
BACKENDS = [None, "numpy"]


def _cases():
    return [(name, dims) for name in sorted(REGISTRY) for dims in DIMS
            if REGISTRY[name].supports(*dims) is None]


def _distinct(pts: np.ndarray) -> np.ndarray:
    """Rows (B,) whose points (B, P, d) are pairwise distinct."""
    diff = (pts[:, :, None, :] == pts[:, None, :, :]).all(-1)
    p = pts.shape[1]
    return (diff.sum(axis=(1, 2)) == p)


def _queries(dims, kind: str, b: int, seed: int, r: int = 2):
    """``b`` valid queries: ``"random"`` normal coordinates, ``"integer"`` coordinates in
    {-2..2} (exactly degenerate: shared columns and heights, points on L_C)."""
    d, n, m = dims
    rng = np.random.default_rng(seed)
    out = []
    while sum(len(o) for o, _ in out) < b:
        if kind == "random":
            pts = rng.normal(size=(4 * b, m + (r * n), d))
        else:
            pts = rng.integers(-2, 3, size=(4 * b, m + (r * n), d)).astype(float)
        # every configuration (obstacles + robots at stage k) must have distinct points
        ok = np.ones(pts.shape[0], bool)
        for k in range(r):
            conf = np.concatenate([pts[:, :m], pts[:, m + k * n:m + (k + 1) * n]], axis=1)
            ok &= _distinct(conf)
        out.append((pts[ok][:, :m], [pts[ok][:, m + k * n:m + (k + 1) * n] for k in range(r)]))
    obstacles = np.concatenate([o for o, _ in out])[:b]
    configs = [np.concatenate([c[k] for _, c in out])[:b] for k in range(r)]
    return obstacles, configs


def _assert_certified(batch, obstacles, configs):
    m = obstacles.shape[1]
    r = len(configs)
    full = [np.concatenate([obstacles, c], axis=1) for c in configs]
    via = [(k / (r - 1), full[k]) for k in range(1, r - 1)]
    clr, clause = certificate(batch.waypoints, full[0], full[-1], m, times=batch.times, via=via)
    assert (clause == 0).all(), np.flatnonzero(clause)
    np.testing.assert_array_equal(clr, batch.clearance)


def _assert_same_batch(a, b):
    for k in ("domain", "strata", "clearance", "times", "waypoints"):
        np.testing.assert_array_equal(getattr(a, k), getattr(b, k), err_msg=k)


def _assert_same_plan(a, b):
    assert (a.domain, a.stratum, a.clearance, a.planner, a.dims) == \
        (b.domain, b.stratum, b.clearance, b.planner, b.dims)
    np.testing.assert_array_equal(a.path.times, b.path.times)
    np.testing.assert_array_equal(a.path.waypoints, b.path.waypoints)


@pytest.mark.parametrize("name, dims", _cases())
def test_labels_are_the_parametrised_tc(name, dims):
    p = REGISTRY[name]
    labels = p.domain_labels(*dims)
    assert len(labels) == len(set(labels)) == api.parametrised_tc(*dims)
    i = pmplan.info(*dims, planner=name)
    assert i.optimal and list(i.labels) == list(labels) and i.planner == name
    if p.sequential:
        assert len(p.domain_labels(*dims, r=3)) == api.parametrised_tc(*dims, r=3)


def _seed(*key) -> int:
    """A seed fixed by ``key`` (the same in every run and process, unlike ``hash``)."""
    return zlib.crc32(repr(key).encode())


@pytest.mark.parametrize("kind", ["random", "integer"])
@pytest.mark.parametrize("name, dims", _cases())
def test_contract(name, dims, kind):
    """Certified, batch == single, kernel == reference, labels in the planner's list."""
    p = REGISTRY[name]
    seed = _seed(name, dims, kind)
    print(f"replay: _queries({dims}, {kind!r}, 24, seed={seed})")  # shown when the test fails
    obstacles, (start, goal) = _queries(dims, kind, 24, seed=seed)
    batches = {be: pmplan.plan_batch(obstacles, start, goal, planner=name, backend=be)
               for be in BACKENDS}
    _assert_same_batch(batches[None], batches["numpy"])  # kernel == reference, bit for bit
    batch = batches[None]
    assert batch.planner == name and len(batch) == 24
    assert set(batch.domain.tolist()) <= set(p.domain_labels(*dims))
    _assert_certified(batch, obstacles, [start, goal])
    for be in BACKENDS:
        for i in range(0, 24, 5):
            _assert_same_plan(pmplan.plan(obstacles[i], start[i], goal[i], planner=name,
                                          backend=be), batch[i])


@pytest.mark.parametrize("kind", ["random", "integer"])
@pytest.mark.parametrize("name, dims", [c for c in _cases() if REGISTRY[c[0]].sequential])
def test_sequential_contract(name, dims, kind):
    obstacles, configs = _queries(dims, kind, 12, seed=7, r=3)
    batches = {be: pmplan.plan_sequence_batch(obstacles, configs, backend=be, planner=name)
               for be in BACKENDS}
    _assert_same_batch(batches[None], batches["numpy"])
    batch = batches[None]
    assert batch.planner == name
    assert set(batch.domain.tolist()) <= set(REGISTRY[name].domain_labels(*dims, r=3))
    _assert_certified(batch, obstacles, configs)
    for be in BACKENDS:
        for i in range(0, 12, 5):
            _assert_same_plan(pmplan.plan_sequence(obstacles[i], [c[i] for c in configs],
                                                   backend=be, planner=name), batch[i])


def test_default_planner_rule():
    assert default_planner(2, 1, 3) == "planar_three"
    assert default_planner(2, 1, 3, sequential=True) == "obstacle_line_compact"
    for dims in [(2, 1, 2), (3, 1, 3), (2, 2, 3), (9, 4, 5)]:
        assert default_planner(*dims) == "obstacle_line_compact"
        assert api.choose_planner(*dims).name == "obstacle_line_compact"


def test_importing_the_planners_registers_both():
    """``pmplan.planners`` imports every planner (an ImportError is not swallowed)."""
    assert {"obstacle_line", "obstacle_line_compact", "planar_three"} <= set(REGISTRY)


# --------------------------------------------------------------------------------------------
# a new planner is one class and a registration: the protocol, fast path included


class _Mirror(Planner):
    """The obstacle-line planner of the mirrored query (x1 -> -x1), mirrored back: a new planner
    in a few lines, with the run loop's reference route and a single-query fast path."""

    name = "mirror_test"
    summary = "test planner: obstacle_line in a mirror"

    def __init__(self):
        self.fast_calls = 0

    def supports(self, d, n, m):
        return OBSTACLE_LINE.supports(d, n, m)

    def domain_labels(self, d, n, m, r=2):
        return OBSTACLE_LINE.domain_labels(d, n, m, r)

    def stratum_name(self, row, d, n, m):
        return "mirror " + OBSTACLE_LINE.stratum_name(row, d, n, m)

    def allocate(self, b, r, m, n, d):
        return OBSTACLE_LINE.allocate(b, r, m, n, d)

    def path_times(self, r):
        return OBSTACLE_LINE.path_times(r)

    @staticmethod
    def _flip(a):
        a = np.array(a, dtype=float)
        a[..., 0] = -a[..., 0]
        return a

    def reference(self, obstacles, configs, lift):
        raw = OBSTACLE_LINE.plan(self._flip(obstacles), *[self._flip(c) for c in configs],
                                 lift=lift, backend="numpy")
        return RawPlan(raw.domain, raw.strata,
                       PiecewiseLinearPath(raw.path.times, self._flip(raw.path.waypoints)))

    def single_query(self, m, n, d):
        """Its single-query call, plugged into the numba backend by the fixture."""
        def run(obstacles, start, goal, lift):
            self.fast_calls += 1
            raw = self.plan(obstacles[None], start[None], goal[None], lift=lift,
                            backend="numpy")
            full = [np.concatenate([obstacles, c])[None] for c in (start, goal)]
            clr, clause = certificate(raw.path.waypoints, full[0], full[1], m,
                                      times=raw.path.times)
            if clause[0]:
                return None
            return (raw.path.times.copy(), raw.path.waypoints[0], int(raw.domain[0]),
                    tuple(raw.strata[0].tolist()), float(clr[0]))

        return run


@pytest.fixture
def mirror(monkeypatch):
    p = _Mirror()
    monkeypatch.setitem(REGISTRY, p.name, p)
    monkeypatch.setattr(single, "_FAST", {})
    return p


@pytest.fixture
def mirror_fast(mirror, monkeypatch):
    """The mirror planner with a single-query call in the numba backend (its glue there: no
    kernel for chunks, so the reference plans them)."""
    glue = (lambda o, c: None, lambda *a: None, lambda d: False, mirror.single_query, None)
    monkeypatch.setitem(backends.select("numba").PLANNERS, mirror, glue)
    return mirror


def test_a_new_planner_is_one_class(mirror):
    """Without any kernel: every backend plans it with its reference."""
    rng = np.random.default_rng(4)
    o, s, g = (rng.normal(size=(10, k, 2)) for k in (2, 2, 2))
    for be in BACKENDS:
        batch = pmplan.plan_batch(o, s, g, planner="mirror_test", backend=be)
        _assert_certified(batch, o, [s, g])
        _assert_same_plan(pmplan.plan(o[3], s[3], g[3], planner="mirror_test", backend=be),
                          batch[3])
    assert mirror.fast_calls == 0


def test_a_new_planner_with_a_fast_path_in_the_backend(mirror_fast):
    mirror = mirror_fast
    rng = np.random.default_rng(4)
    o, s, g = (rng.normal(size=(10, k, 2)) for k in (2, 2, 2))
    batch = pmplan.plan_batch(o, s, g, planner="mirror_test")
    ref = pmplan.plan_batch(o, s, g, planner="obstacle_line")
    np.testing.assert_array_equal(batch.domain, ref.domain)  # a mirror keeps the strata
    _assert_certified(batch, o, [s, g])
    assert batch[3].stratum.startswith("mirror T_")
    single = pmplan.plan(o[3], s[3], g[3], planner="mirror_test")
    assert mirror.fast_calls == 1  # the fast path ran
    _assert_same_plan(single, batch[3])
    assert pmplan.info(2, 2, 2, planner="mirror_test").optimal
    with pytest.raises(pmplan.UnsupportedError, match="via"):
        pmplan.plan_query({"obstacles": o[0], "start": s[0], "goal": g[0], "via": [s[1]]},
                          planner="mirror_test")


# --------------------------------------------------------------------------------------------
# PlanBatch: len, iteration, slices, masks, integer arrays


@pytest.mark.parametrize("name, dims", [("obstacle_line", (2, 2, 2)),
                                         ("planar_three", (2, 1, 3))])
def test_plan_batch_indexing(name, dims):
    d, n, m = dims
    rng = np.random.default_rng(2)
    o, s, g = (rng.normal(size=(9, k, d)) for k in (m, n, n))
    batch = pmplan.plan_batch(o, s, g, planner=name)
    assert len(batch) == 9 and len(list(batch)) == 9
    for key in (slice(2, 7, 2), np.arange(9) % 3 == 0, np.array([8, 0, 8]), [1, 2], slice(0, 0)):
        sub = batch[key]
        assert isinstance(sub, pmplan.PlanBatch) and sub.planner == name and sub.dims == dims
        idx = np.arange(9)[key]
        assert len(sub) == idx.size
        for j, i in enumerate(idx):
            _assert_same_plan(sub[j], batch[int(i)])
        np.testing.assert_array_equal(sub.stratum, batch.stratum[idx])
    _assert_same_plan(batch[-1], batch[8])
    _assert_same_plan(batch[np.int64(4)], batch[4])
    for bad in (np.ones((2, 2), bool), np.array([0.5]), 9):
        with pytest.raises(IndexError):
            batch[bad]


def test_plan_is_frozen():
    p = pmplan.plan([[0, 0], [2, 0]], [[0, 1]], [[1, -1]])
    with pytest.raises(AttributeError):
        p.domain = 3
    q = pmplan.Plan(p.domain, p.stratum, p.clearance, p.path, p.planner, p.dims)
    assert q == p
