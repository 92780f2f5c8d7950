"""``benchmarks/robots_ab.py``: its committed report is its JSON rewritten, and the JSON holds
what the report claims of it (every row of both variants, the design seeds and the seeds drawn
after the barrier's choice, the planners compared)."""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import robots_ab

HERE = Path(robots_ab.__file__).parent


def test_the_committed_report_is_its_json_rewritten():
    res = json.loads((HERE / "robots_ab.json").read_text())
    assert robots_ab.markdown(res) == (HERE / "robots_ab.md").read_text()
    rows = [r for r in res["rows"] if r is not None]
    assert {r["seed"] for r in rows} >= set(robots_ab.DESIGN) | set(robots_ab.FRESH)
    assert {r["n"] for r in rows} == set(robots_ab.NS)
    for r in rows:
        assert r["count"] == 400
        assert r["default"]["planner"] == ["obstacle_line_robots"]
        assert r["before"]["planner"] == ["obstacle_line_walls"]
