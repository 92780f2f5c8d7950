"""The planners. Importing this package registers every planner in ``base.REGISTRY``.

* ``obstacle_line`` -- paper Section 3 and its extensions (SPEC 4a, 4b, 4c).
* ``planar_three`` -- paper Section 4 (d = 2, n = 1, m = 3).
"""

from .base import REGISTRY, Planner, RawPlan
from .obstacle_line import OBSTACLE_LINE

try:  # the planar planner is optional while it is being built
    from .planar_three import PLANAR_THREE  # noqa: F401
except ImportError:  # pragma: no cover
    pass

__all__ = ["REGISTRY", "Planner", "RawPlan", "OBSTACLE_LINE"]
