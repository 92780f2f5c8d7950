"""The frame of a configuration: the line L_C through o1, o2 and a unit normal field nu.

For obstacles ``o1 != o2`` in R^d the paper (Section 3, Figure 1) uses the oriented line
``L_C`` through them with direction ``e_C = (o2 - o1)/|o2 - o1|``, the orthogonal projection
``p_C`` onto it, and a unit tangent vector field ``nu`` on the sphere ``S^{d-1}``, so that
``nu(e) . e = 0`` and ``|nu(e)| = 1``. Here:

* d even (paper, Section 3, subsection "Section over X"), with ``d = 2l``::

      nu(a1, b1, ..., al, bl) = (-b1, a1, ..., -bl, al)

* d odd (Mathematics §4.1, our extension): no continuous unit tangent field exists on ``S^{d-1}``, so with
  ``N = e_d`` and ``a = e_1``::

      xi(v) = (1 - v.N) a + (a.v)(N - v),        nu(v) = xi(v)/|xi(v)|   for v != N,
      nu(N) = a                                                           (exact case e == N).

  Since ``|xi(v)| = 1 - v.N``, ``nu(v) = a + v_1 (N - v)/(1 - v_d)``; ``1 - v_d`` is evaluated as
  ``|w'|^2 / (|w| (|w| + w_d))`` (``w'`` the first d-1 coordinates of ``w``) to avoid
  cancellation near ``N``. ``e == N`` is decided exactly: ``w_1 = ... = w_{d-1} = 0`` and
  ``w_d > 0`` on the floats.

Coordinates in the frame: the column ``s(y) = (y - o1) . e`` and the perpendicular part
``r(y) = (y - o1) - s(y) e``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Frame", "nu", "unit"]


def nu(w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return ``nu(e)`` for ``e = w/|w|``, and the exact flag ``e == N`` (odd d only).

    Parameters
    ----------
    w : ndarray, shape (..., d)
        Nonzero direction vectors ``o2 - o1``.

    Returns
    -------
    nu : ndarray, shape (..., d)
        Unit vectors orthogonal to ``w``.
    at_pole : ndarray of bool, shape (...)
        True where d is odd and ``w`` is exactly a positive multiple of ``N = e_d``; always
        False for even d.

    Examples
    --------
    >>> nu(np.array([3.0, 4.0]))[0]
    array([-0.8,  0.6])
    >>> v, pole = nu(np.array([[0.0, 0.0, 2.0], [1.0, 0.0, 0.0]]))
    >>> v, pole
    (array([[1., 0., 0.],
           [0., 0., 1.]]), array([ True, False]))
    """
    w = np.asarray(w, dtype=float)
    d = w.shape[-1]
    e = unit(w)
    if d % 2 == 0:
        out = np.empty_like(e)
        out[..., 0::2] = -e[..., 1::2]
        out[..., 1::2] = e[..., 0::2]
        return out + 0.0, np.zeros(w.shape[:-1], dtype=bool)
    at_pole = (w[..., :-1] == 0).all(axis=-1) & (w[..., -1] > 0)
    # nu_k = delta_k1 - h_1 h_k (1 + v_d) for k < d and nu_d = v_1, with h = w'/|w'|:
    # algebraically equal to xi/|xi| and free of cancellation and overflow near N.
    h = unit(w[..., :-1])
    out = np.empty_like(e)
    out[..., :-1] = -(h[..., :1] * h) * (1.0 + e[..., -1:])
    out[..., 0] += 1.0
    out[..., -1] = e[..., 0]
    out[at_pole] = 0.0
    out[at_pole, 0] = 1.0
    return out + 0.0, at_pole


def unit(w: np.ndarray) -> np.ndarray:
    """Return ``w/|w|`` along the last axis, scaled to avoid overflow and underflow (0 for 0)."""
    w = np.asarray(w, dtype=float)
    scale = np.abs(w).max(axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        ws = np.where(scale > 0, w / np.where(scale > 0, scale, 1.0), 0.0)
        n = np.sqrt((ws * ws).sum(axis=-1, keepdims=True))
        return np.where(n > 0, ws / np.where(n > 0, n, 1.0), 0.0)


class Frame:
    """The frame (o1, e, nu(e)) of a batch of configurations.

    Attributes
    ----------
    o1 : ndarray, shape (B, d)
    w : ndarray, shape (B, d)       ``o2 - o1``
    norm : ndarray, shape (B,)      ``|w|``
    e : ndarray, shape (B, d)       ``w/|w|``
    nu : ndarray, shape (B, d)      unit normal ``nu(e)``
    at_pole : ndarray of bool, shape (B,)   ``e == N`` (odd d), decided exactly
    """

    __slots__ = ("o1", "w", "norm", "e", "nu", "at_pole")

    def __init__(self, o1: np.ndarray, o2: np.ndarray):
        self.o1 = np.asarray(o1, dtype=float)
        self.w = np.asarray(o2, dtype=float) - self.o1
        self.e = unit(self.w)
        self.norm = (self.w * self.e).sum(axis=-1)
        self.nu, self.at_pole = nu(self.w)

    def columns(self, points: np.ndarray) -> np.ndarray:
        """Return ``s(y) = (y - o1) . e`` for points of shape (B, P, d), as (B, P)."""
        return ((points - self.o1[:, None, :]) * self.e[:, None, :]).sum(axis=-1)

    def perpendicular(self, points: np.ndarray) -> np.ndarray:
        """Return ``r(y) = (y - o1) - s(y) e`` for points of shape (B, P, d), as (B, P, d)."""
        rel = points - self.o1[:, None, :]
        s = (rel * self.e[:, None, :]).sum(axis=-1)
        return rel - s[..., None] * self.e[:, None, :]
