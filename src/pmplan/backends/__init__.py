"""The one backend seam: which implementation plans -- the numba kernels or the numpy references.

A backend is a module with one set of functions, the same names in every backend (as
``scipy.spatial.transform`` selects its array backends); :func:`select` returns it, the one
place that maps a name (``backend=`` of every planning function) to an implementation:

``NAME``
    The backend's name.
``available() -> bool``
    Whether it can run here (numba installed, a GPU present...).
``plan(planner, obstacles, configs, lift, out, validate) -> ndarray``
    Plan and certify a chunk of queries of ``planner`` through ``configs`` into ``out`` (the
    arrays of :meth:`~pmplan.planners.base.Planner.allocate`); return the certificate (B,)
    bool. With ``validate`` (only where ``validates`` says so) it also checks the queries
    (finite, distinct points): an invalid one fails its certificate.
``validates(planner, d) -> bool``
    Whether ``plan`` validates the queries of ``planner`` in dimension ``d`` itself.
``certify(waypoints, start, goal, m, times, via) -> (clearance, codes)``
    The certificate of paths (:func:`pmplan.certify.certificate`'s contract).
``single_query(planner, m, n, d)``, ``sequence_query(planner, r, m, n, d)``
    One query in one call, for :func:`pmplan.plan` / :func:`pmplan.plan_sequence`: a function
    ``run(...)`` (see :meth:`pmplan.backends.numba.single_query`), or None when the backend has
    none for that shape (the general path then plans it as a batch of one).
``refine(times, waypoints, m, r, target, s, steps, walls=None, still=None)``
    The refinement's map (:mod:`pmplan.refine`), in its frame (``walls``: a workspace's
    limits there; ``still``: the raw pieces that stand still,
    :func:`pmplan.refine.reference.refine_paths`).
``measure(waypoints, m, need) -> (values, kept, close) | None``
    The refined paths' clearance and robot and obstacle distances (B, 3), whether they keep
    the distances ``need`` (B,), and the rows too close to call, which the refinement then
    decides exactly; None: it decides every row exactly.
``from_box_linear``, ``into_box``, ``path_into_box_linear``
    The maps of a workspace box, bit for bit the references of :mod:`pmplan.workspace` with
    the band ``frac`` an argument: ``from_box_linear(x, box, frac)`` maps the queries out of
    it, ``into_box(z, box, frac)`` brings a refined path back in, and
    ``path_into_box_linear(times, waypoints, box, frac, width=None)`` is the exact image of
    paths.

Two backends are registered (:data:`REGISTRY`): :mod:`pmplan.backends.numpy`, the references
(exact, every planner's mathematics in numpy), and :mod:`pmplan.backends.numba`, the fused
kernels of :mod:`pmplan.kernels` (bitwise equal to the references; the default where numba is
installed). A third one -- CuPy or JAX on a GPU -- is one more module with these functions and
one line in :data:`REGISTRY` (``docs/architecture.md`` shows it); the contract test
(``tests/test_backends.py``) holds every registered backend to the reference. Nothing outside
this package asks which backend it has by name.
"""

from __future__ import annotations

import importlib
from types import ModuleType

import numpy as np

from ..errors import InputError

__all__ = ["BACKENDS", "NUMBA", "NUMPY", "REGISTRY", "available", "check", "kernel_array",
           "kernels", "module", "planar_kernels", "resolve", "select", "shared_kernels",
           "validation_kernels"]

NUMBA = "numba"
NUMPY = "numpy"
#: the registered backends: name -> module implementing the functions above (the default first)
REGISTRY: dict[str, str] = {NUMBA: "pmplan.backends.numba", NUMPY: "pmplan.backends.numpy"}
#: the backend names a caller may pass (``backend=``), the default first
BACKENDS = tuple(REGISTRY)

_MODULES: dict = {}


def _load(module: str) -> ModuleType:
    """The module ``module``, imported once (a kernel module imports numba)."""
    mod = _MODULES.get(module)
    if mod is None:
        mod = _MODULES[module] = importlib.import_module(module)
    return mod


def module(name: str) -> ModuleType:
    """The module of the registered backend ``name``, whether it can run here or not."""
    return _load(REGISTRY[name])


def check(backend) -> None:
    """Raise :class:`~pmplan.errors.InputError` unless ``backend`` is None or one of
    :data:`BACKENDS`."""
    if backend is not None and backend not in BACKENDS:
        raise InputError(f"unknown backend {backend!r}; choose one of {', '.join(BACKENDS)}")


def resolve(backend: str | None) -> str:
    """The name of the backend ``backend`` selects: itself, or the default (the first
    registered one that is available).

    Raises
    ------
    ValueError
        For any other name, or a backend that cannot run here.
    """
    if backend is None:
        return next(name for name in BACKENDS if _load(REGISTRY[name]).available())
    if backend not in REGISTRY:
        raise ValueError(f"unknown backend {backend!r}; choose one of {', '.join(BACKENDS)}")
    if not _load(REGISTRY[backend]).available():  # pragma: no cover
        raise ValueError(f"backend {backend!r} cannot run here (its package is missing)")
    return backend


def select(backend: str | None = None) -> ModuleType:
    """The backend module ``backend`` names (None: the default), with the functions above."""
    return _load(REGISTRY[resolve(backend)])


def available() -> bool:
    """Whether the numba kernels can run (numba is installed)."""
    return shared_kernels().AVAILABLE


def kernels() -> ModuleType:
    """:mod:`pmplan.kernels.obstacle_line` (the obstacle-line kernels), imported once."""
    return _load("pmplan.kernels.obstacle_line")


def planar_kernels() -> ModuleType:
    """:mod:`pmplan.kernels.planar` (the planar_three kernel), imported once."""
    return _load("pmplan.kernels.planar")


def validation_kernels() -> ModuleType:
    """:mod:`pmplan.kernels.validation` (finite coordinates, distinct points), imported once;
    an accelerator of :mod:`pmplan.configuration` whatever the backend."""
    return _load("pmplan.kernels.validation")


def shared_kernels() -> ModuleType:
    """:mod:`pmplan.kernels.common` (the flag bits every kernel returns, ``AVAILABLE``),
    imported once."""
    return _load("pmplan.kernels.common")


def kernel_array(a) -> np.ndarray:
    """``a`` as a C-contiguous, writeable float64 array (copied only when it is not one).

    The numba kernels are compiled for exactly this array type: a read-only input (a memory
    map, a broadcast view) would otherwise make numba compile a second copy of every kernel.
    """
    a = np.ascontiguousarray(a, dtype=np.float64)
    return a if a.flags.writeable else a.copy()
