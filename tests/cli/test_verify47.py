"""Independent verification of issue 47 on main (after the merge of hostile4 with the drawn
designs): what the verification found still broken, each with the command that showed it."""

from __future__ import annotations

import json

from conftest import ROOT, run_cli


def test_bench_takes_a_drawn_design_whose_settings_are_its_own():
    """A drawn design lists its own bench settings as (method, budget) pairs, as a problem type
    does; bench unpacked them as (method, budget, atlas) and `linkcli bench` with no arguments
    (the packaged set holds bench/drawn_six_bar_path.toml) was a traceback at once:
    `ValueError: not enough values to unpack (expected 3, got 2)`."""
    from linkcli.bench import runs_of, settings_for
    from linkcli.reading.load import load
    path = str(ROOT / "problems" / "bench" / "drawn_six_bar_path.toml")
    assert settings_for(load(path)) == [("auto", None, None)]
    runs = runs_of(path, 2)
    assert [(r.method, r.budget, r.seed, r.atlas) for r in runs] == [("auto", None, 0, None), ("auto", None, 1, None)]
