"""The planar three-obstacle kernel, old against new in the same run (issue 17 item 2).

Run from the repository root:

    python benchmarks/planar_bench.py                  # old = git merge-base with main
    python benchmarks/planar_bench.py --old REV --rounds 3 --B 100000

The *old* code is the tree of ``REV`` (``git archive``, into a temporary folder); the *new* code
is this checkout's ``src``. A worker process of the new code loads the old kernel module beside
the new one and switches the planar planner between them in place (the old one also without
validation in the kernel, so ``plan_batch`` validates in a separate pass, as it did); every
figure is old, new and a copy measured in turn in that process, ``--rounds`` workers:

* ``plan_batch(out=...)`` time / time of ONE ``np.copyto`` of the output waypoints (best of
  ``--repeats``), one core, for generic queries (standard normal coordinates: the top stratum
  T23_44) and for the strata mix of ``benchmarks/_common.py``;
* the scalar kernel alone on every query (the new one through its row selection, which is the
  whole batch here) / the same copy: what splitting ``plan_planar`` into helpers costs; and the
  new ``plan_chunk`` (SIMD path, then the scalar kernel) alone;
* single-query latency of ``pmplan.plan`` (p10 / p50 / p90 over ``--calls`` calls, blocks of
  200 calls old and new alternating);
* the first call of ``pmplan.plan`` on a (2,1,3) query in a fresh process (of the old tree, of
  the new one) with an empty numba cache (``NUMBA_CACHE_DIR``): it compiles every kernel it
  needs (cold start).

Results: ``benchmarks/planar_results.json`` and the section ``benchmarks/planar_results.md``,
which ``benchmarks/_common.write_reports`` includes in ``benchmarks/RESULTS.md`` (this script
also puts it there at once, replacing only its own section). Not a test: pytest never collects
this folder (``benchmarks/conftest.py``).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
SECTION = "## Planar kernel (`benchmarks/planar_bench.py`)"
SEED = 20261201


# --------------------------------------------------------------------------- worker
def _load_old(path: str):
    """The old ``pmplan/kernels/planar.py`` as the module ``pmplan.kernels._planar_old`` (its
    relative imports resolve in this pmplan; numba caches it next to the file)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("pmplan.kernels._planar_old", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


class _Side:
    """Switch this process between the old kernel and the new one, in place: the kernel module
    the numba backend calls (``pmplan.backends.numba.planar_kernels``), whether the planner
    validates in its kernel (the old one did not: ``pmplan.plan_batch`` then validates in a
    separate pass, as it did) and the single-query fast paths cached by :mod:`pmplan.single`."""

    def __init__(self, old):
        import types

        from pmplan import single
        from pmplan.backends import numba as nb
        from pmplan.kernels import planar as kp

        self.single, self.nb, self.new = single, nb, nb.planar_kernels
        self.glue = nb.PLANNERS[nb.PLANAR_THREE]
        self.shim = types.SimpleNamespace(AVAILABLE=True, plan_chunk=old.plan_planar,
                                          plan_planar_one=old.plan_planar_one)
        self.kp = kp

    def __call__(self, side: str) -> None:
        if side == "old":
            self.nb.planar_kernels = lambda: self.shim
            arrays, kernel, _, single, sequence = self.glue
            self.nb.PLANNERS[self.nb.PLANAR_THREE] = (arrays, kernel, lambda d: False, single,
                                                sequence)
        else:
            self.nb.planar_kernels = self.new
            self.nb.PLANNERS[self.nb.PLANAR_THREE] = self.glue
        self.single._FAST.clear()


def _interleaved(fns: dict, repeats: int) -> dict:
    """Best time of every function, the functions called in turn ``repeats`` times."""
    best = dict.fromkeys(fns, float("inf"))
    for _ in range(repeats):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            best[k] = min(best[k], time.perf_counter() - t0)
    return best


def worker(b: int, repeats: int, calls: int, old_file: str) -> dict:
    """Every in-process figure, old and new side by side (one core)."""
    import gc

    sys.path.insert(0, str(HERE))
    from _common import planar_three_mixed

    import pmplan
    from pmplan import planar_strata
    from pmplan.planners import planar_three as p3

    old = _load_old(old_file)
    side = _Side(old)
    kp = side.kp
    gc.disable()
    rng = np.random.default_rng(SEED)
    res: dict = {"B": b}
    batches = {
        "generic": tuple(rng.standard_normal((b, k, 2)) for k in (3, 1, 1)),
        "strata mix": planar_three_mixed(rng, b),
    }
    for family, q in batches.items():
        out = pmplan.plan_batch(*q, planner="planar_three")
        dst = np.empty_like(out.waypoints)
        o, s, g = (np.ascontiguousarray(a) for a in q)
        arr = p3.PLANAR_THREE.allocate(b, 2, 3, 1, 2)
        flags = np.empty(b, np.uint8)
        args = (o, s, g, planar_strata.EVEN, 1.0, True, arr["times"], arr["waypoints"], arr["domain"],
                arr["strata"], arr["clearance"], flags)
        sel = np.arange(b, dtype=np.int64)

        def into(q=q, out=out, which="new"):
            side(which)
            pmplan.plan_batch(*q, out=out, planner="planar_three")

        fns = {
            "copy": lambda dst=dst, src=out.waypoints: np.copyto(dst, src),
            "plan_batch(out=) old": lambda: into(which="old"),
            "plan_batch(out=) new": lambda: into(which="new"),
            "scalar kernel old (one function)": lambda args=args: old.plan_planar(*args),
            "scalar kernel new (helpers)": lambda args=args, sel=sel: kp.plan_planar(*args, sel,
                                                                                  b),
            "kernel new (plan_chunk)": lambda args=args: kp.plan_chunk(*args),
        }
        for fn in fns.values():  # compile, fault the pages in
            fn()
        best = _interleaved(fns, repeats)
        for k, v in best.items():
            if k != "copy":
                res[f"{family}: {k}"] = v / best["copy"]
        side("new")
    # single-query latency, generic queries: blocks of 200 calls, old and new alternating
    o, s, g = (rng.standard_normal((calls, k, 2)) for k in (3, 1, 1))
    lat = {"old": [], "new": []}
    for lo in range(0, calls, 200):
        for which in ("old", "new") if lo % 400 else ("new", "old"):
            side(which)
            pmplan.plan(o[lo], s[lo], g[lo])  # the fast path of this side
            for i in range(lo, min(calls, lo + 200)):
                t0 = time.perf_counter()
                pmplan.plan(o[i], s[i], g[i])
                lat[which].append(time.perf_counter() - t0)
    side("new")
    for which, v in lat.items():
        res[f"latency_us {which}"] = [float(1e6 * x) for x in np.percentile(v, [10, 50, 90])]
    return res


def cold() -> list[float]:
    """Seconds (wall clock, CPU time of the process) of the first ``pmplan.plan`` on a (2,1,3)
    query, after the import. The CPU time (numba compiles on one thread) is the steadier
    figure on a shared machine."""
    import pmplan

    t0 = time.perf_counter()
    c0 = time.process_time()
    pmplan.plan([[0.0, 0.0], [4.0, 0.0], [2.5, 1.5]], [[0.0, -2.0]], [[6.0, 2.5]])
    return [time.perf_counter() - t0, time.process_time() - c0]


# --------------------------------------------------------------------------- driver
def _run(src: Path, args: list[str], cache: str | None = None) -> object:
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1")
    if cache is not None:
        env["NUMBA_CACHE_DIR"] = cache
    out = subprocess.run([sys.executable, str(Path(__file__).resolve()), *args], env=env,
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _old_tree(rev: str, where: Path) -> Path:
    tar = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "src"], capture_output=True,
                         check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(where)], input=tar, check=True)
    return where / "src"


