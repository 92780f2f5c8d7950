"""docs/tutorial.md: every ```python block runs, and the recorded `pmplan verify` output is real."""

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


def test_tutorial_python_blocks_run(tmp_path, monkeypatch):
    """Run the blocks in order, in one namespace, in an empty directory (they write files)."""
    import matplotlib.pyplot as plt

    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "__tutorial__"}
    for k, code in enumerate(_blocks("python"), start=1):
        try:
            exec(compile(code, f"{TUTORIAL.name}, python block {k}", "exec"), namespace)
        finally:
            plt.close("all")
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
