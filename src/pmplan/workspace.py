"""A workspace: motions that stay inside an axis-aligned box ``[lo, hi]`` (issue 25, item 1).

A planner ``s`` for the whole space R^d becomes a planner for the open box ``B`` by
conjugation with a homeomorphism ``phi : R^d -> B``: ``s_B(q) = phi o s(phi^-1(q))``, the
query mapped out of the box, planned, and the motion mapped back into it, point by point and at
every time. ``phi`` is a homeomorphism, so ``s_B`` is continuous exactly where ``s`` is (on the
images ``phi(W_l)`` of its domains: the same number of domains, so an optimal planner stays
optimal; the labels are the unmapped query's), it keeps the endpoints and the obstacles fixed,
and two points never meet in ``B`` since they never meet in R^d (Mathematics §8).

``phi`` acts coordinate by coordinate, ``phi(x)_k = psi_k(x_k)``, with ``psi`` the identity on
the inner interval ``[lo + mu, hi - mu]`` (``mu = BAND (hi - lo)``), so a motion that stays
there is not changed at all, and outside it linear on cells (:func:`into_box_linear`,
:func:`from_box_linear`): affine between the dyadic nodes ``b + mu (2^k - 1)`` above ``b = hi -
mu``, which it sends to ``hi - mu 2^-k`` (the mirror image below), the values there of the
algebraic tail ``hi - mu^2 / (x - b + mu)`` (:func:`into_box`), which brings far excursions of
the raw construction in without crushing them together (an exponential tail rounded distinct
far points to the same corner of the box and failed 44 of 192 certificates of the scene
benchmark). ``phi`` is affine on every cell, so the image of a straight piece of ``s`` is the
polyline through the images of the points where some point crosses a node, at the times it
does: :func:`path_into_box_linear` computes it, and ``plan(bounds=)`` returns it. That
polyline is ``s_B`` at every time (to rounding; Mathematics §8, "The exact image of a path"): it
passes every obstacle on the side ``s_B`` does, stays in the box (a box is convex), and is
certified like every plan, the obstacles and the configurations it passes through restored bit
for bit. Its number of breakpoints depends on the query: every piece of every path of a batch
gets the same number of new ones (:func:`crossing_width`), so that the raw breakpoints keep
their places, and the dask and Zarr paths, whose output shapes are fixed before planning, find
that number by a first pass over the batch.

The polyline through ``phi`` of the raw waypoints alone (the chords) is not ``s_B``: a chord
may pass an obstacle on the other side than the curve ``phi`` makes of the piece, and with the
algebraic map that polyline, pmplan's plan before, jumped class on walls inside a domain
(Mathematics §8, "What the chords are not"; ``benchmarks/box_chords.py``). The refinement of a
plan in the box starts from the plan at the raw breakpoints, which are such chords
(:func:`pmplan.running.box_start`, :data:`RAW_CUTS`): a start whose breakpoints do not come and
go with the query.

A refined motion (:func:`pmplan.refine`) must keep a robot of ``radius`` inside the box: the
refinement pushes the robots back from the limits of :func:`identity_box` of the box shrunk by
``radius`` and holds its moves toward them (``docs/refinement.md``, Walls); after it, a second
map of the same form into the box shrunk by ``radius``, with the narrow band ``SQUEEZE (hi -
lo)``, brings back the few points still outside (the identity wherever the refined path keeps
to those limits), and ``respects_radius`` includes the walls, decided exactly.

Both maps are computed in the box's unit coordinates ``u = (x - lo) / (hi - lo)`` (the band is
``BAND`` there): nothing underflows or overflows at any magnitude of the box, and a query and
its box scaled together by a power of two give the same plan scaled, bit for bit (with
``lift="scene"``, whose plans are themselves equivariant).

The functions here are the references; the planning functions call the maps through the
backend seam (:mod:`pmplan.backends`: ``from_box_linear``, ``path_into_box_linear``,
``into_box``), and the numba backend runs them as kernels, bit for bit these
(``pmplan.kernels.box``).
"""

