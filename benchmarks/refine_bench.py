"""Refined motions (:func:`pmplan.refine`, issue 14): speed, length, radii and continuity.

Usage (from the repository root)::

    python benchmarks/refine_bench.py            # about 2-4 minutes
    python benchmarks/refine_bench.py --quick    # a handful of queries per row

Measures, on the OMPL scene of ``benchmarks/ompl_compare.py`` (obstacles (0.35, 0.5), (0.65,
0.5), r = 0.05, lift 0.1, refined with radius = obstacle_radius = r/2, so every robot-robot and
robot-obstacle distance must stay >= r):

* the latency of one refined query (2, 4, 2) -- ``pmplan.plan(..., refine=True)`` -- and the
  throughput of ``plan_batch(..., refine=True)`` on one core (``workers=1``): wall-clock
  (best of 3 rounds) and process CPU time (what the shared machine's other jobs do not
  inflate), goals 1 ms and 2,000 queries/s;
* per n = 1, 2, 4, 8 and family (generic, blocked; the generators of ompl_compare.py): the
  median length over the straight-line lower bound, raw and refined; the share of refined
  paths keeping >= r; the exact minimum distance; that every path is certified; the
  continuity probe (every start moved by 1e-6, both refined paths resampled at 201 equal
  arc-length parameters, the sup distance), over the pairs in the same domain;
* the trade-off behind the defaults: length ratio and time per query for several
  ``(waypoints, steps)``.

Writes ``benchmarks/refine_results.json`` and ``benchmarks/refine_results.md``, the section
"Refined motions" of ``benchmarks/RESULTS.md`` (replaced in place when present, else appended;
``_common.write_reports`` includes the .md file when it regenerates RESULTS.md). Not a test
module (``benchmarks/conftest.py``).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from ompl_compare import (
    LIFT,
    OBSTACLES,
    PROBE_DELTA,
    R,
    _clearance,
    _lower_bound,
    _sup_distance,
    blocked_query,
    generic_query,
)

import pmplan
from pmplan.certify import certificate
from pmplan.refine import DEFAULT_STEPS, DEFAULT_WAYPOINTS

HERE = Path(__file__).resolve().parent
TITLE = "## Refined motions (`pmplan.refine`)"
GOAL_LATENCY_MS = 1.0
GOAL_RATE = 2000.0
RADIUS = R / 2


def _queries(n: int, family: str, count: int, seed: int):
    rng = np.random.default_rng(seed)
    gen = generic_query if family == "generic" else blocked_query
    return [gen(rng, n) for _ in range(count)], rng


def _refined(start, goal, **kw):
    return pmplan.plan(OBSTACLES, start, goal, lift=LIFT, refine=True, radius=RADIUS,
                       obstacle_radius=RADIUS, **kw)


def _certified(p: pmplan.Plan, start, goal) -> bool:
    m = OBSTACLES.shape[0]
    full = [np.concatenate([OBSTACLES, c])[None] for c in (start, goal)]
    _, clause = certificate(p.path.waypoints[None], full[0], full[1], m, times=p.path.times)
    return bool(clause[0] == 0)


def speed(count: int, rounds: int = 3) -> dict:
    """Latency of one refined (2,4,2) query and one-core batch throughput (wall and CPU)."""
    qs, _ = _queries(4, "generic", count, 101)
    o = np.broadcast_to(OBSTACLES, (count,) + OBSTACLES.shape).copy()
    s = np.stack([q[0] for q in qs])
    g = np.stack([q[1] for q in qs])
    _refined(qs[0][0], qs[0][1])  # compile / load the kernels
    lat_wall, lat_cpu, raw_wall = [], [], []
    for _ in range(rounds):
        w, c, rw = [], [], []
        for st, go in qs:
            t0, c0 = time.perf_counter(), time.process_time()
            _refined(st, go)
            w.append(time.perf_counter() - t0)
            c.append(time.process_time() - c0)
            t0 = time.perf_counter()
            pmplan.plan(OBSTACLES, st, go, lift=LIFT)
            rw.append(time.perf_counter() - t0)
        lat_wall.append(float(np.median(w)))
        lat_cpu.append(float(np.median(c)))
        raw_wall.append(float(np.median(rw)))
    rate_wall, rate_cpu, ref_wall = [], [], []
    for _ in range(rounds):
        t0, c0 = time.perf_counter(), time.process_time()
        pmplan.plan_batch(o, s, g, lift=LIFT, refine=True, radius=RADIUS,
                          obstacle_radius=RADIUS, workers=1)
        rate_wall.append(count / (time.perf_counter() - t0))
        rate_cpu.append(count / (time.process_time() - c0))
        raw = pmplan.plan_batch(o, s, g, lift=LIFT)
        t0 = time.perf_counter()
        pmplan.refine(raw, radius=RADIUS, obstacle_radius=RADIUS)
        ref_wall.append(count / (time.perf_counter() - t0))
    return {
        "count": count,
        "latency_ms_wall": [x * 1e3 for x in lat_wall],
        "latency_ms_cpu": [x * 1e3 for x in lat_cpu],
        "unrefined_latency_ms_wall": [x * 1e3 for x in raw_wall],
        "rate_wall": rate_wall,
        "rate_cpu": rate_cpu,
        "refine_only_rate_wall": ref_wall,
    }


def quality(count: int, count8: int, ns=(1, 2, 4, 8)) -> list[dict]:
    """Length ratios, radii, certificate and continuity probe per (n, family); ``count8``
    queries per row for n = 8, where the probe's tail lives (raw plans with near-contacts)."""
    rows = []
    for n in ns:
        for family in ("generic", "blocked"):
            qs, rng = _queries(n, family, count8 if n == 8 else count, 1000 * n + len(family))
            raw_r, ref_r, clear, keep, cert, probes = [], [], [], 0, 0, []
            same = 0
            t0 = time.perf_counter()
            for st, go in qs:
                lb = _lower_bound(st, go)
                raw = pmplan.plan(OBSTACLES, st, go, lift=LIFT)
                ref = _refined(st, go)
                raw_r.append(raw.path.length() / lb)
                ref_r.append(ref.path.length() / lb)
                c = _clearance(ref.path.waypoints)
                clear.append(c)
                keep += c >= R
                cert += _certified(ref, st, go)
                moved = st + PROBE_DELTA * rng.normal(size=st.shape)
                ref2 = _refined(moved, go)
                if ref2.domain == ref.domain:
                    same += 1
                    probes.append(_sup_distance(ref.path, ref2.path))
            rows.append({
                "n": n, "family": family, "count": len(qs),
                "raw_length_ratio": float(np.median(raw_r)),
                "length_ratio": float(np.median(ref_r)),
                "keep_r": int(keep), "certified": int(cert),
                "clearance_min": float(min(clear)), "clearance_median": float(np.median(clear)),
                "probe_pairs": same,
                "probe_median": float(np.median(probes)) if probes else float("nan"),
                "probe_max": float(max(probes)) if probes else float("nan"),
                "probe_over_1e-4": int(sum(p > 1e-4 for p in probes)),
                "seconds": time.perf_counter() - t0,
            })
            print(f"  n={n} {family:8s} raw {rows[-1]['raw_length_ratio']:.3f} refined "
                  f"{rows[-1]['length_ratio']:.3f} keep>=r {keep}/{len(qs)} probe med "
                  f"{rows[-1]['probe_median']:.2e} max {rows[-1]['probe_max']:.2e}", flush=True)
    return rows


