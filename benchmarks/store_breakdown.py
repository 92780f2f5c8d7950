"""What limits ``pmplan batch IN.zarr --out OUT.zarr``: plan, compress and write, timed apart.

Run from the repository root (needs ``pip install -e ".[dask]"``):

    python benchmarks/store_breakdown.py              # one chunk of 131,072 + a 1 M-query stream
    python benchmarks/store_breakdown.py --stream 0   # the chunk only

One chunk of 131,072 random (2,4,2) queries (the chunk of the 20 M-query run of
``scale_bench.py``) is timed in its three stages, one core, ``--rounds`` rounds each:

* **plan**: ``pmplan.plan_batch`` of the chunk (certificate included);
* **compress**: Zarr's write of every output array of the chunk into an in-memory store
  (``zarr.storage.MemoryStore``) with the store's codec (zstd, ``pmplan.scale.ZSTD_LEVEL``) --
  the encoding alone, no disk --, with Zarr's default (zstd level 3, what stores used before),
  and uncompressed (the copy it costs anyway);
* **write**: the bytes Zarr produced (compressed and not) written to files on the disk of
  ``--dir`` and flushed with ``fsync``; and the disk's sustained write rate (``--disk-mb`` MB
  in 64 MB blocks, one ``fsync``).

From these, the queries/s a process can stream if the stages run one after the other (as
``plan_store`` runs them in one process), and which stage bounds it; then a real streaming run
of ``--stream`` queries, compressed and ``--no-compress`` (fresh processes), to compare, and the
20 M-query rows of ``scale_results.json`` when present. Results: ``store_breakdown.json`` and the
section ``store_breakdown.md`` that ``benchmarks/RESULTS.md`` includes.

Not a test: pytest never collects this folder (``benchmarks/conftest.py``).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CHUNK = 131_072
SEED = 20261202


def _chunk_arrays(batch) -> dict:
    """The arrays ``plan_store`` writes for a chunk of ``batch`` (times shared: not per chunk)."""
    return {k: getattr(batch, k) for k in ("domain", "strata", "clearance", "waypoints")}


def _zarr_encode(arrays: dict, codec) -> tuple[float, dict]:
    """Seconds to write ``arrays`` (one chunk each) into a MemoryStore with the compressors
    ``codec`` (as ``zarr.create_array`` takes them), and the encoded bytes of every stored chunk
    (key -> bytes)."""
    import zarr

    store = zarr.storage.MemoryStore()
    group = zarr.open_group(store, mode="w")
    made = {k: group.create_array(k, shape=a.shape, chunks=a.shape, dtype=a.dtype,
                                  compressors=codec, fill_value=0)
            for k, a in arrays.items()}
    t = time.perf_counter()
    for k, a in arrays.items():
        made[k][...] = a
    took = time.perf_counter() - t
    blobs = {key: bytes(buf.to_bytes()) for key, buf in store._store_dict.items()
             if "/c" in key}
    return took, blobs


def _write_files(blobs: dict, where: Path) -> float:
    """Seconds to write ``blobs`` to files under ``where`` and fsync them."""
    where.mkdir(parents=True, exist_ok=True)
    t = time.perf_counter()
    for i, data in enumerate(blobs.values()):
        with open(where / f"chunk{i}", "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
    took = time.perf_counter() - t
    shutil.rmtree(where)
    return took


def _disk_rate(where: Path, mb: int) -> float:
    """Sustained write rate of the disk under ``where`` in MB/s (64 MB blocks, one fsync)."""
    block = np.random.default_rng(0).bytes(64 * 2**20)
    path = where / "disk_rate.bin"
    t = time.perf_counter()
    with open(path, "wb") as f:
        for _ in range(max(1, mb // 64)):
            f.write(block)
        f.flush()
        os.fsync(f.fileno())
    took = time.perf_counter() - t
    size = path.stat().st_size
    path.unlink()
    return size / took / 1e6


def measure_chunk(rounds: int, where: Path, disk_mb: int) -> dict:
    import pmplan
    from pmplan.scale import compressors

    rng = np.random.default_rng(SEED)
    o, s, g = (rng.normal(size=(CHUNK, k, 2)) for k in (2, 4, 4))
    pmplan.plan_batch(o[:1000], s[:1000], g[:1000])  # load the compiled kernels
    res = {k: [] for k in ("plan", "encode_zstd", "encode_raw", "encode_zarr_default",
                           "write_zstd", "write_raw")}
    for _ in range(rounds):
        t = time.perf_counter()
        batch = pmplan.plan_batch(o, s, g)
        res["plan"].append(time.perf_counter() - t)
        arrays = _chunk_arrays(batch)
        took, zblobs = _zarr_encode(arrays, compressors(True))
        res["encode_zstd"].append(took)
        took, rblobs = _zarr_encode(arrays, None)
        res["encode_raw"].append(took)
        took, dblobs = _zarr_encode(arrays, "auto")
        res["encode_zarr_default"].append(took)
        res["write_zstd"].append(_write_files(zblobs, where / "z"))
        res["write_raw"].append(_write_files(rblobs, where / "r"))
    res["bytes_raw"] = sum(a.nbytes for a in arrays.values())
    res["bytes_zstd"] = sum(len(b) for b in zblobs.values())
    res["bytes_zarr_default"] = sum(len(b) for b in dblobs.values())
    res["bytes_waypoints"] = int(batch.waypoints.nbytes)
    res["disk_mb_s"] = [_disk_rate(where, disk_mb) for _ in range(2)]
    return res


def _stream(b: int, where: Path, compress: bool) -> float:
    """queries/s of ``pmplan batch`` streaming ``b`` (2,4,2) queries Zarr to Zarr in a fresh
    process (process start and kernel loading included)."""
    import zarr

    src, out = where / "in.zarr", where / "out.zarr"
    if not src.exists():
        g = zarr.open_group(str(src), mode="w")
        rng = np.random.default_rng(SEED + 1)
        for k, rows in (("obstacles", 2), ("start", 4), ("goal", 4)):
            a = g.create_array(k, shape=(b, rows, 2), chunks=(CHUNK, rows, 2), dtype="f8")
            a[...] = rng.normal(size=(b, rows, 2))
    shutil.rmtree(out, ignore_errors=True)
    cmd = [sys.executable, "-m", "pmplan", "batch", str(src), "--out", str(out), "--no-progress"]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep
               + os.environ.get("PYTHONPATH", ""))
    t = time.perf_counter()
    subprocess.run(cmd + ([] if compress else ["--no-compress"]), check=True, env=env,
                   capture_output=True)
    took = time.perf_counter() - t
    shutil.rmtree(out)
    return b / took


def _rng(xs, fmt="{:.3f}") -> str:
    lo, hi = min(xs), max(xs)
    return fmt.format(lo) if fmt.format(lo) == fmt.format(hi) else \
        f"{fmt.format(lo)}-{fmt.format(hi)}"


def render(r: dict) -> str:
    from pmplan.scale import ZSTD_LEVEL

    mb = 1e6
    raw = r["bytes_raw"] / mb
    best = {k: min(v) for k, v in r.items() if isinstance(v, list)}
    disk = max(r["disk_mb_s"])

    def per_chunk(encode: str, nbytes: float) -> float:
        """One process runs the stages one after the other: plan, encode, write."""
        return best["plan"] + best[encode] + nbytes / mb / disk

    t_zstd = per_chunk("encode_zstd", r["bytes_zstd"])
    t_raw = per_chunk("encode_raw", r["bytes_raw"])
    t_default = per_chunk("encode_zarr_default", r["bytes_zarr_default"])

    def row(label: str, key: str, nbytes: float = r["bytes_raw"]) -> str:
        return (f"| {label} | {_rng(r[key])} | "
                f"{_rng([nbytes / mb / x for x in r[key]], '{:.0f}')} |")

    lines = [
        "## What limits a Zarr store run (`benchmarks/store_breakdown.py`)",
        "",
        f"One chunk of {CHUNK:,} random (2,4,2) queries (the 20 M-query run's chunk: "
        f"{raw:.0f} MB of plans, {r['bytes_waypoints'] / mb:.0f} MB of them waypoints), one "
        f"core, {len(r['plan'])} rounds (ranges over rounds), on this shared machine. "
        "*Compress*: Zarr's write of the chunk's arrays into an in-memory store with the codec "
        "named (the encoding alone, no disk); *raw*: no codec (the copy every write makes). "
        "*Write*: the encoded bytes written to files and flushed with fsync.",
        "",
        "| stage | seconds per chunk | MB/s of plans |",
        "|---|---|---|",
        row("plan (`plan_batch`, certificate included)", "plan"),
        row(f"compress: the store's codec, zstd level {ZSTD_LEVEL} "
            f"({r['bytes_zstd'] / mb:.0f} MB)", "encode_zstd"),
        row(f"compress: Zarr's default codec, zstd level 3, as before this run "
            f"({r['bytes_zarr_default'] / mb:.0f} MB)", "encode_zarr_default"),
        row("no codec (raw)", "encode_raw"),
        row(f"write + fsync, compressed ({r['bytes_zstd'] / mb:.0f} MB)", "write_zstd"),
        row(f"write + fsync, raw ({raw:.0f} MB)", "write_raw"),
        "",
        f"The disk's sustained write rate here: {_rng(r['disk_mb_s'], '{:.0f}')} MB/s "
        "(64 MB blocks, fsync). Compression ratio of the chunk: "
        f"{r['bytes_raw'] / r['bytes_zstd']:.2f} at level {ZSTD_LEVEL}, "
        f"{r['bytes_raw'] / r['bytes_zarr_default']:.2f} at level 3.",
        "",
        "**What limits it.** A process runs the stages one after the other (`plan_store`: plan, "
        "then write, which encodes). With the best round of each stage: compressed at level "
        f"{ZSTD_LEVEL}, {t_zstd:.2f} s per chunk, {CHUNK / t_zstd:,.0f} queries/s, compression "
        f"{best['encode_zstd'] / t_zstd:.0%} of it; at Zarr's default level 3, {t_default:.2f} s, "
        f"{CHUNK / t_default:,.0f} queries/s, compression "
        f"{best['encode_zarr_default'] / t_default:.0%}; with `--no-compress`, {t_raw:.2f} s, "
        f"{CHUNK / t_raw:,.0f} queries/s, planning {best['plan'] / t_raw:.0%} and the disk "
        f"{r['bytes_raw'] / mb / disk / t_raw:.0%}. So a compressed run is bound by compression "
        "(more worker processes help, until the disk is the limit) and an uncompressed one by "
        "the disk.",
        "",
    ]
    old = r.get("scale20m")
    if old:
        chunks = -(-20_000_000 // CHUNK)
        spent = 20_000_000 / old["zstd"] / chunks
        rest = best["plan"] + r["bytes_zarr_default"] / mb / disk
        lines += [
            f"**The 20 M-query run** (`scale_bench.py`, {old['date']}, zstd level 3, one "
            f"process): {old['zstd']:,.0f} queries/s, {spent:.2f} s per chunk, "
            f"{spent / t_default:.1f} times this run's {t_default:.2f} s. Its uncompressed run "
            f"wrote {old['raw']:,.0f} queries/s, {old['raw'] * r['bytes_raw'] / CHUNK / mb:.0f} MB/s "
            "of plans: the disk held that rate, while the compressed run needed only "
            f"{old['zstd'] * r['bytes_zarr_default'] / CHUNK / mb:.0f} MB/s of it, so its disk "
            "was not the limit. If its plan and write took what they take here, its compression "
            f"ran at {raw / max(spent - rest, 1e-9):.0f} MB/s of plans (here "
            f"{_rng([raw / x for x in r['encode_zarr_default']], '{:.0f}')}): the 20 M run was "
            "compression-bound, on a machine shared with other jobs.",
            "",
        ]
    rows = []
    for label, key in ((f"compressed (zstd level {ZSTD_LEVEL})", "stream_zstd"),
                       ("`--no-compress`", "stream_raw")):
        if r.get(key):
            rows.append(f"| {label}, {r['stream_b']:,} queries, this run | "
                        f"{_rng(r[key], '{:,.0f}')} |")
    if old:
        rows += [f"| compressed (zstd level 3), 20,000,000 queries, {old['date']} | "
                 f"{old['zstd']:,.0f} |",
                 f"| `--no-compress`, 20,000,000 queries, {old['date']} | {old['raw']:,.0f} |"]
    if rows:
        lines += ["Measured streams (one process, `pmplan batch IN.zarr --out OUT.zarr`, process "
                  "start and the input's fingerprints included):", "", "| run | queries/s |",
                  "|---|---|", *rows, ""]
    lines.append(f"Run: {r['date']}.")
    return "\n".join(lines) + "\n"


def _scale20m() -> dict | None:
    """The in-process rows of the 20 M-query runs of ``scale_bench.py`` (compressed:
    ``scale_results.json``, uncompressed: ``scale_results_raw.json``)."""
    got = {}
    for key, name in (("zstd", "scale_results.json"), ("raw", "scale_results_raw.json")):
        path = HERE / name
        if not path.exists():
            return None
        run = json.loads(path.read_text())
        for row in run.get("rows", []):
            if row.get("what", "").startswith("streaming in one process"):
                got[key] = row["qps"]
        got.setdefault("date", run.get("date", ""))
    return got if {"raw", "zstd"} <= set(got) else None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--stream", type=int, default=1_048_576, help="queries streamed (0: none)")
    ap.add_argument("--streams", type=int, default=2, help="rounds of each stream")
    ap.add_argument("--disk-mb", type=int, default=2048)
    ap.add_argument("--dir", default=None, help="where to write (default: a temporary folder "
                    "beside the repository)")
    args = ap.parse_args()
    where = Path(tempfile.mkdtemp(dir=args.dir or ROOT.parent, prefix="pmplan-store-bench-"))
    try:
        r = measure_chunk(args.rounds, where, args.disk_mb)
        r["stream_b"] = args.stream
        if args.stream:
            r["stream_zstd"], r["stream_raw"] = [], []
            for _ in range(args.streams):  # interleaved
                r["stream_zstd"].append(_stream(args.stream, where, True))
                r["stream_raw"].append(_stream(args.stream, where, False))
    finally:
        shutil.rmtree(where, ignore_errors=True)
    r["scale20m"] = _scale20m()
    r["date"] = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    (HERE / "store_breakdown.json").write_text(json.dumps(r, indent=1))
    (HERE / "store_breakdown.md").write_text(render(r))
    sys.path.insert(0, str(HERE))
    from _common import write_reports

    write_reports()
    print(render(r))


if __name__ == "__main__":
    main()
