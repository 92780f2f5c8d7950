"""Refined motions: a planner's path shortened and cleared by a fixed continuous map R.

Definition. For a planner ``s`` with domains of continuity ``W_1..W_k`` and a map ``R`` from
paths to paths that is **continuous**, keeps the endpoints, the intermediate configurations and
the obstacles fixed and never creates a collision, ``R o s`` is again a planner, continuous on
every ``W_l``: it has the same domains, hence the same number of them, and is optimal whenever
``s`` is (paper Section 2: the sectional category counts domains of continuous sections, and a
continuous map of sections keeps their domains). The refined plan keeps the domain label and the
stratum of the unrefined one.

The map ``R`` (:func:`refine_paths`) is a FIXED number of steps of a continuous update of the
waypoints at FIXED times -- no accept/reject, no line search, no stop on convergence, no random
numbers, no discrete choice (only min, max and clip of continuous quantities):

1. *Coarse-to-fine grid.* Every piece of the raw path is cut into ``s = 1, 2, 4, .., S`` equal
   sub-pieces (``S = waypoints``); going from ``s`` to ``2 s`` inserts the midpoint of every
   piece, which keeps the path (and its collision-freeness) and is continuous in the query. A
   piece the planner declares still (:meth:`pmplan.planners.base.Planner.still_pieces`: it
   moves no point for almost every query) stays one piece; the declaration depends on the
   number of configurations alone, so the grid is the same on every domain.
   Every raw breakpoint stays a breakpoint, so the intermediate configurations stay exactly at
   their times.
2. *Steps.* At each level, ``steps`` are split evenly; a step is a *clearing* substep followed
   by a *shortening* substep. At the coarsest level the clearing substep has two passes, the
   pushes at the waypoints then those at the closest points of the pieces; at the finer levels and in
   the final clearing-only steps, the second only. Shortening moves every interior
   waypoint a fraction
   :data:`ALPHA` toward the point of the chord of its two neighbours at its time (red-black:
   the odd waypoints first, then the even ones toward the moved odd ones); clearing
   pushes the two points of a pair apart at the waypoints (weight :data:`OMEGA`) and at the
   *push point* of every piece, along the pair's relative position there
   (:func:`~pmplan.refine.grid.push_points`: the closest point where the pair nearly touches
   mid-piece, so that the push is outward along the piece; Lipschitz in the piece's ends),
   the push shared by the two ends of the piece in the proportions of its
   *soft closest point* (:data:`~pmplan.refine.grid.LAMBDA`), by :data:`BETA` times the deficit ``max(T* - |x_a -
   x_b|, 0)`` below the push target
   ``T* = (1 + ETA) T``. Both moves are multiplied by a *mobility* in [0, 1], a continuous
   function of the times that is 0 at the fixed times (start, goal, intermediate
   configurations) and at zero-duration pieces.
3. *Collision-free by construction.* On a linear piece the relative position of two points is a
   convex combination of its values at the two ends, so if the ends of points a and b move by at
   most ``delta_a`` and ``delta_b`` the pair's distance anywhere on the piece changes by at most
   ``delta_a + delta_b``. Every move of point a at waypoint j is therefore scaled down (a
   continuous clip) to its *cap*: the minimum, over the pairs (a, b) and the two pieces adjacent
   to j, of ``c (D - F(D))`` where ``D`` is the exact closed-form minimum distance of the pair on
   that piece (the certificate's, :func:`pmplan.certify.segment_clearance`), ``F`` a floor below
   ``D`` and ``c = 1/2`` for two robots, ``1`` for a robot and an obstacle (which never moves).
   Then every distance stays above its floor: shortening uses ``F = min(T (1 + MARGIN), D)``
   (a pair at or above the target never goes below it), clearing uses ``F = PHI D`` below ``T``,
   rising continuously to ``T (1 + MARGIN)`` at ``T*``. The clearing spends half of that
   (:data:`SHARE`) isotropically, and may instead move a point further when the *inward* part
   of its move along the piece, ``max_t w(t) (-r(t).move)``, stays within its share of
   ``D^2 - F'^2`` (``|r + dr|^2 >= |r|^2 + 2 r.dr``; :func:`_clear_scale`): a pair that nearly
   touches is pushed out in steps that do not shrink with its distance.

The targets: ``T = 2 radius`` between robots and ``radius + obstacle_radius`` between a robot and
an obstacle; when a target is 0 (no radius asked), ``KAPPA`` times the raw plan's clearance, so
that the refined path keeps a clearance of the order of the raw one. Nothing here is an
absolute length: the map commutes with translations and rotations, and with scalings when the
radii scale too (bit for bit for powers of two).

The final path is certified exactly as every plan (:mod:`pmplan.certify`); the result also
reports the exact minimum robot-robot and robot-obstacle distances and whether the radii are
respected (:func:`radius_report`), decided exactly where the float value is close.

The package, each part once:

* :mod:`pmplan.refine.grid` -- the grid, the schedule and every constant of the map, shared by
* :mod:`pmplan.refine.reference` -- the map in numpy (:func:`refine_paths`), and
* :mod:`pmplan.refine.kernel` -- the map in numba, bitwise equal to the reference; neither of
  the two imports the other;
* :mod:`pmplan.refine.frame` -- the normalised frame the map runs in;
* :mod:`pmplan.refine.stage` -- the stage of the run loop (:class:`~pmplan.refine.stage.RefineStage`): parameters,
  radii, targets, the map by the selected backend, the certificate and the radius report.

The exact radius measures live with the certificate (:func:`pmplan.certify.radius_report`;
their float pre-decision is the kernel :mod:`pmplan.kernels.measure`).
"""

from __future__ import annotations

from ..certify import radius_report
from .frame import from_frame, to_frame  # noqa: F401
from .grid import (  # noqa: F401 (the limits, for the faces)
    CROWD,
    CROWD_FINAL,
    CROWD_STEPS,
    CROWD_WAYPOINTS,
    DEFAULT_STEPS,
    DEFAULT_WAYPOINTS,
    FINAL,
    KAPPA,
    MAX_STEPS,
    MAX_WAYPOINTS,
    PLANE_FINAL,
    PLANE_STEPS,
    SETTLE,
    SPACE_CROWD_STEPS,
    default_effort,
    schedule,
    subdivide_times,
)
from .reference import refine_paths
from .stage import (  # noqa: F401 (the stage and its checks, for the run loop and the faces)
    MSG_PLAN,
    MSG_REFINE_DASK,
    MSG_REFINE_OUT,
    MSG_REFINED,
    RefineStage,
    asks_refine,
    check_parameters,
    check_radii,
    check_radius,
    check_refine_flag,
    targets,
)

__all__ = [
    "CROWD",
    "CROWD_FINAL",
    "CROWD_STEPS",
    "CROWD_WAYPOINTS",
    "DEFAULT_STEPS",
    "DEFAULT_WAYPOINTS",
    "FINAL",
    "PLANE_FINAL",
    "PLANE_STEPS",
    "SETTLE",
    "SPACE_CROWD_STEPS",
    "check_parameters",
    "check_radii",
    "default_effort",
    "radius_report",
    "refine_paths",
    "schedule",
]
