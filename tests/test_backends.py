"""pmplan.backends: the one seam, and the contract every registered backend is held to.

For every backend of :data:`pmplan.backends.REGISTRY` (skipped nowhere: a backend that cannot run
here fails, except where ``available()`` says so and CI is not set), every planner and random
AND exactly degenerate (integer) queries: its ``plan`` fills the output arrays bit for bit as the
numpy reference does and certifies them; its single-query calls give the batch's row; its
``refine`` is the reference map bit for bit; it has every function of the protocol.
"""

from __future__ import annotations

import os
import types
import zlib

import numpy as np
import pytest
from test_contract import _queries

from pmplan import backends
from pmplan.errors import InputError
from pmplan.planners.base import REGISTRY
from pmplan.refine import refine_paths, targets

#: the functions (and constants) of the protocol, in every backend module
PROTOCOL = ("NAME", "available", "arrays", "plan", "validates", "certify", "single_query",
            "sequence_query", "refine", "measure", "from_box_linear", "into_box",
            "path_into_box_linear")
CASES = [("obstacle_line", (2, 3, 2)), ("obstacle_line", (3, 2, 3)),
         ("obstacle_line", (2, 2, 4)), ("planar_three", (2, 1, 3))]


def _backend(name: str) -> types.ModuleType:
    be = backends.module(name)
    if not be.available():  # pragma: no cover - numpy and numba are dependencies
        if os.environ.get("CI"):
            pytest.fail(f"the backend {name!r} cannot run in CI")
        pytest.skip(f"the backend {name!r} cannot run here")
    return be


def _seed(*key) -> int:
    return zlib.crc32(repr(key).encode())


@pytest.mark.parametrize("name", sorted(backends.REGISTRY))
def test_every_backend_has_the_protocol(name):
    be = _backend(name)
    missing = [f for f in PROTOCOL if not hasattr(be, f)]
    assert missing == [] and be.NAME == name


def test_select_is_the_one_place():
    assert backends.select(None) is backends.select(backends.BACKENDS[0])  # the default
    assert backends.select("numpy").NAME == "numpy"
    with pytest.raises(ValueError, match="unknown backend"):
        backends.select("cuda")
    with pytest.raises(InputError, match="choose one of numba, numpy"):
        backends.check("cuda")
    backends.check(None)


@pytest.mark.parametrize("kind", ["random", "integer"])
@pytest.mark.parametrize("planner, dims", CASES)
@pytest.mark.parametrize("name", sorted(backends.REGISTRY))
def test_every_backend_plans_as_the_reference(name, planner, dims, kind):
    be = _backend(name)
    ref = backends.select("numpy")
    p = REGISTRY[planner]
    seed = _seed(name, planner, dims, kind)
    print(f"replay: _queries({dims}, {kind!r}, 20, seed={seed})")
    obstacles, configs = _queries(dims, kind, 20, seed=seed)
    d, n, m = dims
    outs = {}
    for who, mod in (("backend", be), ("reference", ref)):
        out = p.allocate(20, 2, m, n, d)
        arrays = mod.arrays(p, obstacles, configs) or (obstacles, configs)
        ok = mod.plan(p, *arrays, 1.0, out, False)
        assert ok.dtype == bool and ok.shape == (20,) and ok.all(), (who, np.flatnonzero(~ok))
        outs[who] = out
    for k in ("domain", "strata", "clearance", "times", "waypoints"):
        np.testing.assert_array_equal(outs["backend"][k], outs["reference"][k], err_msg=k)
    assert isinstance(be.validates(p, d), bool)
    run = be.single_query(p, m, n, d)
    if run is not None:  # one query in one call: the batch's row
        for i in range(0, 20, 7):
            res = run(*(np.ascontiguousarray(a[i]) for a in (obstacles, *configs)), 1.0)
            if res is None:  # declined: the general path decides (exact re-decision)
                continue
            times, wp, domain, row, clearance = res
            assert domain == outs["reference"]["domain"][i]
            assert tuple(row) == tuple(outs["reference"]["strata"][i].tolist())
            assert clearance == outs["reference"]["clearance"][i]
            t = outs["reference"]["times"]
            t = t[i] if t.ndim == 2 else t
            keep = np.r_[True, np.diff(t) > 0] if t.shape != times.shape else slice(None)
            np.testing.assert_array_equal(wp, outs["reference"]["waypoints"][i][keep])


