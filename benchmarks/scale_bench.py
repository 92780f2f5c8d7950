"""Streaming benchmark: B queries (2,4,2) from a Zarr store to a Zarr store (issue 16).

Run from the repository root (needs ``pip install -e ".[dask]"``):

    python benchmarks/scale_bench.py                 # B = 20,000,000 (needs ~20 GB of disk)
    python benchmarks/scale_bench.py --B 2000000     # a smaller run
    python benchmarks/scale_bench.py --scheduler tcp://HOST:8786   # also on a real cluster

It writes an input store of B random (2,4,2) queries (seeded), then measures, each in a fresh
process (``python -m pmplan batch IN --out OUT.zarr ...``): in-process streaming, and a
dask.distributed LocalCluster of 1 and 2 worker processes (one thread each); and, in the
same run, in-memory ``pmplan.plan_batch`` on a slice of the same queries. For every row:
wall time (process start to exit, cluster start included), queries/s, and the peak resident
memory (RSS) of the whole process tree (sampled every 50 ms with psutil: the sum over the
processes, and the largest single process), also as a multiple of one chunk's output. A chunk
of each output is checked bit for bit against ``plan_batch`` on the same rows. The stores are
deleted afterwards. Results: ``benchmarks/scale_results.json`` and the section
``scale_results.md`` that ``benchmarks/RESULTS.md`` includes.

Not a test: pytest never collects this folder (``benchmarks/conftest.py``).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
SEED = 20240611
M, N, D = 2, 4, 2


def make_input(path: Path, b: int, chunk: int) -> float:
    """Write B random (2,4,2) queries, chunk by chunk; return seconds."""
    import zarr

    t = time.perf_counter()
    g = zarr.open_group(str(path), mode="w")
    arrays = {k: g.create_array(k, shape=(b, rows, D), chunks=(chunk, rows, D), dtype="f8")
              for k, rows in (("obstacles", M), ("start", N), ("goal", N))}
    rng = np.random.default_rng(SEED)
    for lo in range(0, b, chunk):
        hi = min(b, lo + chunk)
        for k, a in arrays.items():
            a[lo:hi] = rng.normal(size=(hi - lo, a.shape[1], D))
    return time.perf_counter() - t


def run_measured(cmd: list[str]) -> dict:
    """Run ``cmd``; wall time and the peak RSS of its process tree (sum, largest process)."""
    import psutil

    env = dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep
               + os.environ.get("PYTHONPATH", ""))
    t = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    root = psutil.Process(proc.pid)
    peak = {"sum": 0, "max": 0}
    stop = threading.Event()

    def sample():
        while not stop.is_set():
            try:
                procs = [root] + root.children(recursive=True)
            except psutil.NoSuchProcess:
                break
            rss = []
            for p in procs:
                try:
                    rss.append(p.memory_info().rss)
                except psutil.Error:
                    pass
            if rss:
                peak["sum"] = max(peak["sum"], sum(rss))
                peak["max"] = max(peak["max"], max(rss))
            stop.wait(0.05)

    th = threading.Thread(target=sample, daemon=True)
    th.start()
    out, err = proc.communicate()
    wall = time.perf_counter() - t
    stop.set()
    th.join()
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({proc.returncode}):\n{err[-2000:]}")
    return {"wall_s": wall, "rss_sum": peak["sum"], "rss_max": peak["max"],
            "stdout": out.strip().splitlines()[-1] if out.strip() else ""}


def child_inmemory(src: str, rows: int, repeats: int) -> None:
    """(child process) plan_batch on the first ``rows`` queries, in memory; print JSON."""
    import zarr

    import pmplan

    g = zarr.open_group(src, mode="r")
    o, s, gl = (np.asarray(g[k][:rows]) for k in ("obstacles", "start", "goal"))
    pmplan.plan_batch(o[:1000], s[:1000], gl[:1000])  # load the compiled kernels
    best = float("inf")
    for _ in range(repeats):
        t = time.perf_counter()
        batch = pmplan.plan_batch(o, s, gl)
        best = min(best, time.perf_counter() - t)
        del batch
    print(json.dumps({"best_s": best}))


def check_chunk(src: Path, out: Path, chunk: int, i: int) -> bool:
    """Chunk ``i`` of the output store equals plan_batch on its rows, bit for bit."""
    import zarr

    import pmplan

    gi = zarr.open_group(str(src), mode="r")
    go = zarr.open_group(str(out), mode="r")
    lo, hi = i * chunk, min(gi["obstacles"].shape[0], (i + 1) * chunk)
    ref = pmplan.plan_batch(*(np.asarray(gi[k][lo:hi]) for k in ("obstacles", "start", "goal")))
    ok = bool(go.attrs["complete"]) and bool(np.asarray(go["done"][:]).all())
    for k in ("domain", "strata", "clearance", "waypoints"):
        ok &= np.asarray(go[k][lo:hi]).tobytes() == getattr(ref, k).tobytes()
    ok &= np.asarray(go["times"][:]).tobytes() == ref.times.tobytes()
    return ok


def du(path: Path) -> int:
    return sum(f.stat().st_size for f in path.rglob("*") if f.is_file())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--B", type=int, default=20_000_000, help="queries (default 20,000,000)")
    ap.add_argument("--chunk", type=int, default=131072, help="queries per chunk")
    ap.add_argument("--slice", type=int, default=1_000_000,
                    help="queries of the in-memory plan_batch row (default 1,000,000)")
    ap.add_argument("--dir", default="/tmp/pmplan-scale-bench", help="where the stores go")
    ap.add_argument("--scheduler", default=None,
                    help="also run on this dask.distributed scheduler (shared filesystem)")
    ap.add_argument("--no-compress", action="store_true",
                    help="write the output uncompressed (pmplan batch --no-compress); the "
                    "results go to scale_results_raw.json, a second table of the same section")
    ap.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        child_inmemory(args.child[0], int(args.child[1]), int(args.child[2]))
        return 0

    import pmplan

    work = Path(args.dir)
    work.mkdir(parents=True, exist_ok=True)
    b, chunk = args.B, args.chunk
    in_bytes = b * (M + 2 * N) * D * 8
    out_bytes = b * (8 * (M + N) * D * 8 + 8 * 8)
    free = shutil.disk_usage(work).free
    if free < 1.3 * (in_bytes + out_bytes):
        raise SystemExit(f"{work}: {free / 1e9:.1f} GB free, this run needs up to "
                         f"{1.3 * (in_bytes + out_bytes) / 1e9:.1f} GB; use a smaller --B")
    src = work / "queries.zarr"
    print(f"B = {b:,} (2,4,2) queries, chunks of {chunk:,}; input {in_bytes / 1e9:.2f} GB, "
          f"output {out_bytes / 1e9:.2f} GB uncompressed; free {free / 1e9:.0f} GB", flush=True)
    t_in = make_input(src, b, chunk)
    print(f"input store written in {t_in:.0f} s ({du(src) / 1e9:.2f} GB on disk)", flush=True)
    chunk_out = chunk * 8 * (M + N) * D * 8  # one chunk of waypoints, bytes

    rows = []
    base = run_measured([sys.executable, __file__, "--child", str(src), "1000", "1"])
    print(f"baseline: a process with pmplan and its kernels loaded, 1,000 queries: "
          f"{base['rss_max'] / 1e6:.0f} MB", flush=True)
    res = run_measured([sys.executable, __file__, "--child", str(src), str(args.slice), "3"])
    best = json.loads(res["stdout"])["best_s"]
    rows.append({"what": f"plan_batch in memory, {args.slice:,} queries (one core)",
                 "queries": args.slice, "wall_s": best, "qps": args.slice / best,
                 "rss_sum": res["rss_sum"], "rss_max": res["rss_max"], "disk": None,
                 "checked": True})
    print(rows[-1], flush=True)
    runs = [("streaming in one process (no dask)", [])]
    runs += [(f"LocalCluster, {w} worker process{'es' if w > 1 else ''}",
              ["--dask-workers", str(w)]) for w in (1, 2)]
    if args.scheduler:
        runs.append((f"scheduler {args.scheduler}", ["--scheduler", args.scheduler]))
    for what, extra in runs:
        out = work / "plans.zarr"
        shutil.rmtree(out, ignore_errors=True)
        res = run_measured([sys.executable, "-m", "pmplan", "batch", str(src), "--out", str(out),
                            "--no-progress", *extra,
                            *(["--no-compress"] if args.no_compress else [])])
        nchunks = -(-b // chunk)
        checked = check_chunk(src, out, chunk, nchunks // 2) and \
            check_chunk(src, out, chunk, nchunks - 1)
        rows.append({"what": what, "queries": b, "wall_s": res["wall_s"],
                     "qps": b / res["wall_s"], "rss_sum": res["rss_sum"],
                     "rss_max": res["rss_max"], "disk": du(out), "checked": checked})
        print(rows[-1], flush=True)
        shutil.rmtree(out, ignore_errors=True)
    shutil.rmtree(src, ignore_errors=True)
    import platform

    result = {
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "B": b, "chunk": chunk, "chunk_out_bytes": chunk_out, "cores": os.cpu_count(),
        "input_write_s": t_in, "baseline_rss": base["rss_max"], "pmplan": pmplan.__version__,
        "python": platform.python_version(),
        "rows": rows, "compress": not args.no_compress,
    }
    name = "scale_results_raw.json" if args.no_compress else "scale_results.json"
    (HERE / name).write_text(json.dumps(result, indent=1))
    runs = [json.loads((HERE / n).read_text()) for n in ("scale_results.json",
                                                         "scale_results_raw.json")
            if (HERE / n).exists()]
    (HERE / "scale_results.md").write_text("\n".join(render(r, first=k == 0)
                                                      for k, r in enumerate(runs)))
    sys.path.insert(0, str(HERE))
    from _common import write_reports

    write_reports()
    print(render(result))
    return 0


def growth(row: dict, r: dict) -> str:
    """(peak RSS of the largest process - baseline) / one chunk of output waypoints; for the
    in-memory row, / its whole output instead (it is not chunked)."""
    if row["disk"] is None:
        whole = row["queries"] * 8 * (M + N) * D * 8
        return f"{(row['rss_max'] - r['baseline_rss']) / whole:.1f} (of its whole output)"
    return f"{(row['rss_max'] - r['baseline_rss']) / r['chunk_out_bytes']:.1f}"


def render(r: dict, first: bool = True) -> str:
    mb = 1e6
    codec = ("zstd, Zarr's default codec" if r.get("compress", True)
             else "uncompressed: `--no-compress`")
    lines = [
        "## Beyond one machine: Zarr to Zarr streaming (`benchmarks/scale_bench.py`)"
        if first else f"### The same, output {codec}",
        "",
        f"B = {r['B']:,} (2,4,2) queries (generic, seeded) in a Zarr store, chunks of "
        f"{r['chunk']:,} queries (one chunk of waypoints: {r['chunk_out_bytes'] / mb:.0f} MB), "
        f"planned by `pmplan batch IN --out OUT.zarr` into a Zarr store ({codec}), on this "
        f"{r['cores']}-core machine shared with other jobs; each row a fresh "
        "process (wall time includes starting Python, loading the kernels and, for the "
        "LocalCluster rows, starting the cluster). Peak RSS: the whole process tree sampled "
        "every 50 ms (sum over processes, and the largest process). *checked*: two chunks of "
        "the output equal `plan_batch` on the same rows, bit for bit, and the store is complete. "
        f"Baseline: a process with pmplan and its compiled kernels loaded planning 1,000 "
        f"queries peaks at {r['baseline_rss'] / mb:.0f} MB; the memory a run adds is compared "
        "with one chunk of output waypoints.",
        "",
        "| run | queries | wall time (s) | queries/s | peak RSS, all processes (MB) | "
        "peak RSS, largest process (MB) | (largest process - baseline) / one chunk | output on "
        "disk (GB) | checked |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for row in r["rows"]:
        disk = "" if row["disk"] is None else f"{row['disk'] / 1e9:.2f}"
        lines.append(
            f"| {row['what']} | {row['queries']:,} | {row['wall_s']:.1f} | {row['qps']:,.0f} | "
            f"{row['rss_sum'] / mb:,.0f} | {row['rss_max'] / mb:,.0f} | "
            f"{growth(row, r)} | {disk} | "
            f"{'yes' if row['checked'] else 'NO'} |")
    lines += ["", f"Run: {r['date']}, pmplan {r['pmplan']}, Python {r['python']}; writing the "
              f"input store took {r['input_write_s']:.0f} s.", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
