"""Checking a planner: certificates, strata and labels covered, continuity inside each domain.

A planner is a partition of the query space into *domains of continuity* W_l with a rule that is
continuous on each (paper Section 2, definition of a tame planner; Mathematics §1). :func:`verify`
gathers the evidence for one (d, n, m):

1. **Certificates** (Mathematics §6). Queries of three families are planned with
   :func:`pmplan.plan_batch`, which certifies every path:

   * ``exact``: exact degenerate queries in every stratum -- :func:`pmplan.generators.column_query`
     for every stratum of :func:`pmplan.generators.strata` (obstacle-line planner), or
     :func:`pmplan.generators.planar_stratum_queries` for the 12 strata of paper Section 4;
   * ``random``: generic queries, :func:`pmplan.generators.random_queries`;
   * ``near-degenerate``: exact degenerate queries whose ties are broken by ``~1e-9`` and
     ``~1e-15`` of the scene (:func:`pmplan.generators.near_degenerate_queries`).

   **The failure rule.** A :class:`~pmplan.errors.CertificationError` on a query is *excused*
   (reported, not a failure) iff the query is nearly degenerate beyond double precision::

       rho(Q) = g(Q) / R(Q) < RHO_MIN = 2**-26  (about 1.5e-8)

   where ``g(Q)`` is the smallest nonzero difference between two distinct exact projections the
   planner decides on -- columns ``(y - o1) . e`` (and for ``planar_three`` also heights
   ``(y - o1) . nu(e)``) among the points of C or of C' -- or the smallest distance between two
   points of C or of C', whichever is smaller, and ``R(Q) = max |y - o1|`` over the query. Below
   ``2**-26`` the near-coincidence uses more than half of the 53 bits of a double, and Mathematics §6
   asks the planner to refuse such a query with this clear error rather than return a colliding
   path. On every other query (in practice: every exact and random query) a certificate failure
   is a failure: ``ok`` is False and ``pmplan verify`` exits with status 1.

2. **Coverage**: the strata met in each domain, and whether every label of
   ``pmplan.info(d, n, m).labels`` was realised.

3. **Continuity inside a domain** (Mathematics §6). Each exact and random query Q is moved inside its
   stratum by about ``delta`` (the planner's ``perturb_within_stratum``:
   :func:`pmplan.generators.perturb_within_stratum`; for ``planar_three`` an exact similarity,
   or moves of the robot and o3 along their column or line,
   :func:`pmplan.generators.perturb_planar_stratum`) to Q'; the *continuity modulus* of a domain
   is the largest ratio ``sup_t |Gamma_Q(t) - Gamma_Q'(t)| / |Q - Q'|`` (:func:`path_distance`,
   :func:`query_distance`). A perturbed query that changes its label is an error.

4. **Jumps across domains**. Each exact query Q is moved by ``delta`` in a generic direction
   (robots only) to Q'; where the labels of Q and Q' differ, the ratio
   ``sup_t |Gamma_Q(t) - Gamma_Q'(t)| / |Q - Q'|`` is recorded for both domains. It is of the
   order of ``1/delta`` (a path at distance O(1) from a query at distance delta): the evidence
   that one continuous rule cannot serve both domains, while the modulus stays O(1) inside each.

5. **Odd d near the pole** (Mathematics §4.1). The lift direction nu(e) is a continuous unit tangent
   field on ``S^{d-1}`` minus N = e_d; such a field must wind around N (index 2 = the Euler
   characteristic of the sphere), so close to N the modulus inside a domain grows like
   ``2 h / angle``, h the highest lane (measured: ``benchmarks/odd_d_pole.py``). Random and
   exact queries rarely come near N, so the report states it as a note (:data:`POLE_NOTE`,
   ``Report.notes``)
   for odd d rather than measuring it.

6. **The refined planner** (``refine=True``, ``pmplan verify --refine``; issue 14). Refinement
   composes the planner with a continuous map of paths that keeps the endpoints and the
   obstacles and creates no collision (:func:`pmplan.refine`, ``docs/refinement.md``), so the
   refined planner has the same domains. Every planned batch is refined (radius 0) and certified
   again, with the same failure rule; a refined plan whose label or stratum differs from its raw
   plan is a problem. The refined continuity modulus of each domain is measured on the same
   pairs (Q, Q') as the raw one and reported beside it (``DomainReport.refined_modulus``).

Norms: ``|Q - Q'|`` is the largest Euclidean displacement of one of the m + 2n points (obstacles,
start and goal robots), and ``sup_t |Gamma(t) - Gamma'(t)|`` the largest Euclidean distance between
corresponding points at equal times; it is computed exactly for piecewise-linear paths (the
maximum over the union of their breakpoints).
"""

from __future__ import annotations

import json
import sys
from dataclasses import asdict, dataclass, field

import numpy as np

from . import api
from . import generators as gen
from .errors import CertificationError, InputError
from .frame import Frame
from .path import PiecewiseLinearPath
from .planners.obstacle_line import POLE_NOTE as OBSTACLE_LINE_POLE_NOTE
from .predicates import projection_classes
from .display import display_for
from .strata import spec_for

__all__ = [
    "RHO_MIN",
    "DELTA",
    "MIN_QUERIES",
    "MAX_QUERIES",
    "MAX_NUMBERS",
    "POLE_NOTE",
    "REFINED",
    "REFINE_DELTAS",
    "REFINE_SCALE",
    "DomainReport",
    "Report",
    "path_distance",
    "query_distance",
    "degeneracy_ratio",
    "verify",
]

