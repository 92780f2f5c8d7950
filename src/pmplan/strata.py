"""What ``pmplan verify`` needs of a planner: its strata, exact queries in them, moves inside
them, and the notes to read a check by -- kept apart from the planner's mathematics
(the package ``pmplan.planners``), as OMPL keeps a planner apart from its benchmark specifications.

Every planner has a :class:`StrataSpec` here, its class's or its nearest ancestor's
(:func:`spec_for`): :class:`ColumnStrata` for a planner that decides on columns as the
obstacle-line planner does (the column strata of the query space, paper Section 3;
:func:`pmplan.generators.strata`), :class:`PlanarStrata` for the 12 strata of paper Section 4.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from . import generators as gen
from .planar_strata import STRATA
from .planners.base import Planner, spec_of_class
from .planners.obstacle_line import POLE_NOTE, ObstacleLinePlanner
from .planners.planar_three import PlanarThreePlanner, classify

__all__ = ["ColumnStrata", "PlanarStrata", "SPECS", "StrataSpec", "spec_for"]


class StrataSpec:
    """The protocol: what :mod:`pmplan.verify` asks of a planner's strata."""

    #: the planner decides on heights (distance to the line L_C) as well as on columns: the
    #: degeneracy of a query (:func:`pmplan.verify.degeneracy_ratio`) counts its heights too
    uses_heights: ClassVar[bool] = False

    def stratum_count(self, d: int, n: int, m: int) -> int:
        """The number of strata :meth:`exact_queries` cycles through for (d, n, m)."""
        raise NotImplementedError

    def exact_queries(self, rng: np.random.Generator, d: int, n: int, m: int, count: int
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """At least ``count`` exact degenerate queries covering every stratum, round robin (the
        first :meth:`stratum_count` queries meet every stratum): obstacles (B, m, d), starts and
        goals (B, n, d)."""
        raise NotImplementedError

    def near_degenerate_queries(self, rng: np.random.Generator, d: int, n: int, m: int,
                                count: int, scale: float
                                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``count`` exact degenerate queries whose ties are broken by about ``scale`` of the
        scene."""
        raise NotImplementedError

    def perturb_within_stratum(self, rng: np.random.Generator, query, delta: float):
        """Move one query (obstacles, start, goal) inside its stratum by about ``delta``; return
        the moved query, or None when the move left the stratum."""
        raise NotImplementedError

    def stratum_row(self, obstacles, start, goal) -> np.ndarray:
        """The record of the stratum of one query, decided exactly (what the planner's
        ``stratum_name`` reads)."""
        raise NotImplementedError

    def notes(self, d: int, n: int, m: int) -> list[str]:
        """Facts to read a check of (d, n, m) by (``pmplan verify`` prints them as notes)."""
        return []


class ColumnStrata(StrataSpec):
    """The column strata of the query space (paper Section 3; :func:`pmplan.generators.strata`),
    for a planner that decides on columns as the obstacle-line planner does."""

    def stratum_count(self, d: int, n: int, m: int) -> int:
        return len(gen.strata(d, n, m))

    def exact_queries(self, rng, d: int, n: int, m: int, count: int):
        """:func:`pmplan.generators.column_query` on every stratum of
        :func:`pmplan.generators.strata`, integer coordinates every other query."""
        obs, st, go = [], [], []
        table = gen.strata(d, n, m)
        for k in range(max(count, len(table))):
            s = table[k % len(table)]
            q = gen.column_query(rng, d, n, m, s.cp_start, s.cp_goal, cp_o=s.cp_o, pole=s.pole,
                                 integer=k % 2 == 0)
            obs.append(q.obstacles)
            st.append(q.start)
            go.append(q.goal)
        return np.stack(obs), np.stack(st), np.stack(go)

    def near_degenerate_queries(self, rng, d: int, n: int, m: int, count: int, scale: float):
        """:func:`pmplan.generators.near_degenerate_queries`."""
        return tuple(gen.near_degenerate_queries(rng, d, n, m, count, scale))

    def perturb_within_stratum(self, rng, query, delta: float):
        """:func:`pmplan.generators.perturb_within_stratum`."""
        return tuple(gen.perturb_within_stratum(rng, query, delta))

    def stratum_row(self, obstacles, start, goal) -> np.ndarray:
        """:func:`pmplan.generators.stratum_of`."""
        return np.asarray(gen.stratum_of((obstacles, start, goal)).record())


class ObstacleLineStrata(ColumnStrata):
    """The obstacle-line planner's: the column strata, and for odd d the note on the pole."""

    def notes(self, d: int, n: int, m: int) -> list[str]:
        """For odd d, :data:`~pmplan.planners.obstacle_line.POLE_NOTE` (the modulus of
        continuity near the pole)."""
        return [POLE_NOTE] if d % 2 == 1 else []


class PlanarStrata(StrataSpec):
    """The 12 strata of paper Section 4 (:data:`pmplan.planar_strata.STRATA`)."""

    uses_heights = True

    def stratum_count(self, d: int, n: int, m: int) -> int:
        return len(STRATA)

    def exact_queries(self, rng, d: int, n: int, m: int, count: int):
        """The same number of exact queries in every stratum
        (:func:`pmplan.generators.planar_stratum_queries`), round robin."""
        obs, st, go = [], [], []
        per = max(1, -(-count // len(STRATA)))
        for name in STRATA:
            o, s, g = gen.planar_stratum_queries(rng, name, per)
            obs.append(o)
            st.append(s)
            go.append(g)
        order = np.arange(per * len(STRATA)).reshape(len(STRATA), per).T.ravel()  # round robin
        return tuple(np.concatenate(a)[order] for a in (obs, st, go))

    def near_degenerate_queries(self, rng, d: int, n: int, m: int, count: int, scale: float):
        """The noise of :func:`pmplan.generators.near_degenerate_queries` on the exact queries
        of :meth:`exact_queries`."""
        q = self.exact_queries(rng, d, n, m, count)
        idx = rng.permutation(q[0].shape[0])[:count]
        return tuple(a[idx] + scale * (1 + np.abs(a[idx])) * rng.normal(size=a[idx].shape)
                     for a in q)

    def perturb_within_stratum(self, rng, query, delta: float):
        """An exact move inside the stratum, :func:`pmplan.generators.perturb_planar_stratum`."""
        return gen.perturb_planar_stratum(rng, query, delta)

    def stratum_row(self, obstacles, start, goal) -> np.ndarray:
        """The record ``(family, i, j)`` of one query,
        :func:`~pmplan.planners.planar_three.classify`."""
        return classify(obstacles[None], start[None], goal[None]).record[0]


#: the strata of every planner class (a planner of a subclass gets its nearest ancestor's):
#: the column strata for any planner that decides on columns
SPECS: dict[type, StrataSpec] = {Planner: ColumnStrata(), ObstacleLinePlanner: ObstacleLineStrata(),
                                 PlanarThreePlanner: PlanarStrata()}


def spec_for(planner) -> StrataSpec:
    """The :class:`StrataSpec` of ``planner`` (a planner, or the name of a registered one):
    the one of its class, or of its nearest ancestor in :data:`SPECS`."""
    return spec_of_class(SPECS, planner)
