"""The one backend seam: which implementation plans -- the numba kernels or the numpy references.

Every other module asks this one: the backend names (:data:`BACKENDS`), whether numba is there
(:func:`available`), the default and the check of a name (:func:`resolve`, :func:`check`), and
the kernel modules of the package :mod:`pmplan.kernels` themselves, imported lazily on first
use (importing them imports numba): :func:`kernels` (:mod:`pmplan.kernels.obstacle_line`),
:func:`planar_kernels` (:mod:`pmplan.kernels.planar`), :func:`validation_kernels`
(:mod:`pmplan.kernels.validation`) and :func:`shared_kernels` (:mod:`pmplan.kernels.common`: the
flag bits, ``AVAILABLE``). Without numba the numpy references plan everything (``AVAILABLE`` is
False); both backends give identical plans.
"""

from __future__ import annotations

import numpy as np

from .errors import InputError

__all__ = ["BACKENDS", "NUMBA", "NUMPY", "available", "check", "kernel_array", "kernels",
           "planar_kernels", "resolve", "shared_kernels", "uses_kernels", "validation_kernels"]

NUMBA = "numba"
NUMPY = "numpy"
#: the backend names a caller may pass (``backend=``), the default first
BACKENDS = (NUMBA, NUMPY)

_MODULES: dict = {}


def _load(name: str):
    """The kernel module ``pmplan.kernels.<name>``, imported once (it imports numba)."""
    mod = _MODULES.get(name)
    if mod is None:
        import importlib

        mod = _MODULES[name] = importlib.import_module(f"pmplan.kernels.{name}")
    return mod


def kernels():
    """:mod:`pmplan.kernels.obstacle_line` (the obstacle-line kernels), imported once."""
    return _load("obstacle_line")


def planar_kernels():
    """:mod:`pmplan.kernels.planar` (the planar_three kernel), imported once."""
    return _load("planar")


def validation_kernels():
    """:mod:`pmplan.kernels.validation` (finite coordinates, distinct points), imported once."""
    return _load("validation")


def shared_kernels():
    """:mod:`pmplan.kernels.common` (the flag bits every kernel returns, ``AVAILABLE``), imported
    once."""
    return _load("common")


def available() -> bool:
    """Whether the numba kernels can run (numba is installed)."""
    return shared_kernels().AVAILABLE


def check(backend) -> None:
    """Raise :class:`~pmplan.errors.InputError` unless ``backend`` is None or one of
    :data:`BACKENDS`."""
    if backend is not None and backend not in BACKENDS:
        raise InputError(f"unknown backend {backend!r}; choose one of {', '.join(BACKENDS)}")


def resolve(backend: str | None) -> str:
    """Return ``"numba"`` or ``"numpy"``: the named backend, or the default (numba if installed).

    Raises
    ------
    ValueError
        For any other name, or ``"numba"`` without numba.
    """
    if backend is None:
        return NUMBA if available() else NUMPY
    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; choose one of {', '.join(BACKENDS)}")
    if backend == NUMBA and not available():  # pragma: no cover
        raise ValueError("backend 'numba' needs the numba package")
    return backend


def uses_kernels(backend) -> bool:
    """Whether ``backend`` (as passed by a caller, not yet checked) asks for the kernels: the
    single-query fast paths run only then (None means the default, numba)."""
    return backend is None or backend == NUMBA


def kernel_array(a) -> np.ndarray:
    """``a`` as a C-contiguous, writeable float64 array (copied only when it is not one).

    The numba kernels are compiled for exactly this array type: a read-only input (a memory
    map, a broadcast view) would otherwise make numba compile a second copy of every kernel.
    """
    a = np.ascontiguousarray(a, dtype=np.float64)
    return a if a.flags.writeable else a.copy()