from __future__ import annotations

import numpy as np

from .configuration import configuration_names
from .errors import InputError

__all__ = [
    "BAND",
    "RAW_CUTS",
    "SQUEEZE",
    "check_bounds",
    "check_inside",
    "check_walls",
    "crossing_width",
    "from_box",
    "from_box_linear",
    "identity_box",
    "inside",
    "interior",
    "into_box",
    "into_box_linear",
    "into_box_linear_slope",
    "into_box_slope",
    "path_into_box_linear",
    "restore",
    "shrunk",
]

#: the width of the band along each wall where the map into the box is not the identity, as a
#: fraction of the box's side. Every width in (0, 1/2) keeps the domains and the labels.
#: benchmarks/band_ab.py (docs: The band of the box's map) measures 1/8 against 3/16, 1/4 and
#: 5/16 on the scene families: the wider bands send fewer paths through gaps narrower than a
#: robot and keep the radii on a few more queries, but raise the modulus of continuity (at a
#: distance w from a wall the map out of the box stretches by (mu / w)^2, so a small move of an
#: obstacle there can move the lanes that much more); 1/8 keeps the most rows within issue 25's
#: continuity goal of the four over all the seeds, 396 of 400 (not in every group of seeds: 3/16,
#: 394 in all, ties it on the design seeds and keeps three rows more on seeds 14-21)
BAND = 0.125
#: the refinement of a plan in the box starts from the plan at the raw planner's breakpoints
#: and at RAW_CUTS - 1 more equally spaced times inside every raw piece
#: (:func:`pmplan.running.box_start`): 1 starts from the chords between the mapped raw
#: waypoints, a start that does not change where the plan's breakpoints come and go.
#: benchmarks/chords_ab.py measured the same start with the algebraic map (1 against 2 and 4:
#: 1 kept the most rows within the continuity goal at no loss in valid share or length)
RAW_CUTS = 1
#: the band of the map that brings a refined path into the box shrunk by ``radius``, as a
#: fraction of the side: the identity wherever the refined path keeps that much more from the
#: walls, the limits the refinement keeps its robots to. Narrow, since the refinement sees the
#: walls (benchmarks/walls_ab.py: 1/256 against the 1/64 of the refinement without walls)
SQUEEZE = 1.0 / 256.0

_MSG_BOUNDS = ("`bounds` must be a pair (lo, hi) of numbers or of length-{d} sequences with "
               "lo < hi in every coordinate (the workspace box), got {value!r}")
_MSG_OUTSIDE = ("{who} is at {coord} = {value:.17g}, outside the workspace box "
                "[{lo:.17g}, {hi:.17g}] in that coordinate{where}: move it inside, or "
                "enlarge `bounds`")
_MSG_WALL = ("in the {name}, robot x{i} is {dist:.6g} from the wall {coord} = {wall:.17g}"
             "{where}, closer than radius = {radius:.6g}: move it away from the wall or use a "
             "smaller radius")


def check_bounds(bounds, d: int) -> np.ndarray:
    """``bounds`` as a float array (2, d) ``[lo, hi]``: a pair of numbers (the same for every
    coordinate) or of length-d sequences, finite, ``lo < hi``; else an InputError.

    >>> check_bounds((0, 10), 2).tolist()
    [[0.0, 0.0], [10.0, 10.0]]
    """
    try:
        if isinstance(bounds, (str, bytes)) or len(bounds) != 2:
            raise TypeError
        parts = []
        for part in bounds:
            if isinstance(part, (bool, np.bool_)):
                raise TypeError
            a = np.asarray(part)
            if a.dtype.kind not in "iuf" or a.ndim > 1 or (a.ndim == 1 and a.shape[0] != d):
                raise TypeError
            parts.append(np.broadcast_to(a.astype(float), (d,)))
        box = np.array(parts)
    except (TypeError, ValueError):
        raise InputError(_MSG_BOUNDS.format(d=d, value=bounds)) from None
    if not np.isfinite(box).all() or not (box[0] < box[1]).all():
        raise InputError(_MSG_BOUNDS.format(d=d, value=bounds))
    return box


