"""Errors raised by pmplan.

Every error pmplan raises on purpose derives from :class:`PmplanError`. Errors caused by the
caller's input also derive from :class:`ValueError`, so ``except ValueError`` keeps working for
code that does not know pmplan.
"""

from __future__ import annotations

__all__ = [
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


class PmplanError(Exception):
    """Root of every error pmplan raises on purpose."""


class InputError(PmplanError, ValueError):
    """The query (or a file holding queries) is malformed."""


class ShapeError(InputError):
    """An array has the wrong shape, e.g. ``Expected `start` to have shape (n, d), got (3,)``."""


class NonFiniteError(InputError):
    """A coordinate is NaN or infinite."""


class CollisionError(InputError):
    """Two points of a configuration coincide, so the configuration is not in F(R^d, m+n).

    Attributes
    ----------
    index : int or None
        Batch index of the first offending query (None for a single query).
    which : str
        ``"start"`` or ``"goal"`` (or ``"config k"`` for sequential queries).
    pair : tuple of str
        The two coinciding points, e.g. ``("o1", "x3")``.
    """

    def __init__(self, message: str, *, index=None, which=None, pair=None):
        super().__init__(message)
        self.index = index
        self.which = which
        self.pair = pair


class ObstacleMismatchError(InputError):
    """The obstacles of the start and goal configurations differ (the query leaves the fibre)."""


class UnsupportedError(InputError):
    """No planner covers this (d, n, m), or the named planner does not apply to it."""


class CertificationError(PmplanError, ArithmeticError):
    """A planned path failed its certificate (Mathematics §6), so it is not returned.

    This happens when the query is so nearly degenerate that double precision cannot represent a
    collision-free path of the planner (e.g. eps(C) below the resolution of the coordinates).

    Attributes
    ----------
    indices : numpy.ndarray
        Batch indices of the queries whose certificate failed.
    """

    def __init__(self, message: str, *, indices=None):
        super().__init__(message)
        self.indices = indices


class StoreError(PmplanError):
    """A run into an output store failed for a reason outside the queries: the disk (full,
    read-only), the dask cluster (scheduler lost, workers killed), or the store itself.

    The message names the store and says whether ``--resume`` (``resume=True``) will finish it.

    Attributes
    ----------
    path : str
        The output store.
    resumable : bool
        True when the store holds a run that ``--resume`` can finish once the cause is fixed;
        False when nothing was written (or nothing that a resume can use).
    """

    def __init__(self, message: str, *, path=None, resumable: bool = False):
        super().__init__(" ".join(message.split()))  # one line, whatever the cause printed
        self.path = None if path is None else str(path)
        self.resumable = resumable
