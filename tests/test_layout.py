"""The pre-created layout (engine.study.layout) is exactly what the case runner produces.

The collective writer creates these datasets before any case runs; a case whose datasets did
not match would fall back to commit-time creation (correct, but no longer independent I/O), so
the layout is checked here against real outcomes: path, shape and dtype, no more, no less.
"""

from __future__ import annotations

import numpy as np
import pytest

from engine.study.case import COMPLETED, CaseRunner
from engine.study.config import parse_study
from engine.study.examples import study_toml
from engine.study.layout import case_layout
from engine.study.plan import make_plan

LOADINGS = {  # changes to engine.study.examples.BASE (16 x 16, mu1 = 0.3), by loading kind
    "static": {"loading": {"kind": "static", "steps": 3}},
    "cyclic": {
        "loading": {"kind": "cyclic", "steps": 3, "cycles": 2000, "record": [0, 500]},
        "sweep": {"wear1": [1.33e-7]},
    },
}


@pytest.mark.parametrize("kind", sorted(LOADINGS))
def test_layout_matches_the_datasets_of_a_completed_case(kind, tmp_path):
    text = study_toml("layout", tmp_path / "layout.h5", LOADINGS[kind], subsurface={"layers": 6})
    config = parse_study(text, source="test")
    case = next(iter(make_plan(config)))
    outcome = CaseRunner(config)(case)
    assert outcome.status == COMPLETED, outcome.message
    produced = {
        path: (np.shape(record.data), np.asarray(record.data).dtype)
        for path, record in outcome.datasets.items()
        if not path.startswith(("history/", "peak_changes/"))  # counts known at run time
    }
    expected = {
        path: (spec.shape, np.dtype(spec.dtype)) for path, spec in case_layout(config).items()
    }
    assert produced == expected
