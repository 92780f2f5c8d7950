"""Clauses 1-9 of the certificate (:mod:`pmplan.certify`) in one compiled pass, for the API.

The fused kernels (:mod:`pmplan._kernels`, :mod:`pmplan._kernels_planar`) compute the clearance
(clause 10) themselves; :func:`pmplan.api._run_fused` and the single-query fast paths then run
:func:`check_chunk` on what is about to be returned, so that no path reaches the caller without
every clause of the certificate -- whatever the kernel wrote. It reads the outputs once
(finite times from 0 to 1 that never decrease; finite waypoints; the start, the goal and every
intermediate configuration reproduced exactly; obstacles fixed) and writes the number of the
first clause that fails, as :func:`pmplan.certify.check_paths` (the reference, used when numba
is missing) numbers them.
"""

from __future__ import annotations

import math

import numpy as np

from .certify import check_paths

try:
    from numba import njit

    AVAILABLE = True
except ImportError:  # pragma: no cover - numba is a dependency; keep the numpy path usable
    AVAILABLE = False

    def njit(*args, **kwargs):
        return lambda f: f

__all__ = ["check_chunk", "check", "check_one"]

_OPTS = {"cache": True, "nogil": True, "error_model": "numpy"}


@njit(**_OPTS)
def check_chunk(times, wp, obstacles, first, last, middle, via_rows, via_times,
                codes):  # pragma: no cover - compiled
    """Write into ``codes`` (B,) the first failing clause 1-9 of every path (0: all hold).

    ``times`` (1, K) (shared) or (B, K); ``wp`` (B, K, m+n, d); ``obstacles`` (B, m, d);
    ``first``, ``last`` (B, n, d); ``middle`` (r-2, B, n, d), passed exactly at breakpoint
    ``via_rows[k]`` whose time must be ``via_times[k]``. Returns the number of failing paths.
    """
    b, kk, p, d = wp.shape
    m = obstacles.shape[1]
    shared = times.shape[0] == 1
    bad = 0
    for q in range(b):
        tq = 0 if shared else q
        code = 0
        finite_t = True
        for t in range(kk):
            if not math.isfinite(times[tq, t]):
                finite_t = False
        if not finite_t:
            code = 1
        elif times[tq, 0] != 0.0:
            code = 2
        elif times[tq, kk - 1] != 1.0:
            code = 3
        else:
            for t in range(1, kk):
                if not times[tq, t] >= times[tq, t - 1]:
                    code = 4
        if code == 0:
            for t in range(kk):
                for i in range(p):
                    for c in range(d):
                        if not math.isfinite(wp[q, t, i, c]):
                            code = 5
        if code == 0:
            for i in range(p):
                for c in range(d):
                    want = obstacles[q, i, c] if i < m else first[q, i - m, c]
                    if wp[q, 0, i, c] != want:
                        code = 6
        if code == 0:
            for i in range(p):
                for c in range(d):
                    want = obstacles[q, i, c] if i < m else last[q, i - m, c]
                    if wp[q, kk - 1, i, c] != want:
                        code = 7
        if code == 0:
            for k in range(via_rows.shape[0]):
                row = via_rows[k]
                if times[tq, row] != via_times[k] or (row + 1 < kk
                                                      and not times[tq, row + 1] > via_times[k]):
                    code = 8
                for i in range(p):
                    for c in range(d):
                        want = obstacles[q, i, c] if i < m else middle[k, q, i - m, c]
                        if wp[q, row, i, c] != want:
                            code = 8
        if code == 0:
            for t in range(1, kk):
                for i in range(m):
                    for c in range(d):
                        if wp[q, t, i, c] != wp[q, 0, i, c]:
                            code = 9
        codes[q] = code
        if code:
            bad += 1
    return bad


def check(times, wp, obstacles, configs, via_rows=None) -> np.ndarray:
    """Clauses 1-9 for paths ``times`` (K,) or (B, K), ``wp`` (B, K, m+n, d) of the queries
    ``obstacles`` (B, m, d), ``configs`` (r arrays (B, n, d)); returns the codes (B,) uint8.

    ``via_rows`` (r-2 ints): the breakpoints at which the intermediate configurations are
    passed (at tau = k/(r-1)); required when r > 2.
    """
    b = wp.shape[0]
    r = len(configs)
    taus = np.arange(1, r - 1) / (r - 1) if r > 2 else np.empty(0)
    if not AVAILABLE or wp.dtype != np.float64:  # pragma: no cover - numba is a dependency
        start = np.concatenate([obstacles, configs[0]], axis=1)
        goal = np.concatenate([obstacles, configs[-1]], axis=1)
        via = [(tau, np.concatenate([obstacles, c], axis=1)) for tau, c in zip(taus, configs[1:-1])]
        return check_paths(times, wp, start, goal, obstacles.shape[1], via)
    codes = np.empty(b, np.uint8)
    t2 = times.reshape(1, -1) if times.ndim == 1 else times
    if r > 2:
        middle = np.stack(configs[1:-1])
        rows = np.asarray(via_rows, dtype=np.int64)
    else:
        middle = np.empty((0,) + configs[0].shape)
        rows = np.empty(0, np.int64)
    check_chunk(t2, wp, obstacles, configs[0], configs[-1], middle, rows, taus, codes)
    return codes


_NO_MIDDLE: dict = {}


def check_one(times, wp, obstacles, configs, planner) -> int:
    """Clauses 1-9 for one path ``times`` (K,), ``wp`` (K, m+n, d) of the query ``obstacles``
    (m, d), ``configs`` (r arrays (n, d)) planned by ``planner``; returns the clause (0: hold).
    (For the single-query fast paths: float64 C-contiguous arrays, as the kernels write them.)
    """
    r = len(configs)
    first, last = configs[0], configs[-1]
    if not AVAILABLE:  # pragma: no cover - numba is a dependency
        return int(check(times, wp[None], obstacles[None], [c[None] for c in configs],
                         getattr(planner, "via_rows", lambda r: [])(r))[0])
    if r == 2:
        key = first.shape
        middle = _NO_MIDDLE.get(key)
        if middle is None:
            middle = _NO_MIDDLE[key] = np.empty((0, 1) + key)
        rows = _NO_ROWS
        taus = _NO_TAUS
    else:
        middle = np.stack(configs[1:-1])[:, None]
        rows = np.asarray(planner.via_rows(r), dtype=np.int64)
        taus = np.arange(1, r - 1) / (r - 1)
    codes = np.empty(1, np.uint8)
    check_chunk(times.reshape(1, -1), wp.reshape((1,) + wp.shape), obstacles.reshape(
        (1,) + obstacles.shape), first.reshape((1,) + first.shape), last.reshape(
        (1,) + last.shape), middle, rows, taus, codes)
    return int(codes[0])


_NO_ROWS = np.empty(0, np.int64)
_NO_TAUS = np.empty(0)
