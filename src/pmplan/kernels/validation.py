"""Validation kernels: finite coordinates and distinct points, one pass over a batch.

:func:`valid_queries` and :func:`first_coincident` are the fast paths of
:func:`pmplan.configuration.check_query` (the numpy code there is the reference and names the
offending query); they decide with ``==`` on the floats, exactly as that reference does.
"""

from __future__ import annotations

import numpy as np

from .common import (
    INLINE,
    MAXF,
    OPTS,
    AVAILABLE,
    njit,
)

__all__ = ["AVAILABLE", "first_coincident", "valid_queries"]


@njit(**OPTS)
def first_coincident(obstacles, robots):  # pragma: no cover - compiled
    """Return the first query b whose configuration ``obstacles[b] u robots[b]`` has two equal
    points (compared with ``==``), or -1; shapes (B, m, d) and (B, n, d), C-contiguous."""
    nb, m, d = obstacles.shape
    n = robots.shape[1]
    p = m + n
    for b in range(nb):
        for i in range(p):
            for j in range(i + 1, p):
                same = True
                for c in range(d):
                    a = obstacles[b, i, c] if i < m else robots[b, i - m, c]
                    z = obstacles[b, j, c] if j < m else robots[b, j - m, c]
                    if a != z:
                        same = False
                        break
                if same:
                    return b
    return -1


@njit(**INLINE)
def _coincide(x, b, i, y, j, d):  # pragma: no cover - compiled
    """Point i of ``x[b]`` equals point j of ``y[b]`` (flat rows of d coordinates)."""
    eq = True
    for c in range(d):
        eq &= x[b, i * d + c] == y[b, j * d + c]
    return eq


@njit(**OPTS)
def valid_queries(obstacles, start, goal):  # pragma: no cover - compiled
    """True when every coordinate is finite and no two points of ``obstacles[b] u start[b]``
    or of ``obstacles[b] u goal[b]`` are equal (``==``), for every query b.

    Shapes (B, m, d), (B, n, d), (B, n, d), C-contiguous. One pass, no temporary: the fast
    path of :func:`pmplan.configuration.check_query`, which runs its reference checks (and
    raises their errors) when this returns False. Equal points have equal keys
    ``sum_c x_c w_c`` (the same float operations), so a configuration whose keys are pairwise
    different has no coincident points; only where two keys are equal are the points compared.
    """
    nb, m, d = obstacles.shape
    n = start.shape[1]
    p = m + n
    wk = np.empty(d)
    for c in range(d):
        wk[c] = 1.0 / (1.0 + 0.7548776662466927 * c)
    o = obstacles.reshape((nb, m * d))
    s = start.reshape((nb, n * d))
    g = goal.reshape((nb, n * d))
    ks = np.empty(p)
    kg = np.empty(p)
    for b in range(nb):
        ok = True
        for x in range(m * d):
            ok &= abs(o[b, x]) <= MAXF  # False for inf and NaN
        for x in range(n * d):
            ok &= abs(s[b, x]) <= MAXF
            ok &= abs(g[b, x]) <= MAXF
        if not ok:
            return False
        for i in range(m):
            v = 0.0
            for c in range(d):
                v += o[b, i * d + c] * wk[c]
            ks[i] = v
            kg[i] = v
        for j in range(n):
            v = 0.0
            u = 0.0
            for c in range(d):
                v += s[b, j * d + c] * wk[c]
                u += g[b, j * d + c] * wk[c]
            ks[m + j] = v
            kg[m + j] = u
        hit = False
        for i in range(1, p):
            a = ks[i]
            z = kg[i]
            for j in range(i):
                hit |= (ks[j] == a) | (kg[j] == z)
        if not hit:
            continue
        for i in range(m):  # some keys are equal: compare those points
            for j in range(i + 1, m):
                if _coincide(o, b, i, o, j, d):
                    return False
            for j in range(n):
                if _coincide(o, b, i, s, j, d) or _coincide(o, b, i, g, j, d):
                    return False
        for i in range(n):
            for j in range(i + 1, n):
                if _coincide(s, b, i, s, j, d) or _coincide(g, b, i, g, j, d):
                    return False
    return True
