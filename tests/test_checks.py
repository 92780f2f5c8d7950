"""pmplan.checks: the checks every entry point shares, one rule and one message each."""

from __future__ import annotations

import os

import numpy as np
import pytest

from pmplan import checks
from pmplan.errors import InputError, UnsupportedError
from pmplan.planners.base import SCENE_CODE


@pytest.mark.parametrize("lift, want", [(1, 1.0), (0.25, 0.25), (np.float32(2), 2.0),
                                        ("scene", SCENE_CODE), (2**-1000, 2.0**-1000)])
def test_check_lift_accepts(lift, want):
    got = checks.check_lift(lift)
    assert type(got) is float and got == want


@pytest.mark.parametrize("lift", [0, -1.0, float("nan"), float("inf"), True, "Scene", None,
                                  "1", [1.0]])
def test_check_lift_refuses(lift):
    with pytest.raises(InputError, match="lift"):
        checks.check_lift(lift)


def test_check_workers():
    assert checks.check_workers(1) == 1 and checks.check_workers(np.int64(3)) == 3
    assert checks.check_workers(-1) == (os.cpu_count() or 1)
    for bad in (0, -2, 1.5, True, "2", None):
        with pytest.raises(InputError, match=r"`workers` must be a positive integer or -1"):
            checks.check_workers(bad)


def test_check_backend():
    for ok in (None, "numba", "numpy"):
        checks.check_backend(ok)
    with pytest.raises(InputError, match="unknown backend 'cuda'; choose one of numba, numpy"):
        checks.check_backend("cuda")


def test_check_sequential():
    checks.check_sequential(None)
    checks.check_sequential("obstacle_line")
    checks.check_sequential("obstacle_line_compact")
    checks.check_sequential("obstacle_line_shared")
    checks.check_sequential("obstacle_line_oneside")
    checks.check_sequential("obstacle_line_walls")
    checks.check_sequential("obstacle_line_robots")
    with pytest.raises(UnsupportedError, match="'via' is planned by the obstacle_line, "
                                               "obstacle_line_compact, obstacle_line_shared, "
                                               "obstacle_line_oneside, obstacle_line_walls or "
                                               "obstacle_line_robots planner"):
        checks.check_sequential("planar_three")
    with pytest.raises(UnsupportedError):
        checks.check_sequential("no_such_planner")


def test_choose_planner():
    assert checks.choose_planner(2, 1, 3).name == "planar_three"
    assert checks.choose_planner(2, 1, 3, "obstacle_line").name == "obstacle_line"
    assert checks.choose_planner(3, 4, 5).name == "obstacle_line_compact"
    assert checks.choose_planner(3, 4, 5, "obstacle_line").name == "obstacle_line"
    assert checks.planner_names() == ["obstacle_line", "obstacle_line_compact",
                                     "obstacle_line_oneside", "obstacle_line_robots",
                                     "obstacle_line_shared", "obstacle_line_walls",
                                     "planar_three"]
    with pytest.raises(UnsupportedError, match="unknown planner 'x'; choose one of"):
        checks.choose_planner(2, 1, 2, "x")
    with pytest.raises(UnsupportedError, match="does not apply to"):
        checks.choose_planner(2, 2, 3, "planar_three")


def test_is_dask():
    a = np.zeros((2, 2, 2))
    assert not checks.is_dask(a, [a], None)
    da = pytest.importorskip("dask.array")  # the test extra installs it: CI runs it
    assert checks.is_dask(a, da.from_array(a))
