"""pmplan.scale: stores that never mix two runs, and runs that fail in one line.

Every failure is real: the disk fills (a tmpfs of a few MB in a private mount namespace), a
directory is read-only (a read-only mount), a chunk's file cannot be written (a regular file
where Zarr needs a directory), the dask scheduler and workers are separate processes killed with
SIGKILL. After each, ``--resume`` is compared bit for bit with ``pmplan.plan_batch``.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from test_scale import (
    assert_same,
    assert_same_refined,
    one_line_error,
    random_queries,
    read_store,
    run,
    write_store,
)

import pmplan
from pmplan import scale

zarr = pytest.importorskip("zarr")
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
PMPLAN = [sys.executable, "-m", "pmplan"]


def cli(*argv, cwd=None, env=ENV, timeout=300):
    """``pmplan ARGV`` in its own process, as a user runs it."""
    return subprocess.run(PMPLAN + [str(a) for a in argv], capture_output=True, text=True,
                          cwd=cwd, env=env, timeout=timeout)


def one_line(res, *matches):
    """Exit status 2 and one line on stderr holding every one of ``matches``."""
    assert res.returncode == 2, (res.returncode, res.stderr)
    assert res.stderr.count("\n") == 1 and "Traceback" not in res.stderr, res.stderr
    for match in matches:
        assert match in res.stderr, (match, res.stderr)


def done_flags(path) -> np.ndarray:
    return np.asarray(zarr.open_group(str(path), mode="r")["done"][:])


# ----------------------------------------------------------------------------------------------
# a resume never mixes two inputs


def test_resume_with_another_input_is_refused_naming_the_chunks(tmp_path, capsys):
    """The reported case: a run stops at a NaN in chunk 5; resuming with ANOTHER input of the
    same shape and chunking used to exit 0 with chunks 0-4 of one input and 5-9 of the other."""
    o, s, g = random_queries(1000, seed=31)
    bad = s.copy()
    bad[537, 0, 0] = np.nan
    a = write_store(tmp_path / "a.zarr", o, bad, g)
    b = write_store(tmp_path / "b.zarr", *random_queries(1000, seed=32))
    dst = tmp_path / "o.zarr"
    status, _, err = run(capsys, "batch", a, "--out", dst, "--no-progress")
    one_line_error(status, err, "at index (537, 0, 0)")  # the row in the batch, not in the chunk
    assert "[chunk 5: queries 500..599 of the batch]" in err
    assert f"{dst} is incomplete (5 of 10 chunks written)" in err and "--resume" in err
    before = {p: p.stat().st_mtime_ns for p in dst.rglob("*")}
    status, _, err = run(capsys, "batch", b, "--out", dst, "--resume", "--no-progress")
    one_line_error(status, err, "differs from the one it was planned from in 5 done chunk(s) "
                                "[0, 1, 2, 3, 4] (queries 0..99, 100..199")
    assert {p: p.stat().st_mtime_ns for p in dst.rglob("*")} == before  # nothing written
    with pytest.raises(pmplan.InputError, match="incomplete"):
        scale.open_plans(dst)
    # one changed row in a chunk already done is enough to refuse
    s2 = s.copy()
    s2[123, 2, 1] += 2.0**-40
    status, _, err = run(capsys, "batch", write_store(tmp_path / "c.zarr", o, s2, g), "--out",
                         dst, "--resume", "--no-progress")
    one_line_error(status, err, "in 1 done chunk(s) [1] (queries 100..199)")
    # the input fixed where it was not yet planned (chunk 5 on): the resume finishes the store
    fixed = s.copy()
    fixed[900:] += 1.0
    src = write_store(tmp_path / "fixed.zarr", o, fixed, g)
    status, out, _ = run(capsys, "batch", src, "--out", dst, "--resume", "--no-progress")
    assert status == 0 and "in 5 of 10 chunks" in out
    assert_same(read_store(dst), pmplan.plan_batch(o, fixed, g))
    fp = np.asarray(zarr.open_group(str(dst), mode="r")["inputs"][:])
    assert fp.shape == (10, 32) and len({bytes(r) for r in fp}) == 10


def test_fingerprint_is_of_the_values_and_shapes():
    o, s, g = random_queries(50, seed=33)
    f = scale._fingerprint((o, [s, g]))
    assert f.dtype == np.uint8 and f.shape == (32,)
    ints = np.round(o * 10) + 0.0  # + 0.0: no negative zeros (the bytes tell -0.0 from 0.0)
    assert np.array_equal(scale._fingerprint((ints, [s, g])),
                          scale._fingerprint((ints.astype(np.int64), [s, g])))  # same values
    for other in ((o, [g, s]), (o, [s, s, g]), (o[:49], [s[:49], g[:49]]), (-o, [s, g])):
        assert not np.array_equal(f, scale._fingerprint(other))


def test_a_resume_names_the_option_it_cannot_honour(tmp_path, capsys):
    o, s, g = random_queries(300, seed=34)
    o[250, 0, 0] = np.inf
    src = write_store(tmp_path / "in.zarr", o, s, g)
    dst = tmp_path / "out.zarr"
    status, _, err = run(capsys, "batch", src, "--out", dst, "--no-progress")
    one_line_error(status, err, "at index (250, 0, 0)")
    before = {p: p.stat().st_mtime_ns for p in dst.rglob("*")}
    for extra, match in ((["--no-compress"], "--no-compress (compress=): stored True, now False"),
                         (["--lift", "2"], "--lift (lift=): stored 1.0, now 2.0"),
                         (["--chunk", "50"], "--chunk (chunk=): stored 100, now 50")):
        status, _, err = run(capsys, "batch", src, "--out", dst, "--resume", *extra)
        one_line_error(status, err, match)
    assert {p: p.stat().st_mtime_ns for p in dst.rglob("*")} == before


def test_an_old_or_broken_store_says_how_to_go_on(tmp_path, capsys):
    """A directory without pmplan's attributes (what a crash while creating a store left
    before stores were created whole) and a store of format 1 (no fingerprints): a resume is
    refused with what to do; a complete format-1 store is still read."""
    o, s, g = random_queries(200, seed=35)
    src = write_store(tmp_path / "in.zarr", o, s, g)
    stuck = tmp_path / "stuck.zarr"
    zarr.open_group(str(stuck), mode="w").create_array("domain", shape=(200,), dtype="i8")
    status, _, err = run(capsys, "batch", src, "--out", stuck, "--resume")
    one_line_error(status, err, "it has no pmplan attributes); remove it")
    old = tmp_path / "old.zarr"
    assert run(capsys, "batch", src, "--out", old, "--no-progress")[0] == 0
    grp = zarr.open_group(str(old), mode="r+")
    grp.attrs["format"] = "pmplan-plans-1"
    assert_same(read_store(old), pmplan.plan_batch(o, s, g))
    status, _, err = run(capsys, "batch", src, "--out", old, "--resume")
    one_line_error(status, err, "without the fingerprints of its inputs")


# ----------------------------------------------------------------------------------------------
# data, then fingerprint, then done: a chunk write made to fail, deterministically


def test_a_failed_chunk_write_is_not_marked_done_and_resume_completes(tmp_path, capsys):
    o, s, g = random_queries(700, seed=36)
    src = write_store(tmp_path / "in.zarr", o, s, g)
    dst = tmp_path / "out.zarr"
    # create the store with chunk 0, then put a regular file where Zarr needs the directory of
    # chunk 3 of `waypoints` (written last, after domain, strata and clearance of chunk 3)
    o_bad = o.copy()
    o_bad[100, 0, 0] = np.nan
    status, _, err = run(capsys, "batch", write_store(tmp_path / "x.zarr", o_bad, s, g),
                         "--out", dst, "--no-progress")
    assert status == 2 and done_flags(dst).tolist() == [True] + [False] * 6
    blocker = dst / "waypoints" / "c" / "3"
    blocker.parent.mkdir(parents=True, exist_ok=True)
    blocker.write_text("not a directory")
    # the fixed input differs only in chunk 1, not yet done: the resume goes on, then fails
    status, _, err = run(capsys, "batch", src, "--out", dst, "--resume", "--no-progress")
    one_line_error(status, err, f"writing {dst} failed")
    assert f"{dst} is incomplete (3 of 7 chunks written)" in err
    assert "then rerun with --resume" in err
    flags = done_flags(dst)
    assert flags.tolist() == [True, True, True, False, False, False, False]
    grp = zarr.open_group(str(dst), mode="r")
    assert np.asarray(grp["domain"][300:400]).any()  # chunk 3's first outputs were written ...
    assert not np.asarray(grp["inputs"][3]).any()    # ... but neither its fingerprint nor done
    blocker.unlink()
    status, out, _ = run(capsys, "batch", src, "--out", dst, "--resume", "--no-progress")
    assert status == 0 and "in 4 of 7 chunks" in out and "(3 chunks were already written)" in out
    assert_same(read_store(dst), pmplan.plan_batch(o, s, g))
    assert not list(dst.rglob("*.partial"))


def test_leftover_partial_files_are_removed_on_resume(tmp_path, capsys):
    o, s, g = random_queries(300, seed=37)
    o[150, 1, 1] = np.nan
    src = write_store(tmp_path / "in.zarr", o, s, g)
    dst = tmp_path / "out.zarr"
    assert run(capsys, "batch", src, "--out", dst, "--no-progress")[0] == 2
    # what a write killed between Zarr's temporary file and its rename leaves behind
    partial = dst / "waypoints" / "c" / "1" / "0" / "0" / "0.5f0e1c2d.partial"
    partial.parent.mkdir(parents=True, exist_ok=True)
    partial.write_bytes(b"\0" * 4096)
    o[150, 1, 1] = 0.5
    src = write_store(tmp_path / "in.zarr", o, s, g)
    status, _, _ = run(capsys, "batch", src, "--out", dst, "--resume", "--no-progress")
    assert status == 0 and not list(dst.rglob("*.partial"))
    assert_same(read_store(dst), pmplan.plan_batch(o, s, g))


# ----------------------------------------------------------------------------------------------
# creating a store: whole or not at all


def test_a_store_is_created_whole_or_not_at_all(tmp_path, capsys, monkeypatch):
    o, s, g = random_queries(200, seed=38)
    src = write_store(tmp_path / "in.zarr", o, s, g)
    dst = tmp_path / "out.zarr"
    # a creation directory left by a process that died (SIGKILL) while creating the store
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    stale = tmp_path / f".out.zarr.creating-{dead.pid}"
    (stale / "domain").mkdir(parents=True)
    sleeper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])
    live = tmp_path / f".out.zarr.creating-{sleeper.pid}"  # another run, creating it now
    live.mkdir()
    # a crash while creating (the attributes are written last): no store, no hidden directory
    real = scale._create_arrays

    def crash(group, *args):
        real(group, *args)
        raise KeyboardInterrupt

    monkeypatch.setattr(scale, "_create_arrays", crash)
    with pytest.raises(KeyboardInterrupt):
        scale.plan_store(src, dst)
    assert not dst.exists() and not stale.exists()
    assert live.exists()  # a live process's directory is not touched
    sleeper.kill()
    sleeper.wait()
    live.rmdir()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.zarr"]
    monkeypatch.setattr(scale, "_create_arrays", real)
    status, _, _ = run(capsys, "batch", src, "--out", dst, "--no-progress")
    assert status == 0
    assert_same(read_store(dst), pmplan.plan_batch(o, s, g))


# ----------------------------------------------------------------------------------------------
# a full disk and a read-only directory, for real: a private mount namespace with a tmpfs


def _namespace_or_fail():
    """Whether this process may make a private mount namespace with a tmpfs (root, as in CI);
    CI fails rather than skips without it."""
    ok = shutil.which("unshare") and subprocess.run(
        ["unshare", "-m", "--propagation", "private", "sh", "-c",
         "mount -t tmpfs -o size=1m tmpfs /mnt"], capture_output=True).returncode == 0
    if not ok:
        if os.environ.get("CI"):
            pytest.fail("a private mount namespace with a tmpfs is needed (run as root)")
        pytest.skip("needs root for a private mount namespace (a tmpfs of a few MB)")


def in_namespace(script: str, tmp_path) -> dict[str, dict]:
    """Run ``script`` (bash, with ``$PMPLAN`` the command and ``$DISK`` a fresh mount point)
    in a private mount namespace; every ``step NAME ARGS...`` line in it runs pmplan and
    records its status and output; returns the records."""
    log = tmp_path / "steps.jsonl"
    disk = tmp_path / "disk"
    disk.mkdir()
    recorder = tmp_path / "record.py"
    recorder.write_text(
        "import json, sys\n"
        "name, rc, out, err = sys.argv[1:]\n"
        "print(json.dumps(dict(name=name, rc=int(rc), out=open(out).read(),\n"
        "                      err=open(err).read())))\n")
    prelude = f"""
