"""pmplan.api: a thin facade -- every public function a few lines over one internal entry
(running.plan_arrays, running.refine_plans, single.plan_one, ...), no private imports; and its
names are pmplan's."""

from __future__ import annotations

import ast
from pathlib import Path

import pmplan
from pmplan import api

#: statements (docstring excluded) a public function of the facade may have
MAX_STATEMENTS = 12


def _public_functions():
    tree = ast.parse(Path(api.__file__).read_text())
    return [n for n in tree.body if isinstance(n, ast.FunctionDef) and not n.name.startswith("_")]


def test_every_public_function_is_a_few_lines():
    long = {}
    for fn in _public_functions():
        body = fn.body[1:] if ast.get_docstring(fn) else fn.body
        count = sum(1 for node in body for _ in ast.walk(node) if isinstance(_, ast.stmt))
        if count > MAX_STATEMENTS:
            long[fn.name] = count
    assert long == {}


def test_the_facade_is_pmplans_api():
    for name in api.__all__:
        assert getattr(pmplan, name) is getattr(api, name), name
    assert {f.name for f in _public_functions()} <= set(api.__all__)
