"""docs/tutorial.md: every ```python block runs, and the recorded `pmplan verify` output is real."""

import ast
import re
from pathlib import Path

import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

TUTORIAL = Path(__file__).resolve().parents[1] / "docs" / "tutorial.md"


def _blocks(kind: str) -> list[str]:
    return re.findall(rf"^```{kind}\n(.*?)^```", TUTORIAL.read_text(), flags=re.S | re.M)


def test_tutorial_has_code():
    assert len(_blocks("python")) >= 6
    assert len(_blocks("text")) >= 1


def _shown(code: str) -> dict[int, str]:
    """The output a block's ``print`` statements show in their comments, by the line the
    statement ends on: the comment after it on that line, or on the next line when that line
    is a comment alone. Comments that describe rather than show (``~0.15``, ``the ...``) are
    left out."""
    lines = code.splitlines()
    shown = {}
    for node in ast.walk(ast.parse(code)):
        if not (isinstance(node, ast.Expr) and isinstance(node.value, ast.Call)
                and isinstance(node.value.func, ast.Name) and node.value.func.id == "print"):
            continue
        end = node.end_lineno
        tail = lines[end - 1][node.end_col_offset:].strip()
        if not tail and end < len(lines) and lines[end].strip().startswith("#"):
            tail = lines[end].strip()
        if tail.startswith("#"):
            text = tail[1:].strip()
            if text and not text.startswith(("~", "the ")):
                shown[end] = text
    return shown


class _Printed(ast.NodeTransformer):
    """``print(...)`` -> ``__printed__(line, ...)``: the first output of every print statement,
    by the line it ends on."""

    def visit_Call(self, node):
        self.generic_visit(node)
        if isinstance(node.func, ast.Name) and node.func.id == "print":
            return ast.copy_location(
                ast.Call(func=ast.Name("__printed__", ast.Load()),
                         args=[ast.Constant(node.end_lineno), *node.args],
                         keywords=node.keywords), node)
        return node


def test_tutorial_python_blocks_run(tmp_path, monkeypatch):
    """Run the blocks in order, in one namespace, in an empty directory (they write files); what
    every ``print`` shows in its comment is what it prints (the text before a ``:`` that starts
    the comment's prose, or all of it; runs of spaces count as one)."""
    import io

    import matplotlib.pyplot as plt

    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "__tutorial__"}
    stale = []
    for k, code in enumerate(_blocks("python"), start=1):
        printed: dict[int, str] = {}

        def record(line, *args, **kwargs):
            buf = io.StringIO()
            print(*args, **{**kwargs, "file": buf})
            printed.setdefault(line, buf.getvalue().rstrip("\n"))

        namespace["__printed__"] = record
        tree = ast.fix_missing_locations(_Printed().visit(ast.parse(code)))
        try:
            exec(compile(tree, f"{TUTORIAL.name}, python block {k}", "exec"), namespace)
        finally:
            plt.close("all")
        for line, text in _shown(code).items():
            out = printed.get(line)
            same = None if out is None else " ".join(out.split())  # (numpy pads its columns)
            seen = " ".join(text.split())
            if same is None or not (seen == same or seen.startswith(same + ":")):
                stale.append(f"python block {k}, line {line}: shows {text!r}, prints {out!r}")
    assert not stale, "docs/tutorial.md shows stale output:\n" + "\n".join(stale)
    assert (tmp_path / "motion.gif").stat().st_size > 0
    assert (tmp_path / "frame.png").stat().st_size > 0


def test_tutorial_pictures_exist():
    text = TUTORIAL.read_text()
    for ref in re.findall(r"\]\((tutorial/[^)]+)\)", text):
        assert (TUTORIAL.parent / ref).is_file(), f"{ref}: run docs/tutorial/make_pictures.py"


@pytest.mark.parametrize("flags", [(), ("--refine",)], ids=["raw", "refine"])
def test_recorded_verify_output_is_real(flags):
    """The `pmplan verify` outputs shown in the tutorial are what the command prints today."""
    from pmplan.verify import verify

    cmd = " ".join(["$ pmplan verify --d 2 --n 2 --m 2", *flags]) + "\n"
    block = next(b for b in _blocks("text") if b.startswith(cmd))
    shown = block.split("\n", 1)[1].split("$ echo $?")[0].rstrip("\n")
    report = verify(d=2, n=2, m=2, progress=False, refine=bool(flags))
    assert shown == report.to_text(), (
        "docs/tutorial.md shows stale `pmplan verify` output: run "
        "`python docs/tutorial/make_pictures.py` and paste docs/tutorial/verify*.txt"
    )
