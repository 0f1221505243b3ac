"""benchmarks/compare_commands.py, the documented way to time whole commands side by side
(docs/performance.md, benchmarks/RESULTS.md): what it counts, never how fast anything is."""

from __future__ import annotations

import importlib.util
import sys

import pytest
from conftest import ROOT

pytestmark = pytest.mark.slow  # the bench timing script: the full suite runs them, the fast lane does not


def _module():
    spec = importlib.util.spec_from_file_location("compare_commands", ROOT / "benchmarks" / "compare_commands.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks its module up there
    spec.loader.exec_module(module)
    return module


def test_ratios_are_taken_round_by_round():
    cc = _module()
    # rounds: 2/1, 3/2, 8/4 -> ratios 2, 1.5, 2: median 2, range 1.5-2 (not 13/7 of the sums)
    assert cc.ratio_summary([2.0, 3.0, 8.0], [1.0, 2.0, 4.0]) == (2.0, 1.5, 2.0)
    with pytest.raises(ValueError):
        cc.ratio_summary([1.0, 2.0], [1.0])


def test_each_command_runs_once_a_round_in_order_and_its_exit_codes_are_kept(tmp_path, capsys):
    cc = _module()
    log = tmp_path / "log"
    first = f"{sys.executable} -c \"open({str(log)!r}, 'a').write('A')\""
    second = f"{sys.executable} -c \"import sys; open({str(log)!r}, 'a').write('B'); sys.exit(3)\""
    assert cc.main(["--runs", "3", "--warmup", "1", first, second]) == 0
    assert log.read_text() == "AB" * 4  # the warm-up round, then three counted rounds, interleaved
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("| command | runs | median wall s | median CPU s | peak MiB | exit |")
    rows = [[cell.strip() for cell in line.split("|")[1:-1]] for line in lines[2:]]
    assert [(r[1], r[5]) for r in rows] == [("3", "0"), ("3", "3")]
    assert rows[0][6] == "1" and float(rows[1][6].split(" ")[0]) > 0
    assert float(rows[0][4]) > 1  # a Python process holds more than a MiB
