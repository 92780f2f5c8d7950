"""Reading queries and writing plans: JSON for one query, npz for batches.

Query JSON (one query)::

    {"obstacles": [[x, y], ...],      # (m, d)
     "start":     [[x, y], ...],      # (n, d)
     "goal":      [[x, y], ...],      # (n, d)
     "via":       [[[x, y], ...], ...],   # optional: intermediate configurations (SPEC 4c)
     "lift":      1.0,                # optional: a positive number, or "scene"
     "planner":   "obstacle_line"}    # optional

Batch npz (``pmplan batch``): arrays ``obstacles`` (B, m, d), ``start`` (B, n, d), ``goal``
(B, n, d). Output npz: ``domain`` (B,), ``clearance`` (B,), ``times`` (K,) or (B, K),
``waypoints`` (B, K, m+n, d), ``strata`` (B, S) and ``stratum`` (B,) names.
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import numpy as np

from .configuration import as_lift, as_real
from .errors import InputError

__all__ = [
    "MAX_POINTS",
    "read_query",
    "parse_query",
    "plan_to_dict",
    "read_queries",
    "write_plans",
]

#: largest number of points (m + n) accepted in one query read from a file
MAX_POINTS = 10_000
_KEYS = {"obstacles", "start", "goal", "via", "lift", "planner"}


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


def _json_int(text: str) -> int:
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
    if "planner" in obj:
        if not isinstance(obj["planner"], str):
            raise InputError(f"`planner` must be a string, got {obj['planner']!r}")
        out["planner"] = obj["planner"]
    npts = out["obstacles"].shape[0] + out["start"].shape[0]
    if npts > MAX_POINTS:
        raise InputError(f"query has {npts} points (m + n); the limit is {MAX_POINTS}")
    return out


def _read_query_npz(path: Path) -> dict:
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: np.asarray(data[k]) for k in data.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise InputError(f"cannot read {path} as npz: {exc}") from None
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
        obj = json.loads(text, parse_int=_json_int)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path} is not valid JSON: {exc.msg} at line {exc.lineno} column {exc.colno}") from None
    return parse_query(obj)


def plan_to_dict(plan, samples: int | None = None) -> dict:
    """Return the JSON-ready dict of a :class:`~pmplan.api.Plan`.

    With ``samples=K`` the path is given as K equally spaced samples instead of its waypoints.
    """
    out = {
        "planner": plan.planner,
        "domain": plan.domain,
        "stratum": plan.stratum,
        "clearance": plan.clearance,
    }
    if samples is not None:
        if samples < 2:
            raise InputError(f"--samples must be at least 2, got {samples}")
        ts = np.linspace(0.0, 1.0, samples)
        out["times"] = ts.tolist()
        out["samples"] = plan.path(ts).tolist()
    else:
        out["times"] = plan.path.times.tolist()
        out["waypoints"] = plan.path.waypoints.tolist()
    return out


def read_queries(path: str | Path) -> dict:
    """Read a batch of queries from npz (arrays ``obstacles``, ``start``, ``goal``) or JSON.

    A JSON file may hold one query object or a list of query objects with equal (m, n, d).
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
        qs = [parse_query(q) for q in items]
        try:
            return {k: np.stack([q[k] for q in qs]) for k in ("obstacles", "start", "goal")}
        except ValueError:
            raise InputError(f"{path}: the queries do not all have the same (m, n, d)") from None
    try:
        with np.load(path, allow_pickle=False) as data:
            missing = {"obstacles", "start", "goal"} - set(data.files)
            if missing:
                raise InputError(
                    f"{path} lacks array(s) {sorted(missing)}; expected obstacles (B, m, d), "
                    "start (B, n, d), goal (B, n, d)"
                )
            out = {k: np.asarray(data[k]) for k in ("obstacles", "start", "goal")}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(f"cannot read {path} as npz: {exc}") from None
    for k, v in out.items():
        if v.dtype.kind not in "iuf":
            raise InputError(f"array `{k}` in {path} must be numeric, got dtype {v.dtype}")
    return out


def write_plans(path: str | Path, batch) -> None:
    """Write a :class:`~pmplan.api.PlanBatch` to an npz file (see the module docstring)."""
    np.savez(
        path,
        domain=batch.domain,
        clearance=batch.clearance,
        times=batch.times,
        waypoints=batch.waypoints,
        strata=batch.strata,
        stratum=batch.stratum.astype(str),
        planner=np.array(batch.planner),
    )
