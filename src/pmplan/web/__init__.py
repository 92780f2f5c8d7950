"""``pmplan explore``: a local web server and its static page (the optional extra
``pmplan[explore]``: Starlette + uvicorn).

This is a face: it imports the library, the library never imports it. The page
(``static/``) is plain hand-written HTML/JS/CSS, shipped in the package, so it works
offline. See :mod:`pmplan.web.server` for the JSON API.
"""

from __future__ import annotations

from ..errors import PmplanError

__all__ = ["MissingExtraError", "INSTALL_HINT", "require_extra"]

#: how to install what ``pmplan explore`` needs (one source for the message)
INSTALL_HINT = 'pip install "pmplan[explore]" (Starlette and uvicorn)'


class MissingExtraError(PmplanError, ImportError):
    """A package of the optional extra ``pmplan[explore]`` is not installed."""


def require_extra() -> None:
    """Raise :class:`MissingExtraError` naming the fix when Starlette or uvicorn is missing."""
    missing = []
    for name in ("starlette", "uvicorn"):
        try:
            __import__(name)
        except ImportError:
            missing.append(name)
    if missing:
        raise MissingExtraError(
            f"pmplan explore needs {' and '.join(missing)}, which is not installed: "
            f"{INSTALL_HINT}")
