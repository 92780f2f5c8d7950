"""The maps of a workspace box (:mod:`pmplan.workspace`) as kernels, bit for bit the numpy
references: :func:`from_box_linear` (the queries mapped out of the box), :func:`into_box`
(the algebraic map that brings a refined path into the box shrunk by the radius) and
:func:`path_into_box_linear` (the exact image of paths under the map linear on cells, every
piece cut where a point crosses a node). One query of the scene benchmark spends about a
millisecond in the references' numpy calls on small arrays; here the same arithmetic runs in
one loop.

Every floating-point operation is the reference's, in the reference's order (no fast-math, no
contraction: :data:`~pmplan.kernels.common.OPTS`). The node index estimated by ``log2`` is
corrected both ways against the node itself, as in the reference, so that a ``log2`` that
rounds differently from numpy's gives the same index.
"""

from __future__ import annotations

import math

import numpy as np

from .common import INLINE, OPTS, njit

__all__ = ["from_box_linear", "into_box", "path_into_box_linear"]

_BIG = np.finfo(float).max


@njit(**INLINE)
def _pow2(f, k):  # pragma: no cover - compiled
    """``f 2^k`` for an integer-valued float ``k`` (``workspace._pow2``)."""
    if k != k:  # (NaN: the reference's int64 of NaN is an exponent far below every float)
        return 0.0
    return math.ldexp(f, int(min(max(k, -4000.0), 4000.0)))


@njit(**INLINE)
def _node(k, b, f):  # pragma: no cover - compiled
    return b + (_pow2(f, k) - f)


@njit(**INLINE)
def _nodes_below(u, b, f):  # pragma: no cover - compiled
    """How many nodes beyond the upper edge ``b`` lie at or below ``u``
    (``workspace._nodes_below``)."""
    u = min(u, _BIG)
    k = np.floor(math.log2(max(u - b, 0.0) + f) - math.log2(f))
    if u < _node(k, b, f):
        k = k - 1.0
    if u >= _node(k + 1.0, b, f):
        k = k + 1.0
    if u < b:
        return 0.0
    return k + 1.0


@njit(**INLINE)
def _linear_up(u, b, f):  # pragma: no cover - compiled
    k = _nodes_below(u, b, f) - 1.0
    y = 1.0 - _pow2(f, -k) + (u - _node(k, b, f)) * _pow2(0.5, -2.0 * k)
    if u == math.inf:
        return 1.0
    return y


@njit(**INLINE)
def _linear_up_inverse(y, b, f):  # pragma: no cover - compiled
    if y >= 1.0:
        return math.inf
    k = np.floor(-math.log2((1.0 - y) / f))
    if y < 1.0 - _pow2(f, -k):
        k = k - 1.0
    if y >= 1.0 - _pow2(f, -(k + 1.0)):
        k = k + 1.0
    return _node(k, b, f) + (y - (1.0 - _pow2(f, -k))) * _pow2(2.0, 2.0 * k)


# the tails of the three maps, in unit coordinates (workspace's lambdas and functions)
_INTO_LINEAR, _FROM_LINEAR, _INTO_ALGEBRAIC = 0, 1, 2


@njit(**INLINE)
def _tail(u, a, b, f, kind):  # pragma: no cover - compiled
    if kind == _INTO_LINEAR:
        if u > b:
            return _linear_up(u, b, f)
        return 1.0 - _linear_up(1.0 - u, b, f)
    if kind == _FROM_LINEAR:
        if u > b:
            return _linear_up_inverse(u, b, f)
        return 1.0 - _linear_up_inverse(1.0 - u, b, f)
    if u > b:
        return 1.0 - f * f / (u - b + f)
    return f * f / (a - u + f)


@njit(**INLINE)
def _map(x, lo, hi, f, kind, clip):  # pragma: no cover - compiled
    """One coordinate through ``workspace._tails`` (and its clip to [lo, hi] for the maps
    into the box)."""
    w = hi - lo
    u = (x - lo) / w
    a = f
    b = 1.0 - f
    if u >= a and u <= b:
        return x
    out = lo + w * _tail(u, a, b, f, kind)
    if clip:
        out = min(max(out, lo), hi)
    return out


@njit(**OPTS)
def _map_all(x, box, f, kind, clip):  # pragma: no cover - compiled
    """Every point of ``x`` (N, d) through :func:`_map` into a new array."""
    n, d = x.shape
    out = np.empty((n, d))
    for i in range(n):
        for c in range(d):
            out[i, c] = _map(x[i, c], box[0, c], box[1, c], f, kind, clip)
    return out


def _points(x, box, f, kind, clip):
    x = np.asarray(x, dtype=float)
    flat = np.ascontiguousarray(x.reshape(-1, x.shape[-1]))
    box = np.ascontiguousarray(np.asarray(box, dtype=float))
    return _map_all(flat, box, float(f), kind, clip).reshape(x.shape)


def from_box_linear(x, box, frac):
    """``workspace.from_box_linear``, bit for bit."""
    return _points(x, box, frac, _FROM_LINEAR, False)


def into_box(z, box, frac):
    """``workspace.into_box``, bit for bit."""
    return _points(z, box, frac, _INTO_ALGEBRAIC, True)


@njit(**INLINE)
def _span(a, b, f, mirror):  # pragma: no cover - compiled
    """``(first, count)``: the nodes of one band strictly between the unit coordinates ``a``
    and ``b`` are ``first .. first + count - 1`` (``workspace._crossings``)."""
    edge = 1.0 - f
    lo = min(a, b)
    hi = max(a, b)
    if mirror:
        lo, hi = 1.0 - hi, 1.0 - lo
    first = _nodes_below(lo, edge, f)
    stop = _nodes_below(hi, edge, f)
    last = stop
    if stop > 0.0 and _node(stop - 1.0, edge, f) == hi:
        last = stop - 1.0
    return first, max(last - first, 0.0)


