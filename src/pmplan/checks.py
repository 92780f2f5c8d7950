"""The checks every entry point shares -- the API, :mod:`pmplan.scale`, the command line and
the web page --, one rule and one message each, and the choice of the planner.

Below the facade (:mod:`pmplan.api`) and above the planners: importing this module registers
the planners (the package ``pmplan.planners``).
"""

from __future__ import annotations

import os
import sys

import numpy as np

from . import backends as _backend
from . import planners as _planners  # noqa: F401  (registers the planners)
from .configuration import as_lift
from .errors import InputError, UnsupportedError
from .planners.base import REGISTRY, Planner, default_planner, lift_code, out_of_scope
from .results import PlannerInfo

__all__ = ["check_backend", "check_lift", "check_sequential", "check_workers", "choose_planner",
           "is_dask", "parametrised_tc", "planner_info", "planner_names"]

_MSG_WORKERS = "`workers` must be a positive integer or -1 (all CPUs), got {value!r}"


def check_lift(lift) -> float:
    """``lift`` checked (:func:`pmplan.configuration.as_lift`: a positive real number or
    ``"scene"``) as the float the planners take (:func:`pmplan.planners.base.lift_code`)."""
    return lift_code(as_lift(lift))


def check_workers(workers) -> int:
    """``workers`` as a thread count: a positive int, or -1 for every CPU of the machine."""
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or not (
        workers >= 1 or workers == -1
    ):
        raise InputError(_MSG_WORKERS.format(value=workers))
    return (os.cpu_count() or 1) if workers == -1 else int(workers)


def check_backend(backend) -> None:
    """Raise :class:`~pmplan.errors.InputError` unless ``backend`` is None or a backend name
    (:data:`pmplan.backends.BACKENDS`)."""
    _backend.check(backend)


def check_sequential(planner: str | None) -> None:
    """Raise :class:`~pmplan.errors.UnsupportedError` if the named planner does not plan
    through intermediate configurations (a query with ``via``)."""
    if planner is not None and not (planner in REGISTRY and REGISTRY[planner].sequential):
        names = [p.name for p in REGISTRY.values() if p.sequential]
        which = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " or " + names[-1]
        raise UnsupportedError(f"a query with 'via' is planned by the {which} planner")


def planner_names() -> list[str]:
    """Return the registered planner names, sorted: ``obstacle_line``,
    ``obstacle_line_compact``, ``obstacle_line_oneside``, ``obstacle_line_shared``,
    ``obstacle_line_walls``, ``obstacle_line_robots`` and ``planar_three``."""
    return sorted(REGISTRY)


def choose_planner(d: int, n: int, m: int, planner: str | None = None,
                   sequential: bool = False, refining: bool = False,
                   bounded: bool = False) -> Planner:
    """Return the planner for (d, n, m): the named one, or the default.

    The default is ``planar_three`` (paper Section 4) for (d, n, m) = (2, 1, 3) and
    ``obstacle_line_compact`` (paper Section 3 and Mathematics §4, with the compact lanes of
    Mathematics §4.4) for every other m >= 2, but for a plan to be refined (``refining``) in
    the plane, in a workspace box (``bounded``), ``obstacle_line_robots`` for
    :data:`~pmplan.planners.base.WALL_LANES` to :data:`~pmplan.planners.base.ROBOT_LANES`
    robots and ``obstacle_line_walls`` for more, else ``obstacle_line_oneside`` from
    :data:`~pmplan.planners.base.CROWD_LANES` robots on; ``obstacle_line`` is the paper's.
    With ``sequential`` (a query through intermediate configurations) the default is the
    sequential planner of (d, n, m)
    (:func:`~pmplan.planners.base.default_planner`); the caller checks a named one with
    ``check_sequential``.
    """
    if planner is None:
        planner = default_planner(d, n, m, sequential=sequential, refining=refining,
                                  bounded=bounded)
    if planner not in REGISTRY:
        raise UnsupportedError(
            f"unknown planner {planner!r}; choose one of {', '.join(planner_names())}"
        )
    p = REGISTRY[planner]
    why = p.supports(d, n, m)
    if why is not None:
        raise UnsupportedError(f"planner {planner!r} does not apply to (d, n, m) = ({d}, {n}, {m}): {why}")
    return p


def is_dask(*arrays) -> bool:
    """Whether any argument is a dask array (then :mod:`pmplan.scale` plans it lazily); dask
    is never imported here: an array of it exists only if the caller imported it."""
    da = sys.modules.get("dask.array")
    return da is not None and any(isinstance(a, da.Array) for a in arrays)


def parametrised_tc(d: int, n: int, m: int, r: int = 2) -> int:
    """Return the (unreduced, sequential) parametrised topological complexity.

    ``2n+m-1`` (d even) / ``2n+m`` (d odd) for r = 2 (paper Theorem 2.6,
    Cohen-Farber-Weinberger); ``rn+m-1`` / ``rn+m`` for r >= 2 (Farber-Paul, unreduced).
    """
    return r * n + m - 1 if d % 2 == 0 else r * n + m


def planner_info(d: int, n: int, m: int, r: int = 2, planner: str | None = None):
    """:func:`pmplan.info`: the planner of (d, n, m, r), its domains and the parametrised TC."""
    why = out_of_scope(d, n, m, r)
    if why is not None:
        return PlannerInfo(d, n, m, r, None, None, (), None, False, f"no planner covers {why}")
    tc = parametrised_tc(d, n, m, r)
    if r > 2:
        check_sequential(planner)
        p = choose_planner(d, n, m, planner, sequential=True)
        labels = tuple(p.domain_labels(d, n, m, r))
        msg = f"sequential planner (Mathematics §4.3) on the {p.name} planner"
    else:
        p = choose_planner(d, n, m, planner)
        labels = tuple(p.domain_labels(d, n, m))
        msg = p.summary
    k = len(labels)
    return PlannerInfo(d, n, m, r, p.name, k, labels, tc, k == tc, msg)
