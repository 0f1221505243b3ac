"""Golden output: every example in problems/ (JSON and table), every bad file in tests/bad/.

Run `pytest --update-goldens` to rewrite them after a deliberate change, then review the diff.
The solver's evaluation count, the one printed field that may differ between machines, is
masked in the golden files and in the output compared with them (machine_fields.py);
every other byte must match.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT, run_cli
from machine_fields import masked

PROBLEMS = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "problems").glob("*.toml"))
BAD = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "tests" / "bad").glob("*.toml"))
GOLDEN = ROOT / "tests" / "golden"


def _compare(path: Path, text: str, update: bool) -> None:
    if update or not path.exists():
        if not update:
            pytest.fail(f"missing golden {path.name}: run pytest --update-goldens and review it")
        path.write_text(text, encoding="utf-8")
        return
    assert text == path.read_text(encoding="utf-8"), f"{path.name} differs from the golden"


@pytest.mark.parametrize("problem", PROBLEMS)
@pytest.mark.parametrize("fmt", ["json", pytest.param("table", marks=pytest.mark.slow)])  # the fast lane: JSON's numbers
def test_problem_golden(problem, fmt, update_goldens):
    code, out, err = run_cli("synth", problem, "--format", fmt)
    assert code in (0, 1), err
    assert "Traceback" not in err
    ext = "json" if fmt == "json" else "txt"
    _compare(GOLDEN / f"{Path(problem).stem}.{ext}", masked(out, fmt), update_goldens)


@pytest.mark.parametrize("bad", BAD)
def test_bad_input_golden(bad, update_goldens):
    code, out, err = run_cli("check", bad)
    assert code == 2
    assert out == ""
    assert "Traceback" not in err
    for line in err.splitlines():
        assert line.startswith(bad + ":"), line
    _compare(ROOT / bad.replace(".toml", ".txt"), err, update_goldens)
    # synth reports the same lines and the same exit code
    code2, _, err2 = run_cli("synth", bad)
    assert code2 == 2 and err2 == err