set -u
PMPLAN="{' '.join(PMPLAN)}"
DISK="{disk}"
step() {{ local name=$1; shift
  $PMPLAN "$@" >"{tmp_path}/out.txt" 2>"{tmp_path}/err.txt"; local rc=$?
  "{sys.executable}" "{recorder}" "$name" $rc "{tmp_path}/out.txt" "{tmp_path}/err.txt" \\
    >>"{log}"; }}
"""
    res = subprocess.run(["unshare", "-m", "--propagation", "private", "bash", "-c",
                          prelude + script], env=ENV, capture_output=True, text=True,
                         timeout=600)
    assert res.returncode == 0, res.stderr
    return {r["name"]: r for r in map(json.loads, log.read_text().splitlines())}


class Res:
    def __init__(self, rec):
        self.returncode, self.stdout, self.stderr = rec["rc"], rec["out"], rec["err"]


def test_a_full_disk_says_so_and_resume_finishes_the_store(tmp_path):
    _namespace_or_fail()
    o, s, g = random_queries(4000, seed=39)
    src = write_store(tmp_path / "in.zarr", o, s, g, chunks=(250, 250, 250))
    # 4000 (2,4,2) queries are 3.3 MB of plans uncompressed: a 1 MB disk fills after a few
    # chunks, 8 MB holds them all
    steps = in_namespace(f"""