def interior(points: np.ndarray, box: np.ndarray) -> np.ndarray:
    """Whether every coordinate of ``points`` (..., d) lies strictly inside the box (2, d)."""
    return (points > box[0]) & (points < box[1])


def check_inside(obstacles: np.ndarray, configs: list, box: np.ndarray, batched: bool) -> None:
    """Raise an InputError naming the first point of the query (obstacle, or robot of a start,
    goal or intermediate configuration) that is not strictly inside ``box`` (2, d)."""
    names = configuration_names(len(configs))
    for name, pts in ((None, obstacles), *zip(names, configs)):
        bad = ~interior(pts, box)  # (B, P, d)
        if bad.any():
            q, i, k = (int(v[0]) for v in np.nonzero(bad))
            who = f"obstacle o{i + 1}" if name is None else f"in the {name}, robot x{i + 1}"
            raise InputError(_MSG_OUTSIDE.format(
                who=who, coord=f"x[{k}]", value=float(pts[q, i, k]), lo=float(box[0, k]),
                hi=float(box[1, k]), where=f" in query {q}" if batched else ""))


def check_walls(configs: list, box: np.ndarray, radius: float, batched: bool) -> None:
    """Raise an InputError naming the first robot of a configuration the path passes through
    that is closer than ``radius`` to a wall of ``box``."""
    if radius == 0:
        return
    lo, hi = box
    names = configuration_names(len(configs))
    for name, pts in zip(names, configs):
        dist = np.minimum(pts - lo, hi - pts)
        bad = dist < radius
        if bad.any():
            q, i, k = (int(v[0]) for v in np.nonzero(bad))
            wall = lo[k] if pts[q, i, k] - lo[k] <= hi[k] - pts[q, i, k] else hi[k]
            raise InputError(_MSG_WALL.format(
                name=name, i=i + 1, dist=float(dist[q, i, k]),
                coord=f"x[{k}]", wall=float(wall), where=f" in query {q}" if batched else "",
                radius=radius))


def _tails(x, box: np.ndarray, frac: float, up, dn) -> np.ndarray:
    """``x`` (..., d) with every coordinate beyond the inner box mapped by its tail -- ``up``
    above it, ``dn`` below, functions of the unit coordinate ``u = (x - lo) / (hi - lo)``, the
    band's lower and upper edges ``a = frac``, ``b = 1 - frac`` and ``frac`` -- and every other
    coordinate left as it is, bit for bit. In unit coordinates nothing underflows at any
    magnitude of the box."""
    lo, hi = box
    w = hi - lo
    x = np.asarray(x, dtype=float)
    a, b = frac, 1.0 - frac
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        u = (x - lo) / w
    tail = ~((u >= a) & (u <= b))  # (the tails only: most points of a query are inside)
    if not tail.any():
        return x.copy()
    out = x.copy()
    lo_t, w_t, ut = np.broadcast_to(lo, x.shape)[tail], np.broadcast_to(w, x.shape)[tail], u[tail]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        up_part = ut > b
        val = np.empty_like(ut)
        val[up_part] = up(ut[up_part], a, b, frac)
        val[~up_part] = dn(ut[~up_part], a, b, frac)
        out[tail] = lo_t + w_t * val
    return out


def from_box(x: np.ndarray, box: np.ndarray, frac: float = BAND) -> np.ndarray:
    """The inverse of the algebraic map :func:`into_box`: points of the open box (..., d) to
    R^d (the identity on the inner box, bit for bit), computed in the box's unit coordinates
    (:func:`_tails`)."""
    return _tails(x, box, frac, lambda u, a, b, f: b - f + f * f / (1.0 - u),
                  lambda u, a, b, f: a + f - f * f / u)


