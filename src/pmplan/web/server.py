"""The local server of ``pmplan explore``: a Starlette app and its JSON API.

Endpoints
---------
``GET /``
    The page (``static/index.html``); its assets under ``/static/``. All assets are read once,
    when the app is built, from the package: a request never makes the server read or write a
    file.
``GET /api/examples``
    The paper's examples: one exact query in every stratum of Section 4
    (:func:`pmplan.figures.figure_queries`) and one in every domain of the demo
    (:func:`pmplan.examples.obstacle_line_examples`, ``planar_three_examples``).
``POST /api/plan`` (optional ``?samples=K``, ``?refine=true&radius=r&obstacle_radius=s``)
    The body is the JSON that ``pmplan plan`` reads (:func:`pmplan.io.parse_query`), the answer
    what it prints (:func:`pmplan.io.plan_to_dict`). With ``refine=true`` the answer is the
    refined motion (:func:`pmplan.refine`, what ``pmplan plan --refine --radius r
    --obstacle-radius s`` prints), same domain and stratum, plus ``raw``: the unrefined
    motion's ``times`` and ``waypoints``.
``POST /api/domain-map``
    ``{"query": Q, "which": "goal" | "start", "robot": 1, "origin": [x0, y0], "step": h,
    "size": [nx, ny]}``: the domain label robot ``robot``'s goal (or start) would get at each
    pixel centre ``(x0 + i h, y0 + j h)``, ``0 <= i < nx``, ``0 <= j < ny``, computed by one
    :func:`pmplan.plan_batch`. Answer: ``domain`` (``ny`` rows of ``nx`` labels, row ``j`` at
    ``y0 + j h``; ``-1`` where the point would coincide with another point of its
    configuration, ``-2`` where the path could not be certified, ``-3`` where the map ran out
    of its time budget :data:`MAP_BUDGET`, ``-4`` outside the query's workspace box
    ``"bounds"``, where the labels are those of the box's planner), ``legend`` (per label: its
    count and the strata, in the paper's notation, met there), ``boundaries`` (the lines
    ``{"point": [x, y], "direction": [u, v]}`` on which the label changes,
    :meth:`pmplan.display.DisplaySpec.map_boundaries`), ``planner``.

Errors are JSON ``{"error": message, "type": name}``: 400 for a body that is not JSON, 413 for
a body over :data:`MAX_BODY` bytes, 422 for a query the library refuses (the message is the
library's own ``InputError`` / ``CertificationError`` text) or a grid over
:data:`MAX_GRID` per side, 404/405 for a wrong address or method. Never a traceback.
"""

from __future__ import annotations

import ipaddress
import json
import socket
import sys
import time
from importlib import resources

import numpy as np

from .. import api
from ..configuration import as_real
from ..display import display_for
from ..errors import CertificationError, InputError, PmplanError
from ..io import json_int, parse_query, plan_to_dict, with_defaults
from ..magnitude import LIMIT, needs_scaling
from ..refine import check_radius, check_refine_flag
from ..workspace import check_bounds, interior
from . import require_extra

__all__ = ["MAX_BODY", "MAX_GRID", "MAX_POINTS", "create_app", "examples", "domain_map",
           "is_loopback", "serve"]

#: largest request body, in bytes (larger: 413)
MAX_BODY = 1_000_000
#: largest side of a domain-map grid, in pixels (larger: 422)
MAX_GRID = 400
#: most points (m + n) of a query the server plans (more: 422); the page uses at most 14
MAX_POINTS = 64
#: a body over MAX_BODY but under this is read and dropped before the 413 (larger: not read)
_DRAIN = 16 * MAX_BODY
#: pixels of a domain map planned by one plan_batch call
MAP_CHUNK = 8192
#: seconds after which a domain map stops starting new chunks (the rest is -3, "unfinished"):
#: some queries (e.g. a scene unit 2**-490 among robots at distance 1) take milliseconds each
MAP_BUDGET = 10.0
_STATIC = {
    "index.html": "text/html; charset=utf-8",
    "explore.js": "text/javascript; charset=utf-8",
    "explore.css": "text/css; charset=utf-8",
}


class _HTTPError(Exception):
    def __init__(self, status: int, message: str, kind: str = "RequestError"):
        super().__init__(message)
        self.status, self.kind = status, kind