@pytest.mark.parametrize("name", sorted(backends.REGISTRY))
def test_every_backend_plans_sequences_as_the_reference(name):
    be = _backend(name)
    p = REGISTRY["obstacle_line"]
    obstacles, configs = _queries((2, 2, 3), "integer", 12, seed=_seed(name, "seq"), r=4)
    outs = []
    for mod in (be, backends.select("numpy")):
        out = p.allocate(12, 4, 3, 2, 2)
        arrays = mod.arrays(p, obstacles, configs) or (obstacles, configs)
        assert mod.plan(p, *arrays, 0.5, out, False).all()
        outs.append(out)
    for k in ("domain", "strata", "clearance", "waypoints"):
        np.testing.assert_array_equal(outs[0][k], outs[1][k], err_msg=k)


@pytest.mark.parametrize("name", sorted(backends.REGISTRY))
def test_every_backend_refines_as_the_reference(name):
    be = _backend(name)
    obstacles, (start, goal) = _queries((2, 3, 2), "random", 16, seed=_seed(name, "refine"))
    p = REGISTRY["obstacle_line"]
    out = p.allocate(16, 2, 2, 3, 2)
    backends.select("numpy").plan(p, obstacles, [start, goal], 1.0, out)
    target = targets(0.01, 0.005, out["clearance"])
    got = be.refine(out["times"], out["waypoints"], 2, 2, target, 2, 24)
    want = refine_paths(out["times"], out["waypoints"], 2, 2, target, 2, 24)
    for a, b in zip(got, want):
        np.testing.assert_array_equal(a, b)


def test_nothing_outside_the_seam_asks_a_backend_its_name():
    """No module outside ``backends/`` compares a backend with "numba" or "numpy"."""
    import ast
    from pathlib import Path

    src = Path(backends.__file__).resolve().parents[1]
    bad = []
    for path in src.rglob("*.py"):
        if "backends" in path.parts:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Compare):
                names = [c for c in [node.left, *node.comparators]
                         if isinstance(c, ast.Name) and c.id in ("NUMBA", "NUMPY")
                         or isinstance(c, ast.Constant) and c.value in ("numba", "numpy")]
                if names:
                    bad.append(f"{path.relative_to(src)}:{node.lineno}")
    assert bad == []


@pytest.mark.parametrize("name", sorted(backends.REGISTRY))
def test_every_backend_measures_as_the_exact_reference(name):
    """``measure``: None (every row decided exactly), or values equal to the exact measure
    where it does not flag a row as too close to call, and the radii decided alike."""
    from pmplan.certify import clearance, radius_report

    be = _backend(name)
    obstacles, (start, goal) = _queries((2, 3, 2), "integer", 16, seed=_seed(name, "measure"))
    p = REGISTRY["obstacle_line"]
    out = p.allocate(16, 2, 2, 3, 2)
    backends.select("numpy").plan(p, obstacles, [start, goal], 1.0, out)
    need = (0.5, 0.25)
    measured = be.measure(out["waypoints"], 2, need)
    if measured is None:
        return
    vals, kept, close = measured
    assert vals.shape == (16, 3) and kept.dtype == bool and close.dtype == bool
    clr = clearance(out["waypoints"], 2)
    rd, od, ok = radius_report(out["waypoints"], 2, need[0] / 2, need[1] - need[0] / 2)
    sure = ~close
    assert sure.any()
    np.testing.assert_array_equal(vals[sure, 0], clr[sure])
    np.testing.assert_array_equal(kept[sure], ok[sure])
    np.testing.assert_allclose(vals[sure, 1], rd[sure], rtol=1e-12)
    np.testing.assert_allclose(vals[sure, 2], od[sure], rtol=1e-12)


