"""The obstacle-line kernels' certificate against n and d (issue 17 items 1 and 3).

Run from the repository root (``PYTHONPATH=$PWD/src`` in a worktree)::

    python benchmarks/cert_bench.py                  # every case, 3 rounds, writes the report
    python benchmarks/cert_bench.py --cases 2,16,2 3,4,2 --rounds 1 --no-write
    PYTHONPATH=OLD/src python benchmarks/cert_bench.py --no-write --save before.json --large 1000
    python benchmarks/cert_bench.py --before before.json   # an older tree's figures beside

For every (d, n, m): B generic queries (standard normal coordinates), one core. In each of
``--rounds`` rounds, ``plan_batch(out=...)`` into the arrays of an earlier batch and one
``np.copyto`` of the output waypoints alternate ``--reps`` times in this process; the round's
ratio is best(plan_batch) / best(copy). The table gives the range of the ratios over the rounds
and the best time per query. Also the single-query ``pmplan.plan`` for large n (best of a few
calls, after one call that compiles) and ``pmplan.certify.clearance`` (the numpy reference) on
the path of one large query. Results: ``benchmarks/cert_results.json`` and the section
``cert_results.md`` that ``benchmarks/RESULTS.md`` includes (``_common.write_reports``); the
section of an existing RESULTS.md is replaced in place, the other sections are kept.

Not a test: pytest never collects this folder (``benchmarks/conftest.py``).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import re
import sys
import time
from pathlib import Path

import numpy as np

import pmplan
from pmplan.certify import clearance as reference_clearance

HERE = Path(__file__).resolve().parent
CASES = [(2, 4, 2), (2, 16, 2), (2, 64, 2), (2, 256, 2), (3, 4, 2), (4, 4, 2), (3, 64, 2),
         (4, 30, 2), (7, 24, 2)]
#: about this many bytes of output waypoints per batch (B = min(100,000, this / query))
OUTPUT_BYTES = 160e6
LARGE_N = (1000, 5000)
SEED = 17


def _batch(d: int, n: int, m: int) -> int:
    per = 8 * (m + n) * d * 8
    return int(min(100_000, max(2_000, OUTPUT_BYTES // per)))


def ratio_case(d: int, n: int, m: int, rounds: int, reps: int) -> dict:
    """The ratio plan_batch(out=...) / np.copyto per round, and the best time per query."""
    rng = np.random.default_rng(SEED)
    b = _batch(d, n, m)
    o = rng.standard_normal((b, m, d))
    s = rng.standard_normal((b, n, d))
    g = rng.standard_normal((b, n, d))
    res = pmplan.plan_batch(o, s, g)  # compiles, and the arrays to plan into
    src = res.waypoints
    dst = np.empty_like(src)
    np.copyto(dst, src)
    ratios, per_query = [], []
    for _ in range(rounds):
        tp, tc = [], []
        for _ in range(reps):
            t0 = time.perf_counter()
            pmplan.plan_batch(o, s, g, out=res)
            tp.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            np.copyto(dst, src)
            tc.append(time.perf_counter() - t0)
        ratios.append(min(tp) / min(tc))
        per_query.append(min(tp) / b)
    return {"case": [d, n, m], "B": b, "ratios": ratios, "us_per_query": 1e6 * min(per_query)}


def single_large(n: int, reps: int) -> dict:
    """``pmplan.plan`` on one generic (2, n, 2) query: best seconds, and the numpy reference
    certify.clearance on its path."""
    rng = np.random.default_rng(SEED + n)
    o = rng.standard_normal((2, 2))
    s = rng.standard_normal((n, 2))
    g = rng.standard_normal((n, 2))
    t0 = time.perf_counter()
    plan = pmplan.plan(o, s, g)
    first = time.perf_counter() - t0
    ts = []
    for _ in range(reps):
        t0 = time.perf_counter()
        pmplan.plan(o, s, g)
        ts.append(time.perf_counter() - t0)
    t0 = time.perf_counter()
    ref = reference_clearance(plan.waypoints[None], 2)[0]
    tref = time.perf_counter() - t0
    return {"n": n, "first_s": first, "best_s": min(ts), "reference_clearance_s": tref,
            "equal": bool(ref == plan.clearance)}


def _markdown(out: dict) -> str:
    rows = [
        "## Certificate (`benchmarks/cert_bench.py`)",
        "",
        (f"Generic queries, one core, {out['rounds']} rounds of {out['reps']} alternations "
         "of `plan_batch(out=...)` and one `np.copyto` of its output in one process; ratio = "
         "best plan_batch / best copy per round (range over the rounds). "
         f"Run {out['date']}, commit {out['commit']}."),
        "",
        "| (d,n,m) | B | ratio, one core | us per query | before: ratio | before: us |",
        "|---|---|---|---|---|---|",
    ]
    before = {tuple(r["case"]): r for r in out.get("before", {}).get("cases", [])}
    for r in out["cases"]:
        lo, hi = min(r["ratios"]), max(r["ratios"])
        old = before.get(tuple(r["case"]))
        was = (f"{min(old['ratios']):.2f}-{max(old['ratios']):.2f} | {old['us_per_query']:.3g}"
               if old else "n/a | n/a")
        rows.append(f"| ({','.join(map(str, r['case']))}) | {r['B']:,} | {lo:.2f}-{hi:.2f} | "
                    f"{r['us_per_query']:.3g} | {was} |")
    rows += ["", ("| single query (2,n,2) | first call s | best s | certify.clearance (numpy) s"
                  " | equal |"), "|---|---|---|---|---|"]
    for tag, singles in (("", out["single"]), ("before: ", out.get("before", {}).get("single",
                                                                                   []))):
        for r in singles:
            rows.append(f"| {tag}n = {r['n']} | {r['first_s']:.3g} | {r['best_s']:.3g} | "
                        f"{r['reference_clearance_s']:.3g} | {r['equal']} |")
    rows += ["", ("First call: the compiled kernels come from numba's disk cache; what is left is "
                  "building the index tables of that shape (none from `SWEEP_MIN` points on, "
                  "where the certificate is the pruned sweep).")]
    if out.get("before"):
        rows += ["", (f"before: commit {out['before']['commit'] or '(unknown)'}, "
                      f"run {out['before']['date']} in another process just before.")]
    return "\n".join(rows) + "\n"


def _commit() -> str:
    import subprocess

    return subprocess.run(["git", "-C", str(HERE), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True, check=False).stdout.strip()


def write(out: dict) -> None:
    """Save the JSON and the section; replace the section in an existing RESULTS.md."""
    (HERE / "cert_results.json").write_text(json.dumps(out, indent=1))
    md = _markdown(out)
    (HERE / "cert_results.md").write_text(md)
    results = HERE / "RESULTS.md"
    text = results.read_text() if results.exists() else ""
    pattern = re.compile(r"^## Certificate \(`benchmarks/cert_bench.py`\).*?(?=^## |\Z)",
                         re.DOTALL | re.MULTILINE)
    if pattern.search(text):
        text = pattern.sub(lambda _: md + "\n", text)
    else:
        text = text.rstrip("\n") + "\n\n" + md
    results.write_text(text)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="*", help="d,n,m triples (default: every case)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--reps", type=int, default=7)
    ap.add_argument("--large", type=int, nargs="*", default=list(LARGE_N))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--save", help="also write this run's JSON here")
    ap.add_argument("--before", help="the JSON of an earlier run (--save), shown beside")
    a = ap.parse_args(argv)
    cases = [tuple(int(x) for x in c.split(",")) for c in a.cases] if a.cases else CASES
    out = {"date": dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
           "commit": _commit(), "rounds": a.rounds, "reps": a.reps, "cases": [], "single": []}
    for d, n, m in cases:
        r = ratio_case(d, n, m, a.rounds, a.reps)
        print(f"({d},{n},{m}) B={r['B']}: ratio {min(r['ratios']):.2f}-{max(r['ratios']):.2f}, "
              f"{r['us_per_query']:.3g} us/query", flush=True)
        out["cases"].append(r)
    for n in a.large:
        r = single_large(n, 3)
        print(f"plan (2,{n},2): first {r['first_s']:.3g} s, best {r['best_s']:.3g} s, "
              f"certify.clearance {r['reference_clearance_s']:.3g} s, equal {r['equal']}",
              flush=True)
        out["single"].append(r)
    if a.before:
        out["before"] = json.loads(Path(a.before).read_text())
    if a.save:
        Path(a.save).write_text(json.dumps(out, indent=1))
    if not a.no_write:
        write(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