@njit(**OPTS)
def _raw_count(u, q, j, f):  # pragma: no cover - compiled
    """How many node crossings (before the filter and the merge of equal fractions) piece j
    of path q has."""
    _, _, p, d = u.shape
    total = 0
    for i in range(p):
        for c in range(d):
            for mirror in (False, True):
                total += int(_span(u[q, j, i, c], u[q, j + 1, i, c], f, mirror)[1])
    return total


@njit(**OPTS)
def _fractions(times, u, q, j, f, buf):  # pragma: no cover - compiled
    """The distinct fractions of piece j of path q where a point crosses a node, strictly
    inside the piece in fraction and time, sorted, into ``buf``; returns how many
    (``workspace._cuts``)."""
    _, _, p, d = u.shape
    t0 = times[q, j]
    t1 = times[q, j + 1]
    n = 0
    for i in range(p):
        for c in range(d):
            a0 = u[q, j, i, c]
            b0 = u[q, j + 1, i, c]
            for mirror in (False, True):
                first, count = _span(a0, b0, f, mirror)
                for r in range(int(count)):
                    z = _node(first + r, 1.0 - f, f)
                    node = 1.0 - z if mirror else z
                    lam = (node - a0) / (b0 - a0)
                    tt = t0 + lam * (t1 - t0)
                    if lam > 0.0 and lam < 1.0 and tt > t0 and tt < t1:
                        buf[n] = lam
                        n += 1
    if n == 0:
        return 0
    buf[:n] = np.sort(buf[:n])
    k = 1
    for r in range(1, n):
        if buf[r] != buf[k - 1]:
            buf[k] = buf[r]
            k += 1
    return k


@njit(**OPTS)
def _path_image(times, wp, box, f, width_in):  # pragma: no cover - compiled
    """``workspace.path_into_box_linear`` of paths ``wp`` (B, K, P, d) with breakpoints
    ``times`` (B, K): ``(out_t, out_w, need)``; with ``width_in`` >= 0 smaller than the
    ``need`` of some piece, empty outputs (the caller raises the reference's error)."""
    bsz, k, p, d = wp.shape
    u = np.empty((bsz, k, p, d))
    for q in range(bsz):
        for j in range(k):
            for i in range(p):
                for c in range(d):
                    u[q, j, i, c] = (wp[q, j, i, c] - box[0, c]) / (box[1, c] - box[0, c])
    # every piece's raw count, then its distinct fractions in one flat buffer
    offsets = np.zeros((bsz, k - 1), dtype=np.int64)
    total = 0
    for q in range(bsz):
        for j in range(k - 1):
            offsets[q, j] = total
            nraw = _raw_count(u, q, j, f)
            total += nraw
    flat = np.empty(max(total, 1))
    count = np.zeros((bsz, k - 1), dtype=np.int64)
    need = 0
    for q in range(bsz):
        for j in range(k - 1):
            got = _fractions(times, u, q, j, f, flat[offsets[q, j]:])
            count[q, j] = got
            need = max(need, got)
    width = need if width_in < 0 else width_in
    if width < need:
        return np.empty((0, 0)), np.empty((0, 0, 0, 0)), need
    kk = (k - 1) * (width + 1) + 1
    out_t = np.empty((bsz, kk))
    out_w = np.empty((bsz, kk, p, d))
    lams = np.empty(width + 1)
    for q in range(bsz):
        for j in range(k - 1):
            cnt = count[q, j]
            lams[0] = 0.0
            for r in range(cnt):
                lams[1 + r] = flat[offsets[q, j] + r]
            last = lams[cnt]
            pad = width - cnt
            for s in range(cnt + 1, width + 1):
                step = (s - cnt) / (pad + 1.0)
                lams[s] = last + step * (1.0 - last)
            t0 = times[q, j]
            t1 = times[q, j + 1]
            for s in range(width + 1):
                lam = lams[s]
                row = j * (width + 1) + s
                out_t[q, row] = t0 if lam == 0.0 else t0 + lam * (t1 - t0)
                for i in range(p):
                    for c in range(d):
                        w0 = wp[q, j, i, c]
                        if lam == 0.0:
                            x = w0
                        else:
                            x = (1.0 - lam) * w0 + lam * wp[q, j + 1, i, c]
                        out_w[q, row, i, c] = _map(x, box[0, c], box[1, c], f,
                                                   _INTO_LINEAR, True)
        out_t[q, kk - 1] = times[q, k - 1]
        for i in range(p):
            for c in range(d):
                out_w[q, kk - 1, i, c] = _map(wp[q, k - 1, i, c], box[0, c], box[1, c], f,
                                              _INTO_LINEAR, True)
    return out_t, out_w, need


def path_into_box_linear(times, waypoints, box, frac, width=None):
    """``workspace.path_into_box_linear``, bit for bit (the same error for a ``width`` below
    what a piece needs)."""
    wp = np.ascontiguousarray(np.asarray(waypoints, dtype=float))
    bsz, k = wp.shape[:2]
    times = np.ascontiguousarray(np.broadcast_to(np.asarray(times, dtype=float), (bsz, k)))
    box = np.ascontiguousarray(np.asarray(box, dtype=float))
    out_t, out_w, need = _path_image(times, wp, box, float(frac), -1 if width is None
                                     else int(width))
    if width is not None and width < need:
        raise ValueError(f"width = {width} is smaller than the {need} crossings of a piece")
    return out_t, out_w