def examples() -> list[dict]:
    """The example queries of the page: every stratum of paper Section 4, every demo domain.

    Returns
    -------
    list of dict
        ``{"group", "name", "query"}``; ``query`` in the JSON form of ``pmplan plan``.
    """
    from ..examples import obstacle_line_examples, planar_three_examples
    from ..figures import figure_queries
    from ..planners.planar_three import DOMAIN_OF

    def q(o, s, g):
        return {"obstacles": np.asarray(o).tolist(), "start": np.asarray(s).tolist(),
                "goal": np.asarray(g).tolist()}

    out = []
    for k, (o, s, g) in enumerate(obstacle_line_examples(3)):
        out.append({"group": "demo: 3 robots, 2 obstacles (Section 3)", "name": f"W_{k + 4}",
                    "query": q(o, s, g)})
    for k, (o, s, g) in enumerate(planar_three_examples()):
        out.append({"group": "demo: 1 robot, 3 obstacles (Section 4)", "name": f"W_{k + 1}",
                    "query": q(o, s, g)})
    for name, (o, s, g) in figure_queries().items():
        out.append({"group": "Section 4: every stratum",
                    "name": f"{name} (W_{DOMAIN_OF[name]})", "query": q(o, s, g)})
    return out


def _check_size(query: dict) -> None:
    npts = query["obstacles"].shape[0] + query["start"].shape[0]
    if npts > MAX_POINTS:
        raise InputError(f"the query has {npts} points (m + n); pmplan explore plans at most "
                         f"{MAX_POINTS} (use pmplan plan or the library for larger queries)")


def refine_options(params) -> dict | None:
    """The refinement asked by the URL parameters ``refine``, ``radius`` and
    ``obstacle_radius`` of ``/api/plan`` (strings): ``None`` for an unrefined plan, else the
    keywords of :func:`pmplan.refine`. Bad values get the library's own message
    (:func:`pmplan.refine.check_refine_flag`, :func:`pmplan.refine.check_radius`)."""
    flag = params.get("refine", "false")
    flag = {"true": True, "false": False}.get(flag, flag)
    radii = {}
    for key in ("radius", "obstacle_radius"):
        text = params.get(key, "0")
        try:
            value = float(text)
        except ValueError:
            value = text  # not a number: refused below with the library's message
        radii[key] = check_radius(value, key)
    return radii if check_refine_flag(flag, radii["radius"], radii["obstacle_radius"]) else None


def plan_json(obj, samples=None, refine: dict | None = None) -> dict:
    """Plan the decoded ``pmplan plan`` query ``obj``; the dict ``pmplan plan`` prints. With
    ``refine`` (the keywords of :func:`pmplan.refine`) the refined motion's dict, with the raw
    motion under ``raw``."""
    query = parse_query(obj)
    _check_size(query)
    plan = api.plan_query(with_defaults(query, refine))
    if refine is None:
        return plan_to_dict(plan, samples=samples)
    out = plan_to_dict(api.refine(plan, **refine), samples=samples)
    out["raw"] = {"times": plan.path.times.tolist(), "waypoints": plan.path.waypoints.tolist()}
    return out


def _int_field(obj: dict, key: str, lo: int, hi: int) -> int:
    v = obj.get(key)
    if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
        shown = f"{v!r}" if not isinstance(v, int) or abs(v) < 10**12 else "a larger integer"
        raise InputError(f"`{key}` must be an integer from {lo} to {hi}, got {shown}")
    return v


#: the fix named when a number of a domain-map request is not a real number
_MAP_FIX = "write plain numbers (not strings, booleans or null)"


def _real_pair(obj: dict, key: str) -> np.ndarray:
    v = obj.get(key)
    if not (isinstance(v, list) and len(v) == 2):
        raise InputError(f"`{key}` must be a list of two numbers, got {v!r}")
    arr = as_real(v, key, fix=_MAP_FIX)  # the library's rule: no bool, no 10**400
    if not np.isfinite(arr).all():
        raise InputError(f"`{key}` must be finite, got {v!r}")
    return arr


def _step(v) -> float:
    if isinstance(v, list) or v is None:
        raise InputError(f"`step` must be a positive finite number, got {v!r}")
    step = float(as_real(v, "step", fix=_MAP_FIX))
    if not 0 < step < float("inf"):
        raise InputError(f"`step` must be a positive finite number, got {v!r}")
    return step


