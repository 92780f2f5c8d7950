"""Robustness of the ``pmplan explore`` server under load (issue 15, item 6).

Starts ``pmplan explore --no-browser --port 0`` as a separate process on 127.0.0.1 and then

1. **load**: 8 concurrent clients (threads, one keep-alive connection each) for 30 s send a mix
   of ``POST /api/plan`` (75 %: the page's examples with a random point moved on the 1/4 grid,
   and 5 % made invalid on purpose, answered 422) and ``POST /api/domain-map`` (25 %: the
   page's grid, about 200 x 150 pixels). Reported: requests/s, p50/p99 latency per kind, the
   status codes (zero 5xx required);
2. **malformed**: 500 requests cycling through bad JSON, wrong types, huge numbers, NaN and
   infinities, deep nesting, oversized bodies (drained and refused, or refused on the declared
   length alone), bad grids and wrong methods: every answer must be a 4xx, and the server must
   answer a valid request afterwards.

Only loopback traffic; every loop is bounded in count and time. Results are printed and written
into ``benchmarks/RESULTS.md`` (section "pmplan explore under load", replaced when present).
Run: ``python benchmarks/explore_load.py [--seconds 30] [--clients 8]``.
"""

from __future__ import annotations

import argparse
import http.client
import json
import os
import platform
import random
import re
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SECTION = "## pmplan explore under load"


