"""An independent, slow reference implementation of Mathematics §3 and §4.1-§4.3.

Written from docs/mathematics.md alone (not from ``pmplan.planners.obstacle_line``) in pure Python:

* every *decision* (equal columns, ``cp``, ``cp_o``, ``e == N``, which pairs enter ``eps``) is
  taken in exact rational arithmetic with :class:`fractions.Fraction` on the input floats;
* every *value* (``|w|``, ``e``, ``nu(e)``, ``eps``, ``lambda``, the waypoints) is computed with
  Fractions as well, the only irrational operation -- the square root -- being approximated to
  ~130 bits, so the returned floats are the correctly rounded values of the exact waypoints
  (up to an error far below one ulp).

So the reference differs from the library by the library's own rounding errors only.

Notation (Mathematics §3, §4.2): ``w = o2 - o1``, ``e = w/|w|``, ``s(y) = (y - o1).e`` (column),
``r(y) = (y - o1) - s(y) e`` (perpendicular part), ``p(y) = o1 + s(y) e``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

__all__ = ["Reference", "reference_plan", "paper_plan_m2", "reference_sequence", "TIMES", "frac_sqrt", "nu_exact"]

#: the 8 breakpoints of the path of Mathematics §3.5
TIMES = tuple(Fraction(a, b) for a, b in
              ((0, 1), (1, 6), (1, 3), (4, 9), (5, 9), (2, 3), (5, 6), (1, 1)))

_BITS = 130


def frac_sqrt(x: Fraction) -> Fraction:
    """Return a dyadic-scaled rational within a relative 2^-128 of ``sqrt(x)`` (x >= 0)."""
    x = Fraction(x)
    if x < 0:
        raise ValueError("negative argument")
    if x == 0:
        return Fraction(0)
    a, b = x.numerator, x.denominator
    ab = a * b
    shift = max(0, _BITS - ab.bit_length() // 2 + 2)
    root = math.isqrt(ab << (2 * shift))  # ~ sqrt(ab) * 2^shift, with >= 130 significant bits
    return Fraction(root, b << shift)


def _round(x: Fraction) -> Fraction:
    """Round to 2^-200 relative-ish precision (keeps denominators small; far below one ulp)."""
    if x == 0:
        return x
    e = max(x.numerator.bit_length() - x.denominator.bit_length(), -2000)
    unit = 200 - e
    if unit <= 0:
        return Fraction(round(x))
    return Fraction(round(x * (1 << unit)), 1 << unit)


def _dot(a, b) -> Fraction:
    return sum((p * q for p, q in zip(a, b)), Fraction(0))


def _sub(a, b):
    return [p - q for p, q in zip(a, b)]


def _add(a, b):
    return [p + q for p, q in zip(a, b)]


def _mul(c, a):
    return [c * p for p in a]


def nu_exact(w: list[Fraction]) -> tuple[list[Fraction], bool]:
    """Return ``(nu(e), e == N)`` for ``e = w/|w|`` (Mathematics §3.4 for even d, §4.1 for odd d).

    Even d = 2l: ``nu(a1, b1, ..., al, bl) = (-b1, a1, ..., -bl, al)``.
    Odd d: ``N = e_d``, ``a = e_1``; ``nu = a`` when ``w`` is a positive multiple of N (exact),
    else ``xi(e)/|xi(e)|`` with ``xi(v) = (1 - v.N) a + (a.v)(N - v)``.
    """
    d = len(w)
    norm = frac_sqrt(_dot(w, w))
    e = [_round(c / norm) for c in w]
    if d % 2 == 0:
        out = []
        for k in range(0, d, 2):
            out += [-e[k + 1], e[k]]
        return out, False
    if all(c == 0 for c in w[:-1]) and w[-1] > 0:
        return [Fraction(1)] + [Fraction(0)] * (d - 1), True
    # 1 - e.N = (|w| - w_d)/|w| = |w'|^2 / (|w| (|w| + w_d)), free of cancellation near N
    wp2 = _dot(w[:-1], w[:-1])
    one_minus = _round(wp2 / (norm * (norm + w[-1]))) if wp2 != 0 else Fraction(2)
    a = [Fraction(1)] + [Fraction(0)] * (d - 1)
    n_minus_e = [-c for c in e]
    n_minus_e[-1] = one_minus  # N - e has last coordinate 1 - e_d
    xi = _add(_mul(one_minus, a), _mul(e[0], n_minus_e))
    xnorm = frac_sqrt(_dot(xi, xi))
    return [_round(c / xnorm) for c in xi], False


@dataclass
class Reference:
    """The reference answer to one query (Mathematics §3, §4.1, §4.2).

    Attributes
    ----------
    label : int
        ``cp(C) + cp(C') - cp_o + 2 - [e == N]``.
    record : tuple
        ``(cp(C), cp(C'), cp_o, pole)``.
    times : tuple of Fraction
        The 8 breakpoints.
    waypoints : list
        8 configurations, each a list of m+n points (lists of d floats), obstacles first.
    exact : list
        The same waypoints as (approximate, ~2^-128 relative) Fractions.
    eps, lam : Fraction
        ``eps(C)``, ``eps(C')`` are in ``eps_start``/``eps_goal``; ``lam`` is lambda.
    nu : list of Fraction
    pole : bool
    """

    label: int
    record: tuple
    times: tuple
    waypoints: list
    exact: list
    eps_start: Fraction
    eps_goal: Fraction
    lam: Fraction
    nu: list
    pole: bool


def _cp(points, o1, w) -> int:
    return len({_dot(_sub(y, o1), w) for y in points})


def _deform(obstacles, robots, o1, w, norm, e, offsets=None):
    """Return (H(C, 1/2), H(C, 1), eps) for one configuration (robots only move); with
    ``offsets`` = nu(e) (the compact lanes, d >= 3) every robot keeps its offset, the part of
    its perpendicular part orthogonal to nu (Mathematics §4.4)."""
    n, m = len(robots), len(obstacles)
    allp = obstacles + robots
    cols = [_dot(_sub(y, o1), w) for y in allp]  # |w| * s(y), exact
    distinct = sorted(set(cols))
    gap = min(b - a for a, b in zip(distinct, distinct[1:]))
    eps = _round(gap / norm / (n + m))
    shared = any(cols.count(cols[m + j]) > 1 for j in range(n))
    if shared:
        desing = [_add(x, _mul((j + 1) * eps, e)) for j, x in enumerate(robots)]
    else:
        desing = [list(x) for x in robots]
    # projection p(y) = o1 + s(y) e, s(y) = (y - o1).e
    proj = [_add(o1, _mul(_round(_dot(_sub(x, o1), e)), e)) for x in desing]
    if offsets is not None and len(o1) > 2:
        rs = [_sub(x, p) for x, p in zip(desing, proj)]
        proj = [_add(p, _sub(r, _mul(_dot(r, offsets), offsets))) for p, r in zip(proj, rs)]
    return desing, proj, eps


def _exact_point(p):
    return [Fraction(c) for c in p]


def lanes_of(configs, o1, w, sides: int = 2) -> list:
    """The compact lanes' chains (Mathematics §4.4), literally: every robot's lane on its side,
    1, 2, ... In ``H(C, 1)`` the robots are in the order of their exact columns, robots of one
    column in the order of their index (the desingularization moves robot j by j eps); the odd
    robots (i = 1, 3, ...) and the even ones are taken separately (``sides=1``: all of them
    together), in that order in ``H(C_1, 1)``, and each joins the first chain whose last robot
    is before it in every configuration, or opens a new one."""
    n = len(configs[0])
    keys = [[(_dot(_sub(x, o1), w), j) for j, x in enumerate(c)] for c in configs]
    lanes = [0] * n
    for side in range(sides):
        chains = []
        for j in sorted(range(side, n, sides), key=lambda j: keys[0][j]):
            for c, chain in enumerate(chains):
                if all(key[chain[-1]] < key[j] for key in keys):
                    chain.append(j)
                    lanes[j] = c + 1
                    break
            else:
                chains.append([j])
                lanes[j] = len(chains)
    return lanes


#: the lanes' sharing of each section (``shared`` of :func:`reference_plan`), by planner name
SHARING = {"obstacle_line_shared": 2, "obstacle_line_oneside": 1}


def reference_plan(obstacles, start, goal, lift: float = 1.0, *, lam=None,
                   compact: bool = False, shared: int = 0, configs=None) -> Reference:
    """Return the reference plan for one query (obstacles (m, d), start, goal (n, d)).

    Implements Mathematics §3 (m = 2, d even), §4.1 (odd d) and §4.2 (any m >= 2) literally:
    desingularization ``x_j + j eps e`` (only when some robot shares a column), projection of the
    robots to ``L``, lift by ``i lambda nu(e)``, slide, descend, and the reverse deformation of C'.
    ``lam`` overrides lambda (to show that ``lambda = lift`` alone is not enough).
    ``compact``: the compact lanes of Mathematics §4.4 (``obstacle_line_compact``): robot i at
    ``+(H_+ + k lift)`` (odd i) or ``-(H_- + k lift)`` (even i), ``k = ceil(i / 2)``, or
    with ``shared = 2`` (``obstacle_line_shared``) its lane on its side (:func:`lanes_of`, over
    ``configs``, all the robot configurations of the query; by default start and goal), with
    ``shared = 1`` (``obstacle_line_oneside``) every robot at ``+(H_+ + k lift)``, ``k`` its
    chain among all the robots; in
    d >= 3 the projection keeps the robots' offsets, in the plane every robot goes straight to
    its lane (waypoints 2 and 5 3/5 of the way from the desingularized robot to its lane).
    """
    obs = [_exact_point(p) for p in obstacles]
    xs = [_exact_point(p) for p in start]
    ys = [_exact_point(p) for p in goal]
    m = len(obs)
    o1, o2 = obs[0], obs[1]
    w = _sub(o2, o1)
    norm = frac_sqrt(_dot(w, w))
    e = [_round(c / norm) for c in w]
    nu, pole = nu_exact(w)
    cp_o = _cp(obs, o1, w)
    cp_s = _cp(obs + xs, o1, w)
    cp_g = _cp(obs + ys, o1, w)
    label = cp_s + cp_g - cp_o + 2 - int(pole)
    # lambda = lift + max_k |r(o_k)|
    rmax = Fraction(0)
    for o in obs:
        rel = _sub(o, o1)
        s = _dot(rel, w) / _dot(w, w)
        r = _sub(rel, _mul(s, w))
        rmax = max(rmax, frac_sqrt(_dot(r, r)))
    lam = Fraction(lift) + rmax if lam is None else Fraction(lam)
    d1, p1, eps_s = _deform(obs, xs, o1, w, norm, e, nu if compact else None)
    d2, p2, eps_g = _deform(obs, ys, o1, w, norm, e, nu if compact else None)
    heights = [(i + 1) * lam for i in range(len(xs))]
    if compact:  # t_k = (o_k - o_1) . nu, k >= 3
        ts = [_dot(_sub(o, o1), nu) for o in obs[2:]]
        hp = max([Fraction(0)] + ts)
        hm = max([Fraction(0)] + [-t for t in ts])
        u = Fraction(lift)
        every = [xs, ys] if configs is None else [[_exact_point(x) for x in c] for c in configs]
        k = (lanes_of(every, o1, w, shared) if shared
             else [i // 2 + 1 for i in range(len(xs))])
        heights = [hp + k[i] * u if i % 2 == 0 or shared == 1 else -(hm + k[i] * u)
                   for i in range(len(xs))]
    lifted1 = [_add(x, _mul(h, nu)) for h, x in zip(heights, p1)]
    lifted2 = [_add(x, _mul(h, nu)) for h, x in zip(heights, p2)]
    if compact and len(o1) == 2:  # the direct lift (Mathematics §4.4): 3/5 of the way up
        p1 = [_add(x, _mul(Fraction(3, 5), _sub(y, x))) for x, y in zip(d1, lifted1)]
        p2 = [_add(x, _mul(Fraction(3, 5), _sub(y, x))) for x, y in zip(d2, lifted2)]
    robots = [xs, d1, p1, lifted1, lifted2, p2, d2, ys]
    exact = [obs + r for r in robots]
    floats = [[[float(c) for c in p] for p in conf] for conf in exact]
    # the endpoints are the inputs themselves
    return Reference(label, (cp_s, cp_g, cp_o, int(pole)), TIMES, floats, exact,
                     eps_s, eps_g, lam, nu, pole)


def reference_sequence(obstacles, configs, lift: float = 1.0, compact: bool = False,
                       shared: int = 0):
    """Return ``(label, record, times, waypoints)`` of Mathematics §4.3 through r configurations.

    The two-configuration path from C_k to C_{k+1} runs on ``[(k-1)/(r-1), k/(r-1)]``;
    label ``sum_k cp(C_k) - (r-1) cp_o + 2 - [e == N]``; record ``(cp(C_1), ..., cp(C_r), cp_o,
    pole)``.
    """
    r = len(configs)
    times, wps = [], []
    cps = []
    for k in range(r - 1):
        ref = reference_plan(obstacles, configs[k], configs[k + 1], lift, compact=compact,
                             shared=shared, configs=configs)
        lo = Fraction(k, r - 1)
        ts = [lo + t / (r - 1) for t in ref.times]
        start = 0 if k == 0 else 1
        times += ts[start:]
        wps += ref.waypoints[start:]
        cps.append(ref.record[0])
        if k == r - 2:
            cps.append(ref.record[1])
        cp_o, pole = ref.record[2], ref.record[3]
    label = sum(cps) - (r - 1) * cp_o + 2 - pole
    return label, (*cps, cp_o, pole), times, wps


def paper_plan_m2(obstacles, start, goal, lift: float = 1.0):
    """Return ``(label, waypoints as Fractions)`` of the paper's Section 3 planner, literally.

    Mathematics §3: m = 2, d even. ``cp`` over the n+2 points; ``eps = min gap / (n+2)``; the
    desingularization ``x_j + t j eps e`` is the identity iff ``cp(C) = n + 2``; the linear
    deformation ``y -> y + t (p(y) - y)``; the section lifts robot i by ``i lift nu(e)``; the path
    is ``H(C, 3 tau)``, section, ``H(C', 3 - 3 tau)``; label ``cp(C) + cp(C')``.
    Written separately from :func:`reference_plan` (which implements the m-obstacle Mathematics §4.2).
    """
    o1, o2 = (_exact_point(p) for p in obstacles)
    w = _sub(o2, o1)
    if len(w) % 2:
        raise ValueError("the paper's Section 3 planner needs an even dimension")
    norm = frac_sqrt(_dot(w, w))
    e = [_round(c / norm) for c in w]
    nu = []
    for k in range(0, len(e), 2):
        nu += [-e[k + 1], e[k]]

    def s(y):
        return _round(_dot(_sub(y, o1), e))

    def h(config):
        n = len(config)
        cols = {_dot(_sub(y, o1), w) for y in [o1, o2] + config}
        cp = len(cols)
        srt = sorted(cols)
        eps = _round(min(b - a for a, b in zip(srt, srt[1:])) / norm / (n + 2))
        half = [list(x) if cp == n + 2 else _add(x, _mul(j * eps, e))
                for j, x in enumerate(config, start=1)]
        end = [_add(y, _sub(_add(o1, _mul(s(y), e)), y)) for y in half]
        return cp, half, end

    xs = [_exact_point(p) for p in start]
    ys = [_exact_point(p) for p in goal]
    cp1, half1, end1 = h(xs)
    cp2, half2, end2 = h(ys)
    up1 = [_add(x, _mul(i * Fraction(lift), nu)) for i, x in enumerate(end1, start=1)]
    up2 = [_add(x, _mul(i * Fraction(lift), nu)) for i, x in enumerate(end2, start=1)]
    robots = [xs, half1, end1, up1, up2, end2, half2, ys]
    return cp1 + cp2, [[o1, o2] + r for r in robots]
