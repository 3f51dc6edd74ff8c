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
    "fretting with fatigue": {  # every criterion: maps, angles, lives and hot spots
        "loading": {"kind": "fretting", "steps": 2, "cycles": 3, "record": [1],
                    "force_amplitude": 20.0},
        "sweep": {"wear1": [1e-8]},
        "fatigue": {
            "criteria": ["crossland", "dang_van", "swt", "fatemi_socie"],
            "sigma_d": 300.0, "tau_d": 200.0,
            "sigma_f": 1000.0, "b": -0.09, "eps_f": 0.6, "c": -0.6,
            "tau_f": 600.0, "gamma_f": 0.9, "b0": -0.09, "c0": -0.6, "k": 0.6,
            "sigma_y": 800.0,
        },
    },
}  # fmt: skip


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