mount -t tmpfs -o size=1m tmpfs "$DISK"
step full batch {src} --out "$DISK/out.zarr" --no-compress --no-progress
mount -o remount,size=8m "$DISK"
step resume batch {src} --out "$DISK/out.zarr" --no-compress --no-progress --resume
cp -r "$DISK/out.zarr" {tmp_path}/copy.zarr
""", tmp_path)
    dst = f"{tmp_path}/disk/out.zarr"
    one_line(Res(steps["full"]), f"writing {dst} failed: No space left on device",
             f"{dst} is incomplete (", "free disk space, then rerun with --resume")
    res = Res(steps["resume"])
    assert res.returncode == 0 and "chunks were already written" in res.stdout, res.stderr
    copy = tmp_path / "copy.zarr"
    assert_same(read_store(copy), pmplan.plan_batch(o, s, g))
    assert not list(copy.rglob("*.partial"))


def test_a_disk_full_while_creating_the_store_leaves_nothing(tmp_path):
    _namespace_or_fail()
    o, s, g = random_queries(100, seed=40)
    src = write_store(tmp_path / "in.zarr", o, s, g)
    steps = in_namespace(f"""
mount -t tmpfs -o size=8k tmpfs "$DISK"
step create batch {src} --out "$DISK/out.zarr" --no-progress
ls -A "$DISK" > {tmp_path}/left.txt
""", tmp_path)
    one_line(Res(steps["create"]), "cannot create the output store", "No space left on device",
             "nothing was written: free disk space")
    assert (tmp_path / "left.txt").read_text() == ""  # neither the store nor a hidden directory


SIBLINGS = """
import asyncio, gc, sys
{quiet}
async def write():
    raise OSError(28, "No space left on device")

