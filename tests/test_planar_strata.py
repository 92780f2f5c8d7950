"""pmplan.planar_strata: the tables of paper Section 4 shared by the planner and its kernel."""

from __future__ import annotations

import numpy as np

from pmplan import planar_strata as ps
from pmplan.kernels import planar as kernels_planar
from pmplan.planners import planar_three


def test_the_twelve_strata_and_their_four_domains():
    assert len(ps.STRATA) == len(set(ps.STRATA)) == 12 and set(ps.DOMAIN_OF) == set(ps.STRATA)
    sizes = {w: sum(1 for s in ps.STRATA if ps.DOMAIN_OF[s] == w) for w in (1, 2, 3, 4)}
    assert sizes == {1: 3, 2: 2, 3: 5, 4: 2}  # paper (4.1)-(4.3)
    assert ps.DOMAIN_BY_CODE.tolist() == [ps.DOMAIN_OF[s] for s in ps.STRATA]


def test_codes_and_lookup_are_inverse():
    for code, name in enumerate(ps.STRATA):
        f, i, j = ps.split_name(name)
        assert f"T{f}_{i}{j}" == name and ps.CODE[(f, i, j)] == code
        assert ps.LUT[ps.FAMILIES.index(f), i, j] == code
    assert (ps.LUT >= 0).sum() == 12


def test_even_breakpoints_and_one_source():
    for k in range(2, ps.WAYPOINTS + 1):
        np.testing.assert_array_equal(ps.EVEN[k, :k], np.linspace(0.0, 1.0, k))
        assert not ps.EVEN[k, k:].any()
    assert planar_three.STRATA is ps.STRATA and kernels_planar.WAYPOINTS == ps.WAYPOINTS
    np.testing.assert_array_equal(kernels_planar.CODE_LUT, ps.LUT)
