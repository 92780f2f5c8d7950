"""pmplan.scale: dask arrays in and out, Zarr streaming, a dask.distributed LocalCluster.

Every result is compared bit for bit with ``pmplan.plan_batch`` on the same numpy input. The
cluster (2 worker processes, one thread each) is started once for the module and closed by its
fixture; one test kills a worker process in the middle of a run.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pmplan
from pmplan.refine import DEFAULT_WAYPOINTS
from pmplan import scale
from pmplan.cli import main

from strategies import queries

da = pytest.importorskip("dask.array")  # the test extra installs it: CI runs every test
distributed = pytest.importorskip("distributed")
zarr = pytest.importorskip("zarr")

FIELDS = ("domain", "strata", "clearance", "waypoints", "times")


def assert_same(batch, ref):
    """Every array of ``batch`` (numpy) equals ``ref``'s, bit for bit, same dtype and shape."""
    assert batch.planner == ref.planner and tuple(batch.dims) == tuple(ref.dims)
    for k in FIELDS:
        a, b = np.asarray(getattr(batch, k)), getattr(ref, k)
        assert a.dtype == b.dtype and a.shape == b.shape, k
        assert a.tobytes() == b.tobytes(), k


def random_queries(b, m=2, n=4, d=2, seed=0):
    rng = np.random.default_rng(seed)
    return (rng.normal(size=(b, m, d)), rng.normal(size=(b, n, d)), rng.normal(size=(b, n, d)))


def degenerate_queries(b, seed=1):
    """Integer queries with shared columns (exact degeneracies: several domains)."""
    rng = np.random.default_rng(seed)
    o = np.zeros((b, 2, 2))
    o[:, 1, 0] = rng.integers(1, 4, b)
    s = np.stack([rng.permutation(np.arange(-4.0, 5.0))[:3] for _ in range(b)])
    g = np.stack([rng.permutation(np.arange(-4.0, 5.0))[:3] for _ in range(b)])
    s = np.stack([rng.integers(-2, 4, (b, 3)).astype(float), s + 10], axis=-1)
    g = np.stack([rng.integers(-2, 4, (b, 3)).astype(float), g - 10], axis=-1)
    return o, s, g


def lazy(*arrays, chunks):
    return [da.from_array(a, chunks=(chunks, -1, -1)) for a in arrays]