#: a certificate failure on a query with degeneracy ratio below this is excused (see module doc)
RHO_MIN = 2.0**-26
#: size of the perturbations used for the continuity modulus and the cross-domain jumps
DELTA = 1e-6
#: scales at which the near-degenerate family breaks exact ties
NEAR_SCALES = (1e-9, 1e-15)
#: the fewest ``queries`` (the size of the base families) :func:`verify` accepts
MIN_QUERIES = 10
#: the most ``queries`` :func:`verify` accepts
MAX_QUERIES = 100_000
#: most coordinates one family may hold in its pairwise-distance array (queries * P**2 * d)
MAX_NUMBERS = 200_000_000
#: what ``verify`` says for odd d, the obstacle-line planner's note (``Planner.notes``)
POLE_NOTE = OBSTACLE_LINE_POLE_NOTE
#: the prefix of the families of refined plans in ``Report.families`` (``verify(refine=True)``)
REFINED = "refined "
#: the perturbation sizes of the refined continuity probe (``verify(refine=True)``): the same
#: base queries moved by each, so that a modulus that does not scale with the size (a jump
#: inside a domain, hidden at one size) shows
REFINE_DELTAS = (1e-6, 1e-9, 1e-12)
#: a domain's refined modulus scales linearly when the largest over :data:`REFINE_DELTAS` is at
#: most this many times the one at the largest size (or the raw modulus, or 1); else it is a
#: problem of the report (and ``pmplan verify --refine`` exits 1)
REFINE_SCALE = 10.0


# ------------------------------------------------------------------------------------------------
# distances


