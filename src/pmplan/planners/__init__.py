"""The planners. Importing this package registers every planner in ``base.REGISTRY``.

* ``obstacle_line`` -- paper Section 3 and its extensions (Mathematics §4.1-§4.3).
* ``obstacle_line_compact`` -- the same with compact lanes (Mathematics §4.4), the default.
* ``obstacle_line_shared`` -- the compact lanes shared by robots that keep their order
  (Mathematics §4.4).
* ``obstacle_line_oneside`` -- the shared lanes all on one side of the line (Mathematics §4.4).
* ``obstacle_line_walls`` -- the one-side lanes, in a box on the side the walls leave the most
  room (Mathematics §8).
* ``obstacle_line_robots`` -- the one-side lanes, in a box with a side per robot
  (Mathematics §8).
* ``planar_three`` -- paper Section 4 (d = 2, n = 1, m = 3).

A new planner is one module here that subclasses :class:`~pmplan.planners.base.Planner` and
calls :func:`~pmplan.planners.base.register`, plus its import below. An import error of a
planner is an error of pmplan (never swallowed: a missing planner would silently route its
queries to another one).
"""

from .base import REGISTRY, Planner, RawPlan, default_planner
from .obstacle_line import (
    OBSTACLE_LINE,
    OBSTACLE_LINE_COMPACT,
    OBSTACLE_LINE_ONESIDE,
    OBSTACLE_LINE_ROBOTS,
    OBSTACLE_LINE_SHARED,
    OBSTACLE_LINE_WALLS,
)
from .planar_three import PLANAR_THREE

__all__ = ["REGISTRY", "Planner", "RawPlan", "OBSTACLE_LINE", "OBSTACLE_LINE_COMPACT",
           "OBSTACLE_LINE_ONESIDE", "OBSTACLE_LINE_ROBOTS", "OBSTACLE_LINE_SHARED",
           "OBSTACLE_LINE_WALLS", "PLANAR_THREE", "default_planner"]
