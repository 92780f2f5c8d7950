"""What a planner is: data computed from arrays (labels, strata, a batch of paths).

A planner takes a batch of queries -- obstacles (B, m, d), starts (B, n, d), goals (B, n, d) --
and returns a :class:`RawPlan`: the domain label of every query, a small integer record of its
stratum, and the batch of piecewise-linear paths. It does not validate, certify, draw, print or
read files; :mod:`pmplan.api` does those.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Protocol

import numpy as np

from ..path import PiecewiseLinearPath

__all__ = ["RawPlan", "Planner", "REGISTRY", "SCENE_CODE", "lift_code", "register", "scene_unit",
           "unit"]

#: how the planners and their kernels receive ``lift="scene"``: a ``lift`` that is not > 0.
#: A positive lift is the unit itself; SCENE_CODE (0.0) asks for the unit u(O) of every query
#: (:func:`scene_unit`), computed by the numpy reference and by the numba kernels alike. A
#: float (not a string or an array), so the kernels keep one signature and scaling the lift
#: by a power of two keeps its meaning.
SCENE_CODE = 0.0


def lift_code(lift) -> float:
    """The float a planner takes for ``lift``: the unit itself, or :data:`SCENE_CODE` for
    ``"scene"`` (the input is already checked, see :func:`pmplan.configuration.as_lift`)."""
    return SCENE_CODE if isinstance(lift, str) else float(lift)


def scene_unit(obstacles: np.ndarray) -> np.ndarray:
    """Return ``u(O) = max_{k >= 2} |o_k - o_1|`` of every query, shape (B,).

    The unit of ``lift="scene"``: the obstacles' radius about o1. It depends on the obstacles
    alone (so it is the same for start and goal and for every configuration of a sequence, and
    the planners stay continuous on every domain), is positive (the obstacles are distinct),
    invariant under translations and rotations and linear in scalings, so that the paths are
    equivariant. Computed as ``sqrt(max_k sum_c (o_k,c - o_1,c)^2)`` with the sum over the d
    coordinates in order -- the operations (and their order) of the numba kernels, which
    reproduce it bitwise (``sqrt`` is monotone and correctly rounded, so the maximum may be
    taken before it).
    """
    diff = obstacles[:, 1:] - obstacles[:, :1]
    return np.sqrt((diff * diff).sum(-1).max(axis=1))


def unit(obstacles: np.ndarray, lift: float) -> np.ndarray:
    """The unit of every query of a batch (B,): ``lift`` when it is positive, else (for
    :data:`SCENE_CODE` or ``"scene"``) :func:`scene_unit`."""
    lift = lift_code(lift)
    if lift > 0:
        return np.full(obstacles.shape[0], float(lift))
    return scene_unit(obstacles)


@dataclass
class RawPlan:
    """Output of a planner on a batch of B queries.

    Attributes
    ----------
    domain : ndarray of int64, shape (B,)
        The label ``l`` of the domain of continuity ``W_l`` of each query.
    strata : ndarray of int64, shape (B, S)
        Planner-specific integers that name the stratum (see ``Planner.stratum_name``).
    path : PiecewiseLinearPath
        Batch of paths, waypoints of shape (B, K, m+n, d).
    """

    domain: np.ndarray
    strata: np.ndarray
    path: PiecewiseLinearPath


class Planner(Protocol):
    """The interface every planner module implements (see ``obstacle_line``, ``planar_three``)."""

    name: ClassVar[str]
    summary: ClassVar[str]

    def supports(self, d: int, n: int, m: int) -> str | None:
        """Return None if (d, n, m) is covered, else a sentence saying why not."""

    def domain_labels(self, d: int, n: int, m: int) -> list[int]:
        """All domain labels the planner uses for (d, n, m)."""

    def plan(self, obstacles, start, goal, *, lift: float = 1.0) -> RawPlan:
        """Plan a batch of queries with the unit ``lift`` (a positive float, or
        :data:`SCENE_CODE` for the unit :func:`scene_unit` of every query)."""

    def stratum_name(self, strata_row, d: int, n: int, m: int) -> str:
        """Human-readable stratum name in the paper's notation."""


REGISTRY: dict[str, Planner] = {}


def register(planner: Planner) -> Planner:
    """Add a planner instance to the registry under its ``name``."""
    REGISTRY[planner.name] = planner
    return planner
