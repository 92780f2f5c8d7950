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


CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
#: Chromium flags: headless, no sandbox (root in CI), and nothing that reaches the network
CHROMIUM_FLAGS = ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                  "--disable-background-networking", "--disable-component-update",
                  "--disable-sync", "--no-first-run", "--window-size=1200,700")


def need_browser():
    """Selenium and Debian's chromium + chromium-driver, or fail in CI / skip elsewhere."""
    need_extra()
    missing = [p for p in (CHROMIUM, CHROMEDRIVER) if not os.path.exists(p)]
    try:
        import selenium  # noqa: F401
    except ImportError:
        missing.append("the selenium package (pip install -e '.[test]')")
    if missing:
        msg = (f"the browser tests need {', '.join(missing)}: apt-get install -y chromium "
               "chromium-driver (.ci/run does it when they are missing)")
        if os.environ.get("CI"):
            pytest.fail(msg + " -- CI is set, so this fails rather than skips")
        pytest.skip(msg + " (outside CI only)")


def chromium(user_data_dir):
    """A headless Chromium driven by Debian's chromedriver: Selenium Manager downloads nothing."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for flag in CHROMIUM_FLAGS:
        opts.add_argument(flag)
    opts.add_argument(f"--user-data-dir={user_data_dir}")
    return webdriver.Chrome(service=Service(executable_path=CHROMEDRIVER), options=opts)
