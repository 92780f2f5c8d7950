"""``benchmarks/sides_ab.py`` and ``benchmarks/robots_ab.py``: each committed report is its JSON
rewritten, and the JSON holds what the report claims of it (every row of both variants, the
design seeds and the seeds drawn after the choice, the planners compared)."""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import robots_ab
import sides_ab

HERE = Path(sides_ab.__file__).parent


def _rows(script) -> list:
    """The rows of a script's committed JSON, after checking that its report is the JSON
    rewritten and that the design and fresh seeds are there."""
    name = Path(script.__file__).stem
    res = json.loads((HERE / f"{name}.json").read_text())
    assert script.markdown(res) == (HERE / f"{name}.md").read_text()
    rows = [r for r in res["rows"] if r is not None]
    assert {r["seed"] for r in rows} >= set(script.DESIGN) | set(script.FRESH)
    return rows


def test_the_wall_side_report_is_its_json_rewritten():
    for r in _rows(sides_ab):
        assert r["default"]["planner"] == ["obstacle_line_walls"]
        assert all(p != "obstacle_line_walls" for p in r["before"]["planner"])


def test_the_side_per_robot_report_is_its_json_rewritten():
    rows = _rows(robots_ab)
    assert {r["n"] for r in rows} == set(robots_ab.NS)
    for r in rows:
        assert r["count"] == 400
        assert r["default"]["planner"] == ["obstacle_line_robots"]
        assert r["before"]["planner"] == ["obstacle_line_walls"]
