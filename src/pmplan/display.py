"""What the faces show of a planner -- how a domain label is written, the named phases of the
pieces of a motion, the lines on the explore page where a point's label changes -- kept apart
from the planner's mathematics (:mod:`pmplan.planners.base`), as :mod:`pmplan.strata` keeps what
``pmplan verify`` needs of it.

Every planner has a :class:`DisplaySpec` here, its class's or its nearest ancestor's
(:func:`display_for`); the faces (the CLI, :mod:`pmplan.verify`, :mod:`pmplan.animation`, the
web page) ask it, never a planner's name.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from .planners.base import Planner, spec_of_class
from .planners.obstacle_line import ObstacleLinePlanner
from .planners.planar_three import PlanarThreePlanner
from .predicates import projection_classes

__all__ = ["DISPLAYS", "DisplaySpec", "ObstacleLineDisplay", "PlanarDisplay", "display_for"]


class DisplaySpec:
    """The protocol, with the defaults of a planner that decides on columns."""

    #: how the faces write domain label l: ``f"{domain_prefix}{l}"`` (``W_5``)
    domain_prefix: ClassVar[str] = "W_"
    #: the named phases ``(name, what happens)`` of the pieces of a path, for the faces that
    #: show a motion (:func:`pmplan.animation.phase_at`): several -- the phases of every leg
    #: between two configurations, in order; one -- every piece is of that kind; none -- the
    #: pieces are unnamed
    phases: ClassVar[tuple[tuple[str, str], ...]] = ()

    def map_boundaries(self, obstacles, others) -> list[tuple[np.ndarray, np.ndarray]]:
        """Return the lines of the plane on which the label of one moving point changes.

        The moving point is one robot's start (or goal); ``obstacles`` (m, 2) and ``others``
        (k, 2), the other robots of the same configuration, stay where they are. Its label
        changes exactly where its column meets another point's column (Mathematics §3.6,
        §4.2), so the default is the column line through every other point.

        Parameters
        ----------
        obstacles : numpy.ndarray
            The obstacles, shape (m, 2).
        others : numpy.ndarray
            The other robots' points of the mapped configuration, shape (k, 2).

        Returns
        -------
        list of tuple
            ``(point, direction)`` pairs of float arrays of shape (2,), one per line, with
            ``direction`` a unit vector; points on one column give one line.
        """
        o = np.asarray(obstacles, dtype=float)
        pts = np.concatenate([o, np.asarray(others, dtype=float).reshape(-1, 2)])
        e = (o[1] - o[0]) / np.hypot(*(o[1] - o[0]))
        nu = np.array([-e[1], e[0]])
        labels = projection_classes(pts[None], o[0][None], o[1][None])[0][0]
        first = [int(np.flatnonzero(labels == lab)[0]) for lab in np.unique(labels)]
        return [(pts[k], nu) for k in sorted(first)]


class ObstacleLineDisplay(DisplaySpec):
    """The obstacle-line planner's: the seven phases of every leg."""

    #: the seven phases of every leg (Mathematics §3, paper Section 3), one piece each
    phases = (
        ("desingularization", "robots step along e off shared columns, paper (3.2)"),
        ("projection to the line",
         "robots move straight onto L_C, paper (3.6)"),
        ("lift", "robot i rises by i*lambda*nu(e), section of paper (3.8)"),
        ("slide", "robots slide parallel to L_C from X to X', section of paper (3.8)"),
        ("descend", "robots descend onto L_C at X', section of paper (3.8)"),
        ("projection reversed", "robots lift back off the line to F(C', 1)"),
        ("desingularization reversed", "robots step back along e to C', paper (3.2) reversed"),
    )


class PlanarDisplay(DisplaySpec):
    """The planar three-obstacle planner's: one kind of piece, and its strata's boundaries."""

    phases = (
        ("polyline leg", "straight leg of the polyline of paper Section 4, at constant speed"),
    )

    def map_boundaries(self, obstacles, others) -> list[tuple[np.ndarray, np.ndarray]]:
        """Return the lines on which the stratum of the robot's start (goal) changes.

        With o3 exactly on the line o1o2 (the family ``T1_ij``) the stratum depends on the
        robot's height only: the boundary is that line. Otherwise (``T22_rs``, ``T23_kl``) it
        depends on the robot's column: the boundaries are the obstacles' columns
        (Mathematics §5.2).

        Parameters
        ----------
        obstacles : numpy.ndarray
            The three obstacles, shape (3, 2).
        others : numpy.ndarray
            The other robots' points (none: n = 1), shape (0, 2).

        Returns
        -------
        list of tuple
            ``(point, direction)`` pairs, ``direction`` a unit vector.
        """
        o = np.asarray(obstacles, dtype=float)
        heights = projection_classes(o[None], o[0][None], o[1][None], perpendicular=True)[1]
        if int(heights[0]) == 1:  # o3 on L_C: heights decide
            return [(o[0], (o[1] - o[0]) / np.hypot(*(o[1] - o[0])))]
        return super().map_boundaries(obstacles, others)


#: what the faces show of every planner class (a subclass gets its nearest ancestor's)
DISPLAYS: dict[type, DisplaySpec] = {Planner: DisplaySpec(),
                                     ObstacleLinePlanner: ObstacleLineDisplay(),
                                     PlanarThreePlanner: PlanarDisplay()}


def display_for(planner) -> DisplaySpec:
    """The :class:`DisplaySpec` of ``planner`` (a planner, or the name of a registered one)."""
    return spec_of_class(DISPLAYS, planner)
