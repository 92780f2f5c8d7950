"""pmplan: optimal parametrised motion planners for point robots among point obstacles.

Implements the explicit planners of Zapata & Gonzalez, *Parametrised collision-free optimal
motion planning algorithms in Euclidean spaces*, and their extensions (see the Mathematics page of the documentation, docs/mathematics.md).

>>> import pmplan
>>> p = pmplan.plan([[0, 0], [2, 0]], [[1, 1]], [[1, -1]])
>>> p.domain, p.stratum, p.clearance > 0
(6, 'T_{3,3}', True)
"""

from .api import (
    Plan,
    PlanBatch,
    PlannerInfo,
    choose_planner,
    info,
    parametrised_tc,
    plan,
    plan_batch,
    plan_configurations,
    plan_query,
    plan_sequence,
    plan_sequence_batch,
    planner_names,
    refine,
)
from .errors import (
    CertificationError,
    CollisionError,
    InputError,
    NonFiniteError,
    ObstacleMismatchError,
    PmplanError,
    ShapeError,
    StoreError,
    UnsupportedError,
)
from .path import PiecewiseLinearPath
from .version import __version__  # noqa: F401  (pmplan.__version__)

__all__ = [
    "Plan",
    "PlanBatch",
    "PlannerInfo",
    "PiecewiseLinearPath",
    "choose_planner",
    "info",
    "parametrised_tc",
    "plan",
    "plan_batch",
    "plan_configurations",
    "plan_query",
    "plan_sequence",
    "plan_sequence_batch",
    "planner_names",
    "refine",
    "PmplanError",
    "InputError",
    "ShapeError",
    "NonFiniteError",
    "CollisionError",
    "ObstacleMismatchError",
    "UnsupportedError",
    "CertificationError",
    "StoreError",
]