def domain_map(obj) -> dict:
    """Answer a ``POST /api/domain-map`` request (decoded JSON ``obj``; see the module doc)."""
    if not isinstance(obj, dict):
        raise InputError(f"a domain-map request must be a JSON object, got {type(obj).__name__}")
    keys = {"query", "which", "robot", "origin", "step", "size"}
    unknown = set(obj) - keys
    if unknown or "query" not in obj:
        raise InputError(f"a domain-map request has the keys {sorted(keys)} (query required); "
                         f"got {sorted(obj)}")
    query = parse_query(obj["query"])
    _check_size(query)
    if "via" in query:
        raise InputError("a domain map is drawn for a query without `via`")
    obstacles, start, goal = query["obstacles"], query["start"], query["goal"]
    if obstacles.ndim != 2 or obstacles.shape[1:] != (2,) or start.shape[1:] != (2,):
        raise InputError(f"a domain map is drawn in the plane (d = 2); the query has points of "
                         f"shape {start.shape[1:]}")
    if start.shape != goal.shape:  # the library names the shapes
        api.plan_query(query)
    which = obj.get("which", "goal")
    if which not in ("goal", "start"):
        raise InputError(f"`which` must be \"goal\" or \"start\", got {which!r}")
    n = start.shape[0]
    robot = _int_field({"robot": obj.get("robot", 1)}, "robot", 1, max(n, 1))
    origin = _real_pair(obj, "origin")
    step = _step(obj.get("step"))
    size = obj.get("size")
    if not (isinstance(size, list) and len(size) == 2):
        raise InputError(f"`size` must be a list [nx, ny] of two integers, got {size!r}")
    nx = _int_field({"size[0]": size[0]}, "size[0]", 1, MAX_GRID)
    ny = _int_field({"size[1]": size[1]}, "size[1]", 1, MAX_GRID)
    with np.errstate(over="ignore", invalid="ignore"):  # checked just below
        xs = origin[0] + step * np.arange(nx)
        ys = origin[1] + step * np.arange(ny)
    if not (np.isfinite(xs).all() and np.isfinite(ys).all()):
        raise InputError("the grid reaches beyond the finite numbers: choose a smaller step")
    pts = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)  # row j = y0 + j h
    lift = query.get("lift", 1.0)
    corners = np.array([[xs[0], ys[0]], [xs[-1], ys[-1]]])
    if needs_scaling([obstacles[None], start[None], goal[None], corners[None]],
                     0.0 if lift == "scene" else lift):
        # such queries are planned one magnitude group at a time (pmplan.magnitude): correct,
        # but a hundred times slower; a map of them would hold the server for minutes
        raise InputError(f"a domain map is drawn for scenes whose coordinates and lift lie "
                         f"within 2**-{LIMIT} .. 2**{LIMIT} (about 1e-129 .. 1e129); plan "
                         f"such queries with pmplan plan or pmplan batch")
    b = pts.shape[0]
    moving = (goal if which == "goal" else start).copy()
    others = np.concatenate([obstacles, np.delete(moving, robot - 1, axis=0)])
    label = np.full(b, -1, dtype=np.int64)
    ok = ~(pts[:, None, :] == others[None]).all(axis=2).any(axis=1)
    box = None if query.get("bounds") is None else check_bounds(query["bounds"], 2)
    if box is not None:  # (the query's own points are checked by the planning call)
        outside = ~interior(pts, box).all(axis=1)
        label[outside] = -4
        ok &= ~outside
    idx = np.flatnonzero(ok)
    legend: dict[int, dict] = {}
    planner = None
    began = time.monotonic()
    fixed = start if which == "goal" else goal
    for lo in range(0, idx.size, MAP_CHUNK):
        if lo and time.monotonic() - began > MAP_BUDGET:  # the rest is -3: not computed
            label[idx[lo:]] = -3
            break
        part = idx[lo:lo + MAP_CHUNK]
        for _ in range(8):  # drop the queries whose certificate fails, replan the rest
            if part.size == 0:
                break
            conf = np.repeat(moving[None], part.size, axis=0)
            conf[:, robot - 1] = pts[part]
            rest = np.repeat(fixed[None], part.size, axis=0)
            s, g = (rest, conf) if which == "goal" else (conf, rest)
            obs = np.repeat(obstacles[None], part.size, axis=0)
            try:
                batch = api.plan_batch(obs, s, g, planner=query.get("planner"), lift=lift,
                                       bounds=box)
            except CertificationError as exc:
                if exc.indices is None or len(exc.indices) == 0:
                    raise
                label[part[np.asarray(exc.indices)]] = -2
                part = np.delete(part, np.asarray(exc.indices))
                continue
            label[part] = batch.domain
            planner = batch.planner
            for i in np.unique(batch.strata, axis=0, return_index=True)[1]:
                p = batch[int(i)]
                legend.setdefault(p.domain, {"domain": p.domain, "strata": []})
                if p.stratum not in legend[p.domain]["strata"]:
                    legend[p.domain]["strata"].append(p.stratum)
            part = part[:0]
        label[part] = -2
    # the lines where the label changes, drawn by the page as continuous lines (the pixels
    # exactly on them are too few once the line o1o2 is tilted)
    chosen = api.choose_planner(2, n, obstacles.shape[0], planner=query.get("planner"))
    # (in a box the boundaries are the images of these lines under the box's map: curves,
    # which the pixels show; no lines are drawn)
    lines = [] if box is not None else \
        display_for(chosen).map_boundaries(obstacles, others[obstacles.shape[0]:])
    for lab, count in zip(*np.unique(label, return_counts=True)):
        if lab >= 0:
            legend[int(lab)]["count"] = int(count)
    return {
        "planner": planner,
        "which": which,
        "robot": robot,
        "origin": origin.tolist(),
        "step": float(step),
        "size": [nx, ny],
        "domain": label.reshape(ny, nx).tolist(),
        "legend": [legend[k] for k in sorted(legend)],
        "boundaries": [{"point": p.tolist(), "direction": v.tolist()} for p, v in lines],
        "invalid": int((label == -1).sum()),
        "uncertified": int((label == -2).sum()),
        "unfinished": int((label == -3).sum()),
        "outside": int((label == -4).sum()),
    }