def into_box(z: np.ndarray, box: np.ndarray, frac: float = BAND) -> np.ndarray:
    """The algebraic map of R^d (..., d) into the closed box (the open one up to rounding; the
    identity, bit for bit, on the inner box, the band ``frac (hi - lo)`` from each wall; the
    tail ``hi - mu^2 / (x - b + mu)`` beyond it), computed in the box's unit coordinates
    (:func:`_tails`): the map that brings a refined path into the box shrunk by ``radius``
    (with :data:`SQUEEZE`), and the values at the nodes of the map of ``plan(bounds=)``
    (:func:`into_box_linear`). It bends straight pieces, so the polyline through the map of
    waypoints is not the map of the path (Mathematics §8)."""
    out = _tails(z, box, frac, lambda u, a, b, f: 1.0 - f * f / (u - b + f),
                 lambda u, a, b, f: f * f / (a - u + f))
    return np.clip(out, box[0], box[1])  # (rounding only: the tails are within [lo, hi])


def into_box_slope(z: np.ndarray, box: np.ndarray, frac: float = BAND) -> np.ndarray:
    """The derivative of the algebraic map :func:`into_box` coordinate by coordinate at points ``z``
    (..., d) of R^d: 1 on the inner box, ``(mu / (mu + t))^2`` at a distance ``t`` beyond its
    edge, ``mu = frac (hi - lo)`` the band's width; ``phi`` maps every coordinate on its own, so
    its Jacobian is the diagonal of these and ``into_box_slope(z, box).prod(-1)`` its
    determinant (the density by which the box's uniform measure pulls back to R^d). Computed in
    the box's unit coordinates, as :func:`into_box`.

    >>> into_box_slope(np.array([[5.0, 10.0]]), np.array([[0.0, 0.0], [10.0, 10.0]]))
    array([[1.  , 0.25]])
    """
    lo, hi = box
    u = (np.asarray(z, dtype=float) - lo) / (hi - lo)
    f = frac
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        up = f * f / (u - (1.0 - f) + f) ** 2
        dn = f * f / (f - u + f) ** 2
    return np.where(u > 1.0 - f, up, np.where(u < f, dn, 1.0))


# --- the map linear on cells (Mathematics §8, "The exact image of a path") -----------------------

def _pow2(f, k):
    """``f 2^k`` for a float array ``k`` of integers, scaled exactly (no overflow of ``2^k`` on
    its own; 0 or inf only where the product is)."""
    return np.ldexp(f, np.clip(k, -4000, 4000).astype(np.int64))


def _node(k, b, f):
    """The k-th node beyond the upper inner edge ``b`` (unit coordinates, band ``f``)."""
    return b + (_pow2(f, k) - f)


def _nodes_below(u, b, f):
    """How many nodes beyond the upper edge lie at or below ``u`` (0 below the first, ``b``),
    consistent with :func:`_node` in floating point (the estimate by log2 corrected both
    ways)."""
    u = np.minimum(u, np.finfo(float).max)  # (a unit coordinate that overflowed: the wall)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.floor(np.log2(np.maximum(u - b, 0.0) + f) - np.log2(f))  # (no overflow)
    k = np.where(u < _node(k, b, f), k - 1.0, k)
    k = np.where(u >= _node(k + 1.0, b, f), k + 1.0, k)
    return np.where(u < b, 0.0, k + 1.0)


def _linear_up(u, a, b, f):
    """The tail above the inner box: affine between the nodes, slope 2^(-2k-1) on the k-th."""
    k = _nodes_below(u, b, f) - 1.0
    with np.errstate(invalid="ignore", over="ignore"):
        y = 1.0 - _pow2(f, -k) + (u - _node(k, b, f)) * _pow2(0.5, -2.0 * k)
    return np.where(u == np.inf, 1.0, y)  # (a unit coordinate that overflowed: the wall)


def _linear_up_inverse(y, a, b, f):
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        k = np.floor(-np.log2((1.0 - y) / f))
    k = np.where(y < 1.0 - _pow2(f, -k), k - 1.0, k)
    k = np.where(y >= 1.0 - _pow2(f, -(k + 1.0)), k + 1.0, k)
    with np.errstate(invalid="ignore", over="ignore"):
        u = _node(k, b, f) + (y - (1.0 - _pow2(f, -k))) * _pow2(2.0, 2.0 * k)
    return np.where(y >= 1.0, np.inf, u)  # (the wall itself: infinitely far)


