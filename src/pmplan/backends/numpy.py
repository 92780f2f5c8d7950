"""The numpy backend: every planner's reference (:meth:`pmplan.planners.base.Planner.reference`,
exact, in numpy), certified by :func:`pmplan.certify.certificate`; the refinement's reference
map (:func:`pmplan.refine.reference.refine_paths`); the maps of a workspace box
(:mod:`pmplan.workspace`). The functions of :mod:`pmplan.backends`."""

from __future__ import annotations

import numpy as np

from .. import workspace
from ..certify import certificate

__all__ = ["NAME", "arrays", "available", "certify", "from_box_linear", "into_box", "measure",
           "path_into_box_linear", "plan", "plan_rows", "refine", "sequence_query",
           "single_query", "validates"]

NAME = "numpy"


def available() -> bool:
    """Always: numpy is a dependency."""
    return True


def arrays(planner, obstacles, configs):
    """None: :meth:`~pmplan.planners.base.Planner.plan` with this backend is the reference."""
    return None


def validates(planner, d: int) -> bool:
    """False: the input is validated apart (:mod:`pmplan.configuration`)."""
    return False


def single_query(planner, m: int, n: int, d: int):
    """None: one query is a batch of one here."""
    return None


def sequence_query(planner, r: int, m: int, n: int, d: int):
    """None: one query is a batch of one here."""
    return None


def certify(waypoints, start, goal, m: int, *, times=None, via=()):
    """The certificate of paths, ``(clearance, codes)``: :func:`pmplan.certify.certificate`."""
    return certificate(waypoints, start, goal, m, times=times, via=via)


def plan(planner, obstacles, configs, lift, out: dict, validate: bool = False,
         down: np.ndarray | None = None) -> np.ndarray:
    """Plan every row of a chunk with the reference into ``out`` and certify it; return the
    certificate (B,) bool (:func:`plan_rows`)."""
    obstacles = np.asarray(obstacles, dtype=float)
    configs = [np.asarray(c, dtype=float) for c in configs]
    return plan_rows(planner, obstacles, configs, lift, np.arange(obstacles.shape[0]), out,
                     down)


def plan_rows(planner, obstacles, configs, lift, idx, out: dict,
              down: np.ndarray | None = None) -> np.ndarray:
    """Plan rows ``idx`` of a chunk with the reference, write them into ``out`` and certify
    them (:func:`pmplan.certify.certificate`, intermediate configurations included); return the
    certificate of those rows (bool, (len(idx),)). Kernels call it for the rows they leave to
    the reference. ``down`` (the chunk's, a :attr:`~pmplan.planners.base.Planner.robot_side`
    planner only) goes to its :meth:`~pmplan.planners.base.Planner.reference`."""
    obs = obstacles[idx]
    cfg = [c[idx] for c in configs]
    r = len(cfg)
    sides = {} if down is None else {"down": down[idx]}
    with np.errstate(all="ignore"):  # what overflows (coordinates ~1e308) fails the certificate
        raw = planner.reference(obs, cfg, lift, **sides)
    pw = raw.path.waypoints
    out["waypoints"][idx] = pw
    out["domain"][idx] = raw.domain
    out["strata"][idx] = raw.strata
    if out["times"].ndim == 2:
        out["times"][idx] = raw.path.times
    full = [np.concatenate([obs, c], axis=1) for c in cfg]
    via = [(k / (r - 1), full[k]) for k in range(1, r - 1)]
    with np.errstate(all="ignore"):  # a non-finite path: NaN clearance, a failed clause
        clr, codes = certificate(pw, full[0], full[-1], obs.shape[1], times=raw.path.times,
                                 via=via)
    out["clearance"][idx] = clr
    return codes == 0


def measure(waypoints, m: int, need):
    """None: the refined paths are measured exactly by the reference
    (:func:`pmplan.certify.clearance`, :func:`pmplan.certify.radius_report`)."""
    return None


def refine(times, waypoints, m: int, r: int, target, s: int, steps: int, walls=None,
           still=None):
    """The refinement's map, the reference (:func:`pmplan.refine.reference.refine_paths`)."""
    from ..refine.reference import refine_paths  # (the refinement imports the backends: not at import)

    return refine_paths(times, waypoints, m, r, target, s, steps, walls, still)


def from_box_linear(x, box, frac: float):
    """Points of the box mapped out of it, the reference (:func:`pmplan.workspace.from_box_linear`)."""
    return workspace.from_box_linear(x, box, frac)


def into_box(z, box, frac: float):
    """The algebraic map into the box, the reference (:func:`pmplan.workspace.into_box`)."""
    return workspace.into_box(z, box, frac)


def path_into_box_linear(times, waypoints, box, frac: float, width: int | None = None):
    """The exact image of paths in the box, the reference
    (:func:`pmplan.workspace.path_into_box_linear`)."""
    return workspace.path_into_box_linear(times, waypoints, box, frac, width)