def tradeoff(count: int) -> list[dict]:
    """Median length ratio and time per query of (waypoints, steps) on n = 4 (both families)."""
    qs = _queries(4, "generic", count, 7)[0] + _queries(4, "blocked", count, 8)[0]
    raws = [(pmplan.plan(OBSTACLES, s, g, lift=LIFT), _lower_bound(s, g)) for s, g in qs]
    out = []
    for wp in (1, 2, 4):
        for steps in (16, 32, 48, 56, 96):
            ratios, times = [], []
            for raw, lb in raws:
                c0 = time.process_time()
                ref = pmplan.refine(raw, radius=RADIUS, obstacle_radius=RADIUS, waypoints=wp,
                                    steps=steps)
                times.append(time.process_time() - c0)
                ratios.append(ref.path.length() / lb)
            out.append({"waypoints": wp, "steps": steps,
                        "length_ratio": float(np.median(ratios)),
                        "ms_cpu": float(np.median(times)) * 1e3})
    return out


def _fmt_range(v: list[float], digits: int = 3) -> str:
    return f"{min(v):.{digits}g} - {max(v):.{digits}g}"


def report(res: dict) -> str:
    sp = res["speed"]
    best_lat = min(sp["latency_ms_cpu"])
    best_rate = max(sp["rate_cpu"])
    lines = [
        TITLE,
        "",
        (f"Generated by `python benchmarks/refine_bench.py` on {res['date']}"
         f"{' (quick)' if res['quick'] else ''}. OMPL scene of `ompl_compare.py`, lift "
         f"{LIFT}, radius = obstacle_radius = r/2 = {RADIUS:g} (every distance must stay >= "
         f"r = {R:g}), defaults `waypoints={DEFAULT_WAYPOINTS}`, `steps={DEFAULT_STEPS}` (see "
         "`pmplan.refine`)."),
        "",
        "### Speed, (2,4,2), one core",
        "",
        "| measure | wall clock (3 rounds) | CPU time of the process (3 rounds) | goal |",
        "|---|---|---|---|",
        (f"| `plan(..., refine=True)` median latency, ms | {_fmt_range(sp['latency_ms_wall'])} "
         f"| {_fmt_range(sp['latency_ms_cpu'])} | <= {GOAL_LATENCY_MS:g} |"),
        (f"| `plan_batch(..., refine=True)`, queries/s ({sp['count']} queries) "
         f"| {_fmt_range(sp['rate_wall'], 4)} | {_fmt_range(sp['rate_cpu'], 4)} "
         f"| >= {GOAL_RATE:,.0f} |"),
        (f"| `refine(batch)` alone, queries/s | {_fmt_range(sp['refine_only_rate_wall'], 4)} "
         "| | |"),
        (f"| unrefined `plan` median latency, ms | {_fmt_range(sp['unrefined_latency_ms_wall'])}"
         " | | |"),
        "",
        (f"Best round: latency {best_lat:.3f} ms CPU "
         f"({'meets' if best_lat <= GOAL_LATENCY_MS else 'misses'} the goal), "
         f"{best_rate:,.0f} queries/s CPU "
         f"({'meets' if best_rate >= GOAL_RATE else 'misses'} the goal). The machine is shared "
         "by several jobs on 2 cores: the wall-clock figures include their load, the CPU "
         "times do not."),
        "",
        "### Length, radii, certificate, continuity (per n and family)",
        "",
        ("| n | family | queries | raw length / LB | refined length / LB | keep >= r | "
         "min distance | certified | probe pairs | probe median | probe max | probes > 1e-4 |"),
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in res["quality"]:
        lines.append(
            f"| {r['n']} | {r['family']} | {r['count']} | {r['raw_length_ratio']:.3f} | "
            f"{r['length_ratio']:.3f} | {r['keep_r']}/{r['count']} | {r['clearance_min']:.4f} | "
            f"{r['certified']}/{r['count']} | {r['probe_pairs']} | {r['probe_median']:.2e} | "
            f"{r['probe_max']:.2e} | {r['probe_over_1e-4']} |")
    q = res["quality"]
    med = float(np.median([r["length_ratio"] for r in q]))
    keep = sum(r["keep_r"] for r in q)
    tot = sum(r["count"] for r in q)
    lines += [
        "",
        (f"Median over rows of the refined median length / lower bound: {med:.3f} (the raw "
         f"plans: {float(np.median([r['raw_length_ratio'] for r in q])):.3f}). Paths keeping "
         f">= r: {keep}/{tot} ({100 * keep / tot:.1f} %). Probe (sup distance after a 1e-6 move "
         "of the starts, resampled at 201 arc-length parameters, pairs in the same domain): "
         f"median of row medians {float(np.nanmedian([r['probe_median'] for r in q])):.2e}, "
         f"max {float(np.nanmax([r['probe_max'] for r in q])):.2e}."),
        "",
        "### The defaults: length / LB and CPU time per query, n = 4 (both families)",
        "",
        "| waypoints | steps | median length / LB | median ms (CPU) |",
        "|---|---|---|---|",
    ]
    for t in res["tradeoff"]:
        lines.append(f"| {t['waypoints']} | {t['steps']} | {t['length_ratio']:.3f} | "
                     f"{t['ms_cpu']:.3f} |")
    lines.append("")
    return "\n".join(lines)


def replace_section(path: Path, title: str, body: str) -> None:
    """Replace the section ``title`` (up to the next ``## `` heading) of ``path``, or append
    it; the other sections are left as they are."""
    text = path.read_text() if path.exists() else ""
    lines = text.splitlines()
    start = next((i for i, ln in enumerate(lines) if ln.strip() == title), None)
    if start is None:
        new = lines + ([""] if lines and lines[-1] else []) + body.splitlines()
    else:
        end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("## ")),
                   len(lines))
        part = body.splitlines()
        gap = [""] if end < len(lines) and part and part[-1] else []  # (before the next one)
        new = lines[:start] + part + gap + lines[end:]
    path.write_text("\n".join(new) + "\n")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    count = 8 if args.quick else 40
    t0 = time.perf_counter()
    print("speed ...", flush=True)
    sp = speed(100 if args.quick else 2000)
    print(f"  latency ms (CPU) {sp['latency_ms_cpu']}, rate q/s (CPU) {sp['rate_cpu']}")
    print("quality ...", flush=True)
    qual = quality(count, 8 if args.quick else 200)
    print("trade-off ...", flush=True)
    trade = tradeoff(4 if args.quick else 12)
    res = {"date": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
           "quick": args.quick, "speed": sp, "quality": qual, "tradeoff": trade,
           "total_s": time.perf_counter() - t0}
    (HERE / "refine_results.json").write_text(json.dumps(res, indent=1, default=float))
    body = report(res)
    (HERE / "refine_results.md").write_text(body)
    replace_section(HERE / "RESULTS.md", TITLE, body)
    print(body)
    return 0


if __name__ == "__main__":
    sys.exit(main())
