"""The planar three-obstacle kernel, old against new in the same run (issue 17 item 2).

Run from the repository root:

    python benchmarks/planar_bench.py                  # old = git merge-base with main
    python benchmarks/planar_bench.py --old REV --rounds 3 --B 100000

The *old* code is the tree of ``REV`` (``git archive``, into a temporary folder); the *new* code
is this checkout's ``src``. Every measurement is made by a worker process (``--worker SRC``),
old and new alternating, ``--rounds`` times; every worker measures its figures against a copy
of its own output in the same process, so the ratios compare across processes:

* ``plan_batch(out=...)`` time / time of ONE ``np.copyto`` of the output waypoints (best of
  ``--repeats`` each, interleaved), one core, for generic queries (standard normal
  coordinates: the top stratum T23_44) and for the strata mix of ``benchmarks/_common.py``;
* the scalar kernel alone on every query (the new one through its row selection, which is the
  whole batch here) / the same copy: what splitting ``plan_planar`` into helpers costs;
* single-query latency of ``pmplan.plan`` (p10 / p50 / p90 over ``--calls`` calls);
* the first call of ``pmplan.plan`` on a (2,1,3) query in a fresh process with an empty numba
  cache (``NUMBA_CACHE_DIR``), i.e. with every kernel it needs compiled (cold start).

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
def _best(fn, repeats: int) -> float:
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return min(out)


def _ratio(fn, copy, repeats: int) -> tuple[float, float]:
    """(best time of fn, best time of copy), interleaved."""
    tf, tc = [], []
    for _ in range(repeats):
        tf.append(_best(fn, 1))
        tc.append(_best(copy, 1))
    return min(tf), min(tc)


def worker(b: int, repeats: int, calls: int) -> dict:
    """Every in-process figure of the code on ``sys.path`` (one core)."""
    import gc

    sys.path.insert(0, str(HERE))
    import pmplan
    from _common import planar_three_mixed
    from pmplan.kernels import planar as kp
    from pmplan.planners import planar_three as p3

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
        np.copyto(dst, out.waypoints)

        def into(q=q, out=out):
            pmplan.plan_batch(*q, out=out, planner="planar_three")

        def copy(dst=dst, src=out.waypoints):
            np.copyto(dst, src)

        into()
        t, c = _ratio(into, copy, repeats)
        res[f"{family}: plan_batch(out=)"] = t / c
        # the scalar kernel alone, every query
        o, s, g = (np.ascontiguousarray(a) for a in q)
        arr = p3.PLANAR_THREE.allocate(b, 2, 3, 1, 2)
        flags = np.empty(b, np.uint8)
        args = (o, s, g, p3._EVEN, 1.0, True, arr["times"], arr["waypoints"], arr["domain"],
                arr["strata"], arr["clearance"], flags)
        if hasattr(kp, "plan_chunk"):  # new: the scalar kernel on a selection of rows (all)
            sel = np.arange(b, dtype=np.int64)

            def scalar(args=args, sel=sel):
                kp.plan_planar(*args, sel, sel.shape[0])
        else:  # old: the one kernel, scalar

            def scalar(args=args):
                kp.plan_planar(*args)

        scalar()
        t, c = _ratio(scalar, copy, repeats)
        res[f"{family}: scalar kernel alone"] = t / c
    # single-query latency, generic queries
    o, s, g = (rng.standard_normal((calls, k, 2)) for k in (3, 1, 1))
    pmplan.plan(o[0], s[0], g[0])
    lat = []
    for i in range(calls):
        t0 = time.perf_counter()
        pmplan.plan(o[i], s[i], g[i])
        lat.append(time.perf_counter() - t0)
    res["latency_us"] = [float(1e6 * v) for v in np.percentile(lat, [10, 50, 90])]
    return res


def cold() -> float:
    """Seconds of the first ``pmplan.plan`` on a (2,1,3) query (after the import)."""
    import pmplan

    t0 = time.perf_counter()
    pmplan.plan([[0.0, 0.0], [4.0, 0.0], [2.5, 1.5]], [[0.0, -2.0]], [[6.0, 2.5]])
    return time.perf_counter() - t0


# --------------------------------------------------------------------------- driver
def _run(src: Path, args: list[str], cache: str | None = None) -> dict:
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
    keys = [k for k in res["rounds"][0]["new"] if k not in ("B", "latency_us")]
    lines = [
        SECTION,
        "",
        (
            f"Old = `{res['old']}`, new = `{res['new']}`, measured in the same run "
            f"({res['date']}): worker processes alternating old / new, {len(res['rounds'])} "
            f"rounds, one core each, B = {res['B']:,}. Each figure is a time divided by the time of "
            "ONE `np.copyto` of the output waypoints measured in the same process (best of "
            f"{res['repeats']} each, interleaved); ranges over the rounds. *generic*: standard "
            "normal coordinates (the top stratum, T23_44); *strata mix*: spread evenly over "
            "the 12 strata. The *scalar kernel alone* rows run the scalar kernel on every query "
            "(old: `plan_planar` in one function; new: `plan_planar` split into helpers, on a selection of rows that is every row)."
        ),
        "",
        "| figure | old | new |",
        "|---|---|---|",
    ]
    for k in keys:
        o = [r["old"][k] for r in res["rounds"]]
        n = [r["new"][k] for r in res["rounds"]]
        lines.append(f"| {k} / one copy | {_rng(o)} | {_rng(n)} |")
    for side in ("old", "new"):
        pass
    lat = {s: np.array([r[s]["latency_us"] for r in res["rounds"]]) for s in ("old", "new")}
    for i, name in enumerate(("p10", "p50", "p90")):
        lines.append(f"| `pmplan.plan` latency {name} (us) | {_rng(lat['old'][:, i])} | "
                     f"{_rng(lat['new'][:, i])} |")
    lines.append(f"| first `pmplan.plan` (2,1,3), empty numba cache (s) | "
                 f"{_rng(res['cold']['old'])} | {_rng(res['cold']['new'])} |")
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
    a = ap.parse_args(argv)
    if a.worker:
        print(json.dumps(worker(a.B, a.repeats, a.calls)))
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
    args = ["--worker", "--B", str(a.B), "--repeats", str(a.repeats), "--calls", str(a.calls)]
    with tempfile.TemporaryDirectory() as tmp:
        srcs = {"old": _old_tree(rev, Path(tmp)), "new": ROOT / "src"}
        for s in ("old", "new"):  # compile and cache both before timing anything
            _run(srcs[s], ["--worker", "--B", "2000", "--repeats", "1", "--calls", "10"])
        for rnd in range(a.rounds):
            row = {}
            for s in ("old", "new") if rnd % 2 == 0 else ("new", "old"):
                row[s] = _run(srcs[s], args)
                with tempfile.TemporaryDirectory() as cache:
                    res["cold"][s].append(_run(srcs[s], ["--cold"], cache=cache))
                print(f"round {rnd + 1} {s}: {row[s]}", file=sys.stderr)
            res["rounds"].append(row)
    (HERE / "planar_results.json").write_text(json.dumps(res, indent=1))
    text = report(res)
    (HERE / "planar_results.md").write_text(text)
    _put_section(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
