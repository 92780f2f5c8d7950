"""Reading queries and writing plans: JSON for one query, npz for batches.

Query JSON (one query)::

    {"obstacles": [[x, y], ...],      # (m, d)
     "start":     [[x, y], ...],      # (n, d)
     "goal":      [[x, y], ...],      # (n, d)
     "via":       [[[x, y], ...], ...],   # optional: intermediate configurations (Mathematics §4.3)
     "lift":      1.0,                # optional: a positive number, or "scene"
     "bounds":    [[0, 0], [10, 10]], # optional: the workspace box [lo, hi] (pmplan.workspace)
     "planner":   "obstacle_line"}    # optional

Batch npz (``pmplan batch``): arrays ``obstacles`` (B, m, d), ``start`` (B, n, d), ``goal``
(B, n, d). Output npz: ``domain`` (B,), ``clearance`` (B,), ``times`` (K,) or (B, K),
``waypoints`` (B, K, m+n, d), ``strata`` (B, S) and ``stratum`` (B,) names, and the fields of
refined motions (:data:`REFINE_FIELDS`, issue 14): ``refined``, ``radius``, ``obstacle_radius``
(B,) always; for a refined batch also ``respects_radius`` (B,), the exact minima
``robot_distance``, ``obstacle_distance`` (B,), ``radius_reason`` (B,) strings (why a plan
misses its radii, :mod:`pmplan.reasons`; empty where it keeps them), ``radius_category`` (B,)
strings (its :attr:`~pmplan.reasons.RadiusMiss.category`: ``gap``, ``robots``, ``obstacle`` or
``wall``; empty where it keeps them) and the unrefined plans'
``raw_clearance`` (B,)
(an unrefined batch has radius 0, and its minimum distance is ``clearance``: measuring the two
minima apart would cost a pass over all pairs, so ``pmplan batch`` without ``--refine`` stays
as fast as before); ``bounds`` (B, 2, d) for a batch planned in a workspace box.

The JSON of one plan (:func:`plan_to_dict`) has the same fields; a distance that has no pair to
measure (``robot_distance`` with one robot) is ``null`` there (``inf`` in the npz).
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import numpy as np

from .configuration import as_lift, as_real, default_lift
from .errors import InputError
from .planners.base import default_planner, out_of_scope

__all__ = [
    "MAX_POINTS",
    "MAX_SAMPLES",
    "MAX_OUTPUT_NUMBERS",
    "REFINE_FIELDS",
    "read_query",
    "parse_query",
    "plan_to_dict",
    "read_queries",
    "same_value",
    "with_defaults",
    "write_plans",
]

def with_defaults(query: dict, refine: dict | None) -> dict:
    """The query ``query`` with the unit and the planner of its plan: its own ``"lift"`` and
    ``"planner"``, else those of a plan refined with the keywords ``refine`` (of
    :func:`pmplan.refine`; None: a raw plan), as the planning functions choose them
    (``pmplan.configuration.default_lift``; ``pmplan.checks.choose_planner``, whose default
    for a refined crowd is ``obstacle_line_oneside``, in a workspace box from
    ``WALL_LANES`` to ``ROBOT_LANES`` robots ``obstacle_line_robots``, with more
    ``obstacle_line_walls``). The faces (``pmplan plan``, ``pmplan
    batch``, ``pmplan explore``) plan raw, then refine: this gives their raw plan the unit and
    the planner ``pmplan.plan(..., refine=True)`` would use. ``query`` holds arrays
    (:func:`parse_query`, :func:`read_queries`: one query or a batch). The radii are checked
    by the refinement."""
    radii = refine or {}
    out = dict(query, lift=default_lift(query.get("lift"), radii.get("radius", 0.0),
                                        radii.get("obstacle_radius", 0.0), refine is not None))
    if refine is not None and query.get("planner") is None:
        try:
            (m, d), n = np.shape(query["obstacles"])[-2:], np.shape(query["start"])[-2]
        except (ValueError, IndexError):  # malformed: the planning function says how
            return out
        if out_of_scope(d, n, m) is None:  # (else the planning function says why)
            out["planner"] = default_planner(d, n, m, "via" in query, refining=True,
                                             bounded=query.get("bounds") is not None)
    return out


#: largest number of points (m + n) accepted in one query read from a file
MAX_POINTS = 10_000
#: largest number of samples of a path (``plan_to_dict(samples=K)``, ``pmplan plan --samples``)
MAX_SAMPLES = 100_000
#: largest number of coordinates K * (m + n) * d in the samples of one path
MAX_OUTPUT_NUMBERS = 10_000_000
_KEYS = {"obstacles", "start", "goal", "via", "lift", "planner", "bounds"}
#: the fields a Plan / PlanBatch reports about refinement and radii (:func:`pmplan.refine`),
#: written by :func:`plan_to_dict` and :func:`write_plans`
REFINE_FIELDS = ("refined", "radius", "obstacle_radius", "robot_distance", "obstacle_distance",
                 "respects_radius", "raw_clearance")


#: the fix named when a query file holds something that is not a real number
_JSON_FIX = "write plain numbers in the query (not strings, booleans or null)"


def _numeric(value, name: str, ndim: int) -> np.ndarray:
    """A list nested ``ndim`` deep of JSON numbers as a float array.

    The numbers follow the rule of :func:`pmplan.configuration.as_real` (also for the API):
    a bool, a string or null is refused, and so is an integer a double cannot hold exactly
    (e.g. ``10**400``), naming the coordinate (``start[0][1]``) -- nothing is rounded.
    """
    def walk(v, depth):
        if depth == 0:
            if isinstance(v, list):
                raise InputError(f"`{name}` must be a list nested {ndim} deep (found a list "
                                 "where a number belongs)")
            return
        if not isinstance(v, list):
            raise InputError(f"`{name}` must be a list nested {ndim} deep (got {type(v).__name__})")
        for item in v:
            walk(item, depth - 1)

    walk(value, ndim)
    try:
        arr = np.asarray(value, dtype=object)
    except ValueError:
        raise InputError(f"`{name}` is ragged: its rows have different lengths") from None
    if arr.ndim != ndim:
        raise InputError(f"`{name}` is ragged: its rows have different lengths")
    return as_real(value, name, fix=_JSON_FIX)


def json_int(text: str) -> int:
    """``parse_int`` of :func:`json.loads`: the integer, or for one of more than 4000 digits
    (which Python will not convert) an integer of more than 4000 digits of the same sign, so
    that :func:`_numeric` refuses it as too large for a double, naming the coordinate."""
    digits = text.lstrip("-")
    if len(digits) <= 4000:
        return int(text)
    return (-1 if text.startswith("-") else 1) * 10**4001


def parse_query(obj) -> dict:
    """Validate the structure of a decoded query object; return arrays and options."""
    if not isinstance(obj, dict):
        raise InputError(f"a query must be a JSON object, got {type(obj).__name__}")
    unknown = set(obj) - _KEYS
    if unknown:
        raise InputError(
            f"unknown key(s) {sorted(unknown)} in query; expected {sorted(_KEYS)}"
        )
    missing = {"obstacles", "start", "goal"} - set(obj)
    if missing:
        raise InputError(f"query is missing key(s) {sorted(missing)}")
    out = {
        "obstacles": _numeric(obj["obstacles"], "obstacles", 2),
        "start": _numeric(obj["start"], "start", 2),
        "goal": _numeric(obj["goal"], "goal", 2),
    }
    if "via" in obj:
        out["via"] = [_numeric(c, f"via[{k}]", 2) for k, c in enumerate(obj["via"])] \
            if isinstance(obj["via"], list) else _numeric(obj["via"], "via", 3)
    if "lift" in obj:
        out["lift"] = as_lift(obj["lift"])  # a positive number, or "scene"
    if "bounds" in obj:  # (checked against d by the planning function: pmplan.workspace)
        b = obj["bounds"]
        if not isinstance(b, list) or len(b) != 2:
            raise InputError(f"`bounds` must be a list [lo, hi] (numbers or coordinate lists), "
                             f"got {b!r}")
        out["bounds"] = [_numeric(v, f"bounds[{k}]", np.ndim(v)) for k, v in enumerate(b)]
    if "planner" in obj:
        if not isinstance(obj["planner"], str):
            raise InputError(f"`planner` must be a string, got {obj['planner']!r}")
        out["planner"] = obj["planner"]
    npts = out["obstacles"].shape[0] + out["start"].shape[0]
    if npts > MAX_POINTS:
        raise InputError(f"query has {npts} points (m + n); the limit is {MAX_POINTS}")
    return out


def _load_npz(path: Path) -> dict:
    """The arrays of an npz file by name; an InputError for anything that is not one
    (a missing file, a .npy, a pickle, a truncated zip)."""
    try:
        data = np.load(path, allow_pickle=False)
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise InputError(f"cannot read {path} as npz: {exc}") from None
    if not isinstance(data, np.lib.npyio.NpzFile):
        raise InputError(f"cannot read {path} as npz: it holds a single array (.npy), not "
                         "named arrays (write it with numpy.savez)")
    try:
        with data:
            return {k: np.asarray(data[k]) for k in data.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise InputError(f"cannot read {path} as npz: {exc}") from None


def _read_query_npz(path: Path) -> dict:
    arrays = _load_npz(path)
    obj = {}
    for key, arr in arrays.items():
        if key in ("lift",) and arr.ndim == 0:
            obj[key] = arr.item()
        elif key == "planner":
            obj[key] = str(arr)
        elif arr.dtype.kind in "iuf":
            obj[key] = arr.tolist()
        else:
            raise InputError(f"array `{key}` in {path} must be numeric, got dtype {arr.dtype}")
    return parse_query(obj)


def read_query(path: str | Path) -> dict:
    """Read and validate one query from a JSON file, or from an npz file with arrays
    ``obstacles`` (m, d), ``start`` (n, d), ``goal`` (n, d) and optional ``via`` (k, n, d),
    ``lift`` (scalar).
    """
    if Path(path).suffix == ".npz":
        return _read_query_npz(Path(path))
    try:
        text = Path(path).read_text()
    except OSError as exc:
        raise InputError(f"cannot read {path}: {exc.strerror or exc}") from None
    try:
        obj = json.loads(text, parse_int=json_int)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path} is not valid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}") from None
    return parse_query(obj)


def plan_to_dict(plan, samples: int | None = None) -> dict:
    """Return the JSON-ready dict of a :class:`~pmplan.Plan`.

    With ``samples=K`` the path is given as K equally spaced samples instead of its waypoints.
    A plan that misses its radii says why twice: ``radius_reason``, the sentence, and
    ``radius_miss``, its fields (:meth:`pmplan.reasons.RadiusMiss.as_dict`: ``contact``,
    ``between``, ``distance``, ``need``, ``t``, ``gap`` and ``category``); both are null when
    the radii are kept.
    """
    out = {
        "planner": plan.planner,
        "domain": plan.domain,
        "stratum": plan.stratum,
        "clearance": plan.clearance,
    }
    if plan.bounds is not None:
        out["bounds"] = np.asarray(plan.bounds).tolist()
    for key in REFINE_FIELDS:
        value = getattr(plan, key)
        if isinstance(value, (bool, np.bool_)):
            out[key] = bool(value)
        else:  # a length: JSON has no infinity (no pair to measure: null)
            out[key] = float(value) if np.isfinite(value) else None
    out["radius_reason"] = plan.radius_reason  # (None when the radii are kept)
    miss = plan.radius_miss
    out["radius_miss"] = None if miss is None else miss.as_dict()
    if samples is not None:
        if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) \
                or not 2 <= samples <= MAX_SAMPLES:
            raise InputError(f"--samples must be an integer from 2 to {MAX_SAMPLES:,}, "
                             f"got {samples!r}")
        d, n, m = plan.dims
        numbers = int(samples) * (m + n) * d
        if numbers > MAX_OUTPUT_NUMBERS:
            raise InputError(
                f"{samples:,} samples of {m + n} points in d = {d} are {numbers:,} numbers, "
                f"more than the limit {MAX_OUTPUT_NUMBERS:,}: ask for at most "
                f"{MAX_OUTPUT_NUMBERS // ((m + n) * d):,} samples"
            )
        ts = np.linspace(0.0, 1.0, samples)
        out["times"] = ts.tolist()
        out["samples"] = plan.path(ts).tolist()
    else:
        out["times"] = plan.path.times.tolist()
        out["waypoints"] = plan.path.waypoints.tolist()
    return out


#: per-query options of a batch: honoured when every query gives the same value, else refused
_BATCH_OPTIONS = ("lift", "planner", "bounds")


def same_value(a, b) -> bool:
    """Whether two values of an option are the same (numbers, words, or a box): the rule of a
    JSON list's per-query options and of a command-line option beside its file's key."""
    if isinstance(a, list) or isinstance(b, list):
        try:
            return bool(np.array_equal(np.asarray(a, dtype=float), np.asarray(b, dtype=float)))
        except (TypeError, ValueError):
            return False
    return a == b


def _common_options(path: Path, qs: list[dict]) -> dict:
    """The options (``lift``, ``planner``, ``bounds``) and stacked ``via`` of a JSON list of
    queries.

    A batch is planned with one lift and one planner, and a ``via`` needs the same number of
    intermediate configurations in every query (:func:`pmplan.plan_sequence_batch`). So an
    option must be given by every query with the same value, or by none; anything else is an
    InputError naming the first query that differs -- never silently ignored.
    """
    out: dict = {}
    for key in _BATCH_OPTIONS:
        given = [i for i, q in enumerate(qs) if key in q]
        if not given:
            continue
        if len(given) < len(qs):
            i = next(i for i, q in enumerate(qs) if key not in q)
            raise InputError(
                f"{path}: query {given[0]} gives \"{key}\" but query {i} does not; a batch is "
                f"planned with one {key}: give every query the same \"{key}\", or none (and use "
                f"--{key})"
            )
        first = qs[0][key]
        for i, q in enumerate(qs):
            if not same_value(q[key], first):
                raise InputError(
                    f"{path}: query {i} has \"{key}\": {q[key]!r} but query 0 has {first!r}; a "
                    f"batch is planned with one {key}: split the file by {key}"
                )
        out[key] = first
    with_via = [i for i, q in enumerate(qs) if "via" in q]
    if with_via:
        if len(with_via) < len(qs):
            i = next(i for i, q in enumerate(qs) if "via" not in q)
            raise InputError(
                f"{path}: query {with_via[0]} has \"via\" but query {i} does not; plan queries "
                f"with and without intermediate configurations in separate batches"
            )
        n_via = len(qs[0]["via"])
        for i, q in enumerate(qs):
            if len(q["via"]) != n_via:
                raise InputError(
                    f"{path}: query {i} has {len(q['via'])} intermediate configuration(s) in "
                    f"\"via\" but query 0 has {n_via}; a batch needs the same number in every "
                    f"query: split the file"
                )
            for k, c in enumerate(q["via"]):
                if np.shape(c) != q["start"].shape:
                    raise InputError(
                        f"{path}: query {i} has via[{k}] of shape {np.shape(c)}; expected the "
                        f"shape (n, d) = {q['start'].shape} of its start"
                    )
        out["via"] = np.array([[np.asarray(c, dtype=float) for c in q["via"]] for q in qs],
                              dtype=float).reshape(len(qs), n_via, *qs[0]["start"].shape)
    return out


def read_queries(path: str | Path) -> dict:
    """Read a batch of queries from npz or JSON.

    npz: arrays ``obstacles`` (B, m, d), ``start`` (B, n, d), ``goal`` (B, n, d) and optional
    ``via`` (B, k, n, d) (k intermediate configurations), ``lift`` (scalar: a number or the
    string ``scene``) and ``planner`` (scalar string). A JSON file may hold one query object or
    a list of query objects with equal (m, n, d); a per-query ``lift``, ``planner`` or ``via``
    is honoured when every query gives it (the same ``lift`` and ``planner``; ``via`` with the
    same number of configurations) and refused otherwise.

    Returns
    -------
    dict
        ``obstacles``, ``start``, ``goal`` (arrays with a leading batch axis B >= 0) and the
        optional keys ``via`` (B, k, n, d), ``lift``, ``planner``.
    """
    path = Path(path)
    if path.suffix == ".json":
        try:
            obj = json.loads(path.read_text())
        except OSError as exc:
            raise InputError(f"cannot read {path}: {exc.strerror or exc}") from None
        except json.JSONDecodeError as exc:
            raise InputError(f"{path} is not valid JSON: {exc.msg} at line {exc.lineno}") from None
        items = obj if isinstance(obj, list) else [obj]
        if not items:
            raise InputError(f"{path} holds an empty list; an empty batch needs its shapes: "
                             "write it as an npz with arrays of shapes (0, m, d), (0, n, d)")
        qs = []
        for i, item in enumerate(items):
            try:
                qs.append(parse_query(item))
            except InputError as exc:
                if len(items) == 1:
                    raise
                raise type(exc)(f"{path}: query {i}: {exc}") from None
        try:
            out = {k: np.stack([q[k] for q in qs]) for k in ("obstacles", "start", "goal")}
        except ValueError:
            raise InputError(f"{path}: the queries do not all have the same (m, n, d)") from None
        out.update(_common_options(path, qs))
        return out
    out = _load_npz(path)
    missing = {"obstacles", "start", "goal"} - set(out)
    if missing:
        raise InputError(
            f"{path} lacks array(s) {sorted(missing)}; expected obstacles (B, m, d), "
            "start (B, n, d), goal (B, n, d)"
        )
    unknown = set(out) - {"obstacles", "start", "goal", "via", "lift", "planner"}
    if unknown:
        raise InputError(
            f"{path} has unknown array(s) {sorted(unknown)}; expected obstacles, start, "
            "goal and optional via, lift, planner"
        )
    for k in ("obstacles", "start", "goal", "via"):
        if k in out and out[k].dtype.kind not in "iuf":
            raise InputError(f"array `{k}` in {path} must be numeric, got dtype {out[k].dtype}")
    if "via" in out:
        via, start = out["via"], out["start"]
        if via.ndim != 4 or via.shape[0] != start.shape[0] or via.shape[2:] != start.shape[1:]:
            raise InputError(
                f"array `via` in {path} has shape {via.shape}; expected (B, k, n, d) = "
                f"({start.shape[0]}, k, {', '.join(map(str, start.shape[1:]))})"
            )
    for k, kinds, what in (("lift", "iufU", "a number or the string 'scene'"),
                           ("planner", "U", "a string")):
        if k in out:
            if out[k].ndim != 0 or out[k].dtype.kind not in kinds:
                raise InputError(f"array `{k}` in {path} must be a scalar, {what}; got shape "
                                 f"{out[k].shape} and dtype {out[k].dtype}")
            out[k] = out[k].item()
    return out



def _misses(batch) -> dict:
    """The npz arrays of why a refined batch's plans miss their radii: ``radius_reason`` and
    ``radius_category`` (B,) strings, empty where the radii are kept."""
    misses = batch.radius_miss
    return {"radius_reason": np.array([mi.sentence if mi else "" for mi in misses], dtype=str),
            "radius_category": np.array([mi.category if mi else "" for mi in misses],
                                        dtype=str)}

def write_plans(path: str | Path, batch) -> Path:
    """Write a :class:`~pmplan.PlanBatch` to an npz file (see the module docstring).

    ``.npz`` is appended to a name without that suffix (as :func:`numpy.savez` does).

    Returns
    -------
    pathlib.Path
        The file written.
    """
    path = Path(path)
    if path.suffix != ".npz":
        path = path.with_name(path.name + ".npz")
    refined = bool(batch.refined.any())
    np.savez(
        path,
        domain=batch.domain,
        clearance=batch.clearance,
        times=batch.times,
        waypoints=batch.waypoints,
        strata=batch.strata,
        stratum=batch.stratum.astype(str),
        planner=np.array(batch.planner),
        **{key: np.asarray(getattr(batch, key))
           for key in (REFINE_FIELDS if refined else REFINE_FIELDS[:3])},
        **(_misses(batch) if refined else {}),
        **({} if batch.bounds is None else {"bounds": np.asarray(batch.bounds)}),
    )
    return path
