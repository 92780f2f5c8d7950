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

__all__ = ["RawPlan", "Planner", "REGISTRY", "register"]


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
        """Plan a batch of queries."""

    def stratum_name(self, strata_row, d: int, n: int, m: int) -> str:
        """Human-readable stratum name in the paper's notation."""


REGISTRY: dict[str, Planner] = {}


def register(planner: Planner) -> Planner:
    """Add a planner instance to the registry under its ``name``."""
    REGISTRY[planner.name] = planner
    return planner
