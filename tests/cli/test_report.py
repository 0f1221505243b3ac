"""Tables for a person never hide digits: a number is shown whole, or folded on a terminal,
never cut with an ellipsis (which once showed -2.03555e-13 as "-2.03555e…")."""

from __future__ import annotations

import io
import json
import re

from conftest import run_cli
from rich.console import Console

from linkcli.report import _emit, render

PARALLELOGRAM = """type = "linkage"
[linkage]
ground = 1
input = 1
coupler = 1
output = 1
[motion]
steps = 72
"""  # rows every 5 deg: a table of at most report.MAX_ROWS rows is shown whole
NUMBER = re.compile(r"^-?\d+(\.\d+)?(e[-+]\d+)?$")


def _report(tmp_path):
    path = tmp_path / "rhombus.toml"
    path.write_text(PARALLELOGRAM)
    code, out, err = run_cli("synth", str(path), "-f", "json")
    assert code == 0, err
    return json.loads(out), path


def test_piped_tables_show_every_digit(tmp_path):
    rep, path = _report(tmp_path)
    code, out, _ = run_cli("synth", str(path))
    assert code == 0 and "…" not in out
    rows = [line.split() for line in out.splitlines() if re.match(r"^\s+\d+\s+(-?\d|-\s)", line)]
    kin = rep["kinematics"]
    assert len(rows) == len(kin)
    # every cell is a whole number. Up to the change point at 180 deg the rhombus is a
    # parallelogram: its coupler stays parallel to the ground (angle 0: its round-off is
    # below the noise floor and prints as 0) and its output follows the input
    assert all(NUMBER.match(c) or c == "-" for r in rows for c in r)
    coupler = [abs(float(r[1])) for r in rows[1:36]]
    assert max(coupler) == 0.0
    assert all(float(r[2]) == float(r[0]) for r in rows[1:36])
    # beyond it, the open branch folds into the kite: the output rests at 180 deg (never
    # shown as -180: positions are in (-180, 180]) while the coupler turns
    assert {float(r[2]) for r in rows[37:]} == {180.0}


def test_terminal_tables_fold_rather_than_cut(tmp_path):
    rep, _ = _report(tmp_path)
    for width in (60, 100):
        buf = io.StringIO()
        con = Console(file=buf, width=width, force_terminal=True, color_system=None)
        _emit(con, render(rep, 6))
        text = buf.getvalue()
        assert "…" not in text
        assert max(len(line) for line in text.splitlines()) <= width


def test_motion_and_positions_rows_carry_their_units():
    """Lengths (slider travel, path points) and angles (output range, function targets)
    are named with their unit in the table view, as the link lengths are."""
    from conftest import run_cli
    _, out, _ = run_cli("synth", "problems/slider_positions.toml")
    assert "slider range (mm)" in out and "stroke (mm)" in out
    assert "target (mm)" in out and "error (mm)" in out
    _, out, _ = run_cli("synth", "problems/firedoor.toml")
    assert "output range (deg)" in out and "output swing (deg)" in out
    assert "target (deg)" in out and "input (deg)" in out
    _, out, _ = run_cli("synth", "problems/motion3.toml")
    assert "target (in, in, deg)" in out


def test_a_value_in_brackets_is_printed_as_written_not_read_as_markup():
    """Table values are text: "[error, size]" (a front's objectives) and "draw it in [joints]"
    (a sweep's note) were read by rich as markup tags and printed blank or cut."""
    from linkcli.report import _kv, _rows
    out = io.StringIO()
    con = Console(file=out, width=200, color_system=None)
    con.print(_kv("Front", [("objectives", ["error", "size"]), ("note", "draw it in [joints] to design it")], 6))
    con.print(_rows("Rows", [{"choice": "a", "note": "[bold]x[/bold] and [joints]"}], 6))
    text = out.getvalue()
    assert "[error, size]" in text and "draw it in [joints] to design it" in text
    assert "[bold]x[/bold] and [joints]" in text
