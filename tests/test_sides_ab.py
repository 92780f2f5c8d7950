"""``benchmarks/sides_ab.py``: its committed report is its JSON rewritten, and the JSON holds what
the report claims of it (every row of both variants, the seeds drawn after the choice)."""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import sides_ab

HERE = Path(sides_ab.__file__).parent


def test_the_committed_report_is_its_json_rewritten():
    res = json.loads((HERE / "sides_ab.json").read_text())
    assert sides_ab.markdown(res) == (HERE / "sides_ab.md").read_text()
    rows = [r for r in res["rows"] if r is not None]
    assert {r["seed"] for r in rows} >= set(sides_ab.DESIGN) | set(sides_ab.FRESH)
    for r in rows:
        assert r["default"]["planner"] == ["obstacle_line_walls"]
        assert all(p != "obstacle_line_walls" for p in r["before"]["planner"])