def _rng(vals) -> str:
    return f"{min(vals):.2f}-{max(vals):.2f}" if len(vals) > 1 else f"{vals[0]:.2f}"


def report(res: dict) -> str:
    rounds = res["rounds"]
    lines = [
        SECTION,
        "",
        (
            f"Old = `{res['old']}` (the kernel before issue 17 item 2), new = `{res['new']}`, "
            f"measured in the same run ({res['date']}), {len(rounds)} rounds (one process each, "
            f"one core), B = {res['B']:,}; ranges over the rounds. Every figure is a time "
            "divided by the time of ONE `np.copyto` of the output waypoints, old, new and the "
            f"copy called in turn in the same process (best of {res['repeats']}). The old "
            "planner is the old kernel behind the same `plan_batch`, with its separate "
            "validation pass. *generic*: standard normal coordinates (the top stratum, T23_44, "
            "which the SIMD path plans); *strata mix*: spread evenly over the 12 strata (exact "
            "constructions: mostly the scalar kernel and its exact stages). The scalar kernel "
            "rows run it on every query: old = one function, new = split into helpers."
        ),
        "",
        "| figure (/ one copy) | generic | strata mix |",
        "|---|---|---|",
    ]
    keys = [k.split(": ", 1)[1] for k in rounds[0] if k.startswith("generic: ")]
    for k in keys:
        g = [r[f"generic: {k}"] for r in rounds]
        m = [r[f"strata mix: {k}"] for r in rounds]
        lines.append(f"| {k} | {_rng(g)} | {_rng(m)} |")
    for new, old in (("plan_batch(out=) new", "plan_batch(out=) old"),
                     ("scalar kernel new (helpers)", "scalar kernel old (one function)")):
        g = [r[f"generic: {new}"] / r[f"generic: {old}"] for r in rounds]
        m = [r[f"strata mix: {new}"] / r[f"strata mix: {old}"] for r in rounds]
        lines.append(f"| {new} / {old}, same round | {_rng(g)} | {_rng(m)} |")
    lines += ["", "| single query, `pmplan.plan` (2,1,3) | old | new |", "|---|---|---|"]
    for i, name in enumerate(("p10", "p50 (median)", "p90")):
        o = [r["latency_us old"][i] for r in rounds]
        n = [r["latency_us new"][i] for r in rounds]
        lines.append(f"| latency {name}, us | {_rng(o)} | {_rng(n)} |")
    for i, name in enumerate(("wall clock", "CPU time")):
        o = [c[i] for c in res["cold"]["old"]]
        n = [c[i] for c in res["cold"]["new"]]
        lines.append(f"| first call, empty numba cache (compiles its kernels), {name}, s | "
                     f"{_rng(o)} | {_rng(n)} |")
    lines.append("")
    return "\n".join(lines)