def start_server():
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    proc = subprocess.Popen([sys.executable, "-m", "pmplan", "explore", "--no-browser", "--port",
                             "0"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env)
    line = proc.stdout.readline()
    m = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
    if not m:
        proc.kill()
        raise SystemExit(f"the server did not start: {line!r} {proc.stderr.read()}")
    return proc, int(m.group(1))


def post(conn, path, body: bytes, method="POST"):
    t = time.perf_counter()
    conn.request(method, path, body=body, headers={"Content-Type": "application/json"})
    r = conn.getresponse()
    r.read()
    return r.status, time.perf_counter() - t


def examples(port):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    conn.request("GET", "/api/examples")
    out = json.loads(conn.getresponse().read())
    conn.close()
    return [e["query"] for e in out]


def load(port, seconds, clients, queries):
    stop = time.monotonic() + seconds
    results = []  # (kind, status, latency)
    lock = threading.Lock()

    def client(seed):
        rng = random.Random(seed)
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
        mine = []
        n = 0
        while time.monotonic() < stop and n < 1_000_000:
            n += 1
            q = json.loads(json.dumps(rng.choice(queries)))
            key = rng.choice(["start", "goal", "obstacles"])
            k = rng.randrange(len(q[key]))
            q[key][k] = [round(rng.uniform(-3, 8) * 4) / 4, round(rng.uniform(-4, 4) * 4) / 4]
            if rng.random() < 0.05:  # an invalid query on purpose: a goal on an obstacle
                q["goal"][0] = q["obstacles"][0]
            if rng.random() < 0.25:
                body = {"query": q, "which": rng.choice(["goal", "start"]), "robot": 1,
                        "origin": [-3.0, -4.0], "step": 0.0625, "size": [200, 150]}
                kind, path = "domain-map", "/api/domain-map"
            else:
                body, kind, path = q, "plan", "/api/plan"
            try:
                status, dt = post(conn, path, json.dumps(body).encode())
            except (OSError, http.client.HTTPException) as exc:
                status, dt = f"connection error: {exc}", 0.0
                conn.close()
                conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
            mine.append((kind, status, dt))
        conn.close()
        with lock:
            results.extend(mine)

    threads = [threading.Thread(target=client, args=(s,)) for s in range(clients)]
    t0 = time.perf_counter()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return results, time.perf_counter() - t0


def malformed_bodies():
    """(name, path, body bytes or None, method, declared length or None) of the bad requests."""
    q = {"obstacles": [[0, 0], [4, 0]], "start": [[1, 1]], "goal": [[3, -1]]}
    grid = {"query": q, "which": "goal", "origin": [0, 0], "step": 0.25, "size": [10, 10]}

    def j(obj):
        return json.dumps(obj).encode()

    cases = [
        ("bad JSON", "/api/plan", b"{obstacles: [[0,0]]", "POST", None),
        ("bad JSON", "/api/plan", b"", "POST", None),
        ("bad JSON", "/api/plan", b"\xff\xfe\xfa", "POST", None),
        ("bad JSON", "/api/domain-map", b'{"query": ', "POST", None),
        ("wrong types", "/api/plan", j({**q, "start": "1,1"}), "POST", None),
        ("wrong types", "/api/plan", j({**q, "start": [["1", 1]]}), "POST", None),
        ("wrong types", "/api/plan", j({**q, "start": [[True, 1]]}), "POST", None),
        ("wrong types", "/api/plan", j({**q, "start": [[None, 1]]}), "POST", None),
        ("wrong types", "/api/plan", j({**q, "lift": "big"}), "POST", None),
        ("wrong types", "/api/plan", j({**q, "planner": 3}), "POST", None),
        ("wrong types", "/api/plan", j([q]), "POST", None),
        ("wrong types", "/api/plan", j({**q, "start": [[1, 1, 1]]}), "POST", None),
        ("wrong types", "/api/plan", j({**q, "start": [[1], [1, 2]]}), "POST", None),
        ("wrong types", "/api/domain-map", j({**grid, "size": "big"}), "POST", None),
        ("wrong types", "/api/domain-map", j({**grid, "robot": "1"}), "POST", None),
        ("huge numbers", "/api/plan", j({**q, "start": [[10**400, 1]]}), "POST", None),
        ("huge numbers", "/api/plan", b'{"obstacles": [[0,0],[4,0]], "start": [[1e999, 1]], '
         b'"goal": [[3, -1]]}', "POST", None),
        ("huge numbers", "/api/plan", j({**q, "start": [[2**53 + 1, 1]]}), "POST", None),
        ("huge numbers", "/api/plan", b'{"obstacles": [[0,0],[4,0]], "start": [[1' + b"0" * 6000
         + b', 1]], "goal": [[3, -1]]}', "POST", None),
        ("huge numbers", "/api/plan?samples=100000000", j(q), "POST", None),
        ("huge numbers", "/api/domain-map", j({**grid, "size": [100000, 10]}), "POST", None),
        ("huge numbers", "/api/domain-map", j({**grid, "step": 1e200, "origin": [1e300, 0]}),
         "POST", None),
        ("NaN", "/api/plan", b'{"obstacles": [[0,0],[4,0]], "start": [[NaN, 1]], '
         b'"goal": [[3, -1]]}', "POST", None),
        ("NaN", "/api/plan", b'{"obstacles": [[0,0],[4,0]], "start": [[Infinity, 1]], '
         b'"goal": [[3, -1]]}', "POST", None),
        ("NaN", "/api/plan", b'{"obstacles": [[0,0],[4,0]], "start": [[1, 1]], '
         b'"goal": [[3, -1]], "lift": NaN}', "POST", None),
        ("NaN", "/api/domain-map", b'{"query": {"obstacles": [[0,0],[4,0]], "start": [[1, 1]], '
         b'"goal": [[3, -1]]}, "origin": [NaN, 0], "step": 0.25, "size": [4, 4]}', "POST", None),
        ("deep nesting", "/api/plan", b"[" * 50_000 + b"]" * 50_000, "POST", None),
        ("deep nesting", "/api/plan", b'{"a":' * 20_000 + b"1" + b"}" * 20_000, "POST", None),
        ("deep nesting", "/api/plan", j({**q, "start": [[[[[[1]]]]]]}), "POST", None),
        ("oversized body", "/api/plan", b'{"obstacles": [' + b"[0.5, 0.5]," * 120_000 + b"[0,0]]}",
         "POST", None),
        ("oversized body", "/api/domain-map", b" " * 2_000_000, "POST", None),
        ("oversized body", "/api/plan", None, "POST", 50_000_000),  # refused on its length
        ("too many points", "/api/plan", j({**q, "start": [[k, 1] for k in range(100)],
                                            "goal": [[k, -1] for k in range(100)]}), "POST",
         None),
        ("coincident points", "/api/plan", j({**q, "goal": [[4, 0]]}), "POST", None),
        ("wrong method", "/api/plan", None, "GET", None),
        ("wrong method", "/api/domain-map", None, "PUT", None),
        ("no such page", "/api/../../etc/passwd", None, "GET", None),
    ]
    return cases


def send_declared(port, path, length):
    """A request that declares ``length`` bytes and sends none: the answer, then close."""
    with socket.create_connection(("127.0.0.1", port), timeout=60) as s:
        s.sendall(f"POST {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json"
                  f"\r\nContent-Length: {length}\r\n\r\n".encode())
        data = s.recv(65536)
    return int(data.split(b" ", 2)[1])


def malformed(port, count):
    cases = malformed_bodies()
    statuses = []
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    for i in range(count):
        name, path, body, method, declared = cases[i % len(cases)]
        if declared is not None:
            status = send_declared(port, path, declared)
        else:
            try:
                status, _ = post(conn, path, body, method=method)
            except (OSError, http.client.HTTPException) as exc:
                status = f"connection error: {exc}"
                conn.close()
                conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
        statuses.append((name, status))
    conn.close()
    return statuses


def _statuses(counts: dict, fmt: str) -> str:
    return ", ".join(f"{k}: {fmt.format(v)}" for k, v in sorted(counts.items(), key=str))


def pct(values, q):
    return float(np.percentile(np.array(values) * 1000, q)) if values else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--clients", type=int, default=8)
    ap.add_argument("--malformed", type=int, default=500)
    ap.add_argument("--no-write", action="store_true", help="do not update RESULTS.md")
    args = ap.parse_args()

    proc, port = start_server()
    try:
        queries = examples(port)
        results, elapsed = load(port, args.seconds, args.clients, queries)
        bad = malformed(port, args.malformed)
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
        after, _ = post(conn, "/api/plan", json.dumps(queries[0]).encode())
        conn.close()
    finally:
        proc.terminate()
        try:
            _, err = proc.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
            _, err = proc.communicate()

    lines = [SECTION, "",
             f"`python benchmarks/explore_load.py` "
             f"({time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, "
             f"{platform.machine()}, {os.cpu_count()} cores shared by the server and its "
             f"clients; server: `pmplan explore` in its own process, uvicorn, loopback).", ""]
    lines += [f"**Load**: {args.clients} concurrent clients for {elapsed:.1f} s, mixed requests "
              "(75 % `POST /api/plan` on the page's examples with one point moved on the 1/4 "
              "grid, 5 % of them invalid on purpose; 25 % `POST /api/domain-map` of "
              "200 x 150 = 30,000 pixels).", "",
              "| kind | requests | requests/s | p50 ms | p99 ms | statuses |",
              "|---|---|---|---|---|---|"]
    fivexx = 0
    for kind in ("plan", "domain-map", "all"):
        rows = [r for r in results if kind == "all" or r[0] == kind]
        lat = [r[2] for r in rows if isinstance(r[1], int)]
        st = {}
        for r in rows:
            st[r[1]] = st.get(r[1], 0) + 1
        if kind == "all":
            fivexx = sum(v for k, v in st.items() if not isinstance(k, int) or k >= 500)
        lines.append(f"| {kind} | {len(rows):,} | {len(rows) / elapsed:,.1f} | {pct(lat, 50):.1f} "
                     f"| {pct(lat, 99):.1f} | {_statuses(st, '{:,}')} |")
    lines += ["", f"5xx or connection errors under load: **{fivexx}**.", ""]
    by = {}
    for name, status in bad:
        by.setdefault(name, {}).setdefault(status, 0)
        by[name][status] += 1
    all4xx = all(isinstance(s, int) and 400 <= s < 500 for _, s in bad)
    lines += [f"**Malformed**: {len(bad)} requests, cycling through {len(malformed_bodies())} "
              "kinds:", "", "| kind | statuses |", "|---|---|"]
    for name, st in by.items():
        lines.append(f"| {name} | {_statuses(st, '{}')} |")
    internal = err.count("internal error")
    lines += ["", f"All 4xx: **{'yes' if all4xx else 'NO'}**; a valid request afterwards: "
              f"**{after}**; internal errors in the server's log: **{internal}**.", ""]
    text = "\n".join(lines)
    print(text)
    if not args.no_write:
        path = ROOT / "benchmarks" / "RESULTS.md"
        old = path.read_text()
        if SECTION in old:
            head, rest = old.split(SECTION, 1)
            nxt = rest.find("\n## ")
            old = head + (rest[nxt + 1:] if nxt >= 0 else "")
        path.write_text(old.rstrip("\n") + "\n\n" + text)
        print(f"wrote {path}")
    ok = fivexx == 0 and all4xx and after == 200 and internal == 0
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
