"""The refinement as a stage of the run loop (:class:`RefineStage`, behind the protocol of
:class:`pmplan.planners.base.Stage`): the checks of its parameters and radii, the targets, and
per chunk the map in its frame by the selected backend (:func:`pmplan.backends.select`: the
kernel :mod:`pmplan.refine.kernel` or the reference :mod:`pmplan.refine.reference`), then the
whole certificate and the exact radius report (:mod:`pmplan.certify`).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from ..backends import select
from ..certify import (
    CLEARANCE,
    check_paths,
    clearance,
    describe,
    exact_segment_clearance,
    exact_segment_dist2,
    radius_report,
)
from ..configuration import configuration_names
from ..errors import CertificationError, CollisionError, InputError
from ..planners.base import Stage
from ..workspace import SQUEEZE, identity_box, inside, restore, shrunk
from .frame import from_frame, limits_to_frame, to_frame
from .grid import (
    KAPPA,
    MAX_STEPS,
    MAX_WAYPOINTS,
    default_effort,
    pairs,
    raw_positions,
    subdivide_times,
)

__all__ = ["RefineStage", "asks_refine", "check_parameters", "check_radii", "check_radius",
           "check_refine_flag", "targets"]


# the messages of the parameter checks (one source; the CLI prints them as they are)
_MSG_RADIUS = ("`{name}` must be a finite real number >= 0 (a length in the scene's units), "
               "got {value!r}")
_MSG_WAYPOINTS = ("`waypoints` must be a power of two from 1 to {max} (sub-pieces per piece of "
                  "the raw path), got {value!r}")
_MSG_STEPS = "`steps` must be an int from 1 to {max} (refinement steps), got {value!r}"
_MSG_REFINE = "`refine` must be True or False, got {value!r}"
MSG_PLAN = "refine() takes a Plan or a PlanBatch returned by pmplan, got {value}"
MSG_REFINED = ("this plan is already refined (radius {radius}); refine the unrefined plan "
                "(plan(..., refine=False)) with the radii you want")
MSG_REFINE_OUT = ("`out=` cannot be combined with refine=True (a refined batch has more "
                   "breakpoints): plan into `out`, then call pmplan.refine on it")
MSG_REFINE_DASK = ("refine() takes a computed batch, and this PlanBatch holds dask arrays: "
                    "plan it with refine=True (plan_batch on dask arrays then refines every "
                    "block lazily), or compute it first (pmplan.scale.compute)")
_MSG_RADII_UNREFINED = ("`radius` and `obstacle_radius` apply to refined motions: pass "
                        "refine=True (or call pmplan.refine on the plan)")
_MSG_TOO_CLOSE = ("{what}: {pair} are {dist:.6g} apart{where}, closer than {need} = "
                  "{value:.6g}; move them apart or use smaller radii")


def _is_real(x) -> bool:
    return isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(
        x, (bool, np.bool_))


def check_radius(value, name: str) -> float:
    """``value`` as a float if it is a finite real >= 0 (not a bool), else an InputError."""
    if not _is_real(value) or not math.isfinite(float(value)) or float(value) < 0:
        raise InputError(_MSG_RADIUS.format(name=name, value=value))
    return float(value)


def check_parameters(radius, obstacle_radius, waypoints, steps, n: int = 1, d: int = 2):
    """Validate the refinement parameters; return ``(radius, obstacle_radius, waypoints,
    steps)`` with the defaults for plans of ``n`` robots in R^d filled in
    (:func:`~pmplan.refine.grid.default_effort`). Raises :class:`~pmplan.errors.InputError`
    naming the parameter and what it must be.

    Examples
    --------
    >>> check_parameters(0, 0.5, None, None)
    (0.0, 0.5, 4, 56)
    >>> check_parameters(0, 0.5, None, None, n=16)
    (0.0, 0.5, 4, 112)
    >>> check_parameters(0, 0.5, None, None, n=16, d=3)
    (0.0, 0.5, 4, 112)
    >>> check_parameters(-1.0, 0, None, None)
    Traceback (most recent call last):
    ...
    pmplan.errors.InputError: `radius` must be a finite real number >= 0 (a length in the scene's units), got -1.0
    """
    radius = check_radius(radius, "radius")
    obstacle_radius = check_radius(obstacle_radius, "obstacle_radius")
    default_waypoints, default_steps = default_effort(n, d)
    if waypoints is None:
        waypoints = default_waypoints
    elif (isinstance(waypoints, (bool, np.bool_)) or not isinstance(waypoints, (int, np.integer))
          or not 1 <= waypoints <= MAX_WAYPOINTS or waypoints & (waypoints - 1)):
        raise InputError(_MSG_WAYPOINTS.format(max=MAX_WAYPOINTS, value=waypoints))
    if steps is None:
        steps = default_steps
    elif (isinstance(steps, (bool, np.bool_)) or not isinstance(steps, (int, np.integer))
          or not 1 <= steps <= MAX_STEPS):
        raise InputError(_MSG_STEPS.format(max=MAX_STEPS, value=steps))
    return radius, obstacle_radius, int(waypoints), int(steps)


def check_refine_flag(refine, radius, obstacle_radius) -> bool:
    """The ``refine=`` argument of the planning functions: a bool; radii without it are refused
    (they would be silently ignored)."""
    if not isinstance(refine, (bool, np.bool_)):
        raise InputError(_MSG_REFINE.format(value=refine))
    if not refine:
        check_radius(radius, "radius")
        check_radius(obstacle_radius, "obstacle_radius")
        if radius != 0 or obstacle_radius != 0:
            raise InputError(_MSG_RADII_UNREFINED)
    return bool(refine)


# --- the radii -------------------------------------------------------------------------------

def targets(radius: float, obstacle_radius: float, raw_clearance: np.ndarray) -> np.ndarray:
    """The target distances (B, 2): ``2 radius`` (robot-robot) and ``radius + obstacle_radius``
    (robot-obstacle), each replaced by ``KAPPA`` times the raw clearance when it is 0."""
    c = KAPPA * np.asarray(raw_clearance, dtype=float)
    rr = 2.0 * radius
    ro = radius + obstacle_radius
    return np.stack([c if rr == 0 else np.full(c.shape, rr),
                     c if ro == 0 else np.full(c.shape, ro)], axis=1)


def check_radii(obstacles: np.ndarray, configs: list, radius: float, obstacle_radius: float,
                batched: bool, backend=None) -> None:
    """Raise :class:`~pmplan.errors.CollisionError` (an InputError) if a configuration the path
    must pass through (start, goal, intermediate) violates the radii: two robots closer than
    ``2 radius`` or a robot closer than ``radius + obstacle_radius`` to an obstacle (exact)."""
    if radius == 0 and obstacle_radius == 0:
        return
    names = configuration_names(len(configs))
    m = obstacles.shape[1]
    full = np.concatenate([np.concatenate([obstacles, c], axis=1) for c in configs])
    wp = np.stack([full, full], axis=1)  # constant paths, (r B, 2, P, d)
    ok = None
    measured = None if backend is None else \
        backend.measure(wp, m, (2.0 * radius, radius + obstacle_radius))
    if measured is not None:  # the backend's measure; exact when close
        _, kept, close = measured
        if not close.any():
            ok = kept
    if ok is None:
        _, _, ok = radius_report(wp, m, radius, obstacle_radius)
    if ok.all():
        return
    k, i = divmod(int(np.flatnonzero(~ok)[0]), obstacles.shape[0])
    _raise_too_close(full[k * obstacles.shape[0] + i], m, radius, obstacle_radius, names[k],
                     i if batched else None)


def _raise_too_close(conf, m, radius, obstacle_radius, name, index) -> None:
    p = conf.shape[0]
    a, b, _ = pairs(p, m)
    label = [f"o{k + 1}" for k in range(m)] + [f"x{k + 1}" for k in range(p - m)]
    for pa, pb in zip(a, b):  # (check_radii's decision is exact: one pair is too close)
        need, value = (("2 * radius", 2 * Fraction(radius)) if pa >= m else
                       ("radius + obstacle_radius", Fraction(radius) + Fraction(obstacle_radius)))
        if exact_segment_dist2(conf[pa], conf[pb], conf[pa], conf[pb]) < value * value:
            break
    dist = exact_segment_clearance(conf[pa], conf[pb], conf[pa], conf[pb])
    pa, pb, value = label[pa], label[pb], float(value)
    where = f" in query {index}" if index is not None else ""
    raise CollisionError(
        _MSG_TOO_CLOSE.format(what=f"the {name} configuration" if name in ("start", "goal")
                              else name, pair=f"points {pa} and {pb}",
                              dist=dist, where=where, need=need, value=value),
        index=index, which=name, pair=(pa, pb))


# --- the stage: refine a batch chunk by chunk, certified ---------------------------------------

_MSG_FAILED = ("the refined path failed its certificate{where}: {what}; the query is too nearly "
               "degenerate for the refinement in double precision: use the unrefined plan "
               "(refine=False); nothing was returned")


class RefineStage(Stage):
    """The refinement of a batch of certified paths as a stage of the run loop
    (:func:`pmplan.running.run_stage`): per chunk, the kernel (:mod:`pmplan.refine.kernel`)
    or the numpy reference (:func:`~pmplan.refine.reference.refine_paths`), then the whole certificate (clauses 1-9 by
    :func:`pmplan.certify.check_paths`, the clearance by :func:`pmplan.certify.clearance` or the
    kernel's measurement in its arithmetic; never skipped) and the radii (:func:`~pmplan.certify.radius_report`).

    Parameters
    ----------
    times : ndarray, shape (K,) or (B, K)
    waypoints : ndarray, shape (B, K, P, d)
        The certified raw paths (not modified).
    clearance : ndarray, shape (B,)
        Their clearance (the targets when a radius is 0, see :func:`targets`).
    m : int
        Obstacles (the first m points).
    fixed : sequence of int, length r
        The raw waypoints the path passes through its r configurations (start, intermediate
        ones at ``k / (r - 1)``, goal): :meth:`pmplan.planners.base.Planner.fixed_waypoints`.
        The refinement keeps them exactly (at the refined waypoint where raw waypoint
        ``fixed[k]`` is, :func:`~pmplan.refine.grid.raw_positions`).
    radius, obstacle_radius : float
    waypoints_per_piece, steps : int
    backend : str or None
        ``"numpy"``: the reference; else the kernel.
    box : ndarray, shape (2, d), optional
        The workspace.
    still : tuple of bool, length K - 1, optional
        The raw pieces that stand still for almost every query, one sub-piece each
        (:meth:`pmplan.planners.base.Planner.still_pieces`); None: every piece is cut.
    """

    chunk = 512
    label = "refining"

    def __init__(self, times, waypoints, clearance, m: int, fixed, radius: float,
                 obstacle_radius: float, waypoints_per_piece: int, steps: int, backend=None,
                 box=None, still=None):
        self.box = box  # the workspace (2, d), or None (pmplan.workspace)
        self.raw_times = np.asarray(times, dtype=float)
        self.raw = waypoints
        self.size = waypoints.shape[0]
        self.fixed = [int(kj) for kj in fixed]
        self.m, self.r = m, len(self.fixed)
        self.radius, self.obstacle_radius = radius, obstacle_radius
        self.s, self.steps = waypoints_per_piece, steps
        self.backend = select(backend)
        self.raw_clearance = np.asarray(clearance, dtype=float)
        self.target = targets(radius, obstacle_radius, clearance)
        k = self.raw_times.shape[-1]
        self.still = None if still is None else tuple(bool(v) for v in still)
        self.at = raw_positions(k, self.s, self.still)  # the raw waypoints in the refined grid
        w = int(self.at[-1]) + 1
        b, _, p, d = waypoints.shape
        self.times = subdivide_times(self.raw_times, self.s, self.still)
        self.waypoints = np.empty((b, w, p, d))
        self.clearance = np.empty(b)
        self.robot_distance = np.empty(b)
        self.obstacle_distance = np.empty(b)
        self.respects = np.empty(b, dtype=bool)
        self.clause = np.zeros(b, np.uint8)

    def _refine(self, times, wp, target, walls=None):
        """The map in the frame, by the backend (:func:`pmplan.backends.select`)."""
        return self.backend.refine(times, wp, self.m, self.r, target, self.s, self.steps, walls,
                                   self.still)

    def _walls(self, b: int, back):
        """The workspace's limits in the frame (B, 2, d), or None: the robots should keep to
        the inner box where the final map into the box is the identity
        (:func:`pmplan.workspace.identity_box`)."""
        if self.box is None:
            return None
        inner = identity_box(shrunk(self.box, self.radius), SQUEEZE)
        return np.ascontiguousarray(
            limits_to_frame(np.broadcast_to(inner, (b,) + inner.shape), back))

    def run(self, lo: int, hi: int) -> np.ndarray:
        raw = self.raw[lo:hi]
        times = self.raw_times if self.raw_times.ndim == 1 else self.raw_times[lo:hi]
        y, tgt, back = to_frame(raw, self.target[lo:hi])
        out = self.waypoints[lo:hi]
        ref = self._refine(times, y, tgt, self._walls(hi - lo, back))[1]
        out[...] = from_frame(ref, back)
        # the obstacles, and every raw waypoint the refinement left in place (the fixed
        # configurations, a padded row's repeated goal), exactly: the frame rounds them
        out[:, :, :self.m] = raw[:, :1, :self.m]
        at = self.at
        same = (ref[:, at] == y).all(axis=-1)  # (B, K, P)
        kept = out[:, at]
        kept[same] = raw[same]
        out[:, at] = kept
        for kj in self.fixed:
            out[:, at[kj]] = raw[:, kj]
        if self.box is not None:  # into the box shrunk by the radius (pmplan.workspace)
            out[...] = self.backend.into_box(out, shrunk(self.box, self.radius), SQUEEZE)
            restore(out, self.m, [at[kj] for kj in self.fixed],
                    [raw[:, kj, self.m:] for kj in self.fixed], raw[:, 0, :self.m])
        self._certify(lo, hi, raw, out, np.zeros(hi - lo, dtype=bool))
        return self.clause[lo:hi] == 0

    def _certify(self, lo, hi, raw, out, exact) -> None:
        """The whole certificate of the refined rows (clauses 1-9 by
        :func:`pmplan.certify.check_paths`; the clearance, clause 10, and the radii by the
        kernel's measurement in the certificate's arithmetic, re-decided by
        :func:`pmplan.certify.clearance` and :func:`~pmplan.certify.radius_report` where it flags a row --
        or by them alone)."""
        m, r = self.m, self.r
        tt = self.times if self.times.ndim == 1 else self.times[lo:hi]
        configs = [raw[:, kj] for kj in self.fixed]
        via = [(j / (r - 1), configs[j]) for j in range(1, r - 1)]
        with np.errstate(all="ignore"):
            clause = check_paths(tt, out, configs[0], configs[-1], m, via)
        clr = self.clearance[lo:hi]
        rd, od, ok = (self.robot_distance[lo:hi], self.obstacle_distance[lo:hi],
                      self.respects[lo:hi])
        measured = self.backend.measure(out, m, (2.0 * self.radius,
                                                 self.radius + self.obstacle_radius))
        if measured is not None:
            vals, kept, close = measured
            clr[:], rd[:], od[:] = vals[:, 0], vals[:, 1], vals[:, 2]
            ok[:] = kept
            redo = np.flatnonzero(exact | close)
        else:
            redo = np.arange(hi - lo)
        if redo.size:
            sub = out[redo]
            with np.errstate(all="ignore"):  # (clauses 1-9 are in ``clause`` already)
                clr[redo] = clearance(sub, m)
                rd[redo], od[redo], ok[redo] = radius_report(sub, m, self.radius,
                                                             self.obstacle_radius)
        clause[(clause == 0) & ~(clr > 0)] = CLEARANCE
        if self.box is not None:  # the walls are part of the radii: exact comparisons
            ok &= inside(out, self.box, self.radius)
            clause[(clause == 0) & ~inside(out, self.box)] = CLEARANCE
        self.clause[lo:hi] = clause

    def fail(self, bad: np.ndarray) -> None:
        idx = np.flatnonzero(bad)
        where = f" for queries {idx[:10].tolist()}{'...' if idx.size > 10 else ''}" \
            if self.size > 1 else ""
        raise CertificationError(
            _MSG_FAILED.format(where=where, what=describe(int(self.clause[idx[0]]))),
            indices=idx)

    def extra(self) -> dict:
        """The refinement record of the batch (:attr:`pmplan.results.PlanBatch._extra`)."""
        b = self.size
        return {"radius": np.full(b, self.radius), "obstacle_radius": np.full(b, self.obstacle_radius),
                    "refined": np.ones(b, dtype=bool), "robot_distance": self.robot_distance,
                    "obstacle_distance": self.obstacle_distance, "respects_radius": self.respects,
                    "raw_clearance": self.raw_clearance,
                    **({} if self.box is None else
                       {"bounds": np.broadcast_to(self.box, (b,) + self.box.shape)})}


def asks_refine(refine, radius, obstacle_radius, out=None) -> bool:
    """Whether a planning function was asked ``refine=True`` (the flag and the radii checked:
    :func:`pmplan.refine.stage.check_refine_flag`; radii without the flag are refused, and so is
    ``out=`` with it: a refined batch has other shapes)."""
    if refine is False and type(radius) is float and type(obstacle_radius) is float \
            and radius == 0.0 and obstacle_radius == 0.0:
        return False
    if check_refine_flag(refine, radius, obstacle_radius):
        check_parameters(radius, obstacle_radius, None, None)
        if out is not None:
            raise InputError(MSG_REFINE_OUT)
        return True
    return False
