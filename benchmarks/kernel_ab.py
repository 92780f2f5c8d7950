"""A/B of the obstacle-line kernels of several git refs, in ONE process, in CPU time.

Usage (from the repository root)::

    python benchmarks/kernel_ab.py 8632269 HEAD                 # generic queries, SIMD path
    python benchmarks/kernel_ab.py 8632269 HEAD --scalar        # every query by the scalar kernel
    python benchmarks/kernel_ab.py A B --cases "2,1,2;3,4,2" --rounds 60 --batch 32768

Each ref's ``src/pmplan`` is exported (``git archive``) into a temporary folder as a package of
its own name (``pmplan_ab0``, ``pmplan_ab1``, ...), so that every version's kernels live in one
process; their first calls compile them (not timed). Then, for every case, the same generic
queries are planned by each version's ``plan_chunk`` (chunks of 8,192, as ``plan_batch`` does;
``--scalar``: the scalar kernel ``_plan`` on every query), the versions alternating round by
round, and the outputs are checked equal bit for bit. Times are the calling thread's CPU time
(``time.thread_time``): on a machine shared with other jobs the wall clock also counts the
time the process waits for a core, which the CPU time does not. Best and median per version,
and each version's best over the first one's.

Kernel code only (no validation in Python, no allocation, no certificate re-decision): what
``benchmarks/run.py`` measures around it is the public call. Not a test (pytest never collects
this folder).
"""

from __future__ import annotations

import argparse
import gc
import importlib
import io
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
CHUNK = 8192


def _export(ref: str, dest: Path, name: str) -> str:
    """``src/pmplan`` of git ref ``ref`` into ``dest/name``; returns the ref's short commit."""
    sha = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--verify", f"{ref}^{{commit}}"],
                         check=True, capture_output=True, text=True).stdout.strip()
    data = subprocess.run(["git", "-C", str(ROOT), "archive", sha, "src/pmplan"], check=True,
                          capture_output=True).stdout
    with tarfile.open(fileobj=io.BytesIO(data)) as tar:
        tar.extractall(dest / "tmp", filter="data")
    (dest / "tmp" / "src" / "pmplan").rename(dest / name)
    return sha[:10]


def _kernel_module(name: str):
    """The obstacle-line kernel module of an exported package (its place changed over time)."""
    for mod in ("kernels.obstacle_line", "_kernels"):
        try:
            return importlib.import_module(f"{name}.{mod}")
        except ImportError:
            continue
    raise ImportError(f"no obstacle-line kernel module in {name}")


def _caller(kern, q, b: int, n: int, d: int, scalar: bool):
    """A closure planning the queries ``q`` with ``kern`` into its own output arrays."""
    o, s, g = q
    m = o.shape[1]
    wp = np.empty((b, 8, m + n, d))
    dom = np.empty(b, np.int64)
    st = np.empty((b, 4), np.int64)
    cl = np.empty(b)
    fl = np.empty(b, np.uint8)
    tab = kern.tables(2, m, n, d)
    sel = np.arange(b)
    # the scalar kernel: plan_queries (named _plan in refs before the backend seam)
    scalar_kernel = getattr(kern, "plan_queries", None) or getattr(kern, "_plan")

    def call():
        if scalar:
            scalar_kernel(o, s, g, np.empty((0, b, n, d)), 1.0, True, wp, dom, st, cl, fl, tab,
                       sel, b)
            return
        for lo in range(0, b, CHUNK):
            hi = min(b, lo + CHUNK)
            kern.plan_chunk(o[lo:hi], s[lo:hi], g[lo:hi], np.empty((0, hi - lo, n, d)), 1.0, True,
                            wp[lo:hi], dom[lo:hi], st[lo:hi], cl[lo:hi], fl[lo:hi], tab)

    return call, (wp, cl, fl)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("refs", nargs="+", help="git refs to compare (the first is the reference)")
    ap.add_argument("--cases", default="2,1,2;2,4,2;3,4,2;2,16,2", help="d,n,m;d,n,m;...")
    ap.add_argument("--rounds", type=int, default=30)
    ap.add_argument("--batch", type=int, default=32768)
    ap.add_argument("--scalar", action="store_true", help="time the scalar kernel _plan")
    ap.add_argument("--seed", type=int, default=20240611)
    args = ap.parse_args(argv)
    cases = [tuple(int(v) for v in c.split(",")) for c in args.cases.split(";")]
    with tempfile.TemporaryDirectory(prefix="pmplan-kernel-ab-") as tmp:
        names, kernels = [], []
        for i, ref in enumerate(args.refs):
            name = f"pmplan_ab{i}"
            sha = _export(ref, Path(tmp), name)
            names.append(f"{ref} ({sha})")
            kernels.append(name)
        sys.path.insert(0, tmp)
        kernels = [_kernel_module(k) for k in kernels]
        rng = np.random.default_rng(args.seed)
        b = args.batch
        print(f"{'scalar kernel' if args.scalar else 'plan_chunk'}, B = {b:,}, best of "
              f"{args.rounds} alternating rounds, CPU time (ms)")
        for d, n, m in cases:
            q = (rng.standard_normal((b, m, d)), rng.standard_normal((b, n, d)),
                 rng.standard_normal((b, n, d)))
            calls = [_caller(k, q, b, n, d, args.scalar) for k in kernels]
            for call, _ in calls:
                call()  # compiles (not timed)
            ref = calls[0][1]
            for nm, (_, outs) in zip(names, calls):
                for a, r in zip(outs, ref):
                    if not np.array_equal(a, r, equal_nan=True):
                        print(f"  ({d},{n},{m}) {nm}: output differs from {names[0]}")
            times: list[list[float]] = [[] for _ in calls]
            for r in range(args.rounds):
                for k in [(r + j) % len(calls) for j in range(len(calls))]:
                    gc.collect()
                    t0 = time.thread_time()
                    calls[k][0]()
                    times[k].append(time.thread_time() - t0)
            best0 = min(times[0])
            cols = [f"{nm}: {1e3 * min(t):.2f} (median {1e3 * float(np.median(t)):.2f}, "
                    f"x{min(t) / best0:.3f})" for nm, t in zip(names, times)]
            print(f"  ({d},{n},{m})  " + "   ".join(cols), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
