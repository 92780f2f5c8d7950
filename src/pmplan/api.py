"""The public facade: choose a planner, validate, plan in chunks, certify, return plans.

Data flows one way: input arrays -> validation (:mod:`pmplan.configuration`) -> the run loop
(:mod:`pmplan.running`) -> planner (:mod:`pmplan.planners`) -> path (:mod:`pmplan.path`) ->
certificate (:mod:`pmplan.certify`) -> :class:`~pmplan.results.Plan` /
:class:`~pmplan.results.PlanBatch` (:mod:`pmplan.results`, re-exported here). A single query
is a batch of one; :func:`plan` and :func:`plan_sequence` first try a lean path (one
validating kernel call, :mod:`pmplan.single`) that gives the same :class:`Plan` and declines
anything unusual. Each public function here is a few lines over :mod:`pmplan.running`,
:mod:`pmplan.single` and :mod:`pmplan.checks`.
"""

from __future__ import annotations

import numpy as np

from .checks import choose_planner, is_dask, parametrised_tc, planner_info, planner_names
from .configuration import as_config_list, as_points, check_same_obstacles, default_lift
from .errors import InputError, ShapeError, UnsupportedError
from .planners.base import out_of_scope
from .refine import asks_refine
from .results import Plan, PlanBatch, PlannerInfo
from .running import plan_arrays, refine_plans
from .single import plan_one, plan_one_in_box, plan_one_sequence

__all__ = [
    "Plan",
    "PlanBatch",
    "PlannerInfo",
    "plan",
    "plan_batch",
    "plan_configurations",
    "plan_sequence",
    "plan_sequence_batch",
    "plan_query",
    "refine",
    "info",
    "planner_names",
    "parametrised_tc",
    "choose_planner",
]