def _put_section(text: str) -> None:
    """Replace (or append) this script's section of benchmarks/RESULTS.md, nothing else."""
    path = HERE / "RESULTS.md"
    old = path.read_text().splitlines() if path.exists() else []
    if SECTION in old:
        i = old.index(SECTION)
        j = next((k for k in range(i + 1, len(old)) if old[k].startswith("## ")), len(old))
        new = old[:i] + text.splitlines() + old[j:]
    else:
        new = old + [""] + text.splitlines()
    path.write_text("\n".join(new) + "\n")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", default=None, help="git revision of the old code "
                    "(default: the merge-base with main)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--B", type=int, default=100_000)
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--calls", type=int, default=3000)
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--cold", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--old-file", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--report", action="store_true",
                    help="only write the report again from benchmarks/planar_results.json")
    a = ap.parse_args(argv)
    if a.report:
        text = report(json.loads((HERE / "planar_results.json").read_text()))
        (HERE / "planar_results.md").write_text(text)
        _put_section(text)
        print(text)
        return 0
    if a.worker:
        print(json.dumps(worker(a.B, a.repeats, a.calls, a.old_file)))
        return 0
    if a.cold:
        print(json.dumps(cold()))
        return 0
    git = ["git", "-C", str(ROOT)]
    rev = a.old or subprocess.run([*git, "merge-base", "HEAD", "main"], capture_output=True,
                                  text=True, check=True).stdout.strip()
    head = subprocess.run([*git, "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True, check=True).stdout.strip()
    res = {"B": a.B, "repeats": a.repeats, "old": rev[:10], "new": head,
           "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "rounds": [],
           "cold": {"old": [], "new": []}}
    with tempfile.TemporaryDirectory() as tmp:
        srcs = {"old": _old_tree(rev, Path(tmp)), "new": ROOT / "src"}
        old_file = str(srcs["old"] / "pmplan" / "kernels" / "planar.py")
        args = ["--worker", "--B", str(a.B), "--repeats", str(a.repeats), "--calls",
                str(a.calls), "--old-file", old_file]
        _run(srcs["new"], [*args[:2], "2000", "--repeats", "1", "--calls", "400", *args[-2:]])
        for rnd in range(a.rounds):
            row = _run(srcs["new"], args)
            print(f"round {rnd + 1}: {row}", file=sys.stderr)
            res["rounds"].append(row)
            for s in ("old", "new") if rnd % 2 == 0 else ("new", "old"):
                with tempfile.TemporaryDirectory() as cache:
                    res["cold"][s].append(_run(srcs[s], ["--cold"], cache=cache))
    (HERE / "planar_results.json").write_text(json.dumps(res, indent=1))
    text = report(res)
    (HERE / "planar_results.md").write_text(text)
    _put_section(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
