"""The house rules, read from the code with the standard library's ``ast``: no import circles
among pmplan's modules (imports inside functions included), kernels never import planners, the
core never imports a face, and no module imports another's private names."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "pmplan"
#: the faces: they draw, print, read files, serve or scale out; the core never imports them
FACES = {"pmplan.cli", "pmplan.io", "pmplan.plotting", "pmplan.figures", "pmplan.animation",
         "pmplan.verify", "pmplan.scale", "pmplan.web", "pmplan.web.server", "pmplan.examples",
         "pmplan.api", "pmplan"}
#: the mathematics and the machinery under the facade
CORE_PREFIXES = ("pmplan.predicates", "pmplan.frame", "pmplan.path", "pmplan.certify",
                 "pmplan.planners", "pmplan.kernels", "pmplan.refine", "pmplan.magnitude",
                 "pmplan.configuration", "pmplan.backends", "pmplan.checks", "pmplan.running",
                 "pmplan.results", "pmplan.planar_strata", "pmplan.single", "pmplan.errors",
                 "pmplan.reasons")


def _modules() -> dict[str, Path]:
    mods = {}
    for p in SRC.rglob("*.py"):
        parts = p.relative_to(SRC.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        mods[name] = p
    return mods


MODULES = _modules()


def _imports(name: str) -> list[tuple[str, str | None, int]]:
    """(imported module, imported name or None, line) of every import in module ``name``,
    inside functions too; ``from pkg import mod`` counts as an import of ``pkg.mod``."""
    path = MODULES[name]
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out += [(a.name, None, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            for a in node.names:
                sub = f"{mod}.{a.name}"
                out.append((sub, None, node.lineno) if sub in MODULES else
                           (mod, a.name, node.lineno))
    return [(m, n, line) for m, n, line in out if m == "pmplan" or m.startswith("pmplan.")]


GRAPH = {name: {m for m, _, _ in _imports(name) if m in MODULES and m != name}
         for name in MODULES}


def _cycles() -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(GRAPH[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(GRAPH):
        if v not in index:
            visit(v)
    return out


def test_the_module_graph_is_read():
    """The reader sees the edges it must (the test below could fail)."""
    assert "pmplan.running" in GRAPH["pmplan.api"]
    assert "pmplan.scale" in GRAPH["pmplan.api"]  # inside a function
    assert "pmplan.certify" in GRAPH["pmplan.kernels.common"]
    assert len(MODULES) > 30


#: no circle left: the refinement's reference and kernel share the grid, schedule and constants
#: of pmplan.refine.grid, and neither imports the other (issue 24)
KNOWN: list = []


def test_no_import_circles():
    assert [c for c in _cycles() if c not in KNOWN] == []


def test_kernels_never_import_planners():
    bad = [(k, m, line) for k in MODULES if k.startswith("pmplan.kernels")
           for m, _, line in _imports(k) if m.startswith("pmplan.planners")]
    assert bad == []


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.startswith(CORE_PREFIXES)))
def test_the_core_never_imports_a_face(module):
    bad = [(m, line) for m, _, line in _imports(module) if m in FACES]
    assert bad == []


def test_no_module_imports_another_modules_private_names():
    bad = []
    for k in MODULES:
        for m, n, line in _imports(k):
            if n is not None and n.startswith("_") and not n.startswith("__"):
                bad.append((k, m, n, line))
        # attribute access on an imported pmplan module: api._check_lift(...)
        tree = ast.parse(MODULES[k].read_text())
        aliases = {a.asname or a.name for node in ast.walk(tree)
                   if isinstance(node, ast.ImportFrom) and (node.level or
                                                           (node.module or "").startswith("pmplan"))
                   for a in node.names
                   if f"{node.module or ''}.{a.name}".lstrip(".") and a.name[0].islower()}
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
                    and node.value.id in aliases and node.attr.startswith("_") \
                    and not node.attr.startswith("__") and node.value.id != "self":
                bad.append((k, node.value.id, node.attr, node.lineno))
    assert bad == []


#: the core modules whose tests are not named after them, and where they are
TESTED_IN = {"pmplan.planners.base": "test_contract.py",  # the protocol every planner keeps
             "pmplan.backends.numpy": "test_backends.py",
             "pmplan.backends.numba": "test_backends.py",
             "pmplan.refine.kernel": "test_refine.py",  # the kernel == the reference, bitwise
             "pmplan.refine.reference": "test_refine.py",
             "pmplan.refine.stage": "test_refine.py",  # parameters, radii, the certified stage
             "pmplan.refine.frame": "test_refine_exact.py",  # equivariance at every magnitude
             "pmplan.kernels.measure": "test_refine_exact.py",  # flags against exact arithmetic
             "pmplan.version": "test_io_cli.py"}  # pmplan --version and the store attribute


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.startswith(CORE_PREFIXES)
                                          and m not in ("pmplan.planners", "pmplan.kernels")))
def test_every_core_module_has_its_test_module(module):
    """A maintainer finds a module's tests in ``tests/test_<name>.py`` (kernels:
    ``test_kernels_<name>.py``), or where :data:`TESTED_IN` says."""
    parts = module.split(".")[1:]
    if parts[0] == "planners":
        parts = parts[1:]
    want = TESTED_IN.get(module, "test_" + "_".join(parts) + ".py")
    assert (Path(__file__).parent / want).exists(), want