def plan_batch(
    obstacles, start, goal, *, planner: str | None = None,
    lift: float | str | None = None,
    progress: bool = False, backend: str | None = None, workers: int = 1,
    out: PlanBatch | None = None, refine: bool = False, radius: float = 0.0,
    obstacle_radius: float = 0.0, bounds=None,
) -> PlanBatch:
    """Plan a batch of B queries at once (vectorised :func:`plan`).

    Parameters
    ----------
    obstacles : array_like, shape (B, m, d)
    start, goal : array_like, shape (B, n, d)
        Dask arrays (chunked along the batch axis only) are planned lazily by
        :func:`pmplan.scale.plan_batch`: the PlanBatch then holds dask arrays.
    planner : str, optional
        A name of :func:`planner_names`: ``"obstacle_line"`` (the paper's lanes),
        ``"obstacle_line_compact"``, ``"obstacle_line_shared"``, ``"obstacle_line_oneside"``,
        ``"obstacle_line_walls"``, ``"obstacle_line_robots"`` or ``"planar_three"``. Default
        chosen from (d, n, m) (:func:`~pmplan.checks.choose_planner`): ``planar_three`` for
        (2, 1, 3),
        ``obstacle_line_compact`` otherwise, but ``obstacle_line_oneside`` for a refined plan
        of at least :data:`pmplan.planners.base.CROWD_LANES` robots in the plane
        (Mathematics §8, "Crowds") and, with ``bounds``, for a refined plan in the plane,
        ``obstacle_line_robots`` for :data:`pmplan.planners.base.WALL_LANES` to
        :data:`pmplan.planners.base.ROBOT_LANES` robots (the one-side lanes with a side per
        robot, Mathematics §8, "A side per robot") and ``obstacle_line_walls`` for more (the
        one-side lanes on the side the walls leave the most room, Mathematics §8, "The side of
        the lanes").
    lift : float or "scene", optional
        The unit of the motion (the spacing of the lanes of the obstacle-line planners, the 1
        of ``H`` and ``s3`` in the planar one). Default: for a refined plan (``refine=True``
        with a positive radius) the robots' diameter ``max(2 radius, radius +
        obstacle_radius)``, so that the lanes are as far apart as the robots need; otherwise
        1, the paper's (``pmplan.configuration.default_lift``). ``"scene"``: the
        obstacles' radius ``u(O) = max_k |o_k - o_1|`` of each query, for scenes far from
        unit size (millimetres, kilometres) and for equivariance (a scaled, translated or
        rotated query gets the scaled, translated or rotated plan). A bool or a string other
        than ``"scene"`` is refused.
    progress : bool
        Show a progress bar (tqdm, on stderr) when the batch takes more than a few chunks, and
        say so when numba compiles the kernels (the first run only: they are cached on disk);
        the bar's estimate starts after that. Without it nothing is written.
    backend : {"numba", "numpy"}, optional
        Implementation of the obstacle-line and planar_three planners: the fused numba kernels
        (default when numba is installed) or the numpy references; both give identical plans.
    workers : int
        Threads that plan chunks of the batch in parallel (-1: one per CPU). The result does not
        depend on it. Only the fused planners (obstacle-line, planar_three) use threads.
    out : PlanBatch, optional
        A batch returned by an earlier call with the same planner, (d, n, m) and B: its arrays
        are overwritten with this batch's answers and ``out`` itself is returned, so that
        planning batch after batch allocates nothing (as ``np.copyto`` writes into an existing
        array). If the call raises, the contents of ``out`` are unspecified.
    bounds : (lo, hi), optional
        A workspace box ``[lo, hi]`` (numbers, or length-d sequences): every point of every
        query must lie strictly inside it, and every path stays in it -- a refined one in the
        box shrunk by ``radius``, which ``respects_radius`` then includes. The planner is
        conjugated by a homeomorphism of R^d onto the open box, the identity away from the
        walls, which keeps its number of domains and its continuity; the path returned is the
        polyline through the mapped waypoints, whose chords can cut past an obstacle on the
        other side, so inside a domain its class jumps across walls where a chord meets an
        obstacle (:mod:`pmplan.workspace`, Mathematics §8). Default: no box (R^d).

    Returns
    -------
    PlanBatch
        ``domain`` (B,), ``clearance`` (B,), ``waypoints`` (B, K, m+n, d), ``times``.

    Raises
    ------
    InputError
        (a ValueError) for malformed input: see :mod:`pmplan.errors`.
    CertificationError
        If a path fails a clause of its certificate (:data:`pmplan.certify.CLAUSES`, named in
        the message): e.g. it would not be collision-free in double precision, or it is not
        representable at the query's magnitude (the message says what to do).

    Notes
    -----
    Every returned path passes the whole certificate of :mod:`pmplan.certify` (finite times
    from 0 to 1 that never decrease; finite waypoints from exactly the start to exactly the
    goal; obstacles fixed; clearance > 0). Any finite input, from 5e-324 to 1.8e308, gets a
    certified path or a pmplan error: queries beyond ``2**430`` (or, with ``lift``, below
    ``2**-430``) are planned scaled by a power of two, which is exact, and scaled back
    (:mod:`pmplan.magnitude`); ordinary queries are not touched. ``B = 0`` is a valid empty
    batch.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> batch = plan_batch(rng.normal(size=(5, 2, 2)), rng.normal(size=(5, 3, 2)),
    ...                    rng.normal(size=(5, 3, 2)))
    >>> batch.domain.shape, batch.waypoints.shape, batch.times.shape
    ((5,), (5, 8, 5, 2), (8,))
    """
    refining = asks_refine(refine, radius, obstacle_radius, out)
    lift = default_lift(lift, radius, obstacle_radius, refining)
    if is_dask(obstacles, start, goal):  # lazy plans of dask arrays (the optional extra)
        from . import scale

        return scale.plan_batch(obstacles, start, goal, planner=planner, lift=lift,
                                progress=progress, backend=backend, workers=workers, out=out,
                                refine=_radii(refining, radius, obstacle_radius), bounds=bounds)
    batch = plan_arrays(obstacles, [start, goal], planner=planner, lift=lift, backend=backend,
                        workers=workers, progress=progress, out=out, bounds=bounds,
                        refining=refining)
    if refining:
        return refine_plans(batch, radius=radius, obstacle_radius=obstacle_radius,
                            progress=progress, workers=workers, backend=backend)
    return batch