def _load_static() -> dict[str, tuple[bytes, str]]:
    root = resources.files("pmplan.web") / "static"
    return {name: ((root / name).read_bytes(), ctype) for name, ctype in _STATIC.items()}


def _decode(body: bytes):
    try:
        return json.loads(body, parse_int=json_int)
    except RecursionError:
        raise _HTTPError(400, "the request body is nested too deeply to be a query",
                         "JSONDecodeError") from None
    except json.JSONDecodeError as exc:
        raise _HTTPError(400, f"the request body is not valid JSON: {exc.msg} at line "
                         f"{exc.lineno} column {exc.colno}", "JSONDecodeError") from None
    except (UnicodeDecodeError, ValueError) as exc:
        raise _HTTPError(400, f"the request body is not valid JSON: {exc}",
                         "JSONDecodeError") from None


def create_app():
    """Return the Starlette application of ``pmplan explore``."""
    require_extra()
    from starlette.applications import Starlette
    from starlette.concurrency import run_in_threadpool
    from starlette.exceptions import HTTPException
    from starlette.requests import Request
    from starlette.responses import JSONResponse, Response
    from starlette.routing import Route

    static = _load_static()

    def error(status: int, message: str, kind: str) -> JSONResponse:
        return JSONResponse({"error": message, "type": kind}, status_code=status)

    async def read_json(request: Request):
        too_large = _HTTPError(413, f"the request body is larger than {MAX_BODY:,} bytes",
                               "PayloadTooLarge")
        length = request.headers.get("content-length")
        if length is not None and (not length.isdigit() or int(length) > _DRAIN):
            raise too_large
        chunks, size = [], 0
        async for chunk in request.stream():
            size += len(chunk)
            if size > _DRAIN:
                raise too_large
            if size <= MAX_BODY:
                chunks.append(chunk)
        # a body over the bound is read (up to _DRAIN) and dropped before the 413, so that the
        # client, still sending, gets the answer rather than a reset connection
        if size > MAX_BODY:
            raise too_large
        return _decode(b"".join(chunks))

    async def answer(request: Request, fn, *args):
        try:
            obj = await read_json(request)
            return JSONResponse(await run_in_threadpool(fn, obj, *args))
        except _HTTPError as exc:
            return error(exc.status, str(exc), exc.kind)
        except (InputError, CertificationError) as exc:
            return error(422, str(exc), type(exc).__name__)
        except PmplanError as exc:  # pragma: no cover - every pmplan error is one of the above
            return error(422, str(exc), type(exc).__name__)

    async def plan_endpoint(request: Request):
        samples = request.query_params.get("samples")
        if samples is not None:
            try:
                samples = int(samples)
            except ValueError:
                return error(422, f"`samples` must be an integer, got {samples!r}", "InputError")
        try:
            refine = refine_options(request.query_params)
        except InputError as exc:
            return error(422, str(exc), type(exc).__name__)
        return await answer(request, plan_json, samples, refine)

    async def map_endpoint(request: Request):
        return await answer(request, domain_map)

    async def examples_endpoint(request: Request):
        return JSONResponse(EXAMPLES)

    async def page(request: Request):
        body, ctype = static["index.html"]
        return Response(body, media_type=ctype)

    async def asset(request: Request):
        name = request.path_params["name"]
        if name not in static:
            return error(404, f"no asset {name!r}", "NotFound")
        body, ctype = static[name]
        return Response(body, media_type=ctype)

    async def http_error(request: Request, exc: HTTPException):
        return error(exc.status_code, str(exc.detail), "HTTPError")

    async def internal(request: Request, exc: Exception):  # a bug: no traceback to the client
        print(f"pmplan explore: internal error on {request.url.path}: "
              f"{type(exc).__name__}: {exc}", file=sys.stderr)
        return error(500, "internal error (see the server's log)", "InternalError")

    EXAMPLES = examples()
    return Starlette(
        routes=[
            Route("/", page),
            Route("/static/{name}", asset),
            Route("/api/examples", examples_endpoint),
            Route("/api/plan", plan_endpoint, methods=["POST"]),
            Route("/api/domain-map", map_endpoint, methods=["POST"]),
        ],
        exception_handlers={HTTPException: http_error, Exception: internal},
    )