async def run():
    lost = asyncio.ensure_future(write())  # a sibling write nobody awaits
    await asyncio.sleep(0.01)
    assert lost.done()
    asyncio.get_running_loop().call_exception_handler({{"message": "another asyncio error"}})

asyncio.run(run())
gc.collect()
print("end", file=sys.stderr)
"""


@pytest.mark.parametrize("quiet", [False, True])
def test_failed_sibling_writes_are_not_logged_after_the_one_line(quiet):
    """``pmplan batch`` into a store drops asyncio's "Task exception was never retrieved" (the
    writes Zarr gathered beside the one whose error the one line reports, which the disk-full
    test above meets when the garbage collector finds them) and nothing else of asyncio's."""
    code = SIBLINGS.format(quiet="from pmplan import cli; cli._quiet_sibling_writes()"
                           if quiet else "")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=ENV, timeout=120)
    assert res.returncode == 0, res.stderr
    assert ("Task exception was never retrieved" in res.stderr) is not quiet, res.stderr
    assert "another asyncio error" in res.stderr and res.stderr.endswith("end\n"), res.stderr


def test_a_read_only_directory(tmp_path):
    _namespace_or_fail()
    o, s, g = random_queries(600, seed=41)
    bad = o.copy()
    bad[450, 0, 1] = np.nan
    a = write_store(tmp_path / "a.zarr", o, s, g)
    b = write_store(tmp_path / "b.zarr", bad, s, g)
    steps = in_namespace(f"""
mount -t tmpfs -o size=16m tmpfs "$DISK"
mount -o remount,ro "$DISK"
step create batch {a} --out "$DISK/out.zarr" --no-progress
mount -o remount,rw "$DISK"
step partial batch {b} --out "$DISK/out.zarr" --no-progress
mount -o remount,ro "$DISK"
step resume_ro batch {a} --out "$DISK/out.zarr" --no-progress --resume
mount -o remount,rw "$DISK"
step resume batch {a} --out "$DISK/out.zarr" --no-progress --resume
cp -r "$DISK/out.zarr" {tmp_path}/copy.zarr
""", tmp_path)
    dst = f"{tmp_path}/disk/out.zarr"
    one_line(Res(steps["create"]), f"cannot create the output store {dst}: Read-only file system",
             "nothing was written: make the directory writable or choose another --out")
    one_line(Res(steps["partial"]), "at index (450, 0, 1)", "4 of 6 chunks written")
    one_line(Res(steps["resume_ro"]), f"{dst}", "Read-only file system", "4 of 6 chunks",
             "make the directory writable or choose another --out, then rerun with --resume")
    assert Res(steps["resume"]).returncode == 0
    assert_same(read_store(tmp_path / "copy.zarr"), pmplan.plan_batch(o, s, g))