def into_box_linear(z: np.ndarray, box: np.ndarray, frac: float = BAND) -> np.ndarray:
    """The map of R^d (..., d) into the box that is linear on cells: coordinate by coordinate
    the identity on the inner box and, beyond its edge ``b = hi - mu`` (``mu = frac (hi -
    lo)``), affine between the dyadic nodes ``b + mu (2^k - 1)``, which it sends to ``hi - mu
    2^-k`` (the values of :func:`into_box`'s tail there), with slope ``2^(-2k-1)``; the mirror
    image below. A homeomorphism onto the open box (the closed one up to rounding), affine on
    every cell of the product of these intervals, so that the image of a straight piece is the
    polyline :func:`path_into_box_linear` computes (Mathematics §8, "The exact image of a path"):
    the map of ``plan(bounds=)``, whose queries are planned at :func:`from_box_linear` of
    them.

    >>> box = np.array([[0.0], [8.0]])
    >>> into_box_linear(np.array([[4.0], [7.0], [8.0], [10.0], [-1.0]]), box)[:, 0].tolist()
    [4.0, 7.0, 7.5, 7.75, 0.375]
    """
    out = _tails(z, box, frac, _linear_up, lambda u, a, b, f: 1.0 - _linear_up(1.0 - u, a, b, f))
    return np.clip(out, box[0], box[1])


def into_box_linear_slope(z: np.ndarray, box: np.ndarray, frac: float = BAND) -> np.ndarray:
    """The derivative of :func:`into_box_linear` coordinate by coordinate at points ``z``
    (..., d) of R^d (off the nodes; the slope of the cell to the right at a node above the
    inner box): 1 on the inner box, ``2^(-2k-1)`` on the k-th cell beyond it. As for
    :func:`into_box_slope`, ``.prod(-1)`` is the density by which the box's uniform measure
    pulls back to R^d.

    >>> z = np.array([[5.0], [7.5], [8.5], [10.0], [-3.0]])
    >>> into_box_linear_slope(z, np.array([[0.0], [8.0]]))[:, 0].tolist()
    [1.0, 0.5, 0.125, 0.03125, 0.03125]
    """
    lo, hi = box
    u = (np.asarray(z, dtype=float) - lo) / (hi - lo)
    f, b = frac, 1.0 - frac
    with np.errstate(invalid="ignore", over="ignore"):
        up = _pow2(0.5, -2.0 * (_nodes_below(u, b, f) - 1.0))
        dn = _pow2(0.5, -2.0 * (_nodes_below(1.0 - u, b, f) - 1.0))
    return np.where(u > b, up, np.where(u < f, dn, 1.0))


def from_box_linear(x: np.ndarray, box: np.ndarray, frac: float = BAND) -> np.ndarray:
    """The inverse of :func:`into_box_linear`: points of the open box (..., d) to R^d (the
    identity on the inner box, bit for bit)."""
    return _tails(x, box, frac, _linear_up_inverse,
                  lambda u, a, b, f: 1.0 - _linear_up_inverse(1.0 - u, a, b, f))


def _crossings(a, b, f):
    """For the pieces from ``a`` to ``b`` (N,) in unit coordinates: the node values strictly
    between them, as (entry index, value) arrays, both bands."""
    edge = 1.0 - f
    idx, val = [], []
    for mirror in (False, True):
        lo = np.minimum(a, b)
        hi = np.maximum(a, b)
        if mirror:
            lo, hi = 1.0 - hi, 1.0 - lo
        first = _nodes_below(lo, edge, f)  # nodes <= lo
        stop = _nodes_below(hi, edge, f)   # nodes <= hi
        last = np.where((stop > 0) & (_node(stop - 1.0, edge, f) == hi), stop - 1.0, stop)
        count = np.maximum(last - first, 0.0).astype(np.int64)
        rows = np.repeat(np.arange(a.shape[0]), count)
        k = first[rows] + (np.arange(rows.size) - np.repeat(np.cumsum(count) - count, count))
        z = _node(k, edge, f)
        idx.append(rows)
        val.append(1.0 - z if mirror else z)
    return np.concatenate(idx), np.concatenate(val)


