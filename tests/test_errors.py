"""pmplan.errors: one root, input errors are ValueErrors, a store's error is one line."""

from __future__ import annotations

import pytest

import pmplan
from pmplan import errors


def test_hierarchy():
    for name in errors.__all__:
        cls = getattr(errors, name)
        assert issubclass(cls, errors.PmplanError) and getattr(pmplan, name) is cls
    for cls in (errors.InputError, errors.ShapeError, errors.NonFiniteError,
                errors.CollisionError, errors.ObstacleMismatchError, errors.UnsupportedError):
        assert issubclass(cls, ValueError)
    assert issubclass(errors.CertificationError, ArithmeticError)
    assert not issubclass(errors.StoreError, ValueError)


def test_attributes():
    e = errors.CollisionError("x", index=3, which="goal", pair=("o1", "x2"))
    assert (e.index, e.which, e.pair) == (3, "goal", ("o1", "x2"))
    assert errors.CertificationError("y", indices=[1]).indices == [1]


def test_store_error_is_one_line():
    e = errors.StoreError("the dask cluster failed (CommClosedError: in <TCP>\n  closed)\n; "
                          "o.zarr is incomplete", path="o.zarr", resumable=True)
    assert "\n" not in str(e) and "  " not in str(e)
    assert (e.path, e.resumable) == ("o.zarr", True)
    assert errors.StoreError("z").path is None
    with pytest.raises(errors.PmplanError):
        raise e
