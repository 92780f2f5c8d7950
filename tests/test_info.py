"""``pmplan.info`` and ``pmplan.parametrised_tc`` against the TC values of Mathematics §1.3 and §4.3."""

from __future__ import annotations

import pytest

import pmplan
from pmplan.planners.base import REGISTRY


def tc_table(d: int, n: int, m: int, r: int = 2) -> int:
    """Mathematics §1.3 (Cohen-Farber-Weinberger) and §4.3 (Farber-Paul, unreduced), written out."""
    if r == 2:
        return 2 * n + m - 1 if d % 2 == 0 else 2 * n + m
    return r * n + m - 1 if d % 2 == 0 else r * n + m


CASES = [(d, n, m, r) for d in (2, 3, 4, 5, 6) for n in (1, 2, 5) for m in (2, 3, 7)
         for r in (2, 3, 5)]


@pytest.mark.parametrize("d, n, m, r", CASES)
def test_domains_equal_tc(d, n, m, r):
    i = pmplan.info(d, n, m, r)
    assert pmplan.parametrised_tc(d, n, m, r) == tc_table(d, n, m, r)
    assert i.tc == tc_table(d, n, m, r)
    assert i.domains == i.tc and i.optimal
    assert len(i.labels) == i.domains == len(set(i.labels))
    assert (i.d, i.n, i.m, i.r) == (d, n, m, r)
    if i.planner == "obstacle_line":
        low = 4 if d % 2 == 0 else 3
        assert i.labels == tuple(range(low, r * n + m + 3))


@pytest.mark.parametrize("m", [0, 1])
def test_no_planner_for_fewer_than_two_obstacles(m):
    i = pmplan.info(3, 2, m)
    assert i.planner is None and i.domains is None and not i.optimal and i.labels == ()
    assert f"m = {m}" in i.message and "m >= 2" in i.message


@pytest.mark.parametrize("d, n, r, what", [(1, 1, 2, "d = 1"), (2, 0, 2, "n = 0"),
                                           (2, 1, 1, "r = 1")])
def test_no_planner_messages(d, n, r, what):
    i = pmplan.info(d, n, 2, r)
    assert i.planner is None and what in i.message


def test_default_planner_213():
    if "planar_three" not in REGISTRY:
        pytest.skip("planar_three is not registered yet")
    i = pmplan.info(2, 1, 3)
    assert i.planner == "planar_three"
    assert i.domains == 4 == i.tc and i.optimal
    j = pmplan.info(2, 1, 3, planner="obstacle_line")
    assert j.planner == "obstacle_line" and j.domains == 4
    assert pmplan.info(2, 2, 3).planner == "obstacle_line_compact"
    assert pmplan.info(2, 1, 3, 3).planner == "obstacle_line_compact"  # sequential


def test_unknown_planner_raises():
    with pytest.raises(pmplan.UnsupportedError, match="unknown planner"):
        pmplan.info(2, 1, 2, planner="nope")


def test_sequential_info_names_either_sequential_planner():
    """r > 2: the default sequential planner, or the one named -- the paper's lanes plan
    sequences too (plan_sequence(planner="obstacle_line")); a planner that cannot is refused
    with the sequence entries' message."""
    assert pmplan.info(2, 2, 2, 3).planner == "obstacle_line_compact"
    i = pmplan.info(2, 2, 2, 3, planner="obstacle_line")
    assert i.planner == "obstacle_line" and i.domains == i.tc == 3 * 2 + 2 - 1 and i.optimal
    with pytest.raises(pmplan.UnsupportedError, match="'via' is planned by the obstacle_line"):
        pmplan.info(2, 1, 3, 3, planner="planar_three")