def _cuts(times, waypoints, box, frac):
    """The node crossings of every piece of paths (B, K, P, d): ``(q, j, lam)``, the query, the
    piece and the fraction of the piece where some point crosses a node of the map linear on
    cells in some coordinate, sorted by (q, j, lam), one entry per distinct fraction, and only
    those whose time falls strictly inside the piece (a crossing that rounds onto an end is
    that end, to rounding)."""
    wp = np.asarray(waypoints, dtype=float)
    lo, hi = box
    with np.errstate(invalid="ignore", over="ignore"):
        u = (wp - lo) / (hi - lo)
    a, b = u[:, :-1], u[:, 1:]  # (B, K-1, P, d)
    rows, node = _crossings(a.ravel(), b.ravel(), frac)
    a0, b0 = a.ravel()[rows], b.ravel()[rows]
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        lam = (node - a0) / (b0 - a0)
    q, j = np.unravel_index(rows, a.shape)[:2]
    t0, t1 = times[q, j], times[q, j + 1]
    with np.errstate(invalid="ignore", over="ignore"):
        tt = t0 + lam * (t1 - t0)
    keep = (lam > 0.0) & (lam < 1.0) & (tt > t0) & (tt < t1)
    q, j, lam = q[keep], j[keep], lam[keep]
    order = np.lexsort((lam, j, q))
    q, j, lam = q[order], j[order], lam[order]
    fresh = np.ones(q.size, dtype=bool)
    fresh[1:] = (q[1:] != q[:-1]) | (j[1:] != j[:-1]) | (lam[1:] != lam[:-1])
    return q[fresh], j[fresh], lam[fresh]


def crossing_width(times, waypoints, box: np.ndarray, frac: float = BAND) -> int:
    """The largest number of breakpoints :func:`path_into_box_linear` inserts into one piece of
    paths with breakpoints ``times`` (K,) or (B, K) and waypoints (B, K, P, d): the ``width``
    that fits every path of the batch (0 when no path crosses a node). A first pass over a
    batch whose output shapes are fixed before it is planned (:mod:`pmplan.scale`)."""
    wp = np.asarray(waypoints, dtype=float)
    bsz, k = wp.shape[:2]
    times = np.broadcast_to(np.asarray(times, dtype=float), (bsz, k))
    q, j, _ = _cuts(times, wp, box, frac)
    if q.size == 0:
        return 0
    return int(np.bincount(q * (k - 1) + j).max())