@pytest.fixture(scope="module")
def cluster():
    """A LocalCluster of 2 worker processes (one thread each) and its client."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as c, distributed.Client(c) as client:
        yield c, client


# ----------------------------------------------------------------------------------------------
# dask arrays in, lazy dask arrays out


@pytest.mark.parametrize("scheduler", ["sync", "threads"])
@pytest.mark.parametrize("chunks", [13, 500, 4096])
def test_dask_plan_batch_equals_numpy(scheduler, chunks):
    for o, s, g in (random_queries(1000), degenerate_queries(1000)):
        ref = pmplan.plan_batch(o, s, g)
        assert len(set(ref.domain.tolist())) > 1 or o is not None
        batch = pmplan.plan_batch(*lazy(o, s, g, chunks=chunks))
        assert isinstance(batch.waypoints, da.Array) and isinstance(batch.domain, da.Array)
        assert batch.waypoints.chunks[0] == da.from_array(o, chunks=(chunks, -1, -1)).chunks[0]
        assert_same(scale.compute(batch, scheduler=scheduler), ref)


def test_degenerate_queries_span_several_domains():
    o, s, g = degenerate_queries(1000)
    assert len(np.unique(pmplan.plan_batch(o, s, g).domain)) >= 4


@settings(max_examples=15)
@given(q=st.booleans().flatmap(lambda dg: queries(2, 2, 3, degenerate=dg)), k=st.integers(1, 6),
       lift=st.sampled_from([1.0, "scene", 0.25]))
def test_dask_equals_numpy_hypothesis(q, k, lift):
    """Random and exactly degenerate queries, repeated into a batch, any chunking and lift."""
    o, s, g = (np.repeat(np.asarray(x, dtype=float)[None], 9, axis=0) for x in q[:3])
    ref = pmplan.plan_batch(o, s, g, lift=lift)
    assert_same(scale.compute(pmplan.plan_batch(*lazy(o, s, g, chunks=k), lift=lift),
                              scheduler="sync"), ref)


def test_planar_three_and_sequences_and_mixed_numpy():
    o, s, g = random_queries(3000, m=3, n=1, seed=3)
    ref = pmplan.plan_batch(o, s, g)
    batch = pmplan.plan_batch(*lazy(o, s, chunks=700), g)  # goal a numpy array: chunked alike
    assert batch.planner == "planar_three" and isinstance(batch.times, da.Array)
    assert_same(scale.compute(batch), ref)
    rng = np.random.default_rng(4)
    o = rng.normal(size=(2000, 2, 3))
    configs = [rng.normal(size=(2000, 2, 3)) for _ in range(4)]
    ref = pmplan.plan_sequence_batch(o, configs, lift="scene")
    batch = pmplan.plan_sequence_batch(lazy(o, chunks=300)[0], lazy(*configs, chunks=300),
                                       lift="scene")
    assert_same(scale.compute(batch, scheduler="threads"), ref)


def test_result_is_lazy_with_explicit_meta():
    """Nothing runs before compute: an input whose blocks raise when computed is accepted."""
    def explode(block):
        raise RuntimeError("computed too early")

    o, s, g = random_queries(100)
    bomb = da.from_array(o, chunks=(10, -1, -1)).map_blocks(explode, dtype=float)
    batch = pmplan.plan_batch(bomb, *lazy(s, g, chunks=10))
    for k in ("domain", "strata", "clearance", "waypoints"):
        a = getattr(batch, k)
        assert type(a._meta) is np.ndarray and a._meta.dtype == a.dtype
    assert batch.domain.dtype == np.int64 and batch.waypoints.dtype == np.float64
    assert batch.waypoints.shape == (100, 8, 6, 2) and batch.strata.shape == (100, 4)
    with pytest.raises(RuntimeError, match="computed too early"):
        batch.domain.compute(scheduler="sync")


def test_dask_bad_inputs():
    o, s, g = random_queries(100)
    with pytest.raises(pmplan.InputError, match=r"rechunk\(\{1: -1, 2: -1\}\)"):
        pmplan.plan_batch(da.from_array(o, chunks=(10, 1, 2)), *lazy(s, g, chunks=10))
    with pytest.raises(pmplan.InputError, match="chunked differently along the batch axis"):
        pmplan.plan_batch(*lazy(o, s, chunks=10), *lazy(g, chunks=20))
    with pytest.raises(pmplan.InputError, match="dtype complex128"):
        pmplan.plan_batch(*lazy(o.astype(complex), s, g, chunks=10))
    with pytest.raises(pmplan.InputError, match="dtype bool"):
        pmplan.plan_batch(*lazy(o, s > 0, g, chunks=10))
    with pytest.raises(pmplan.InputError, match="unknown chunk sizes"):
        x = da.from_array(o, chunks=(10, -1, -1))
        pmplan.plan_batch(x[x[:, 0, 0] > 0], *lazy(s, g, chunks=10))
    with pytest.raises(pmplan.InputError, match="different batch sizes"):
        pmplan.plan_batch(*lazy(o, s, chunks=10), *lazy(g[:50], chunks=10))
    with pytest.raises(pmplan.InputError, match="out="):
        pmplan.plan_batch(*lazy(o, s, g, chunks=10), out=pmplan.plan_batch(o, s, g))
    with pytest.raises(pmplan.InputError, match="lift"):
        pmplan.plan_batch(*lazy(o, s, g, chunks=10), lift=-1)


@pytest.mark.parametrize("cuts", [1, 2])
def test_plans_in_a_box_where_output_shapes_are_fixed_first(monkeypatch, tmp_path, cuts):
    """The dask and Zarr paths fix their output shapes before planning: plans in a box (whose
    number of breakpoints depends on the queries) get them from a first pass over the input,
    and equal the in-memory batch, raw and refined, with the refinement's start cut
    (pmplan.workspace.RAW_CUTS) or not, the planar_three planner (per-query breakpoints)
    included; the chunks of the store run on a LocalCluster."""
    import zarr

    from pmplan import workspace
    from pmplan.planners.base import REGISTRY

    monkeypatch.setattr(workspace, "RAW_CUTS", cuts)
    for planner, (o, s, g) in (("obstacle_line_compact", random_queries(30)),
                               ("planar_three", random_queries(30, n=1, m=3))):
        o, s, g = o + 5.0, s + 5.0, g + 5.0  # inside the box (0, 10)
        for refine in (False, True):
            want = pmplan.plan_batch(o, s, g, bounds=(0, 10), planner=planner, refine=refine,
                                     radius=0.01 if refine else 0.0)
            got = pmplan.plan_batch(*lazy(o, s, g, chunks=10), bounds=(0, 10), planner=planner,
                                    refine=refine, radius=0.01 if refine else 0.0)
            assert np.array_equal(np.asarray(got.waypoints), want.waypoints)
            assert np.array_equal(np.asarray(got.times), want.times)
    o, s, g = random_queries(30)
    o, s, g = o + 5.0, s + 5.0, g + 5.0
    want = pmplan.plan_batch(o, s, g, bounds=(0, 10))
    pieces = REGISTRY[want.planner].path_times(2).size - 1
    assert want.times.ndim == 2 and want.times.shape[1] > 2 * pieces  # (the plans cross nodes)
    out = tmp_path / "x.zarr"
    scale.plan_store(dict(zip(("obstacles", "start", "goal"), (o, s, g))), out, chunk=10,
                     bounds=(0, 10), dask_workers=1)
    group = zarr.open_group(str(out), mode="r")
    assert np.array_equal(group["waypoints"][:], want.waypoints)
    assert np.array_equal(group["times"][:], want.times)
    assert group.attrs["box_width"] == (want.times.shape[1] - 1) // pieces - 1


def test_dask_query_errors_name_the_rows_of_the_whole_batch():
    o, s, g = random_queries(100)
    s[57, 2] = o[57, 1]
    batch = pmplan.plan_batch(*lazy(o, s, g, chunks=20))
    with pytest.raises(pmplan.CollisionError, match=r"query 57 .*queries 40\.\.59") as info:
        scale.compute(batch, scheduler="sync")
    assert info.value.index == 57 and info.value.pair == ("o2", "x3")


def test_core_does_not_import_dask_or_zarr():
    code = ("import sys, numpy as np, pmplan, pmplan.cli, pmplan.scale\n"
            "pmplan.plan_batch(np.zeros((1, 2, 2)) + [[0, 0], [1, 0]], np.ones((1, 1, 2)),\n"
            "                  2 * np.ones((1, 1, 2)))\n"
            "print(sorted(m for m in ('dask', 'distributed', 'zarr') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    assert out.stdout.strip() == "[]"


def test_missing_extra_says_how_to_install(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "zarr", None)  # as if zarr were not installed
    with pytest.raises(pmplan.InputError, match=r'pip install "pmplan\[dask\]"'):
        scale.plan_store(dict(zip(("obstacles", "start", "goal"), random_queries(5))),
                         tmp_path / "p.zarr")
    o, s, g = random_queries(5)
    np.savez(tmp_path / "q.npz", obstacles=o, start=s, goal=g)
    assert main(["batch", str(tmp_path / "q.npz"), "--out", str(tmp_path / "p.zarr")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and 'pip install "pmplan[dask]"' in err
    assert not (tmp_path / "p.zarr").exists()


# ----------------------------------------------------------------------------------------------
# Zarr streaming: pmplan batch IN --out OUT.zarr


def write_store(path, o, s, g, chunks=(100, 100, 100), dtype="f8", skip=()):
    grp = zarr.open_group(str(path), mode="w")
    for (name, a), c in zip((("obstacles", o), ("start", s), ("goal", g)), chunks):
        if name not in skip:
            arr = grp.create_array(name, shape=a.shape, chunks=(c, *a.shape[1:]), dtype=dtype)
            arr[...] = a.astype(dtype)
    return path


def read_store(path):
    return scale.compute(scale.open_plans(path), scheduler="sync")


def run(capsys, *argv):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def one_line_error(status, err, match):
    assert status == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert match in err, err


def test_zarr_to_zarr_equals_numpy(tmp_path, capsys):
    o, s, g = degenerate_queries(950)
    src = write_store(tmp_path / "in.zarr", o, s, g, chunks=(200, 200, 200))
    status, out, err = run(capsys, "batch", src, "--out", tmp_path / "out.zarr", "--lift",
                           "scene")
    assert status == 0 and "planned 950 queries in 5 of 5 chunks" in out
    ref = pmplan.plan_batch(o, s, g, lift="scene")
    assert_same(read_store(tmp_path / "out.zarr"), ref)
    grp = zarr.open_group(str(tmp_path / "out.zarr"), mode="r")
    attrs = dict(grp.attrs)
    assert attrs["planner"] == "obstacle_line_compact" and attrs["lift"] == "scene"
    assert attrs["pmplan_version"] == pmplan.__version__ and attrs["dims"] == [2, 3, 2]
    assert attrs["complete"] is True and attrs["chunk"] == 200 and attrs["B"] == 950
    assert grp["waypoints"].chunks == (200, 8, 5, 2) and grp["done"].shape == (5,)
    assert np.asarray(grp["done"][:]).all()
    assert attrs["compress"] is True and attrs["format"] == scale.FORMAT
    assert grp["waypoints"].compressors == (zarr.codecs.ZstdCodec(level=scale.ZSTD_LEVEL),)


def test_npz_to_zarr_planar_three_with_chunk_option(tmp_path, capsys):
    o, s, g = random_queries(301, m=3, n=1, seed=5)
    np.savez(tmp_path / "q.npz", obstacles=o, start=s, goal=g, lift=np.array(0.5))
    status, out, _ = run(capsys, "batch", tmp_path / "q.npz", "--out", tmp_path / "p.zarr",
                         "--chunk", 64, "--no-progress", "--no-compress")
    assert status == 0 and "in 5 of 5 chunks with planar_three" in out
    assert_same(read_store(tmp_path / "p.zarr"), pmplan.plan_batch(o, s, g, lift=0.5))
    grp = zarr.open_group(str(tmp_path / "p.zarr"), mode="r")
    assert grp["waypoints"].compressors == () and grp.attrs["compress"] is False


def test_sequence_store_with_via(tmp_path, capsys):
    rng = np.random.default_rng(60)
    o, s, g = random_queries(130, n=2, seed=6)
    via = rng.normal(size=(130, 2, 2, 2))
    grp = zarr.open_group(str(tmp_path / "in.zarr"), mode="w")
    for name, a in (("obstacles", o), ("start", s), ("goal", g), ("via", via)):
        grp.create_array(name, shape=a.shape, chunks=(50, *a.shape[1:]), dtype="f8")[...] = a
    status, out, err = run(capsys, "batch", tmp_path / "in.zarr", "--out", tmp_path / "p.zarr")
    assert status == 0, err
    assert status == 0
    ref = pmplan.plan_sequence_batch(o, [s, via[:, 0], via[:, 1], g])
    assert_same(read_store(tmp_path / "p.zarr"), ref)


def test_bad_stores_write_nothing(tmp_path, capsys):
    o, s, g = random_queries(300)
    dst = tmp_path / "out.zarr"
    cases = [
        (write_store(tmp_path / "a.zarr", o, s, g, skip=("goal",)), "lacks array(s) ['goal']"),
        (write_store(tmp_path / "b.zarr", o, s, g, dtype="c16"), "dtype complex128"),
        (write_store(tmp_path / "c.zarr", o, s, g, chunks=(100, 50, 100)),
         "chunked differently along the batch axis"),
        (write_store(tmp_path / "d.zarr", o, s[:200], g[:200]), "expected (B, m, d)"),
        (tmp_path / "missing.zarr", "cannot read"),
    ]
    for src, match in cases:
        status, out, err = run(capsys, "batch", src, "--out", dst)
        one_line_error(status, err, match)
        assert not dst.exists()
    status, out, err = run(capsys, "batch", cases[0][0], "--out", tmp_path / "out.npz",
                           "--dask-workers", 2)
    one_line_error(status, err, "give --out a name ending in .zarr")


def test_existing_output_without_resume_is_left_untouched(tmp_path, capsys):
    o, s, g = random_queries(300)
    src = write_store(tmp_path / "in.zarr", o, s, g)
    dst = tmp_path / "out.zarr"
    assert run(capsys, "batch", src, "--out", dst)[0] == 0
    before = {p: p.stat().st_mtime_ns for p in dst.rglob("*")}
    status, _, err = run(capsys, "batch", src, "--out", dst)
    one_line_error(status, err, "already exists; pass --resume")
    assert {p: p.stat().st_mtime_ns for p in dst.rglob("*")} == before
    status, _, err = run(capsys, "batch", src, "--out", dst, "--resume", "--lift", 2)
    one_line_error(status, err, "cannot resume")  # another run's output: refused
    assert {p: p.stat().st_mtime_ns for p in dst.rglob("*")} == before


def test_interrupted_run_resumes_only_missing_chunks(tmp_path, capsys):
    o, s, g = degenerate_queries(1000)
    src = write_store(tmp_path / "in.zarr", o, s, g)
    dst = tmp_path / "out.zarr"

    def interrupt(i, done, total):
        if done == 4:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        scale.plan_store(src, dst, on_chunk=interrupt)
    grp = zarr.open_group(str(dst), mode="r+")
    assert np.asarray(grp["done"][:]).sum() == 4 and grp.attrs["complete"] is False
    with pytest.raises(pmplan.InputError, match="incomplete"):
        scale.open_plans(dst)
    # a chunk cut in the middle: waypoints written, the done flag not (done is written last)
    grp["waypoints"][100:200] = -1.0
    grp["done"][1] = False
    def chunk_files():  # waypoints chunk i is waypoints/c/i/0/0/0
        return {p.relative_to(dst / "waypoints").parts[1]: p.stat().st_mtime_ns
                for p in (dst / "waypoints" / "c").rglob("*") if p.is_file()}

    written = chunk_files()
    status, out, _ = run(capsys, "batch", src, "--out", dst, "--resume")
    assert status == 0 and "in 7 of 10 chunks" in out and "(3 chunks were already written)" in out
    assert_same(read_store(dst), pmplan.plan_batch(o, s, g))
    after = chunk_files()
    assert sorted(written) == [str(i) for i in range(4)] and len(after) == 10
    for i in ("0", "2", "3"):  # the chunks already done were not written again
        assert after[i] == written[i]
    assert after["1"] != written["1"]  # the cut one was


def test_ctrl_c_then_resume_from_the_command_line(tmp_path, capsys, monkeypatch):
    o, s, g = random_queries(700, seed=12)
    src = write_store(tmp_path / "in.zarr", o, s, g)
    dst = tmp_path / "out.zarr"
    real = scale._run_chunk

    def interrupted(spec, i, rows=None, group=None):
        if i == 3:
            raise KeyboardInterrupt
        return real(spec, i, rows, group)

    monkeypatch.setattr(scale, "_run_chunk", interrupted)
    status, out, err = run(capsys, "batch", src, "--out", dst, "--no-progress")
    assert status == 130 and out == "" and err.count("\n") == 1 and "--resume" in err
    assert np.asarray(zarr.open_group(str(dst), mode="r")["done"][:]).tolist() == \
        [True] * 3 + [False] * 4
    monkeypatch.setattr(scale, "_run_chunk", real)
    status, out, _ = run(capsys, "batch", src, "--out", dst, "--resume", "--no-progress")
    assert status == 0 and "in 4 of 7 chunks" in out
    assert_same(read_store(dst), pmplan.plan_batch(o, s, g))


def test_sigkilled_run_resumes_to_the_equal_result(tmp_path):
    """The CLI process killed (SIGKILL) in the middle of a run: no chunk is half counted, and
    --resume completes it to the plan_batch result."""
    o, s, g = random_queries(40 * 5000, seed=13)
    src = write_store(tmp_path / "in.zarr", o, s, g, chunks=(5000, 5000, 5000))
    dst = tmp_path / "out.zarr"
    cmd = [sys.executable, "-m", "pmplan", "batch", str(src), "--out", str(dst), "--no-progress"]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    flags = dst / "done" / "c"
    while proc.poll() is None and not (flags.is_dir() and len(list(flags.iterdir())) >= 2):
        time.sleep(0.005)
    proc.kill()
    proc.communicate()
    done = np.asarray(zarr.open_group(str(dst), mode="r")["done"][:])
    assert 2 <= done.sum() < done.size  # killed in the middle of the run
    res = subprocess.run(cmd + ["--resume"], env=env, capture_output=True, text=True)
    assert res.returncode == 0 and f"in {done.size - done.sum()} of 40 chunks" in res.stdout
    assert_same(read_store(dst), pmplan.plan_batch(o, s, g))


def test_invalid_query_mid_run_leaves_an_incomplete_store(tmp_path, capsys):
    o, s, g = random_queries(500)
    g[333, 1] = o[333, 0]
    src = write_store(tmp_path / "in.zarr", o, s, g)
    dst = tmp_path / "out.zarr"
    status, _, err = run(capsys, "batch", src, "--out", dst, "--no-progress")
    one_line_error(status, err, "query 333")
    assert "incomplete" in err and "--resume" in err
    with pytest.raises(pmplan.InputError, match="incomplete"):
        scale.open_plans(dst)


# ----------------------------------------------------------------------------------------------
# refined motions (pmplan.refine) chunk by chunk

REFINED = ("robot_distance", "obstacle_distance", "respects_radius", "radius", "obstacle_radius",
           "refined", "raw_clearance")


def assert_same_refined(batch, ref):
    """:func:`assert_same` and the refinement record, bit for bit."""
    assert_same(batch, ref)
    assert ref.refined.all()
    for k in REFINED:
        a, b = np.asarray(getattr(batch, k)), getattr(ref, k)
        assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes(), k


@pytest.mark.parametrize("chunks", [7, 250])
def test_dask_refined_equals_numpy(chunks):
    o, s, g = degenerate_queries(400)  # integer points: every distance >= 1
    kw = dict(refine=True, radius=0.25, obstacle_radius=0.125)
    ref = pmplan.plan_batch(o, s, g, **kw)
    assert len(np.unique(ref.domain)) >= 4 and ref.respects_radius.sum() > 300
    batch = pmplan.plan_batch(*lazy(o, s, g, chunks=chunks), **kw)
    assert isinstance(batch.waypoints, da.Array) and isinstance(batch.respects_radius, da.Array)
    assert batch.waypoints.shape == ref.waypoints.shape and batch.times.shape == ref.times.shape
    assert_same_refined(scale.compute(batch, scheduler="threads"), ref)


def test_dask_refined_planar_three_and_sequences():
    o, s, g = random_queries(300, m=3, n=1, seed=3)
    ref = pmplan.plan_batch(o, s, g, refine=True)  # per-query times, refined
    batch = pmplan.plan_batch(*lazy(o, s, g, chunks=64), refine=True)
    assert batch.planner == "planar_three" and batch.times.shape == ref.times.shape
    assert_same_refined(scale.compute(batch, scheduler="sync"), ref)
    rng = np.random.default_rng(4)
    o = rng.normal(size=(200, 2, 3))
    configs = [rng.normal(size=(200, 2, 3)) for _ in range(3)]
    ref = pmplan.plan_sequence_batch(o, configs, refine=True, radius=1e-4)
    batch = pmplan.plan_sequence_batch(lazy(o, chunks=50)[0], lazy(*configs, chunks=50),
                                       refine=True, radius=1e-4)
    assert_same_refined(scale.compute(batch, scheduler="threads"), ref)


def test_refine_of_a_lazy_batch_says_how():
    batch = pmplan.plan_batch(*lazy(*random_queries(20), chunks=10))
    with pytest.raises(pmplan.InputError, match="plan it with refine=True"):
        pmplan.refine(batch)
    with pytest.raises(pmplan.InputError, match="`radius` must be a finite real number"):
        pmplan.plan_batch(*lazy(*random_queries(20), chunks=10), refine=True, radius=-1.0)


def test_refined_zarr_store_resume_and_errors(tmp_path, capsys):
    o, s, g = degenerate_queries(450)
    src = write_store(tmp_path / "in.zarr", o, s, g, chunks=(200, 200, 200))
    dst = tmp_path / "out.zarr"
    status, out, err = run(capsys, "batch", src, "--out", dst, "--refine", "--radius", 0.25,
                           "--steps", 24, "--no-progress")
    assert status == 0, err
    ref = pmplan.refine(pmplan.plan_batch(o, s, g, lift=0.5), radius=0.25, steps=24)  # (lift 2 r)
    assert f"refined, radii respected by {int(ref.respects_radius.sum())} of 450" in out
    assert_same_refined(read_store(dst), ref)
    grp = zarr.open_group(str(dst), mode="r")
    assert dict(grp.attrs)["refine"] == {"radius": 0.25, "obstacle_radius": 0.0,
                                         "waypoints": DEFAULT_WAYPOINTS, "steps": 24}
    assert set(scale.REFINED_OUTPUTS) <= set(grp.array_keys())
    assert grp["respects_radius"].dtype == bool  # 5 moving pieces cut, 2 still ones whole:
    assert grp["waypoints"].shape == (450, 5 * DEFAULT_WAYPOINTS + 2 + 1, 5, 2)
    # a resume must ask for the same refinement (or none, for a raw store)
    before = {p: p.stat().st_mtime_ns for p in dst.rglob("*")}
    for extra in (["--refine", "--radius", 0.5], [], ["--refine", "--radius", 0.25]):
        status, _, err = run(capsys, "batch", src, "--out", dst, "--resume", *extra)
        one_line_error(status, err, "cannot resume")
    assert {p: p.stat().st_mtime_ns for p in dst.rglob("*")} == before
    # a radius a start violates: the library's message with the rows, the store incomplete
    status, _, err = run(capsys, "batch", src, "--out", tmp_path / "x.zarr", "--refine",
                         "--radius", 0.75, "--no-progress")
    one_line_error(status, err, "closer than 2 * radius = 1.5")
    assert "[chunk 0: queries 0..199 of the batch]" in err and "is incomplete" in err
    with pytest.raises(pmplan.InputError, match="unknown refinement option"):
        scale.plan_store(src, tmp_path / "y.zarr", refine={"radius": 0.1, "width": 2})
    assert not (tmp_path / "y.zarr").exists()


# ----------------------------------------------------------------------------------------------
# on a dask.distributed LocalCluster (2 worker processes)


def test_cluster_dask_arrays_equal_numpy(cluster):
    _, client = cluster
    o, s, g = degenerate_queries(3000)
    batch = pmplan.plan_batch(*lazy(o, s, g, chunks=400))
    res = scale.compute(batch)  # the client is the default scheduler
    assert_same(res, pmplan.plan_batch(o, s, g))
    assert len(client.scheduler_info()["workers"]) == 2


def test_cluster_streaming_via_the_cli(cluster, tmp_path, capsys):
    c, _ = cluster
    o, s, g = random_queries(2000, seed=8)
    src = write_store(tmp_path / "in.zarr", o, s, g, chunks=(250, 250, 250))
    status, out, _ = run(capsys, "batch", src, "--out", tmp_path / "out.zarr", "--scheduler",
                         c.scheduler_address, "--no-progress")
    assert status == 0 and "in 8 of 8 chunks" in out
    assert_same(read_store(tmp_path / "out.zarr"), pmplan.plan_batch(o, s, g))
    res = subprocess.run(
        [sys.executable, "-m", "pmplan", "batch", str(src), "--out", str(tmp_path / "x.zarr"),
         "--scheduler", "tcp://127.0.0.1:9"], capture_output=True, text=True,
        env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path),
                 DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT="2s"))
    one_line_error(res.returncode, res.stderr, "cannot reach the dask scheduler")
    assert not (tmp_path / "x.zarr").exists()


def test_cluster_refined_dask_arrays_and_store(cluster, tmp_path):
    c, _ = cluster
    o, s, g = degenerate_queries(600)
    ref = pmplan.plan_batch(o, s, g, refine=True, radius=0.25)
    batch = pmplan.plan_batch(*lazy(o, s, g, chunks=150), refine=True, radius=0.25)
    assert_same_refined(scale.compute(batch), ref)  # the client is the default scheduler
    rep = scale.plan_store({"obstacles": o, "start": s, "goal": g}, tmp_path / "p.zarr",
                           chunk=150, scheduler=c.scheduler_address, refine={"radius": 0.25})
    assert rep.planned == 4 and rep.respects_radius == int(ref.respects_radius.sum())
    assert_same_refined(read_store(tmp_path / "p.zarr"), ref)


def test_cluster_first_pass_of_a_store_in_a_box_runs_on_the_cluster(cluster, tmp_path):
    """The first pass of a store of plans in a box (the breakpoints every piece gets) runs as
    one task per chunk on the cluster, the input's rows read by the workers from an input
    store or sent with the tasks, and the store equals the in-memory batch; an invalid query
    is reported with its rows, and nothing is written."""
    import zarr

    c, client = cluster
    o, s, g = random_queries(400, seed=12)
    o, s, g = o + 5.0, s + 5.0, g + 5.0  # inside the box (0, 10)
    want = pmplan.plan_batch(o, s, g, bounds=(0, 10))
    src = write_store(tmp_path / "in.zarr", o, s, g, chunks=(100, 100, 100))
    for source, out in ((str(src), tmp_path / "a.zarr"),
                        ({"obstacles": o, "start": s, "goal": g}, tmp_path / "b.zarr")):
        with distributed.get_task_stream(client) as stream:
            rep = scale.plan_store(source, out, chunk=100, bounds=(0, 10),
                                   scheduler=c.scheduler_address)
        keys = [str(t["key"]) for t in stream.data]
        assert sum("_width_task" in k for k in keys) == 4, keys  # the first pass, per chunk
        assert sum("_run_chunk" in k for k in keys) == 4 and rep.planned == 4
        group = zarr.open_group(str(out), mode="r")
        assert group.attrs["box_width"] > 0
        assert np.array_equal(group["waypoints"][:], want.waypoints)
        assert np.array_equal(group["times"][:], want.times)
    s[257, 1] = o[257, 1]  # a robot on an obstacle, in the third chunk
    with pytest.raises(pmplan.CollisionError, match=r"query 257 .*\[chunk 2: queries 200\.\.299"):
        scale.plan_store({"obstacles": o, "start": s, "goal": g}, tmp_path / "c.zarr",
                         chunk=100, bounds=(0, 10), scheduler=c.scheduler_address)
    assert not (tmp_path / "c.zarr").exists()


def test_dask_workers_option_starts_a_local_cluster(tmp_path):
    """``pmplan batch --dask-workers 2`` as a user runs it: its own process, its own cluster."""
    o, s, g = random_queries(600, seed=9)
    np.savez(tmp_path / "q.npz", obstacles=o, start=s, goal=g)
    res = subprocess.run(
        [sys.executable, "-m", "pmplan", "batch", str(tmp_path / "q.npz"), "--out",
         str(tmp_path / "p.zarr"), "--dask-workers", "2", "--chunk", "100", "--no-progress"],
        capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    assert res.returncode == 0 and "in 6 of 6 chunks" in res.stdout, res.stderr
    assert_same(read_store(tmp_path / "p.zarr"), pmplan.plan_batch(o, s, g))


def test_a_killed_worker_still_gives_the_complete_equal_result(cluster, tmp_path):
    """Fault injection: SIGKILL one worker process after the first chunk is written."""
    c, client = cluster
    o, s, g = degenerate_queries(6000)
    src = write_store(tmp_path / "in.zarr", o, s, g, chunks=(250, 250, 250))
    pids = client.run(os.getpid)
    assert len(pids) == 2
    killed = {}

    def kill_one(i, done, total):
        if not killed:
            victim = sorted(pids.values())[0]
            os.kill(victim, signal.SIGKILL)
            killed.update(pid=victim, done=done, total=total)

    rep = scale.plan_store(src, tmp_path / "out.zarr", scheduler=c.scheduler_address,
                           on_chunk=kill_one)
    assert killed and killed["done"] < killed["total"]  # killed in the middle of the run
    assert rep.planned == rep.chunks == 24 and rep.queries == 6000
    assert_same(read_store(tmp_path / "out.zarr"), pmplan.plan_batch(o, s, g))
    client.wait_for_workers(2, timeout=60)  # the nanny restarted the killed worker
    assert killed["pid"] not in client.run(os.getpid).values()


def test_a_killed_worker_during_a_dask_array_computation(cluster):
    """Fault injection on the lazy arrays: SIGKILL a worker once the first block is planned;
    the blocks it held are planned again and the result is complete and equal."""
    _, client = cluster
    client.wait_for_workers(2, timeout=60)
    o, s, g = degenerate_queries(24000, seed=11)
    batch = pmplan.plan_batch(*lazy(o, s, g, chunks=400))
    kept = client.persist([batch.domain, batch.strata, batch.clearance, batch.waypoints])
    futures = distributed.futures_of(kept)
    assert len(futures) == 4 * 60
    next(iter(distributed.as_completed(futures)))
    assert not all(f.done() for f in futures)  # killed in the middle of the computation
    pid = sorted(client.run(os.getpid).values())[0]
    os.kill(pid, signal.SIGKILL)
    domain, strata, clearance, waypoints = client.gather(client.compute(kept))
    ref = pmplan.plan_batch(o, s, g)
    for k, a in zip(("domain", "strata", "clearance", "waypoints"),
                    (domain, strata, clearance, waypoints)):
        assert np.asarray(a).tobytes() == getattr(ref, k).tobytes(), k
    client.wait_for_workers(2, timeout=60)
    assert pid not in client.run(os.getpid).values()


def test_compute_plans_every_block_once(monkeypatch):
    calls = []
    real = scale._plan_chunk_arrays

    def counted(obstacles, *args):
        calls.append(obstacles.shape[0])
        return real(obstacles, *args)

    monkeypatch.setattr(scale, "_plan_chunk_arrays", counted)
    o, s, g = random_queries(1000, seed=14)
    batch = pmplan.plan_batch(*lazy(o, s, g, chunks=300))
    assert calls == []  # lazy
    assert_same(scale.compute(batch, scheduler="sync"), pmplan.plan_batch(o, s, g))
    assert sorted(calls) == [100, 300, 300, 300]


def test_dask_refined_crowd_gets_the_crowds_default_effort():
    """More than pmplan.refine.CROWD robots: the lazy batch is refined with the crowd's default
    effort, bit for bit the in-memory one (its breakpoints say which effort it was)."""
    from pmplan.refine import CROWD, CROWD_WAYPOINTS

    o, s, g = random_queries(40, m=3, n=CROWD + 1, seed=5)
    ref = pmplan.plan_batch(o, s, g, refine=True, radius=1e-3)
    assert ref.times.shape[-1] == 5 * CROWD_WAYPOINTS + 2 + 1  # (2 still pieces of 7: whole)
    batch = pmplan.plan_batch(*lazy(o, s, g, chunks=16), refine=True, radius=1e-3)
    assert batch.times.shape == ref.times.shape
    assert_same_refined(scale.compute(batch, scheduler="threads"), ref)
