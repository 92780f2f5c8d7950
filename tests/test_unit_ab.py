"""The verdict of ``benchmarks/unit_ab.py`` (issue 25 item 2), which RESULTS.md's goal tables
take: the default's median len/LB against each fixed lift's over the queries of a set for
both, the largest ratio, and a lift left out with fewer than SAME_LEAST such queries."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import unit_ab
from scenes_section import SAME_LEAST


def _rec(ratio, keeps=True, inside=True):
    return [ratio, keeps, inside]


def test_the_ratio_is_over_the_queries_of_the_set_for_both():
    """lift 0.1 is 10 % shorter than the default on the queries both keep valid and much
    longer on a query where it leaves the room: the *all* set sees the long one, *valid* not."""
    default = [_rec(1.1), _rec(1.1), _rec(1.1), _rec(1.1), _rec(1.1)]
    lift = [_rec(1.0), _rec(1.0), _rec(1.0), _rec(1.0), _rec(9.0, inside=False)]
    got = unit_ab.ratios({unit_ab.DEFAULT: default, "lift 0.1": lift})
    assert got["valid"]["lift 0.1"] == (pytest.approx(1.1), 4)
    assert got["keeps r"]["lift 0.1"] == (pytest.approx(1.1), 5)
    assert got["all"]["lift 0.1"] == (pytest.approx(1.1), 5)  # (medians: 1.1 / 1.0)
    assert unit_ab.largest(got["valid"]) == (pytest.approx(1.1), "lift 0.1", 4)
    assert unit_ab.largest(got["valid"])[0] > unit_ab.GOAL


def test_a_lift_with_too_few_shared_queries_decides_nothing():
    few = SAME_LEAST - 1
    default = [_rec(1.0)] * (few + 2)
    lift = [_rec(0.5)] * few + [None, _rec(0.5, keeps=False)]  # refused, misses r
    got = unit_ab.ratios({unit_ab.DEFAULT: default, "lift 1": lift})
    assert got["valid"]["lift 1"] is None and got["keeps r"]["lift 1"] is None
    assert got["all"]["lift 1"] == (pytest.approx(2.0), few + 1)
    assert unit_ab.largest(got["valid"]) is None


def test_the_worst_lift_and_the_skip():
    cells = {"lift 0.03": (1.0, 40), "lift 0.1": (0.95, 40), "lift 1": (1.02, 12), "x": None}
    assert unit_ab.largest(cells) == (1.02, "lift 1", 12)
    assert unit_ab.largest(cells, "lift 1") == (1.0, "lift 0.03", 40)
