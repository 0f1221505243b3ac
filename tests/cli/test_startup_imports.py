"""What `linkcli synth problems/firedoor.toml` must not import (issue 33: start-up). A
closed-form problem printed as a table needs no optional table's records, no other
mechanism's or problem type's classes, no forces, tolerance or strength analysis, no
scipy, no JSON or CSV writer, no progress display (stderr is not a terminal) and no
rich help formatting. Checked in a fresh process by the modules it holds at exit; no
timing here (docs/performance.md's start-up rows are measured with
benchmarks/compare_commands.py)."""

from __future__ import annotations

import importlib.util
import subprocess
import sys

import pytest

MUST_NOT_LOAD = (
    "scipy",
    "json", "csv",  # --format json / csv only
    "linkcli.model.tolerance", "linkcli.model.loads", "linkcli.model.strength",  # optional tables
    "linkcli.model.linkage", "linkcli.model.path_generation", "linkcli.model.motion_generation",
    "linkcli.model.function_generation", "linkcli.model.flipper_cylinder", "linkcli.model.quick_return",
    "linkcli.mechanisms.five_bar.model", "linkcli.mechanisms.drawn.model",  # other mechanisms
    "linkcli.io.joints", "linkcli.reading.tolerance_keys",  # [joints], [sections], [tolerance]
    "linkcli.reading.result_motion",  # analyze of a result file
    "linkcli.analysis.forces", "linkcli.analysis.loads", "linkcli.analysis.tolerance", "linkcli.analysis.tolerance_report",
    "linkcli.analysis.strength", "linkcli.mechanisms.four_bar.loads", "linkcli.mechanisms.four_bar.tolerance",
    "linkcli.search", "linkcli.plot",
    "linkcli.atlas",  # the coupler-curve atlas: free-timing path searches only
    "rich.progress", "typer.rich_utils",
)

PROGRAM = """\
import sys
sys.argv = ["linkcli", "synth", "problems/firedoor.toml"]
from linkcli.cli import main
try:
    main()
finally:
    sys.stderr.write("\\nLOADED " + " ".join(sorted(sys.modules)) + "\\n")
"""


@pytest.mark.parametrize("name", MUST_NOT_LOAD)
def test_each_listed_module_exists(name):
    """A misspelt name would pass the test below for nothing."""
    assert importlib.util.find_spec(name) is not None


def test_synth_of_the_fire_door_loads_none_of_them():
    res = subprocess.run([sys.executable, "-c", PROGRAM], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert res.stdout.startswith("Fire-door closer")
    loaded = set(res.stderr.rsplit("LOADED ", 1)[1].split())
    assert "numpy" in loaded and "rich.table" in loaded  # it did solve and print a table
    assert sorted(m for m in MUST_NOT_LOAD if m in loaded) == []


CHECK_PROGRAM = """\
import glob, sys
sys.argv = ["linkcli", "check"] + sorted(glob.glob("problems/*.toml"))
from linkcli.cli import main
try:
    main()
finally:
    sys.stderr.write("\\nLOADED " + " ".join(sorted(sys.modules)) + "\\n")
"""


def test_check_of_every_example_imports_neither_numpy_nor_scipy():
    """`check` is pure Python (docs/format.md): every example, drawings, drawn designs and
    topologies included (a drawn design's file imported numpy through the population's
    groups, a function-generation file through the noise floor's module)."""
    from conftest import ROOT
    res = subprocess.run([sys.executable, "-c", CHECK_PROGRAM], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert res.stdout.count(": ok\n") >= 40
    loaded = set(res.stderr.rsplit("LOADED ", 1)[1].split())
    assert "linkcli.mechanisms.drawn.structure" in loaded  # it did read the drawings
    assert sorted(m for m in ("numpy", "scipy") if m in loaded) == []