def path_into_box_linear(times: np.ndarray, waypoints: np.ndarray, box: np.ndarray,
                         frac: float = BAND, width: int | None = None):
    """The image under :func:`into_box_linear` of paths of R^d with breakpoints ``times`` (K,)
    or (B, K) and waypoints (B, K, P, d), exactly: every piece cut at the times where some
    point crosses a node of the map in some coordinate, the cut points mapped. On each cut
    piece the map is affine, so the polyline through them is the image of the path at every
    time (to rounding; Mathematics §8, "The exact image of a path").

    Every piece of every path gets the same number ``width`` of new breakpoints (default: the
    most any piece of the batch needs, :func:`crossing_width`; a smaller ``width`` is an
    error): a piece with fewer crossings has its last part, which lies in one cell, cut into
    equal parts (the same motion). So the original breakpoints are every ``(width + 1)``-th
    one, with their times bit for bit and ``into_box_linear`` of their waypoints, at the same
    indices in every path of the batch. Returns ``(times, waypoints)``, (B, K') and (B, K', P,
    d) with ``K' = (K - 1)(width + 1) + 1``.

    >>> box = np.array([[0.0, 0.0], [8.0, 8.0]])
    >>> path = np.array([[[[4.0, 4.0]], [[10.0, 4.0]]]])  # one point from x = 4 to x = 10
    >>> t, w = path_into_box_linear(np.array([0.0, 1.0]), path, box)
    >>> t[0].round(4).tolist(), w[0, :, 0, 0].tolist()  # the nodes 7 and 8 crossed
    ([0.0, 0.5, 0.6667, 1.0], [4.0, 7.0, 7.5, 7.75])
    """
    wp = np.asarray(waypoints, dtype=float)
    bsz, k = wp.shape[:2]
    times = np.broadcast_to(np.asarray(times, dtype=float), (bsz, k))
    q, j, lam = _cuts(times, wp, box, frac)
    count = np.zeros((bsz, k - 1), dtype=np.int64)
    np.add.at(count, (q, j), 1)
    need = int(count.max(initial=0))
    if width is None:
        width = need
    elif width < need:
        raise ValueError(f"width = {width} is smaller than the {need} crossings of a piece")
    # the fractions of every piece: 0 (its start), its crossings, then the last part cut
    frac_of = np.zeros((bsz, k - 1, width + 1))
    rank = np.arange(q.size) - np.searchsorted(q * (k - 1) + j, q * (k - 1) + j)
    frac_of[q, j, 1 + rank] = lam
    last = np.take_along_axis(frac_of, np.minimum(count, width)[..., None], axis=2)  # (B, K-1, 1)
    slot = np.arange(width + 1)
    pad = width - count[..., None]  # padding points of the piece
    step = (slot - count[..., None]) / (pad + 1.0)
    frac_of = np.where(slot > count[..., None], last + step * (1.0 - last), frac_of)
    lam = frac_of.reshape(bsz, -1)  # (B, (K-1)(width+1))
    piece = np.repeat(np.arange(k - 1), width + 1)
    t0, t1 = times[:, piece], times[:, piece + 1]
    w0, w1 = wp[:, piece], wp[:, piece + 1]
    lw = lam[..., None, None]
    with np.errstate(invalid="ignore", over="ignore"):
        ts = np.where(lam == 0.0, t0, t0 + lam * (t1 - t0))
        ws = np.where(lw == 0.0, w0, (1.0 - lw) * w0 + lw * w1)
    out_t = np.concatenate([ts, times[:, -1:]], axis=1)
    out_w = into_box_linear(np.concatenate([ws, wp[:, -1:]], axis=1), box, frac)
    return out_t, out_w


def restore(waypoints: np.ndarray, m: int, fixed, originals: list, obstacles: np.ndarray) -> None:
    """Put the obstacles (every waypoint) and the configurations the path passes through (at
    the waypoints ``fixed``) back bit for bit, in place: the maps round them."""
    waypoints[:, :, :m] = obstacles[:, None]
    for kj, conf in zip(fixed, originals):
        waypoints[:, kj, m:] = conf


def inside(waypoints: np.ndarray, box: np.ndarray, margin: float = 0.0) -> np.ndarray:
    """Whether every waypoint of every path (B, K, P, d) lies in the closed box shrunk by
    ``margin`` (B,) -- exactly (comparisons of floats); a polyline whose waypoints are in a
    box stays in it."""
    lo, hi = box
    b = waypoints.shape[0]
    ok = (waypoints >= lo + margin) & (waypoints <= hi - margin)
    return ok.reshape(b, -1).all(axis=1)


def identity_box(box: np.ndarray, frac: float = BAND) -> np.ndarray:
    """The inner box (2, d) where :func:`into_box` and :func:`from_box` with the band ``frac``
    are the identity: ``frac (hi - lo)`` in from every wall (up to rounding at its edge)."""
    w = box[1] - box[0]
    return np.array([box[0] + frac * w, box[1] - frac * w])


def shrunk(box: np.ndarray, radius: float) -> np.ndarray:
    """The box shrunk by ``radius`` on every side (2, d); the caller has checked that it is not
    empty (:func:`check_walls` on the start)."""
    return np.array([box[0] + radius, box[1] - radius])