@pytest.mark.parametrize("kind", ["random", "integer"])
@pytest.mark.parametrize("dims", [(2, 3, 2), (3, 2, 3), (2, 8, 6)])
@pytest.mark.parametrize("name", sorted(backends.REGISTRY))
def test_every_backend_certifies_as_the_reference(name, dims, kind):
    """``certify``: the reference's clearance and clauses, bit for bit, on paths made apart
    from the planner (a workspace box's: the plans mapped into [0, 10]^d), on the same paths
    with a robot moved onto an obstacle (clearance 0) or 1e-300 off it, with a waypoint made
    NaN, and with every coordinate rounded (exact degeneracies: touching, collinear pieces)."""
    from pmplan.certify import certificate
    from pmplan.workspace import into_box

    be = _backend(name)
    d, n, m = dims
    obstacles, (start, goal) = _queries(dims, kind, 12, seed=_seed(name, "certify", dims, kind))
    p = REGISTRY["obstacle_line"]
    out = p.allocate(12, 2, m, n, d)
    backends.select("numpy").plan(p, obstacles, [start, goal], 1.0, out)
    box = np.array([[0.0] * d, [10.0] * d])
    wp = into_box(out["waypoints"], box)
    times = out["times"]
    paths = [wp]
    touch = wp.copy()
    mid = wp.shape[1] // 2
    touch[0::2, mid, m] = touch[0::2, mid, 0]
    touch[1::2, mid, m] = touch[1::2, mid, 0] + np.array([1e-300] + [0.0] * (d - 1))
    paths.append(touch)
    nan = wp.copy()
    nan[0, mid, m, 0] = np.nan
    paths.append(nan)
    paths.append(np.round(wp))
    for w in paths:
        s, g = w[:, 0], w[:, -1]
        got = be.certify(w, s, g, m, times=times)
        want = certificate(w, s, g, m, times=times)
        np.testing.assert_array_equal(got[0], want[0])
        np.testing.assert_array_equal(got[1], want[1])


@pytest.mark.parametrize("kind", ["random", "integer"])
@pytest.mark.parametrize("name", sorted(backends.REGISTRY))
def test_every_backend_maps_the_box_as_the_reference(name, kind):
    """The maps of a workspace box: the queries mapped out of [0, 10]^d, the reference's plans
    of them mapped back in (every piece cut at the nodes), and those paths brought into the
    box shrunk by a radius, bit for bit :mod:`pmplan.workspace` (integer queries: points on
    the nodes of the map)."""
    from pmplan import workspace as W

    be = _backend(name)
    for dims in [(2, 3, 2), (3, 2, 3), (2, 8, 6)]:
        d, n, m = dims
        obstacles, configs = _queries(dims, kind, 12, seed=_seed(name, "box", dims, kind))
        box = np.array([[0.0] * d, [10.0] * d])
        obstacles = W.into_box_linear(obstacles, box)
        configs = [W.into_box_linear(c, box) for c in configs]
        if kind == "integer":  # (on the nodes 8.75, 10 (the wall, left out), and eighths)
            obstacles = np.clip(np.round(obstacles * 8) / 8, 0.125, 9.875)
            configs = [np.clip(np.round(c * 8) / 8, 0.125, 9.875) for c in configs]
        outs = [be.from_box_linear(x, box, W.BAND) for x in [obstacles] + configs]
        wants = [W.from_box_linear(x, box) for x in [obstacles] + configs]
        for got, want in zip(outs, wants):
            np.testing.assert_array_equal(got, want)
        p = REGISTRY["obstacle_line"]
        out = p.allocate(12, 2, m, n, d)
        ok = backends.select("numpy").plan(p, wants[0], wants[1:], 1.0, out)
        assert ok.any()
        got = be.path_into_box_linear(out["times"], out["waypoints"], box, W.BAND)
        want = W.path_into_box_linear(out["times"], out["waypoints"], box)
        np.testing.assert_array_equal(got[0], want[0])
        np.testing.assert_array_equal(got[1], want[1])
        inner = W.shrunk(box, 0.15)
        np.testing.assert_array_equal(be.into_box(out["waypoints"], inner, W.SQUEEZE),
                                      W.into_box(out["waypoints"], inner, W.SQUEEZE))