# ----------------------------------------------------------------------------------------------
# a real scheduler and real workers, separate processes, killed for real


class Cluster:
    """``dask scheduler`` and ``dask worker`` processes started as a user starts them, in a
    directory of their own (so relative paths would not resolve there)."""

    def __init__(self, tmp_path, workers=2, env=None, hide=None):
        self.dir = tmp_path / "cluster"
        self.dir.mkdir(exist_ok=True)
        self.file = self.dir / f"scheduler-{time.monotonic_ns()}.json"
        self.env = dict(ENV, **(env or {}))
        self.procs = []
        self.scheduler = self._start("distributed.cli.dask_scheduler", "--scheduler-file",
                                     self.file, "--host", "127.0.0.1", "--port", "0",
                                     "--no-dashboard")
        deadline = time.monotonic() + 60
        while not self.file.exists():
            assert time.monotonic() < deadline, "the scheduler did not start"
            time.sleep(0.05)
        time.sleep(0.2)
        self.address = json.loads(self.file.read_text())["address"]
        self.workers = [self._start("distributed.cli.dask_worker", "--scheduler-file",
                                    self.file, "--host", "127.0.0.1", "--nthreads", "1",
                                    "--no-nanny", "--no-dashboard", hide=hide)
                        for _ in range(workers)]
        import distributed

        with distributed.Client(self.address, timeout=60) as c:
            c.wait_for_workers(workers, timeout=120)

    def _start(self, module, *args, hide=None):
        """``python -m module args``; with ``hide``, in a private mount namespace where an
        empty tmpfs covers the directory ``hide`` (a worker that does not see those files)."""
        cmd = [sys.executable, "-m", module, *map(str, args)]
        if hide is not None:
            cmd = ["unshare", "-m", "--propagation", "private", "sh", "-c",
                   f'mount -t tmpfs tmpfs "{hide}" && exec "$@"', "sh", *cmd]
        p = subprocess.Popen(cmd, cwd=self.dir, env=self.env, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
        self.procs.append(p)
        return p

    def close(self):
        for p in self.procs:
            if p.poll() is None:
                p.kill()
            p.wait()


@pytest.fixture
def separate(tmp_path):
    made = []

    def start(**kw):
        c = Cluster(tmp_path, **kw)
        made.append(c)
        return c

    yield start
    for c in made:
        c.close()


def _wait_for_done(dst: Path, proc, count: int) -> None:
    flags = dst / "done" / "c"
    deadline = time.monotonic() + 240
    while not (flags.is_dir() and len(list(flags.iterdir())) >= count):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.01)