def is_loopback(host: str) -> bool:
    """Whether ``host`` names this machine only (``localhost``, 127.0.0.0/8, ``::1``)."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def bind(host: str, port: int) -> socket.socket:
    """A listening TCP socket on ``(host, port)`` (port 0: a free one); OSError if refused."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, port))
        sock.listen(128)
    except OSError:
        sock.close()
        raise
    return sock


def url_of(sock: socket.socket) -> str:
    """The ``http://host:port/`` address of a bound socket."""
    host, port = sock.getsockname()[:2]
    return f"http://[{host}]:{port}/" if ":" in host else f"http://{host}:{port}/"


def warm_up() -> None:
    """Plan one small query per planner (compiles or loads the numba kernels once)."""
    from ..examples import obstacle_line_examples, planar_three_examples

    for o, s, g in (obstacle_line_examples(1)[0], planar_three_examples()[0]):
        api.plan(o, s, g)
        api.plan_batch(o[None], s[None], g[None])


def serve(host: str = "127.0.0.1", port: int = 8765, open_browser: bool = True) -> None:
    """Serve the page until interrupted (Ctrl-C); print the address first.

    Raises
    ------
    MissingExtraError
        If Starlette or uvicorn is missing (the message says how to install them).
    OSError
        If the address cannot be bound (e.g. the port is in use).
    """
    require_extra()
    import uvicorn

    app = create_app()
    if not is_loopback(host):
        print(f"pmplan explore: warning: serving on {host}, which is not the loopback "
              f"address: anyone who can reach this machine can use the server (it has no "
              f"authentication); use --host 127.0.0.1 to keep it local", file=sys.stderr)
    sock = bind(host, port)
    url = url_of(sock)
    print("pmplan explore: loading the planners (the first run after installing compiles "
          "the numba kernels)...", file=sys.stderr, flush=True)
    warm_up()
    print(f"pmplan explore: serving on {url} (Ctrl-C to stop)", flush=True)
    if open_browser:
        import webbrowser

        webbrowser.open(url)
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning", lifespan="off"))
    try:
        server.run(sockets=[sock])
    except KeyboardInterrupt:
        pass
    finally:
        sock.close()
