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
from pmplan import running
from pmplan._compiling import COMPILING, announce_compile
from pmplan.cli import main

NOTICE = f"pmplan: {COMPILING}"

SCRIPT = r"""
import sys

import numpy as np

import pmplan
from pmplan import api, running
from pmplan.kernels import planar as kernels_planar
from pmplan.kernels import validation as kernels_validation

running.CHUNK = 4  # 20 queries: 5 chunks, enough for the bar
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
    print("validation kernel compiled", misses(kernels_validation.valid_queries))
    pmplan.plan_batch(o, s, g, progress=True)  # compiles the planar kernel
    mark("cold")
    print("planar kernel compiled", misses(kernels_planar.plan_planar))
    pmplan.plan_batch(o, s, g, progress=True)  # compiled before in this process
    mark("again")
else:
    pmplan.plan_batch(o, s, g, progress=True)  # loaded from the disk cache
    mark("warm")
    print("planar kernel loaded", hits(kernels_planar.plan_planar), "compiled",
          misses(kernels_planar.plan_planar))
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


def _check_bar(err: str, total: int = 5) -> None:
    """A bar over ``total`` chunks that starts at 1 with no rate, never shows 0, and ends at
    ``total``."""
    frames = [f for f in err.replace("\r", "\n").split("\n") if f.startswith("planning")]
    assert frames, err
    assert f"1/{total} [" in frames[0] and "?chunk/s" in frames[0], frames
    assert f"{total}/{total} [" in frames[-1], frames
    assert not any(f"0/{total} [" in f for f in frames), frames


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


def _pmplan_function(name: str):
    """A new jitted function that numba sees as pmplan's (its module is ``pmplan.*``): its
    first call is a real (and tiny) compilation, never a cache load."""
    numba = __import__("numba")
    namespace = {"__name__": "pmplan._test_first_run"}
    exec(f"def {name}(x):\n    return x + 1\n", namespace)  # noqa: S102
    return numba.njit(namespace[name])


def test_announce_compile_once_until_rearmed():
    shown = []
    f, g, h = (_pmplan_function(name) for name in "fgh")
    with announce_compile(shown.append) as handle:
        assert shown == []
        f(1)
        g(1)
        f(2)
        assert shown == [COMPILING]
        handle.rearm()
        f(3)  # compiled before: nothing
        assert shown == [COMPILING]
        h(1)
        assert shown == [COMPILING, COMPILING]
    _pmplan_function("k")(1)  # after the block: nothing
    assert shown == [COMPILING, COMPILING]


def test_progress_announces_a_compile_after_the_bar_started_once_more(capsys):
    """A kernel that only a later chunk needs is announced again, above the running bar."""
    with running._Progress(True, 6) as progress:
        _pmplan_function("a")(1)
        progress.update()  # the first chunk is done: the bar starts here, at 1/6
        _pmplan_function("b")(1)
        _pmplan_function("c")(1)
        for _ in range(5):
            progress.update()
    err = capsys.readouterr().err
    assert err.count(NOTICE) == 2
    first, second = (err.index(NOTICE), err.index(NOTICE, err.index(NOTICE) + 1))
    assert "planning" not in err[:first]
    assert "1/6 [" in err[first:second]
    _check_bar(err, total=6)


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
