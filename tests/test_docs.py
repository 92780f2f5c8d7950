"""The documentation: citations, the README, the docs site's sources.

* The code and the docs cite the project's own mathematics page (``docs/mathematics.md``) by its
  numbered sections, and the paper by its printed numbers: never an unshipped specification
  ("SPEC") and never a LaTeX label of the paper's source ("Theorem gongra").
* Every "Mathematics §N.M" citation names a section that exists.
"""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"

#: the paper's LaTeX labels, which a reader of the printed paper cannot find
LATEX_LABELS = re.compile(
    r"gongra|lapart|\(desin\)|algorithm-gamma|linear-transformation-obs|constructing-sections"
    r"|cerraduras2|sigmaij|porhoy|(?<![A-Za-z_.])\(w[234]\)"
    r"|Figures?\s+`{0,2}(?:T111|Tstraight|porenmedio|t2223|grid|algorithm[1-4]|Lc)\b"
)


def _sources() -> list[Path]:
    """Every text file of src/pmplan, tests and docs (sources, not build output), and the README."""
    out = [ROOT / "README.md"]
    for top in (ROOT / "src" / "pmplan", ROOT / "tests", DOCS):
        for p in sorted(top.rglob("*")):
            if not p.is_file() or p.suffix not in {".py", ".md", ".rst", ".txt", ".html", ".js"}:
                continue
            if any(part.startswith(("_build", "auto_examples", "generated", "__pycache__"))
                   for part in p.relative_to(ROOT).parts):
                continue
            out.append(p)
    return out


SOURCES = _sources()
THIS = Path(__file__).resolve()


def test_sources_found():
    names = {p.name for p in SOURCES}
    assert {"README.md", "mathematics.md", "api.py", "certify.py"} <= names


def test_no_spec_citation():
    """No "SPEC" (the reference spec is not shipped): cite Mathematics §N instead."""
    bad = [f"{p.relative_to(ROOT)}:{i}: {line.strip()}"
           for p in SOURCES if p != THIS
           for i, line in enumerate(p.read_text(errors="replace").splitlines(), 1)
           if re.search(r"\bSPEC\b|SPEC\.md", line)]
    assert not bad, "\n".join(bad)


def test_no_latex_label_citation():
    """The paper is cited by printed numbers (Theorem 2.6, Figure 6), never by LaTeX labels."""
    bad = [f"{p.relative_to(ROOT)}:{i}: {line.strip()}"
           for p in SOURCES if p != THIS
           for i, line in enumerate(p.read_text(errors="replace").splitlines(), 1)
           if LATEX_LABELS.search(line)]
    assert not bad, "\n".join(bad)


def _math_sections() -> set[str]:
    heads = re.findall(r"^#{2,4} (\d+(?:\.\d+)*) ", (DOCS / "mathematics.md").read_text(),
                       re.MULTILINE)
    return set(heads)


def test_mathematics_sections_numbered():
    secs = _math_sections()
    assert {"1", "2", "3", "4", "4.1", "4.2", "4.3", "5", "5.2", "6", "6.2", "7"} <= secs


def test_every_mathematics_citation_exists():
    """Every "Mathematics §a.b" (and the "§c" that follow it in one list) names a real section."""
    secs = _math_sections()
    cited = set()
    for p in SOURCES:
        for m in re.finditer(r"Mathematics\s+((?:§\d+(?:\.\d+)*(?:\s*(?:,|-|and|/)\s*)?)+)",
                             p.read_text(errors="replace")):
            cited |= set(re.findall(r"§(\d+(?:\.\d+)*)", m.group(1)))
    assert len(cited) >= 10
    assert cited <= secs, sorted(cited - secs)


def test_api_reference_lists_every_public_name():
    """docs/api.rst names every name of ``pmplan.__all__`` (autosummary makes its page)."""
    import pmplan

    listed = set(re.findall(r"^   (\w+)$", (DOCS / "api.rst").read_text(), re.MULTILINE))
    assert set(pmplan.__all__) <= listed, sorted(set(pmplan.__all__) - listed)


@pytest.mark.parametrize("number", ["2.6", "2.5", "4.1"])
def test_paper_printed_numbers_are_used(number):
    text = (DOCS / "mathematics.md").read_text()
    assert number in text


# --------------------------------------------------------------------------------------------
# the README: short, its commands are CI's, its examples run, no hand-copied results


README = ROOT / "README.md"
CI_RUN = ROOT / ".ci" / "run"


def _commands(text: str) -> list[str]:
    """The shell lines of the ```bash blocks that install pmplan."""
    blocks = re.findall(r"^```bash\n(.*?)^```", text, flags=re.DOTALL | re.MULTILINE)
    return [line.strip() for b in blocks for line in b.splitlines() if "pip install" in line]


def test_readme_is_short():
    lines = README.read_text().splitlines()
    assert len(lines) <= 200, f"README.md has {len(lines)} lines (at most 200)"


def test_readme_commands_are_the_ones_ci_runs():
    """Two commands install and run (the demo; the test suite), one builds the docs; the test
    and docs commands are the very lines .ci/run executes."""
    cmds = _commands(README.read_text())
    assert cmds == [
        "python -m pip install . && pmplan demo",
        'python -m pip install -e ".[test]" && python -m pytest',
        ('python -m pip install -e ".[docs]" && python -m sphinx -W --keep-going -b html docs '
         "docs/_build/html"),
    ]
    ci = [line.strip() for line in CI_RUN.read_text().splitlines()
          if line.strip() and not line.lstrip().startswith("#")]
    assert cmds[1] in ci
    # CI installs the docs extra quietly; the build command itself is the README's
    build = cmds[2].split(" && ")[1]
    assert any(line.endswith("&& " + build) and '".[docs]"' in line for line in ci)
    assert "python -m venv .venv && . .venv/bin/activate" in README.read_text()


def test_readme_states_no_measured_results():
    """Measured numbers live in benchmarks/RESULTS.md (generated); the README links to them."""
    text = README.read_text()
    units = re.findall(r"\d[\d,.]*\s*(?:queries/s|q/s|ms\b|µs|seconds?\b|s per|MB/s|GB\b"
                       r"|times faster|x faster)", text)
    assert not units, units
    assert "benchmarks/RESULTS.md" in text


def test_readme_links_and_pictures_exist():
    for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", README.read_text()):
        if not target.startswith("http"):
            assert (ROOT / target).exists(), target


@pytest.mark.parametrize("page, least", [("README.md", 5), ("docs/usage.md", 5),
                                         ("docs/refinement.md", 4)])
def test_examples_print_what_they_show(page, least):
    """Every ``>>>`` example of the README, the usage page and the refinement page runs and
    prints what it shows."""
    import doctest

    failures, tried = doctest.testfile(str(ROOT / page), module_relative=False,
                                       optionflags=doctest.NORMALIZE_WHITESPACE)
    assert tried >= least and failures == 0
