"""Sphinx configuration of pmplan's documentation.

Build (from the repository root, after ``python -m pip install -e ".[docs]"``)::

    python -m sphinx -W --keep-going -b html docs docs/_build/html
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

import pmplan

project = "pmplan"
author = "the pmplan developers"
copyright = "the pmplan developers"
release = version = pmplan.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
templates_path = ["_templates"]
exclude_patterns = ["_build", "_templates", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "auto_examples/*.md5", "auto_examples/*.codeobj.json",
                    "tutorial/*.txt"]

# --- myst: the Markdown pages (tutorial, refinement, architecture, mathematics, ...) ---------
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

# --- API reference: autosummary over pmplan.__all__ and the public modules, numpydoc -----
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": False}
autodoc_typehints = "none"  # numpydoc's Parameters sections say the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
# numpydoc's own validation hook (numpydoc_validation_checks) crashes on some objects under
# Sphinx 9 (StopIteration while it looks for a source line), so _validate_docstrings below runs
# numpydoc.validate on every public function, class and method itself, with the structural
# checks: a docstring whose sections do not parse, are unknown, out of order, or document
# parameters the signature does not have, fails the build.
VALIDATION_CHECKS = {"GL01", "GL03", "GL05", "GL06", "GL07", "GL09", "GL10", "SS01", "SS02",
                     "SS03", "SS04", "PR02", "PR03", "PR04", "PR05", "PR06", "PR08", "PR09",
                     "PR10", "RT02", "RT04", "RT05", "SA02", "SA03", "SA04"}
#: the modules whose ``__all__`` is public (pmplan itself: the top-level names)
PUBLIC_MODULES = ["pmplan", "pmplan.scale", "pmplan.refine", "pmplan.certify",
                  "pmplan.predicates", "pmplan.frame", "pmplan.path", "pmplan.generators",
                  "pmplan.examples", "pmplan.io", "pmplan.plotting", "pmplan.figures",
                  "pmplan.animation", "pmplan.verify", "pmplan.planners.base",
                  "pmplan.planners.obstacle_line", "pmplan.planners.planar_three",
                  "pmplan.magnitude", "pmplan.configuration"]


def public_objects():
    """Yield (dotted name, object) for every public function, class and method."""
    import importlib
    import inspect

    for modname in PUBLIC_MODULES:
        importlib.import_module(modname)
        mod = sys.modules[modname]
        for name in mod.__all__:
            obj = getattr(mod, name)
            if not (inspect.isfunction(obj) or inspect.isclass(obj)):
                continue
            yield f"{modname}.{name}", obj
            if inspect.isclass(obj):
                for attr, member in vars(obj).items():
                    if not attr.startswith("_") and inspect.isfunction(member):
                        yield f"{modname}.{name}.{attr}", member


def _validate_docstrings(app) -> None:
    from numpydoc.validate import validate
    from sphinx.util import logging

    log = logging.getLogger("pmplan.docstrings")
    for full, _obj in public_objects():
        try:
            report = validate(full)
        except Exception as exc:  # noqa: BLE001 -- numpydoc cannot locate some generated members
            log.debug("%s: not validated (%s)", full, exc)
            continue
        for code, message in report["errors"]:
            if code in VALIDATION_CHECKS:
                log.warning("%s: numpydoc %s: %s", full, code, message,
                            type="numpydoc", subtype=code)


def setup(app):
    app.connect("builder-inited", _validate_docstrings)


# --- warnings are errors (sphinx -W); cross references are checked ------------------------
nitpicky = True
#: the references the build does not resolve, each group with its reason
nitpick_ignore_regex = [
    # third-party and builtin types named in numpydoc "Parameters"/"Returns" lines as prose
    # (the build is offline: no intersphinx inventories of numpy, matplotlib, dask, zarr)
    (r"py:.*", (r"(numpy|np|matplotlib|mpl|dask|distributed|zarr|fractions|starlette|uvicorn"
                r"|socket)\..*")),
    # private names (a leading underscore) cited in docstrings: the reference never documents
    # them, by design
    (r"py:.*", r"(.*\.)?_[A-Za-z0-9]\w*"),
    # module constants outside ``__all__`` of pmplan.refine and pmplan.scale cited by name in
    # their docstrings: those modules are reworked in parallel (issues 23, 24);
    # docs/refinement.md states what the refinement's constants mean
    (r"py:data", r"ALPHA|BETA|OMEGA|SHARE|GROWTH|pmplan\.refine\.KAPPA|OUTPUTS|ZSTD_LEVEL"),
]

intersphinx_mapping = {}


def _write_refine_page() -> None:
    """Write api/refine.rst: the module pmplan.refine, member by member from its ``__all__``.

    ``pmplan.refine`` is both a function (the facade's, documented with the top-level names)
    and a module; an ``automodule`` would describe the object ``pmplan.refine`` twice, so the
    module's text is shown without an index entry and its members are documented one by one.
    """
    import inspect

    import pmplan.refine  # noqa: F401 -- the module (the attribute pmplan.refine is a function)

    mod = sys.modules["pmplan.refine"]
    lines = ["pmplan.refine (the module)", "==========================", "",
             ".. automodule:: pmplan.refine", "   :no-index:", "",
             ".. currentmodule:: pmplan.refine", ""]
    for name in mod.__all__:
        obj = getattr(mod, name)
        kind = ("autoclass" if inspect.isclass(obj) else
                "autofunction" if callable(obj) else "autodata")
        lines += [f".. {kind}:: {name}", ""]
    page = Path(__file__).parent / "api" / "refine.rst"
    text = "\n".join(lines)
    if not page.exists() or page.read_text() != text:
        page.write_text(text)


_write_refine_page()  # offline build: no inventories are downloaded

# --- the gallery: examples/ -> docs/auto_examples/ ---------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("matplotlib",),
    "matplotlib_animations": False,
    "show_memory": False,
    "abort_on_example_error": True,
}

# --- HTML ------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"pmplan {version}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": [],
}
html_static_path: list[str] = []
html_show_sourcelink = False