def _refined_store(tmp_path, b=3000, chunk=50, seed=42):
    o, s, g = random_queries(b, seed=seed)
    src = write_store(tmp_path / "in.zarr", o, s, g, chunks=(chunk, chunk, chunk))
    return (o, s, g), src


def test_scheduler_lost_then_resume_on_a_new_cluster(tmp_path, separate):
    """Relative paths, workers in another directory; the scheduler SIGKILLed mid-run: one
    line naming the store and --resume; a new cluster finishes it bit for bit."""
    (o, s, g), _ = _refined_store(tmp_path)
    c = separate()
    args = ["batch", "in.zarr", "--out", "out.zarr", "--scheduler", c.address, "--refine",
            "--radius", "1e-4", "--no-progress"]
    proc = subprocess.Popen(PMPLAN + args, cwd=tmp_path, env=ENV, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    dst = tmp_path / "out.zarr"
    _wait_for_done(dst, proc, 3)
    c.scheduler.send_signal(signal.SIGKILL)
    out, err = proc.communicate(timeout=240)
    res = subprocess.CompletedProcess(args, proc.returncode, out, err)
    one_line(res, "the dask cluster failed", f"{dst} is incomplete (", "rerun with --resume")
    done = done_flags(dst)
    assert 3 <= done.sum() < done.size
    c.close()
    c2 = separate()
    args[args.index("--scheduler") + 1] = c2.address
    res = cli(*args, "--resume", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert f"in {done.size - done.sum()} of {done.size} chunks" in res.stdout
    assert_same_refined(read_store(dst), pmplan.plan_batch(o, s, g, refine=True, radius=1e-4))


def test_killed_workers_say_resume_and_no_finished_chunk_is_planned_again(tmp_path, separate):
    """With the scheduler's allowed failures at 0, a worker SIGKILLed while it plans a chunk
    ends the run (KilledWorker) in one line; the chunks finished before were written once."""
    (o, s, g), src = _refined_store(tmp_path, seed=43)
    c = separate(env={"DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "0"})
    dst = tmp_path / "out.zarr"
    proc = subprocess.Popen(PMPLAN + ["batch", str(src), "--out", str(dst), "--scheduler",
                                      c.address, "--refine", "--radius", "1e-4",
                                      "--no-progress"],
                            env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    _wait_for_done(dst, proc, 4)
    written = {p: (p.stat().st_ino, p.stat().st_mtime_ns)
               for p in (dst / "waypoints").rglob("*") if p.is_file()}
    c.workers[0].send_signal(signal.SIGKILL)
    out, err = proc.communicate(timeout=240)
    one_line(subprocess.CompletedProcess([], proc.returncode, out, err),
             "the dask cluster failed (KilledWorker", f"{dst} is incomplete (",
             "rerun with --resume")
    for p, stat in written.items():  # chunks finished before the kill: never written again
        assert (p.stat().st_ino, p.stat().st_mtime_ns) == stat, p
    res = cli("batch", src, "--out", dst, "--resume", "--refine", "--radius", "1e-4",
              "--no-progress")
    assert res.returncode == 0, res.stderr
    assert_same_refined(read_store(dst), pmplan.plan_batch(o, s, g, refine=True, radius=1e-4))


def test_a_dead_worker_does_not_make_finished_chunks_run_again(tmp_path, separate):
    """The default allowed failures: a worker SIGKILLed mid-run, the other finishes; every
    chunk file is written exactly once (its inode and mtime never change after its done flag)."""
    (o, s, g), src = _refined_store(tmp_path, seed=44)
    c = separate()
    dst = tmp_path / "out.zarr"
    seen = {}

    def watch(i, done, total):
        f = dst / "waypoints" / "c" / str(i) / "0" / "0" / "0"
        seen[i] = (f.stat().st_ino, f.stat().st_mtime_ns)
        if done == 5:
            c.workers[0].send_signal(signal.SIGKILL)

    rep = scale.plan_store(src, dst, scheduler=c.address, refine={"radius": 1e-4},
                           on_chunk=watch)
    assert rep.planned == rep.chunks == 60 and len(seen) == 60
    for i, stat in seen.items():
        f = dst / "waypoints" / "c" / str(i) / "0" / "0" / "0"
        assert (f.stat().st_ino, f.stat().st_mtime_ns) == stat, i
    assert_same_refined(read_store(dst), pmplan.plan_batch(o, s, g, refine=True, radius=1e-4))


def test_a_failing_chunk_on_a_local_cluster_prints_one_line(tmp_path):
    """--dask-workers: the chunk's error once (no dask log lines), with the batch's row and the
    store's real count of chunks done."""
    o, s, g = random_queries(700, seed=45)
    g[537, 1] = o[537, 0]
    src = write_store(tmp_path / "in.zarr", o, s, g)
    dst = tmp_path / "out.zarr"
    res = cli("batch", src, "--out", dst, "--dask-workers", "2", "--no-progress")
    one_line(res, "query 537", "[chunk 5: queries 500..599 of the batch]")
    done = int(done_flags(dst).sum())
    assert f"{dst} is incomplete ({done} of 7 chunks written)" in res.stderr


def test_workers_that_do_not_see_the_input_say_so(tmp_path, separate):
    """Workers in a mount namespace where the input's directory is an empty tmpfs (another
    machine without the shared filesystem): one line that says what the workers need, and
    --resume then finishes the store."""
    _namespace_or_fail()
    o, s, g = random_queries(400, seed=46)
    (tmp_path / "data").mkdir()
    src = write_store(tmp_path / "data" / "in.zarr", o, s, g)
    c = separate(hide=tmp_path / "data")
    dst = tmp_path / "out.zarr"
    res = cli("batch", "data/in.zarr", "--out", "out.zarr", "--scheduler", c.address,
              "--no-progress", cwd=tmp_path)
    one_line(res, "could not open its stores on host", str(src),
             "every worker must see the input and output stores at the same absolute paths",
             f"{dst} is incomplete (0 of 4 chunks written)", "rerun with --resume")
    res = cli("batch", src, "--out", dst, "--resume", "--no-progress")
    assert res.returncode == 0, res.stderr
    assert_same(read_store(dst), pmplan.plan_batch(o, s, g))