def _evaluate_rows(times: np.ndarray, wp: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Evaluate B paths at per-path times.

    times (B, K), wp (B, K, P, d), t (B, T) -> (B, T, P, d).
    """
    k = times.shape[1]
    idx = np.clip((times[:, None, :] <= t[:, :, None]).sum(-1) - 1, 0, k - 2)
    t0 = np.take_along_axis(times, idx, axis=1)
    t1 = np.take_along_axis(times, idx + 1, axis=1)
    dur = t1 - t0
    with np.errstate(invalid="ignore", divide="ignore"):
        frac = np.where(dur > 0, (t - t0) / np.where(dur > 0, dur, 1.0), 0.0)
    bidx = np.arange(wp.shape[0])[:, None]
    a, b = wp[bidx, idx], wp[bidx, idx + 1]
    return a + frac[..., None, None] * (b - a)


def path_distance(a: PiecewiseLinearPath, b: PiecewiseLinearPath) -> np.ndarray:
    """Return ``sup_t max_k |a_k(t) - b_k(t)|`` for batches of piecewise-linear paths.

    The difference of two piecewise-linear paths is linear between consecutive points of the
    union of their breakpoints, and the norm of a linear map is convex, so the supremum is the
    maximum over that union: computed exactly (up to rounding), not sampled.

    Parameters
    ----------
    a, b : PiecewiseLinearPath
        Batches of B paths with the same number of points P and dimension d (any breakpoints).

    Returns
    -------
    ndarray, shape (B,)

    Examples
    --------
    >>> from pmplan.path import linear
    >>> z = np.zeros((1, 1, 2)); e1 = np.array([[[1.0, 0.0]]])
    >>> a = linear(z, e1)                      # 0 -> e1 at constant speed
    >>> b = linear(z, e1 / 2).join(linear(e1 / 2, e1), at=[0.25])  # faster, then slower
    >>> path_distance(a, b)                    # largest gap at t = 1/4: |1/2 - 1/4|
    array([0.25])
    """
    bsz = a.waypoints.shape[0]
    ta = np.broadcast_to(a.times, (bsz, a.times.shape[-1]))
    tb = np.broadcast_to(b.times, (bsz, b.times.shape[-1]))
    t = np.concatenate([ta, tb], axis=1)
    diff = _evaluate_rows(ta, a.waypoints, t) - _evaluate_rows(tb, b.waypoints, t)
    return np.sqrt((diff * diff).sum(-1)).max(axis=(1, 2))


def query_distance(q, q2) -> np.ndarray:
    """Return the largest Euclidean displacement of a point between two batches of queries.

    ``q``, ``q2``: ``(obstacles (B, m, d), start (B, n, d), goal (B, n, d))``; result (B,).

    Examples
    --------
    >>> o = np.zeros((1, 2, 2)); o[0, 1] = 1
    >>> x = np.ones((1, 1, 2))
    >>> query_distance((o, x, x), (o, x + [[[3.0, 4.0]]], x))
    array([5.])
    """
    out = None
    for a, b in zip(q, q2):
        dif = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
        dist = np.sqrt((dif * dif).sum(-1)).max(axis=1)
        out = dist if out is None else np.maximum(out, dist)
    return out


def degeneracy_ratio(obstacles, start, goal, *, heights: bool = False) -> np.ndarray:
    """Return ``rho(Q) = g(Q) / R(Q)`` of the failure rule (module docstring), shape (B,).

    Parameters
    ----------
    obstacles, start, goal : ndarray, shapes (B, m, d), (B, n, d), (B, n, d)
    heights : bool
        Also count gaps between distinct heights (planar three-obstacle planner, d = 2).

    Examples
    --------
    A robot 2^-40 to the right of the column of o1 is nearly degenerate; on it, exactly, is not:

    >>> o = np.array([[[0.0, 0.0], [1.0, 0.0]]] * 2)
    >>> x = np.array([[[2.0**-40, 1.0]], [[0.0, 1.0]]])
    >>> degeneracy_ratio(o, x, x) < RHO_MIN
    array([ True, False])
    """
    obstacles = np.asarray(obstacles, dtype=float)
    fr = Frame(obstacles[:, 0], obstacles[:, 1])
    g = np.full(obstacles.shape[0], np.inf)
    radius = np.zeros(obstacles.shape[0])
    for robots in (np.asarray(start, dtype=float), np.asarray(goal, dtype=float)):
        pts = np.concatenate([obstacles, robots], axis=1)
        _, _, gap = projection_classes(pts, fr.o1, fr.o1 + fr.w)
        g = np.minimum(g, gap / fr.norm)
        if heights:
            _, _, hgap = projection_classes(pts, fr.o1, fr.o1 + fr.w, perpendicular=True)
            g = np.minimum(g, hgap / fr.norm)
        dif = pts[:, :, None, :] - pts[:, None, :, :]
        dist = np.sqrt((dif * dif).sum(-1))
        iu = np.triu_indices(pts.shape[1], k=1)
        g = np.minimum(g, dist[:, iu[0], iu[1]].min(axis=1))
        rel = pts - fr.o1[:, None, :]
        radius = np.maximum(radius, np.sqrt((rel * rel).sum(-1)).max(axis=1))
    return g / radius


# ------------------------------------------------------------------------------------------------
# the report


@dataclass
class DomainReport:
    """What :func:`verify` found in one domain W_l.

    Attributes
    ----------
    label : int
        The domain label l (``pmplan.Plan.domain``).
    queries : int
        Planned (certified) queries in this domain, all families.
    strata : list of str
        Strata met (paper notation), sorted.
    min_clearance : float or None
        Smallest certified clearance; None if no query landed here.
    modulus : float or None
        Continuity modulus: largest ``sup|path - path'| / |Q - Q'|`` over stratum-preserving
        perturbations of size ~delta (None if none was made in this domain).
    perturbations : int
        Number of such perturbations.
    jump : float or None
        Largest ``sup|path - path'| / |Q - Q'|`` over pairs of queries at distance ~delta with
        different labels, one of them in this domain (None if none was seen).
    jump_median : float or None
        Median of those ratios.
    jumps : int
        Number of such pairs.
    refined_queries : int
        Refined (and certified) plans in this domain (``verify(refine=True)``; else 0).
    refined_min_clearance : float or None
        Smallest certified clearance of those refined plans.
    refined_modulus : float or None
        Continuity modulus of the refined planner: the largest over the perturbation sizes
        :data:`REFINE_DELTAS` (the first on the same pairs as ``modulus``).
    refined_perturbations : int
        Number of those pairs whose refined plans were both certified.
    refined_moduli : list
        The refined modulus at each size of :data:`REFINE_DELTAS` (None where no pair was made).
    refined_linear : bool or None
        Whether the refined modulus scales linearly (:data:`REFINE_SCALE`).
    """

    label: int
    queries: int = 0
    strata: list = field(default_factory=list)
    min_clearance: float | None = None
    modulus: float | None = None
    perturbations: int = 0
    jump: float | None = None
    jump_median: float | None = None
    jumps: int = 0
    refined_queries: int = 0
    refined_min_clearance: float | None = None
    refined_modulus: float | None = None
    refined_perturbations: int = 0
    refined_moduli: list = field(default_factory=list)
    refined_linear: bool | None = None


@dataclass
class Report:
    """The result of :func:`verify`.

    Attributes
    ----------
    ok : bool
        No certificate failed (under the rule of the module docstring), every label was
        realised, and no stratum-preserving perturbation changed a label.
    planner : str
    dims : list of int
        ``[d, n, m]``.
    seed : int
    delta : float
        Perturbation size.
    labels : list of int
        The planner's labels, ``pmplan.info(d, n, m).labels``.
    realised : list of int
        The labels met.
    domains : list of DomainReport
        One per label of the planner.
    families : dict
        For each family (``exact``, ``random``, ``near-degenerate``): ``queries``, ``planned``,
        ``excused`` (refused, nearly degenerate), ``failed``.
    failures : list of dict
        Every counted failure: ``family``, ``index`` (in the family), ``rho``, ``stratum``,
        ``error`` (the exception's name).
    problems : list of str
        Why ``ok`` is False (empty when it is True).
    notes : list of str
        Facts to read the numbers by: for odd d, :data:`POLE_NOTE`.
    lift : float or str
        The lift the queries were planned with.
    refine : bool
        Whether the refined planner was checked too (``families`` then also holds ``refined
        <family>`` entries, and the domains their ``refined_*`` fields).
    """

    ok: bool
    planner: str
    dims: list
    seed: int
    delta: float
    labels: list
    realised: list
    domains: list
    families: dict
    failures: list
    problems: list
    notes: list = field(default_factory=list)
    lift: float | str = 1.0
    refine: bool = False

    def to_dict(self) -> dict:
        """Return the report as plain JSON-ready data."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict) -> Report:
        """Rebuild a report from :meth:`to_dict` (or parsed :meth:`to_json`) data."""
        data = dict(data)
        data["domains"] = [DomainReport(**d) for d in data["domains"]]
        return cls(**data)

    def to_json(self, indent: int | None = 2) -> str:
        """Return the report as JSON (strict: no NaN or infinities)."""
        return json.dumps(self.to_dict(), indent=indent, allow_nan=False)

    @classmethod
    def from_json(cls, text: str) -> Report:
        """Parse :meth:`to_json` output."""
        return cls.from_dict(json.loads(text))

    @property
    def separation(self) -> float | None:
        """Smallest per-domain jump divided by the largest continuity modulus (None if unknown)."""
        jumps = [d.jump for d in self.domains if d.jump is not None]
        mods = [d.modulus for d in self.domains if d.modulus is not None]
        if not jumps or not mods:
            return None
        top = max(mods)
        return float("inf") if top == 0 else min(jumps) / top

    def to_text(self) -> str:
        """Return a human-readable summary (the default output of ``pmplan verify``)."""
        d, n, m = self.dims
        w = display_for(self.planner).domain_prefix
        fam = ", ".join(f"{k} {v['queries']}" for k, v in self.families.items()
                        if not k.startswith(REFINED))
        lines = [
            f"pmplan verify: {self.planner} planner"
            + (" and its refinement (pmplan.refine)" if self.refine else "")
            + f", (d, n, m) = ({d}, {n}, {m}), "
            + ("" if self.lift == 1.0 else f"lift {self.lift}, ") + f"seed {self.seed}",
            f"queries: {fam}; perturbation size delta = {self.delta:g}",
            "",
            f"{'domain':<7} {'queries':>7} {'strata':>6}  {'min clearance':>13}  "
            f"{'continuity':>10}  "
            + (f"{'refined':>10}  {'refined clearance':>17}  " if self.refine else "")
            + f"{'jump (max)':>10}  {'jump (median)':>13}  examples of strata",
        ]

        def num(x):
            return f"{x:.3g}" if x is not None else "-"

        for dr in self.domains:
            shown = ", ".join(dr.strata[:3]) + (", ..." if len(dr.strata) > 3 else "")
            lines.append(
                f"{w + str(dr.label):<7} {dr.queries:>7} {len(dr.strata):>6}  "
                f"{num(dr.min_clearance):>13}  {num(dr.modulus):>10}  "
                + (f"{num(dr.refined_modulus):>10}  {num(dr.refined_min_clearance):>17}  "
                   if self.refine else "")
                + f"{num(dr.jump):>10}  {num(dr.jump_median):>13}  {shown}"
            )
        lines.append("")
        missing = sorted(set(self.labels) - set(self.realised))
        lines.append(
            f"labels realised: {len(self.labels) - len(missing)}/{len(self.labels)}"
            + (f" (missing {missing})" if missing else " (all)")
        )
        for what, fams in (("certificates", {k: v for k, v in self.families.items()
                                             if not k.startswith(REFINED)}),
                           ("refined certificates", {k: v for k, v in self.families.items()
                                                     if k.startswith(REFINED)})):
            if not fams:
                continue
            planned = sum(v["planned"] for v in fams.values())
            excused = sum(v["excused"] for v in fams.values())
            failed = sum(v["failed"] for v in fams.values())
            lines.append(
                f"{what}: {planned} passed, {failed} failed"
                + (f"; {excused} nearly degenerate "
                   f"{'query' if excused == 1 else 'queries'} (rho < 2^-26) refused with "
                   "CertificationError, as Mathematics §6.2 allows" if excused else "")
            )
        sep = self.separation
        if sep is not None:
            top = max(d.modulus for d in self.domains if d.modulus is not None)
            low = min(d.jump for d in self.domains if d.jump is not None)
            lines.append(
                f"continuity: largest modulus inside a domain {top:.3g}; "
                f"smallest cross-domain jump {low:.3g} ({sep:.3g} times larger)"
            )
        refined = [d.refined_modulus for d in self.domains if d.refined_modulus is not None]
        if refined:
            raw = [d.modulus for d in self.domains if d.modulus is not None]
            per = [max((d.refined_moduli[k] for d in self.domains
                        if len(d.refined_moduli) > k and d.refined_moduli[k] is not None),
                       default=None) for k in range(len(REFINE_DELTAS))]
            bad = [w + str(d.label) for d in self.domains if d.refined_linear is False]
            lines.append(
                f"refined continuity: largest modulus inside a domain {max(refined):.3g} "
                + (f"(raw {max(raw):.3g}); " if raw else "; ")
                + "at perturbation sizes "
                + ", ".join(f"{dl:g}: {num(v)}" for dl, v in zip(REFINE_DELTAS, per))
                + ("; scales linearly in every domain" if not bad else
                   f"; does NOT scale linearly in {', '.join(bad)}")
                + "; the refined planner keeps the raw labels and strata"
            )
        for f in self.failures[:10]:
            lines.append(
                f"FAILED: {f['family']} query {f['index']} in {f['stratum']} "
                f"(rho = {f['rho']:.3g}): {f['error']}, the certificate failed"
            )
        if len(self.failures) > 10:
            lines.append(f"... and {len(self.failures) - 10} more failures (see --json)")
        for note in self.notes:
            lines.append(f"note: {note}")
        for p in self.problems:
            lines.append(f"problem: {p}")
        lines.append("OK" if self.ok else "NOT OK")
        return "\n".join(lines)


# ------------------------------------------------------------------------------------------------
# planning that survives certificate failures


def _surviving(run, count: int):
    """Call ``run(keep)`` on the indices ``keep = 0..count-1``, dropping the queries a
    CertificationError names until it succeeds; return (result or None, kept, refused)."""
    keep = np.arange(count)
    refused: list[tuple[int, str]] = []
    while keep.size:
        try:
            return run(keep), keep, refused
        except CertificationError as exc:
            bad = np.asarray(exc.indices, dtype=np.int64)
            if bad.size == 0:  # pragma: no cover - plan_batch and refine name the queries
                raise
            refused.extend((int(keep[i]), type(exc).__name__) for i in bad)
            keep = np.delete(keep, bad)
    return None, keep, refused


def _plan_each(q, planner: str, lift=1.0):
    """Plan a batch, dropping queries whose certificate fails; return (batch, kept, refused)."""
    obs, st, go = (np.asarray(a, dtype=float) for a in q)
    return _surviving(lambda k: api.plan_batch(obs[k], st[k], go[k], planner=planner,
                                               lift=lift), obs.shape[0])


def _refine_each(batch):
    """Refine a batch (radius 0), dropping plans whose refined certificate fails; return
    (refined batch or None, kept indices, refused [(index, error name)])."""
    return _surviving(lambda k: api.refine(batch[k]), len(batch))


def _refined_rows(refined: dict, fams: np.ndarray, rows: np.ndarray):
    """The refined plans of the planned family rows ``(fams[j], rows[j])`` that the family
    pass refined (``refined[family] = (refined batch or None, kept rows)``, :func:`_refine_each`
    of the family's planned batch): return (their paths, with per-path breakpoints, or None
    when there is none; the positions j they are for, ascending)."""
    at, times, wp = [], [], []
    for fname in dict.fromkeys(fams.tolist()):
        rb, rk = refined[fname]
        if rb is None:
            continue
        here = np.flatnonzero(fams == fname)
        j = np.minimum(np.searchsorted(rk, rows[here]), rk.size - 1)
        hit = rk[j] == rows[here]
        at.append(here[hit])
        times.append(np.broadcast_to(rb.times, (len(rb), rb.times.shape[-1]))[j[hit]])
        wp.append(rb.waypoints[j[hit]])
    if not at:
        return None, np.zeros(0, dtype=np.int64)
    at = np.concatenate(at)
    order = np.argsort(at, kind="stable")
    return (PiecewiseLinearPath(np.concatenate(times)[order], np.concatenate(wp)[order]),
            at[order])


def _rows(batch, idx) -> PiecewiseLinearPath:
    """The paths of plans ``idx`` of a batch."""
    return PiecewiseLinearPath(batch.times if batch.times.ndim == 1 else batch.times[idx],
                               batch.waypoints[idx])


def _moved_copies(p, rng, base, size: float):
    """The base queries moved within their strata by ``size`` (Q' = Q where the planner has no
    such move: distance 0, left out) and their distances."""
    moved = []
    for i in range(base[0].shape[0]):
        one = (base[0][i], base[1][i], base[2][i])
        mv = spec_for(p).perturb_within_stratum(rng, one, size)
        moved.append(one if mv is None else mv)
    mq = tuple(np.stack([mv[k] for mv in moved]) for k in range(3))
    return mq, query_distance(base, mq)


def _refined_probe(name, lift, b0, k0, r0, k0r, moved, dist):
    """``(label, sup |R(Q) - R(Q')| / |Q - Q'|)`` of the base queries whose raw plans (``b0``
    at rows ``k0``) and refined plans (``r0`` at rows ``k0r``) exist, against the moved
    queries ``moved`` planned and refined, over the pairs with the same label."""
    if r0 is None:
        return []
    b1, k1, _ = _plan_each(moved, name, lift)
    if b1 is None:
        return []
    both = np.intersect1d(np.intersect1d(k0, k1), k0r)
    both = both[dist[both] > 0]
    la = b0.domain[np.searchsorted(k0, both)]
    lb = b1.domain[np.searchsorted(k1, both)]
    same = both[la == lb]
    if same.size == 0:
        return []
    r1, k1r, _ = _refine_each(b1[np.searchsorted(k1, same)])
    if r1 is None:
        return []
    kk = same[k1r]
    j0 = np.searchsorted(k0r, kk)
    ratio = path_distance(PiecewiseLinearPath(r0.times[j0], r0.waypoints[j0]),
                          _rows(r1, np.arange(k1r.size))) / dist[kk]
    labels = b0.domain[np.searchsorted(k0, kk)]
    return list(zip(labels.tolist(), ratio.tolist()))


def _stratum_name(p, d: int, n: int, m: int, q, i: int) -> str:
    """Return the stratum of query i of a batch, decided exactly (for failure reports)."""
    one = tuple(np.asarray(a, dtype=float)[i] for a in q)
    return p.stratum_name(np.asarray(spec_for(p).stratum_row(*one)), d, n, m)


def _take(q, idx):
    return tuple(np.asarray(a)[idx] for a in q)


# ------------------------------------------------------------------------------------------------
# verify


def verify(*, planner: str | None = None, d: int = 2, n: int = 2, m: int = 2,
           lift: float | str = 1.0, queries: int = 400, seed: int = 0,
           progress: bool = True, refine: bool = False) -> Report:
    """Check a planner on (d, n, m): certificates, labels, continuity modulus and jumps.

    Parameters
    ----------
    planner : str, optional
        A name of :func:`pmplan.planner_names`; default chosen from (d, n, m) as in
        :func:`pmplan.plan` (with ``refine``, as for a refined plan).
    d, n, m : int
        Dimension, robots, obstacles.
    lift : float or str
        Passed to :func:`pmplan.plan_batch` (default 1, the paper's unit).
    queries : int
        From :data:`MIN_QUERIES` to :data:`MAX_QUERIES`. Size of the base families: 40% exact degenerate (at least one per stratum), 30% random,
        30% nearly degenerate; plus perturbed copies of half of the exact (at least one per
        stratum) and a third of the random queries, and one generic neighbour of each exact query.
    seed : int
        Seed of the random generator, >= 0 (the report is reproducible).
    progress : bool
        Show a progress bar (tqdm, on stderr).
    refine : bool
        Also check the refined planner (:func:`pmplan.refine`, radius 0): certificates of the
        refined plans (same failure rule), labels and strata kept, and the refined continuity
        modulus of each domain on the same perturbation pairs (module docstring, item 6).

    Returns
    -------
    Report
        ``ok``, per-domain results, ``to_text()``, ``to_json()``; see the module docstring for
        what is checked and the rule that excuses refusals of nearly degenerate queries.

    Raises
    ------
    InputError
        ``queries`` or ``seed`` out of range, or a case so large that one family would hold
        more than :data:`MAX_NUMBERS` numbers at once.

    Examples
    --------
    >>> r = verify(d=2, n=1, m=2, queries=40, progress=False)
    >>> r.ok, r.realised == r.labels, r.separation > 100
    (True, True, True)
    >>> r = verify(d=2, n=1, m=2, queries=40, progress=False, refine=True)
    >>> r.ok, all(d.refined_modulus is not None for d in r.domains)
    (True, True)
    """
    _check_arguments(queries, seed, refine)
    check = _Check(api.choose_planner(d, n, m, planner, refining=bool(refine)), d, n, m, lift,
                   int(queries),
                   int(seed), bool(refine), progress)
    check.plan_families()
    if refine:
        check.refine_families()
    check.continuity()
    check.jumps()
    return check.report()


def _check_arguments(queries, seed, refine) -> None:
    for what, value, lo, hi in (("queries", queries, MIN_QUERIES, MAX_QUERIES),
                                ("seed", seed, 0, None)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < lo \
                or (hi is not None and value > hi):
            bound = f"from {lo} to {hi:,}" if hi is not None else f"at least {lo}"
            raise InputError(f"`{what}` must be an integer {bound}, got {value!r}")
    if not isinstance(refine, (bool, np.bool_)):
        raise InputError(f"`refine` must be True or False, got {refine!r}")


class _Check:
    """One run of :func:`verify`: its query families, the state the steps share (the domains'
    reports, failures, problems, the planned and refined families) and the steps, in order."""

    def __init__(self, p, d: int, n: int, m: int, lift, queries: int, seed: int, refine: bool,
                 progress: bool):
        from tqdm import tqdm

        self.p, self.name, self.dims, self.lift, self.seed = p, p.name, (d, n, m), lift, seed
        self.spec, self.refine = spec_for(p), refine
        self.heights = self.spec.uses_heights
        self.labels = [int(v) for v in api.info(d, n, m, planner=self.name).labels]
        # the exact family has at least one query per stratum: (m - 1) (n + 1)^2, twice for odd d
        largest = max(queries, (m - 1) * (n + 1) ** 2 * (2 if d % 2 else 1))
        numbers = largest * (m + n) ** 2 * d
        if numbers > MAX_NUMBERS:
            raise InputError(
                f"verify on (d, n, m) = ({d}, {n}, {m}) with {largest:,} queries in a family "
                f"would hold about {numbers:,} numbers at once, more than {MAX_NUMBERS:,}: use "
                "fewer queries, or fewer robots, obstacles or dimensions"
            )
        self.rng = np.random.default_rng(seed)
        self.bar = tqdm(total=7 if refine else 6, desc=f"verify {self.name} ({d},{n},{m})",
                        unit="step", file=sys.stderr, disable=not progress, leave=False)
        n_exact, n_random = int(0.4 * queries), int(0.3 * queries)
        n_near = queries - n_exact - n_random
        rng, spec = self.rng, self.spec
        self.families = {"exact": spec.exact_queries(rng, d, n, m, n_exact)}
        self.n_strata = spec.stratum_count(d, n, m)
        self.families["random"] = tuple(gen.random_queries(rng, d, n, m, n_random))
        near = [spec.near_degenerate_queries(rng, d, n, m, k, s)
                for k, s in zip((n_near // 2, n_near - n_near // 2), NEAR_SCALES)]
        self.families["near-degenerate"] = tuple(np.concatenate(parts) for parts in zip(*near))
        self.bar.update(1)
        self.dom = {label: DomainReport(label=label) for label in self.labels}
        self.met_strata: dict[int, set] = {label: set() for label in self.labels}
        self.fam_stats: dict[str, dict] = {}
        self.failures: list[dict] = []
        self.problems: list[str] = []
        self.planned: dict[str, tuple] = {}
        self.refined_plans: dict[str, tuple] = {}  # family -> (refined batch or None, rows)

    def domain(self, label: int) -> DomainReport:
        return self.dom.setdefault(label, DomainReport(label=label))

    def count_failures(self, family: str, q, refused, rows=None) -> int:
        """Record the refusals ``(j, message)`` of queries ``q[rows[j]]`` (``rows``: None, the
        identity) that double precision can represent; return how many."""
        rho = degeneracy_ratio(*q, heights=self.heights)
        counted = 0
        for j, msg in refused:
            i = int(j if rows is None else rows[j])
            if not rho[i] < RHO_MIN:
                counted += 1
                self.failures.append({"family": family, "index": i, "rho": float(rho[i]),
                                      "stratum": _stratum_name(self.p, *self.dims, q, i),
                                      "error": msg})
        return counted

    def plan_families(self) -> None:
        """Plan every family: certificates (the failure rule), labels, strata, clearances."""
        for fname, q in self.families.items():
            batch, kept, refused = _plan_each(q, self.name, self.lift)
            failed = self.count_failures(fname, q, refused)
            self.fam_stats[fname] = {"queries": int(q[0].shape[0]), "planned": int(kept.size),
                                     "excused": len(refused) - failed, "failed": failed}
            self.bar.update(1)
            if batch is None:
                continue
            self.planned[fname] = (batch, kept)
            names = batch.stratum
            for label in np.unique(batch.domain).tolist():
                sel = batch.domain == label
                dr = self.domain(label)
                self.met_strata.setdefault(label, set()).update(names[sel].tolist())
                dr.queries += int(sel.sum())
                low = float(batch.clearance[sel].min())
                dr.min_clearance = low if dr.min_clearance is None else min(dr.min_clearance,
                                                                             low)

    def refine_families(self) -> None:
        """The refined planner on every planned family: certificates, labels and strata kept."""
        changed = 0
        for fname, (batch, kept) in self.planned.items():
            rb, rk, refused = _refine_each(batch)
            self.refined_plans[fname] = (rb, rk)
            fails = self.count_failures(REFINED + fname, self.families[fname], refused, kept)
            self.fam_stats[REFINED + fname] = {
                "queries": len(batch), "planned": int(rk.size),
                "excused": len(refused) - fails, "failed": fails}
            if rb is None:
                continue
            changed += int(((rb.domain != batch.domain[rk])
                            | (rb.stratum != batch.stratum[rk])).sum())
            for label in np.unique(rb.domain).tolist():
                sel = rb.domain == label
                dr = self.domain(label)
                dr.refined_queries += int(sel.sum())
                low = float(rb.clearance[sel].min())
                dr.refined_min_clearance = (low if dr.refined_min_clearance is None
                                            else min(dr.refined_min_clearance, low))
        if changed:
            self.problems.append(f"{changed} refined plans changed the label or stratum of "
                                 "their raw plan")
        self.bar.update(1)

    def _perturbation_pairs(self):
        """Stratum-preserving perturbations of a share of the exact and random queries:
        (base, moved, distance, family and row of each base query), or None."""
        base_o, base_s, base_g, pert, source = [], [], [], [], []
        for fname, share in (("exact", 2), ("random", 3)):
            if fname not in self.planned:
                continue
            _, kept = self.planned[fname]
            q = _take(self.families[fname], kept)
            # the exact family is built round robin over the strata: its first queries cover
            # every stratum
            for i in range(min(kept.size, max(self.n_strata, kept.size // share))):
                moved = self.spec.perturb_within_stratum(self.rng, (q[0][i], q[1][i], q[2][i]),
                                                         DELTA)
                if moved is None:
                    continue
                base_o.append(q[0][i])
                base_s.append(q[1][i])
                base_g.append(q[2][i])
                pert.append(moved)
                source.append((fname, i))
        if not pert:
            return None
        base = (np.stack(base_o), np.stack(base_s), np.stack(base_g))
        moved = tuple(np.stack([pq[k] for pq in pert]) for k in range(3))
        dist = query_distance(base, moved)
        use = dist > 0
        return (_take(base, use), _take(moved, use), dist[use],
                np.array([f for f, _ in source])[use],
                np.array([i for _, i in source], dtype=np.int64)[use])

    def continuity(self) -> None:
        """Continuity inside each domain: the raw modulus, and the refined one at every size of
        :data:`REFINE_DELTAS` (does it scale linearly?)."""
        ratios: dict[int, list] = {}
        refined_ratios: dict[int, dict] = {}  # label -> size index -> ratios
        pairs = self._perturbation_pairs()
        if pairs is not None:
            base, moved, dist, src_fam, src_row = pairs
            b0, k0, r0 = _plan_each(base, self.name, self.lift)
            b1, k1, r1 = _plan_each(moved, self.name, self.lift)
            self.count_failures("exact+random", base, r0)
            self.count_failures("perturbed", moved, r1)
            both = np.intersect1d(k0, k1)
            if both.size:
                i0, i1 = np.searchsorted(k0, both), np.searchsorted(k1, both)
                la, lb = b0.domain[i0], b1.domain[i1]
                changed = np.flatnonzero(la != lb)
                if changed.size:
                    self.problems.append(
                        f"{changed.size} stratum-preserving perturbations changed the label "
                        f"(e.g. {int(la[changed[0]])} -> {int(lb[changed[0]])})")
                ratio = path_distance(_rows(b0, i0), _rows(b1, i1)) / dist[both]
                for label, r, same in zip(la.tolist(), ratio.tolist(), (la == lb).tolist()):
                    if same:
                        ratios.setdefault(label, []).append(r)
            if self.refine and b0 is not None:
                # the refined planner at every size of REFINE_DELTAS, on the same base queries
                # Q (the family pass refined their plans already: b0 plans the same queries of
                # the exact and random families, alike); only the moved queries Q' are new
                rr0, k0r = _refined_rows(self.refined_plans, src_fam, src_row)
                for level, size in enumerate(REFINE_DELTAS):
                    mq, md = (moved, dist) if level == 0 else \
                        _moved_copies(self.p, self.rng, base, size)
                    for label, r in _refined_probe(self.name, self.lift, b0, k0, rr0, k0r, mq,
                                                   md):
                        refined_ratios.setdefault(label, {}).setdefault(level, []).append(r)
        for label, rs in ratios.items():
            dr = self.domain(label)
            dr.modulus = float(max(rs))
            dr.perturbations = len(rs)
        for label, by_size in refined_ratios.items():
            self._refined_modulus(label, by_size)
        self.bar.update(1)

    def _refined_modulus(self, label: int, by_size: dict) -> None:
        dr = self.domain(label)
        mods = [float(max(by_size[k])) if by_size.get(k) else None
                for k in range(len(REFINE_DELTAS))]
        seen = [v for v in mods if v is not None]
        dr.refined_moduli = mods
        dr.refined_modulus = max(seen)
        dr.refined_perturbations = len(by_size.get(0, []))
        ref = max(mods[0] or 0.0, dr.modulus or 0.0, 1.0)
        dr.refined_linear = max(seen) <= REFINE_SCALE * ref
        if not dr.refined_linear:
            self.problems.append(
                f"domain {display_for(self.p).domain_prefix}{label}: the refined modulus does "
                "not scale linearly with the perturbation ("
                + ", ".join(f"{v:.3g} at {dl:g}" for dl, v in zip(REFINE_DELTAS, mods)
                            if v is not None)
                + "): the refined path jumps inside the domain")

    def jumps(self) -> None:
        """Jumps across domains: exact queries against generic neighbours at distance ~delta."""
        jumps: dict[int, list] = {}
        if "exact" in self.planned:
            batch, kept = self.planned["exact"]
            q = _take(self.families["exact"], kept)
            noise = [self.rng.normal(size=a.shape) for a in q[1:]]
            scale = np.maximum(*(np.sqrt((z * z).sum(-1)).max(axis=1) for z in noise))
            near_q = (q[0], *(a + DELTA * z / scale[:, None, None] for a, z in zip(q[1:], noise)))
            # refusals here are not failures: Q' is not exact
            b1, k1, _ = _plan_each(near_q, self.name, self.lift)
            if b1 is not None:
                la, lb = batch.domain[k1], b1.domain
                diff = np.flatnonzero(la != lb)
                if diff.size:
                    times0 = batch.times if batch.times.ndim == 1 else batch.times[k1[diff]]
                    times1 = b1.times if b1.times.ndim == 1 else b1.times[diff]
                    pa = PiecewiseLinearPath(times0, batch.waypoints[k1[diff]])
                    pb = PiecewiseLinearPath(times1, b1.waypoints[diff])
                    ratio = path_distance(pa, pb) / query_distance(_take(q, k1[diff]),
                                                                   _take(near_q, k1[diff]))
                    for a_, b_, r in zip(la[diff].tolist(), lb[diff].tolist(), ratio.tolist()):
                        jumps.setdefault(a_, []).append(r)
                        jumps.setdefault(b_, []).append(r)
        for label, rs in jumps.items():
            dr = self.domain(label)
            dr.jump = float(max(rs))
            dr.jump_median = float(np.median(rs))
            dr.jumps = len(rs)
        self.bar.update(1)
        self.bar.close()

    def report(self) -> Report:
        """The report: every domain's findings, and the problems that make it not ok."""
        for label, dr in self.dom.items():
            dr.strata = sorted(self.met_strata.get(label, set()))
        realised = sorted(label for label, dr in self.dom.items() if dr.queries > 0)
        missing = sorted(set(self.labels) - set(realised))
        problems = list(self.problems)
        if self.failures:
            problems.insert(0, f"{len(self.failures)} certificate failure(s) on queries that "
                               "double precision can represent")
        if missing:
            problems.append(f"labels never realised: {missing}")
        unknown = sorted(set(realised) - set(self.labels))
        if unknown:
            problems.append(f"labels outside the planner's list {self.labels}: {unknown}")
        d, n, m = self.dims
        return Report(
            ok=not problems, planner=self.name, dims=[d, n, m], seed=self.seed, delta=DELTA,
            labels=self.labels, realised=realised,
            domains=[self.dom[label] for label in sorted(self.dom)], families=self.fam_stats,
            failures=self.failures, problems=problems, notes=self.spec.notes(d, n, m),
            lift=self.lift, refine=self.refine,
        )
