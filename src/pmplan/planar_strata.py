"""The 12 strata of paper Section 4 and their domains: the tables the planar three-obstacle
planner (:mod:`pmplan.planners.planar_three`) and its kernel (:mod:`pmplan.kernels.planar`)
share -- plain data, below both (kernels never import planners).
"""

from __future__ import annotations

import numpy as np

__all__ = ["DOMAIN_BY_CODE", "DOMAIN_OF", "EVEN", "FAMILIES", "LUT", "PAPER_SUPER", "STRATA",
           "WAYPOINTS", "split_name"]

#: the names of the 12 strata of paper Section 4 in pmplan's notation (Mathematics §5.2), in a fixed order: the stratum
#: code of :class:`~pmplan.planners.planar_three.StratumClassification` is the index here (0..11)
STRATA: tuple[str, ...] = (
    "T1_11", "T1_12", "T1_21", "T1_22",
    "T22_22", "T22_23", "T22_32", "T22_33",
    "T23_33", "T23_34", "T23_43", "T23_44",
)

#: the domain W_a (a in 1..4) of every stratum, paper (4.1)-(4.3)
DOMAIN_OF: dict[str, int] = {
    "T1_11": 1, "T22_33": 1, "T23_44": 1,
    "T1_22": 2, "T22_22": 2,
    "T1_12": 3, "T1_21": 3, "T22_23": 3, "T22_32": 3, "T23_33": 3,
    "T23_34": 4, "T23_43": 4,
}

#: common number of waypoints of a batch (the longest polyline, T23_33, has 5 legs)
WAYPOINTS = 6

FAMILIES = (1, 22, 23)
PAPER_SUPER = {1: "1", 22: "2,2", 23: "2,3"}


def split_name(name: str) -> tuple[int, int, int]:
    """``(family, i, j)`` of a stratum name, e.g. ``(22, 2, 3)`` for ``"T22_23"``."""
    fam, ij = name[1:].split("_")
    return int(fam), int(ij[0]), int(ij[1])


#: the stratum code (index in :data:`STRATA`) of every ``(family, i, j)``
CODE = {split_name(s): c for c, s in enumerate(STRATA)}
#: the stratum code of every ``(family index, i, j)``: ``LUT[f, i, j]`` (or -1)
LUT = np.full((3, 5, 5), -1, dtype=np.int64)
for (_f, _i, _j), _c in CODE.items():
    LUT[FAMILIES.index(_f), _i, _j] = _c
DOMAIN_BY_CODE = np.array([DOMAIN_OF[s] for s in STRATA], dtype=np.int64)
#: the breakpoints of a path of length 0 with k waypoints: ``EVEN[k, :k] = linspace(0, 1, k)``
#: (:meth:`pmplan.path.PiecewiseLinearPath.arc_length_reparametrised`), for the kernel
EVEN = np.zeros((WAYPOINTS + 1, WAYPOINTS))
for _k in range(2, WAYPOINTS + 1):
    EVEN[_k, :_k] = np.linspace(0.0, 1.0, _k)
