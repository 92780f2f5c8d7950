"""The Section 4 figures are drawn from the planner's own (certified) output."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from pmplan.figures import FIGURE_OF, figure_queries, make_figures, to_frame
from pmplan.planners.planar_three import STRATA, classify, stratum_short_name

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def test_make_figures_writes_13_pngs(tmp_path):
    paths = make_figures(tmp_path / "figs")
    assert len(paths) == 13
    assert [p.stem for p in paths[:12]] == list(STRATA) and paths[12].name == "overview.png"
    for p in paths:
        data = p.read_bytes()
        assert p.parent == tmp_path / "figs" and len(data) > 1000 and data[:8] == PNG_MAGIC


def test_figure_queries_lie_in_their_strata():
    qs = figure_queries()
    assert set(qs) == set(STRATA) == set(FIGURE_OF)
    for name, (o, s, g) in qs.items():
        assert stratum_short_name(classify(o[None], s[None], g[None]).record[0]) == name


def test_to_frame_puts_o1_at_origin_and_o2_on_the_axis():
    o = figure_queries()["T23_33"][0]
    uh = to_frame(o, o)
    assert np.allclose(uh[0], 0) and abs(uh[1, 1]) < 1e-12 and uh[1, 0] > 0
