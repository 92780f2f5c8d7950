"""A real ``pmplan explore`` server for the tests: uvicorn in a thread on a free loopback port."""

from __future__ import annotations

import contextlib
import json
import os
import threading
import time
import urllib.error
import urllib.request

import pytest


def need_extra():
    """Starlette and uvicorn, or fail in CI (they are in the ``test`` extra) / skip elsewhere."""
    try:
        import starlette  # noqa: F401
        import uvicorn  # noqa: F401
    except ImportError as exc:
        if os.environ.get("CI"):
            pytest.fail(f"{exc.name} is not installed although CI is set: .ci/run installs the "
                        "test extra (pip install -e '.[test]'), which includes pmplan[explore]")
        pytest.skip(f"{exc.name} not installed (outside CI only): pip install -e '.[test]'")


@contextlib.contextmanager
def running_server():
    """Yield the base URL of a server started in a thread; stop it afterwards."""
    need_extra()
    import uvicorn

    from pmplan.web.server import bind, create_app, url_of, warm_up

    warm_up()
    sock = bind("127.0.0.1", 0)
    server = uvicorn.Server(uvicorn.Config(create_app(), log_level="warning", lifespan="off"))
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    for _ in range(200):
        if server.started:
            break
        time.sleep(0.05)
    assert server.started, "the test server did not start"
    try:
        yield url_of(sock).rstrip("/")
    finally:
        server.should_exit = True
        thread.join(timeout=10)
        sock.close()


def request(base: str, path: str, body=None, *, raw: bytes | None = None, method=None,
            headers=None):
    """(status, decoded JSON or text) of one request; ``body`` is sent as JSON."""
    data = raw if raw is not None else (None if body is None else json.dumps(body).encode())
    req = urllib.request.Request(base + path, data=data, method=method,
                                 headers={"Content-Type": "application/json", **(headers or {})})
    try:
        with urllib.request.urlopen(req, timeout=60) as r:
            status, text = r.status, r.read().decode()
    except urllib.error.HTTPError as exc:
        status, text = exc.code, exc.read().decode()
    try:
        return status, json.loads(text)
    except json.JSONDecodeError:
        return status, text