def plan(obstacles, start, goal, *, planner: str | None = None, lift: float | str | None = None,
         backend: str | None = None, refine: bool = False, radius: float = 0.0,
         obstacle_radius: float = 0.0, bounds=None) -> Plan:
    """Plan one query: a certified collision-free motion from ``start`` to ``goal``.

    Parameters
    ----------
    obstacles : array_like, shape (m, d)
        The obstacles o_1..o_m (m >= 2); they stay fixed.
    start, goal : array_like, shape (n, d)
        Robot positions x_1..x_n and x'_1..x'_n.
    planner : str, optional
        A name of :func:`planner_names`; default chosen from (d, n, m): see
        :func:`plan_batch`.
    lift : float or "scene", optional
        The unit of the motion (default: the robots' diameter for a refined plan, else 1, the
        paper's; ``"scene"``: each query's obstacles' radius): see :func:`plan_batch`.
    backend : {"numba", "numpy"}, optional
        See :func:`plan_batch`.
    refine : bool
        Return the refined motion (:func:`refine`, with ``radius`` and ``obstacle_radius``).
    radius, obstacle_radius : float
        See :func:`refine`.
    bounds : (lo, hi), optional
        A workspace box the motion stays in: see :func:`plan_batch`.

    Returns
    -------
    Plan
        ``domain``, ``stratum``, ``clearance`` and ``path`` (waypoints (K, m+n, d)).

    Raises
    ------
    InputError, CertificationError
        As :func:`plan_batch` (whose Notes describe the certificate and extreme magnitudes).

    Examples
    --------
    A robot in the column of o1 (exact degeneracy: cp(C) = 2) going to a generic goal:

    >>> p = plan([[0, 0], [2, 0]], [[0, 1]], [[1, -1]])
    >>> p.domain, p.stratum, p.path.waypoints.shape
    (5, 'T_{2,3}', (8, 3, 2))
    >>> p.path(0.0)[2], p.path(1.0)[2]
    (array([0., 1.]), array([ 1., -1.]))
    """
    refining = asks_refine(refine, radius, obstacle_radius)
    lift = default_lift(lift, radius, obstacle_radius, refining)
    if bounds is not None or refining:
        return plan_one_in_box(obstacles, [start, goal], bounds, planner, lift, backend,
                               radii=(radius, obstacle_radius) if refining else None)
    return plan_one(obstacles, start, goal, planner, lift, backend)


def plan_configurations(c_start, c_goal, m: int = 2, **kwargs) -> Plan:
    """Plan between two full configurations (m+n, d) whose first m rows are the obstacles.

    Raises :class:`~pmplan.errors.ObstacleMismatchError` if the obstacles differ.
    """
    if isinstance(m, (bool, np.bool_)) or not isinstance(m, (int, np.integer)):
        raise InputError(f"`m` (the number of obstacles) must be an int, got {type(m).__name__} "
                         f"{m!r}")
    c_start = as_points(c_start, "start configuration", False)
    c_goal = as_points(c_goal, "goal configuration", False)
    if c_start.shape != c_goal.shape:
        raise ShapeError(
            f"Expected both configurations to have the same shape, got {c_start.shape} and "
            f"{c_goal.shape}."
        )
    if m < 2:
        raise UnsupportedError(out_of_scope(2, 1, m))
    if m >= c_start.shape[0]:
        raise ShapeError(f"m = {m} obstacles leave no robot in a configuration of {c_start.shape[0]} points")
    check_same_obstacles(c_start, c_goal, m, batched=False)
    return plan(c_start[:m], c_start[m:], c_goal[m:], **kwargs)


def plan_sequence_batch(obstacles, configs, *, lift: float | str | None = None,
                        backend: str | None = None, progress: bool = False,
                        workers: int = 1, out: PlanBatch | None = None, refine: bool = False,
                        radius: float = 0.0, obstacle_radius: float = 0.0,
                        bounds=None, planner: str | None = None) -> PlanBatch:
    """Plan batches of motions through r >= 2 configurations (Mathematics §4.3).

    ``obstacles`` (B, m, d); ``configs`` a list of r arrays (B, n, d). The path passes through
    configuration k at tau = (k-1)/(r-1); labels sum_k cp(C_k) - (r-1) cp_o + 2 (- 1 when
    e == N in odd d). ``lift``, ``backend``, ``progress``, ``workers``, ``out``, ``bounds``:
    see :func:`plan_batch`. ``planner``: a sequential planner (an obstacle-line one: default
    as in :func:`plan_batch`).
    """
    refining = asks_refine(refine, radius, obstacle_radius, out)
    lift = default_lift(lift, radius, obstacle_radius, refining)
    if isinstance(configs, (list, tuple)) and is_dask(obstacles, *configs):
        from . import scale

        return scale.plan_sequence_batch(obstacles, configs, lift=lift, progress=progress,
                                         backend=backend, workers=workers, out=out,
                                         refine=_radii(refining, radius, obstacle_radius),
                                         bounds=bounds, planner=planner)
    batch = plan_arrays(obstacles, as_config_list(configs), lift=lift, backend=backend,
                        workers=workers, progress=progress, out=out, sequential=True,
                        bounds=bounds, planner=planner, refining=refining)
    if refining:
        return refine_plans(batch, radius=radius, obstacle_radius=obstacle_radius,
                            progress=progress, workers=workers, backend=backend)
    return batch


