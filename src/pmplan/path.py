"""Piecewise-linear paths in F(R^d, m+n), and the path algebra the planners are built from.

A *piecewise-linear path* is a map ``[0, 1] -> (R^d)^P`` given by breakpoints
``0 = t_0 <= t_1 <= ... <= t_{K-1} = 1`` and waypoints ``P_0, ..., P_{K-1}`` (configurations of
P points in R^d, obstacles first), linear between consecutive breakpoints. A batch of B paths
stores waypoints of shape (B, K, P, d) and breakpoints of shape (K,) (shared) or (B, K).

The algebra: :func:`linear` (the straight motion between two configurations), :meth:`~PiecewiseLinearPath.join`
(concatenation with time fractions), :meth:`~PiecewiseLinearPath.reversed`, evaluation ``path(t)``,
:meth:`~PiecewiseLinearPath.resample`, and :meth:`~PiecewiseLinearPath.arc_length_reparametrised` (constant speed). With it, the
generic composition of the paper's Remark 2.5
is written once, in :func:`compose_via_deformations`.

A zero-duration piece (``t_k == t_{k+1}``) is allowed in batches (it pads paths with fewer legs
to a common K); its two waypoints must then be equal.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["DIRECT_AT", "PiecewiseLinearPath", "linear", "compose_via_deformations", "cut_along"]

#: the direct lift of the compact lanes in the plane (Mathematics §4.4): waypoint 2 of a leg of
#: :func:`compose_via_deformations` (tau = 1/3) as the point this far along the straight move
#: from waypoint 1 (tau = 1/6) to waypoint 3 (tau = 4/9), (1/3 - 1/6) / (4/9 - 1/6), and
#: waypoint 5 (2/3) as far along the move from waypoint 6 (5/6) to waypoint 4 (5/9): the motion
#: is then that straight move at constant speed
DIRECT_AT = 0.6


class PiecewiseLinearPath:
    """A piecewise-linear path, or a batch of them.

    Parameters
    ----------
    times : array_like, shape (K,) or (B, K)
        Non-decreasing breakpoints from 0 to 1.
    waypoints : array_like, shape (K, P, d) or (B, K, P, d)
        Configurations at the breakpoints (obstacles first).

    Examples
    --------
    >>> a = np.zeros((2, 2)); b = np.array([[0.0, 0.0], [2.0, 0.0]])
    >>> p = linear(a, b)
    >>> p(0.25)
    array([[0. , 0. ],
           [0.5, 0. ]])
    >>> p(np.array([0.0, 1.0])).shape
    (2, 2, 2)
    >>> p.join(p.reversed())(np.array([0.5, 0.75]))[:, 1]
    array([[2., 0.],
           [1., 0.]])
    """

    __slots__ = ("times", "waypoints")

    def __init__(self, times, waypoints):
        self.times = np.asarray(times, dtype=float)
        self.waypoints = np.asarray(waypoints, dtype=float)
        if self.waypoints.ndim not in (3, 4):
            raise ValueError(
                f"Expected `waypoints` to have shape (K, P, d) or (B, K, P, d), "
                f"got {self.waypoints.shape}."
            )
        k = self.waypoints.shape[-3]
        if self.times.shape[-1:] != (k,) or self.times.ndim > 2:
            raise ValueError(
                f"Expected `times` to have shape ({k},) or (B, {k}), got {self.times.shape}."
            )
        if self.times.ndim == 2 and self.waypoints.ndim == 3:
            raise ValueError("per-path `times` of shape (B, K) need batched waypoints (B, K, P, d)")

    # --- shape -----------------------------------------------------------------------------
    @property
    def is_batch(self) -> bool:
        """True for a batch of paths (waypoints of shape (B, K, P, d))."""
        return self.waypoints.ndim == 4

    @property
    def shape(self) -> tuple[int, ...]:
        """``()`` for one path, ``(B,)`` for a batch."""
        return self.waypoints.shape[:-3]

    def __len__(self) -> int:
        if not self.is_batch:
            raise TypeError("Single path has no len().")
        return self.waypoints.shape[0]

    def __getitem__(self, index) -> PiecewiseLinearPath:
        if not self.is_batch:
            raise TypeError("Single path is not subscriptable.")
        times = self.times if self.times.ndim == 1 else self.times[index]
        return PiecewiseLinearPath(times, self.waypoints[index])

    def __iter__(self):
        for b in range(len(self)):
            yield self[b]

    def __repr__(self) -> str:
        return f"PiecewiseLinearPath(shape={self.shape}, K={self.waypoints.shape[-3]}, " \
               f"points={self.waypoints.shape[-2]}, d={self.waypoints.shape[-1]})"

    def as_array(self) -> np.ndarray:
        """Return the waypoints array."""
        return self.waypoints

    # --- algebra ---------------------------------------------------------------------------
    def reversed(self) -> PiecewiseLinearPath:
        """Return the reverse path ``t -> self(1 - t)`` (a new object)."""
        return PiecewiseLinearPath(1.0 - self.times[..., ::-1], self.waypoints[..., ::-1, :, :])

    def join(self, *others: PiecewiseLinearPath, at: Sequence[float] | None = None):
        """Concatenate paths end to start; path i runs on ``[at[i-1], at[i]]``.

        Parameters
        ----------
        *others : PiecewiseLinearPath
            Paths to follow this one; each must start exactly where the previous one ends.
        at : sequence of float, optional
            The interior breakpoints, strictly increasing in (0, 1), one fewer than the number
            of paths. Default: equal durations.
        """
        return join([self, *others], at)

    # --- evaluation ------------------------------------------------------------------------
    def __call__(self, t):
        """Evaluate at t in [0, 1].

        Returns an array of shape ``self.shape + np.shape(t) + (P, d)``.
        """
        t = np.asarray(t, dtype=float)
        scalar = t.ndim == 0
        tshape = t.shape
        tt = t.reshape(-1)
        if np.any(~np.isfinite(tt)) or np.any((tt < 0) | (tt > 1)):
            raise ValueError("path parameter t must lie in [0, 1]")
        times = self.times
        k = times.shape[-1]
        if times.ndim == 1:
            idx = np.clip(np.searchsorted(times, tt, side="right") - 1, 0, k - 2)
            t0, t1 = times[idx], times[idx + 1]
        else:
            idx = np.clip((times[:, None, :] <= tt[None, :, None]).sum(-1) - 1, 0, k - 2)
            t0 = np.take_along_axis(times, idx, axis=1)
            t1 = np.take_along_axis(times, idx + 1, axis=1)
        dur = t1 - t0
        with np.errstate(invalid="ignore", divide="ignore"):
            frac = np.where(dur > 0, (tt - t0) / np.where(dur > 0, dur, 1.0), 0.0)
        wp = self.waypoints
        if wp.ndim == 3:
            a, b = wp[idx], wp[idx + 1]
        else:
            bidx = np.arange(wp.shape[0])[:, None]
            if idx.ndim == 1:
                idx = np.broadcast_to(idx, (wp.shape[0], idx.shape[0]))
                frac = np.broadcast_to(frac, idx.shape)
            a, b = wp[bidx, idx], wp[bidx, idx + 1]
        f = frac[..., None, None]
        # exact at the breakpoints: t_k gives P_k and t_{k+1} gives P_{k+1} bit for bit
        with np.errstate(over="ignore", invalid="ignore"):
            step = b - a
            out = np.where(f == 1.0, b, a + f * step)
            wide = ~np.isfinite(step) & np.isfinite(a) & np.isfinite(b)
            if wide.any():  # waypoints ~1e308 apart: the same point from the halves, exactly
                half = 2.0 * (0.5 * a + f * (0.5 * b - 0.5 * a))
                out = np.where(wide & (f != 1.0), half, out)
        if scalar:
            return out[..., 0, :, :]
        return out.reshape(out.shape[:-3] + tshape + out.shape[-2:])

    def resample(self, k: int) -> PiecewiseLinearPath:
        """Return the path sampled at ``k >= 2`` equally spaced times, as a new path."""
        if k < 2:
            raise ValueError("resample needs k >= 2")
        ts = np.linspace(0.0, 1.0, k)
        wp = self(ts)
        return PiecewiseLinearPath(ts, wp)

    def leg_lengths(self) -> np.ndarray:
        """Return, for every piece, the sum over points of the distance each point travels.

        Shape ``self.shape + (K - 1,)``.
        Overflow-free: where a displacement or its square leaves the float range (coordinates
        beyond ~1e154) the lengths are computed on the waypoints scaled by a power of two
        (exact) and scaled back, so they are infinite only when the true value exceeds the
        largest double. In the normal range the value is the plain ``sqrt(sum of squares)``.
        """
        with np.errstate(over="ignore", invalid="ignore"):
            disp = np.diff(self.waypoints, axis=-3)
            out = np.sqrt((disp * disp).sum(-1)).sum(-1)
        bad = ~np.isfinite(out)
        if bad.any() and np.isfinite(self.waypoints).all():
            out = np.where(bad, _scaled_lengths(self.waypoints), out)
        return out

    def length(self) -> np.ndarray | float:
        """Return the total distance travelled, summed over all points (robots).

        ``inf`` only when it exceeds the largest double."""
        with np.errstate(over="ignore"):
            out = self.leg_lengths().sum(-1)
        return float(out) if out.ndim == 0 else out

    def arc_length_reparametrised(self) -> PiecewiseLinearPath:
        """Return the same polyline traversed at constant speed (times proportional to length).

        A path of length 0 becomes a constant path with equally spaced breakpoints.
        """
        legs = self.leg_lengths()
        with np.errstate(over="ignore"):
            total = legs.sum(-1, keepdims=True)
        if not np.isfinite(total).all() and np.isfinite(self.waypoints).all():
            # lengths beyond the float range (coordinates ~1e308): the same fractions from the
            # waypoints scaled by 2**-600 (exact; a length that then underflows is negligible)
            legs = np.where(np.isfinite(total), legs,
                            PiecewiseLinearPath(self.times, np.ldexp(self.waypoints, -600))
                            .leg_lengths())
            total = legs.sum(-1, keepdims=True)
        cum = np.concatenate([np.zeros_like(total), np.cumsum(legs, axis=-1)], axis=-1)
        k = self.waypoints.shape[-3]
        even = np.broadcast_to(np.linspace(0.0, 1.0, k), cum.shape)
        with np.errstate(invalid="ignore", divide="ignore"):
            times = np.where(total > 0, cum / np.where(total > 0, total, 1.0), even)
        times[..., -1] = 1.0
        return PiecewiseLinearPath(times, self.waypoints)

    def compact(self) -> PiecewiseLinearPath:
        """For a single path, drop zero-duration pieces so breakpoints are strictly increasing."""
        if self.is_batch:
            raise TypeError("compact() applies to a single path")
        keep = np.concatenate([[True], np.diff(self.times) > 0])
        if keep.all():
            return self
        return PiecewiseLinearPath(self.times[keep], self.waypoints[keep])


def _scaled_lengths(waypoints: np.ndarray) -> np.ndarray:
    """Leg lengths of finite waypoints (..., K, P, d) computed without overflow or underflow:
    every leg (and point) is scaled by the power of two of its largest displacement, exactly."""
    with np.errstate(over="ignore", invalid="ignore"):
        disp = np.diff(waypoints, axis=-3)  # may overflow: then from the halves, exactly
        if not np.isfinite(disp).all():
            disp = np.diff(np.ldexp(waypoints, -1), axis=-3)
            twice = 1
        else:
            twice = 0
        big = np.abs(disp).max(-1, keepdims=True)
        _, e = np.frexp(np.where(big > 0, big, 1.0))
        unit = np.ldexp(disp, -e)
        per_point = np.ldexp(np.sqrt((unit * unit).sum(-1)), e[..., 0] + twice)
        return per_point.sum(-1)


def cut_along(x: np.ndarray, cuts: int, axis: int = -1) -> np.ndarray:
    """Breakpoints (or waypoints) ``x`` with every piece along ``axis`` cut into ``cuts`` equal
    pieces: ``x_k + (j / cuts)(x_{k+1} - x_k)``, j = 0..cuts-1, then the last, so K entries
    become (K - 1) cuts + 1 and every original one stays, bit for bit.

    >>> cut_along(np.array([0.0, 1.0, 3.0]), 2).tolist()
    [0.0, 0.5, 1.0, 2.0, 3.0]
    """
    x = np.moveaxis(np.asarray(x), axis, 0)
    fr = (np.arange(cuts) / cuts).reshape((cuts,) + (1,) * (x.ndim - 1))
    inner = x[:-1, None] + fr * (x[1:] - x[:-1])[:, None]
    out = np.concatenate([inner.reshape((-1,) + x.shape[1:]), x[-1:]])
    return np.moveaxis(out, 0, axis)


def unchecked_path(times: np.ndarray, waypoints: np.ndarray) -> PiecewiseLinearPath:
    """A :class:`PiecewiseLinearPath` of arrays already known to be valid, without the checks.

    For the single-query fast paths of :mod:`pmplan.api` only: ``times`` (K,) and ``waypoints``
    (K, P, d) are float64 arrays written by a certified kernel (so ``np.asarray`` would return
    them unchanged and the shape checks of the constructor hold). The public constructor always
    validates.
    """
    path = _NEW(PiecewiseLinearPath)
    path.times = times
    path.waypoints = waypoints
    return path


_NEW = object.__new__


def linear(start, end) -> PiecewiseLinearPath:
    """Return the straight motion ``t -> start + t (end - start)`` (batched or not)."""
    start = np.asarray(start, dtype=float)
    end = np.asarray(end, dtype=float)
    return PiecewiseLinearPath(np.array([0.0, 1.0]), np.stack([start, end], axis=-3))


def join(paths: Sequence[PiecewiseLinearPath], at: Sequence[float] | None = None):
    """Concatenate paths end to start, path i on ``[at[i-1], at[i]]`` (see the method)."""
    paths = list(paths)
    if not paths:
        raise ValueError("join needs at least one path")
    q = len(paths)
    if at is None:
        at = [i / q for i in range(1, q)]
    bounds = np.concatenate([[0.0], np.asarray(at, dtype=float), [1.0]])
    if bounds.shape != (q + 1,) or np.any(np.diff(bounds) <= 0):
        raise ValueError(f"`at` must be {q - 1} increasing breakpoints in (0, 1), got {list(at)}")
    for i in range(1, q):
        # NaN == NaN here: a path that overflowed is still joined, and its certificate fails
        if not np.array_equal(paths[i - 1].waypoints[..., -1, :, :],
                              paths[i].waypoints[..., 0, :, :], equal_nan=True):
            raise ValueError(f"path {i} does not start where path {i - 1} ends")
    per_path = any(p.times.ndim == 2 for p in paths)
    times, wps = [], []
    for i, p in enumerate(paths):
        t = p.times
        if per_path and t.ndim == 1:
            t = np.broadcast_to(t, p.waypoints.shape[:1] + t.shape)
        t = bounds[i] + t * (bounds[i + 1] - bounds[i])
        w = p.waypoints
        if i > 0:
            t = t[..., 1:]
            w = w[..., 1:, :, :]
        times.append(t)
        wps.append(w)
    times = np.concatenate(times, axis=-1)
    times[..., -1] = 1.0
    return PiecewiseLinearPath(times, np.concatenate(wps, axis=-3))


def compose_via_deformations(h_start, section, h_goal) -> PiecewiseLinearPath:
    """Return the path of paper Remark 2.5.

    Given deformations ``h_start`` of C and ``h_goal`` of C' (paths from C, C' into the set U
    where a section is known) and the ``section`` path from ``h_start(1)`` to ``h_goal(1)``::

        s_V(v)(tau) = h_1(v, 3 tau)              0   <= tau <= 1/3
                      s_U(H(v, 1))(3 tau - 1)    1/3 <= tau <= 2/3
                      h_2(v, 3 - 3 tau)          2/3 <= tau <= 1
    """
    return join([h_start, section, h_goal.reversed()], [1.0 / 3.0, 2.0 / 3.0])
