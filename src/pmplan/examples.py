"""Named example queries with exact degeneracies (integer and dyadic coordinates).

These are the embedded defaults of ``pmplan demo``: one query in every domain of continuity.
"""

from __future__ import annotations

import numpy as np

__all__ = ["crowded_room", "crowded_room_plans", "line_configuration", "obstacle_line_examples",
           "planar_three_examples"]

# columns and heights (for n = 3) giving cp = 2..5 with obstacles o1 = (0, 0), o2 = (4, 0)
_START = {
    2: ([0.0, 4.0, 0.0], [1.5, -1.0, -1.5]),
    3: ([1.0, 1.0, 4.0], [1.0, -1.0, 1.25]),
    4: ([1.0, 2.5, 1.0], [1.0, -1.0, -1.5]),
    5: ([1.0, 2.0, 3.0], [1.0, -1.0, 1.5]),
}
_GOAL = {
    2: ([4.0, 0.0, 4.0], [-1.5, 1.0, 1.0]),
    3: ([3.0, 3.0, 0.0], [-1.0, 1.0, -1.0]),
    4: ([3.0, 1.5, 3.0], [-1.0, 1.0, 1.5]),
    5: ([3.25, 2.25, 0.75], [-1.25, 1.25, -0.75]),
}


def line_configuration(cp: int, n: int, *, goal: bool = False) -> np.ndarray:
    """Return n robot positions (n, 2) with exactly ``cp`` distinct columns in total.

    Obstacles are o1 = (0, 0), o2 = (4, 0), so the column of a point is its x coordinate.
    ``2 <= cp <= n + 2``. Robots 1..cp-2 get new columns, the others share o1's or o2's.
    """
    if not 2 <= cp <= n + 2:
        raise ValueError(f"cp must lie in 2..{n + 2}, got {cp}")
    if n == 3:
        cols, heights = (_GOAL if goal else _START)[cp]
        return np.column_stack([cols, heights])
    new = cp - 2
    cols = [4.0 * (k + 1) / (new + 1) for k in range(new)]
    cols += [0.0 if k % 2 == 0 else 4.0 for k in range(n - new)]
    sign = -1.0 if goal else 1.0
    heights = [sign * (1.0 + 0.5 * k) * (1 if k % 2 == 0 else -1) for k in range(n)]
    return np.column_stack([cols, heights])


def obstacle_line_examples(n: int = 3):
    """Return [(obstacles, start, goal)], one query for each domain W_4..W_{2n+4} (m = 2, d = 2).

    Domain l = cp(C) + cp(C') uses cp(C) = ceil(l/2), cp(C') = floor(l/2).
    """
    obstacles = np.array([[0.0, 0.0], [4.0, 0.0]])
    out = []
    for label in range(4, 2 * n + 5):
        i, j = (label + 1) // 2, label // 2
        out.append((obstacles, line_configuration(i, n), line_configuration(j, n, goal=True)))
    return out


def planar_three_examples() -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Return four exact queries ``(obstacles (3, 2), start (1, 2), goal (1, 2))`` of the
    ``planar_three`` planner (paper Section 4), in W1..W4.

    Obstacles o1 = (0, 0), o2 = (4, 0); strata T23_44 (W1, Figure 6 right),
    T22_22 (W2, Figure 8 right), T23_33 (W3, Figure 10), T23_34 (W4).

    Examples
    --------
    >>> from pmplan.planners.planar_three import classify
    >>> [int(classify(o[None], s[None], g[None]).domain[0]) for o, s, g in planar_three_examples()]
    [1, 2, 3, 4]
    """

    def f(*rows):
        return np.array(rows, dtype=float)

    return [
        (f([0, 0], [4, 0], [5, 1.5]), f([1.5, -3]), f([7, -1.5])),
        (f([0, 0], [4, 0], [0, 1.5]), f([4, 1.5]), f([0, -1.5])),
        (f([0, 0], [4, 0], [2.5, 1.5]), f([2.5, -1.5]), f([0, 3])),
        (f([0, 0], [4, 0], [2.5, 1.5]), f([0, -2]), f([6, 2.5])),
    ]


#: the crowded room of ``pmplan demo`` and the tutorial: its side, required distance and draw
ROOM_SIZE, ROOM_GAP, ROOM_SEED = 10.0, 0.3, 3


def crowded_room(n: int = 8, m: int = 6, seed: int = ROOM_SEED):
    """A crowded room: ``(obstacles (m, 2), start (n, 2), goal (n, 2), bounds)`` in the box
    ``[0, 10]^2`` -- the scene family *room* of ``benchmarks/scenes.py``: obstacles at least
    ``3 ROOM_GAP`` apart and ``ROOM_GAP`` from the walls, robots at least ``1.1 ROOM_GAP`` from
    every other point of their configuration and from the walls (seeded rejection sampling)."""
    rng = np.random.default_rng(seed)

    def draw(count, others, gap_others, gap_self, margin):
        pts = []
        while len(pts) < count:
            x = rng.uniform(margin, ROOM_SIZE - margin, 2)
            if others.size and np.linalg.norm(others - x, axis=1).min() < gap_others:
                continue
            if pts and np.linalg.norm(np.asarray(pts) - x, axis=1).min() < gap_self:
                continue
            pts.append(x)
        return np.asarray(pts)

    o = draw(m, np.empty((0, 2)), 0.0, 3 * ROOM_GAP, ROOM_GAP)
    g = 1.1 * ROOM_GAP
    s = draw(n, o, g, g, g)
    t = draw(n, o, g, g, g)
    return o, s, t, (0.0, ROOM_SIZE)


def crowded_room_plans():
    """The crowded room (:func:`crowded_room`) in its box, planned as ``pmplan demo`` and the
    tutorial show it: ``(raw, refined)``, the refined plan ``pmplan.plan(..., refine=True)``
    returns for robots and obstacles of radius ``ROOM_GAP / 2`` and the raw plan it refines
    (the planner and the unit a refined plan takes by default: for 8 robots in a box in the
    plane the one-side lanes on the wall side, the robots' diameter)."""
    from . import api
    from .io import with_defaults

    o, s, g, bounds = crowded_room()
    radii = {"radius": ROOM_GAP / 2, "obstacle_radius": ROOM_GAP / 2}
    # (as pmplan plan --refine does: the raw plan with the unit and planner of a refined one)
    raw = api.plan_query(with_defaults({"obstacles": o, "start": s, "goal": g,
                                        "bounds": bounds}, radii))
    return raw, api.refine(raw, **radii)