def plan_sequence(obstacles, configs, *, lift: float | str | None = None,
                  backend: str | None = None, refine: bool = False, radius: float = 0.0,
                  obstacle_radius: float = 0.0, bounds=None, planner: str | None = None) -> Plan:
    """Plan one motion through r >= 2 robot configurations with the same obstacles (Mathematics §4.3).

    Parameters
    ----------
    obstacles : array_like, shape (m, d)
    configs : sequence of r array_like, each (n, d)
    lift : float or "scene", optional
        The unit of the motion (default: the robots' diameter for a refined plan, else 1, the
        paper's; ``"scene"``: each query's obstacles' radius): see :func:`plan_batch`.
    backend : {"numba", "numpy"}, optional
        See :func:`plan_batch`.
    planner : str, optional
        A sequential planner (an obstacle-line one: default as in :func:`plan_batch`).

    Examples
    --------
    >>> p = plan_sequence([[0, 0], [2, 0]], [[[0, 1]], [[1, -1]], [[3, 3]]])
    >>> p.domain, p.path.waypoints.shape
    (6, (15, 3, 2))
    >>> p.path(0.5)[2]
    array([ 1., -1.])
    """
    refining = asks_refine(refine, radius, obstacle_radius)
    lift = default_lift(lift, radius, obstacle_radius, refining)
    if bounds is not None or refining:
        return plan_one_in_box(obstacles, configs, bounds, planner, lift, backend, sequential=True,
                               radii=(radius, obstacle_radius) if refining else None)
    return plan_one_sequence(obstacles, configs, lift, backend, planner)


def info(d: int, n: int, m: int, r: int = 2, planner: str | None = None) -> PlannerInfo:
    """Which planner applies to (d, n, m, r), how many domains it has, and whether it is optimal.

    Examples
    --------
    >>> i = info(2, 3, 2)
    >>> i.planner, i.domains, i.tc, i.optimal
    ('obstacle_line_compact', 7, 7, True)
    >>> info(3, 1, 1).message
    'no planner covers m = 1: the planners need m >= 2 obstacles (they define the line L_C)'
    """
    return planner_info(d, n, m, r, planner)


def plan_query(query: dict, planner: str | None = None) -> Plan:
    """Plan a query given as a dict (the form :func:`pmplan.io.read_query` returns).

    Keys ``obstacles``, ``start``, ``goal`` and optional ``via`` (intermediate configurations:
    then :func:`plan_sequence`), ``lift``, ``bounds`` (the workspace box) and ``planner``
    (overridden by ``planner``).

    Examples
    --------
    >>> plan_query({"obstacles": [[0, 0], [2, 0]], "start": [[0, 1]], "goal": [[1, -1]],
    ...             "via": [[[3, 3]]]}).stratum
    'T_{2,3,3}'
    """
    planner = planner or query.get("planner")
    lift, bounds = query.get("lift"), query.get("bounds")
    if "via" in query:
        configs = [query["start"], *query["via"], query["goal"]]
        return plan_sequence(query["obstacles"], configs, lift=lift, bounds=bounds,
                             planner=planner)
    return plan(query["obstacles"], query["start"], query["goal"], planner=planner, lift=lift,
                bounds=bounds)


