"""The first run: the progress display announces the compilation of the kernels (issue 12).

Numba compiles pmplan's kernels the first time they run and caches them on disk. With
``progress=True`` (``pmplan batch``) the notice :data:`pmplan._compiling.COMPILING` is written
on stderr exactly when a kernel is compiled -- not when it is loaded from the cache or was
compiled before in the process -- and before the progress bar starts, which then counts the
first chunk, so that no rate or time estimate includes the compilation; with
``progress=False`` nothing is written. The cold runs are subprocesses with an empty
``NUMBA_CACHE_DIR`` planning tiny batches: the planar planner's kernel is the cheapest to
compile (a few seconds).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import pmplan
from pmplan._compiling import COMPILING, announce_compile
from pmplan.cli import main

NOTICE = f"pmplan: {COMPILING}"

SCRIPT = r"""
import sys

import numpy as np

import pmplan
from pmplan import _kernels as K, _kernels_planar as KP, api

api.CHUNK = 4  # 20 queries: 5 chunks, enough for the bar
rng = np.random.default_rng(5)
o, s, g = (rng.normal(size=(20, k, 2)) for k in (3, 1, 1))
o2, s2, g2 = (rng.normal(size=(6, k, 2)) for k in (2, 1, 1))


def mark(text):
    sys.stderr.write(f"@@{text}\n")
    sys.stderr.flush()


def misses(kernel):
    return sum(kernel.stats.cache_misses.values())


def hits(kernel):
    return sum(kernel.stats.cache_hits.values())


if sys.argv[1] == "cold":
    pmplan.plan_batch(o2, s2, g2, backend="numpy")  # compiles the validation kernel
    mark("progress=False")
    print("validation kernel compiled", misses(K.valid_queries))
    pmplan.plan_batch(o, s, g, progress=True)  # compiles the planar kernel
    mark("cold")
    print("planar kernel compiled", misses(KP.plan_planar))
    pmplan.plan_batch(o, s, g, progress=True)  # compiled before in this process
    mark("again")
else:
    pmplan.plan_batch(o, s, g, progress=True)  # loaded from the disk cache
    mark("warm")
    print("planar kernel loaded", hits(KP.plan_planar), "compiled", misses(KP.plan_planar))
"""


def _run(phase: str, cache: Path) -> tuple[str, dict[str, str]]:
    """Run SCRIPT's ``phase`` with numba's cache in ``cache``: (stdout, stderr by marker)."""
    src = str(Path(pmplan.__file__).resolve().parents[1])
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache),
               PYTHONPATH=os.pathsep.join([src, os.environ.get("PYTHONPATH", "")]))
    res = subprocess.run([sys.executable, "-c", SCRIPT, phase], env=env, capture_output=True,
                         text=True, timeout=600, check=False)
    assert res.returncode == 0, res.stderr
    parts, text = {}, res.stderr
    while "@@" in text:
        before, _, rest = text.partition("@@")
        name, _, text = rest.partition("\n")
        parts[name] = before
    assert text == ""
    return res.stdout, parts


def _check_bar(err: str) -> None:
    """A bar over 5 chunks that starts at 1/5 with no rate, never at 0/5, and ends at 5/5."""
    frames = [f for f in err.replace("\r", "\n").split("\n") if f.startswith("planning")]
    assert frames, err
    assert "1/5 [" in frames[0] and "?chunk/s" in frames[0], frames
    assert "5/5 [" in frames[-1], frames
    assert not any("0/5 [" in f for f in frames), frames


def test_progress_announces_a_compile_and_only_then(tmp_path):
    out, err = _run("cold", tmp_path)
    # progress=False: a kernel was compiled, and nothing was written
    assert "validation kernel compiled 1" in out
    assert err["progress=False"] == ""
    # progress=True on a cold cache: the notice, once, then the bar (no estimate before it)
    assert "planar kernel compiled 1" in out
    cold = err["cold"]
    assert cold.startswith(NOTICE + "\n"), cold
    assert cold.count(COMPILING) == 1
    _check_bar(cold[len(NOTICE):])
    # the same batch again in the process: nothing to compile, no notice
    assert COMPILING not in err["again"]
    _check_bar(err["again"])
    # a new process with the cache filled: the kernel is loaded, not compiled -- no notice
    out, err = _run("warm", tmp_path)
    assert "planar kernel loaded 1 compiled 0" in out
    assert COMPILING not in err["warm"]
    _check_bar(err["warm"])


def test_no_progress_writes_nothing(capfd):
    rng = np.random.default_rng(2)
    for k in (2, 3):  # the obstacle-line and planar kernels (compiled or loaded: silent)
        o, s, g = (rng.normal(size=(30, j, 2)) for j in (k, 1, 1))
        pmplan.plan_batch(o, s, g)
        pmplan.plan_batch(o, s, g, progress=False, workers=2)
    pmplan.plan(o[0], s[0], g[0])
    out, err = capfd.readouterr()
    assert (out, err) == ("", "")


def test_announce_compile_ignores_other_code():
    """Only pmplan's kernels are announced, not a compilation of the caller's own code."""
    numba = __import__("numba")
    shown = []

    @numba.njit
    def twice(x):
        return 2 * x

    with announce_compile(shown.append):
        assert twice(21) == 42
    assert shown == []


def test_demo_mentions_a_compile_only_when_one_happens(tmp_path, capsys):
    for k in range(2):
        assert main(["demo", "--out", str(tmp_path / f"demo{k}.png")]) == 0
        err = capsys.readouterr().err
        # the first call may compile (when this process has not planned before), never the
        # second: every kernel it needs is compiled by then
        assert err in ("", f"pmplan demo: {COMPILING}\n") if k == 0 else err == "", err
