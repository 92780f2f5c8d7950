"""The notice of the one-time compilation of pmplan's numba kernels (the first run only).

Numba compiles a kernel of the package :mod:`pmplan.kernels` the first time it is called in a
process, unless numba's on-disk cache (``cache=True``, next to the sources or under
``NUMBA_CACHE_DIR``) already holds its machine code, which loads in a fraction
of a second. Numba reports a real compilation -- never a load from that cache, nor a kernel
already compiled in the process -- as a ``numba:compile`` event before it starts, so the
notice is shown exactly when a compilation happens. The progress display of the batch
functions (``progress=True``, :func:`pmplan.plan_batch`) and ``pmplan demo`` show it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager

__all__ = ["COMPILING", "announce_compile"]

#: the notice, shown once when a kernel is compiled (docs/install.md, "The first run compiles the kernels")
COMPILING = ("compiling kernels, first run only (cached on disk for later runs; "
             "it takes some 10 to 30 seconds)")


class _Silent:
    def rearm(self) -> None:  # pragma: no cover - numba is a dependency
        pass


@contextmanager
def announce_compile(write: Callable[[str], None]) -> Iterator:
    """Within the block, call ``write(COMPILING)`` once, when numba starts compiling a pmplan
    kernel (in any thread); nothing when every kernel is loaded from the cache or was compiled
    before. Without numba there is nothing to compile and nothing is written.

    Yields a handle whose ``rearm()`` lets a later compilation be announced once more (the
    progress display rearms it when its bar starts).
    """
    try:
        from numba.core import event
    except ImportError:  # pragma: no cover - numba is a dependency
        yield _Silent()
        return

    class Notice(event.Listener):
        def __init__(self) -> None:
            self.lock = threading.Lock()
            self.shown = False

        def on_start(self, ev) -> None:
            func = getattr(ev.data.get("dispatcher"), "py_func", None)
            if not getattr(func, "__module__", "").startswith("pmplan."):
                return
            with self.lock:
                if self.shown:
                    return
                self.shown = True
            write(COMPILING)

        def on_end(self, ev) -> None:
            pass

        def rearm(self) -> None:
            with self.lock:
                self.shown = False

    with event.install_listener("numba:compile", Notice()) as notice:
        yield notice