def refine(plan_or_batch: Plan | PlanBatch, *, radius: float = 0.0, obstacle_radius: float = 0.0,
           waypoints: int | None = None, steps: int | None = None, workers: int = 1,
           progress: bool | None = None, backend: str | None = None) -> Plan | PlanBatch:
    """Refine a plan (or a batch): a shorter motion that keeps the radii, still certified,
    continuous on the same domains (so still optimal). See :mod:`pmplan.refine`.

    Parameters
    ----------
    plan_or_batch : Plan or PlanBatch
        Unrefined plans returned by :func:`plan`, :func:`plan_batch`, :func:`plan_sequence` or
        :func:`plan_sequence_batch`.
    radius : float
        The robots' radius: the refinement aims at keeping any two robots ``2 radius`` apart
        and every robot ``radius + obstacle_radius`` off every obstacle. Default 0: it keeps
        half the raw plan's clearance instead (:data:`pmplan.refine.KAPPA`).
    obstacle_radius : float
        The obstacles' radius.
    waypoints : int, optional
        Sub-pieces per piece of the raw path at the finest level, a power of two (default
        :data:`pmplan.refine.DEFAULT_WAYPOINTS` = 4: 22 pieces per leg of the obstacle-line
        planner; for a crowd of more than :data:`pmplan.refine.CROWD` = 8 robots
        :data:`pmplan.refine.CROWD_WAYPOINTS` = 4). A piece the planner declares still (it
        moves no point for almost every query, :meth:`pmplan.planners.base.Planner.still_pieces`:
        the obstacle-line planner's desingularization) stays one piece. The refined path has
        ``(K - 1) waypoints + 1`` breakpoints, less ``waypoints - 1`` per still piece.
    steps : int, optional
        Refinement steps (default :data:`pmplan.refine.DEFAULT_STEPS` = 56; in the plane
        :data:`pmplan.refine.PLANE_STEPS` = 72 for 5 to 8 robots; for a crowd
        :data:`pmplan.refine.CROWD_STEPS` = 112 in the plane and
        :data:`pmplan.refine.SPACE_CROWD_STEPS` = 112 in d >= 3), split over the
        coarse-to-fine levels 1, 2, 4, .., ``waypoints``, then clearing-only steps at the
        finest level: a quarter as many (:data:`pmplan.refine.FINAL`), but in the plane as
        many for more than :data:`pmplan.refine.SETTLE` = 4 robots
        (:data:`pmplan.refine.PLANE_FINAL`) and twice as many for a crowd
        (:data:`pmplan.refine.CROWD_FINAL`). The defaults were chosen from the length /
        time measurements of ``benchmarks/refine_bench.py`` and ``benchmarks/plane_final.py``,
        the crowd's from ``benchmarks/scenes_effort.py``, ``benchmarks/crowd_ab.py`` and
        ``benchmarks/crowd_effort.py``; they depend on the dimension and the number of robots
        alone, so the refinement stays continuous on every domain
        (:func:`pmplan.refine.default_effort`, :func:`pmplan.refine.grid.final_steps`).
    workers : int
        Threads refining separate chunks (-1: one per CPU); the result does not depend on it.
    progress : bool, optional
        Show a progress bar for large batches (as :func:`plan_batch`).
    backend : {"numba", "numpy"}, optional
        The kernel (default) or the numpy reference; both give identical paths.

    Returns
    -------
    Plan or PlanBatch
        The same type as given, with the same domains and strata; ``refined`` True,
        ``radius``, ``obstacle_radius``, ``robot_distance``, ``obstacle_distance`` (exact
        minima along the refined path) and ``respects_radius`` (decided exactly: never True
        when the radii are not kept).

    Raises
    ------
    InputError
        For a bad parameter, an already refined plan, or a start, goal or intermediate
        configuration that violates the radii (:class:`~pmplan.errors.CollisionError` naming
        the two points).
    CertificationError
        If a refined path fails its certificate (nothing is returned).

    Examples
    --------
    >>> p = plan([[0.35, 0.5], [0.65, 0.5]], [[0.1, 0.5]], [[0.9, 0.5]])
    >>> q = refine(p, radius=0.025, obstacle_radius=0.025)
    >>> q.domain == p.domain, q.stratum == p.stratum, q.refined, q.respects_radius
    (True, True, True, True)
    >>> bool(q.path.length() < p.path.length())
    True
    """
    return refine_plans(plan_or_batch, radius=radius, obstacle_radius=obstacle_radius,
                        waypoints=waypoints, steps=steps, workers=workers, progress=progress,
                        backend=backend)


def _radii(refining: bool, radius, obstacle_radius) -> dict | None:
    """The refinement options handed to :mod:`pmplan.scale` (None: raw plans)."""
    return {"radius": radius, "obstacle_radius": obstacle_radius} if refining else None
