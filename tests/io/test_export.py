"""Output that scales (issue 33, item 4): JSON and CSV rounded at the leaves as they are
written, with the bytes of the reference writers; the table view of a long row table cut
to a bounded number of rows, whatever the row count; writes in bounded pieces."""

from __future__ import annotations

import csv
import io
import json
import math

import numpy as np
import pytest
from conftest import run_cli
from hypothesis import given, settings
from hypothesis import strategies as st

from linkcli.io.csv_tables import to_csv, write_csv
from linkcli.io.export import to_json, write_json
from linkcli.textnum import num

# -- an independent reference: the writers as they were (a rounded copy, then json.dumps) --

def reference_rounded(obj, digits):
    if isinstance(obj, dict):
        return {str(k): reference_rounded(v, digits) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [reference_rounded(v, digits) for v in obj]
    if isinstance(obj, str):
        import re
        return re.sub("\ue000([^\ue001]*)\ue001",
                      lambda m: "0" if float(f"{float(m.group(1)):.{digits}g}") == 0 else
                      f"{float(m.group(1)):.{digits}g}" if math.isfinite(float(m.group(1))) else m.group(1),
                      obj)
    if isinstance(obj, bool) or obj is None or isinstance(obj, int):
        return obj
    if hasattr(obj, "item"):
        return reference_rounded(obj.item(), digits)
    x = float(obj)
    if not math.isfinite(x):
        return None
    value = 0.0 if x == 0 else float(f"{x:.{digits}g}") + 0.0
    return value if math.isfinite(value) else None  # a rounding beyond the largest double


def reference_json(obj, digits):
    return json.dumps(reference_rounded(obj, digits), indent=2, ensure_ascii=False) + "\n"


floats = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from(
    [0.0, -0.0, 5e-324, -1.7976931348623157e308, 999999.5, 0.1235, 1e16, 123456789.0])
scalars = (floats | st.integers(-10**20, 10**20) | st.booleans() | st.none()
           | st.text(max_size=8) | floats.map(lambda x: f"mu {num(x)} deg")
           | floats.filter(math.isfinite).map(np.float64) | st.integers(-5, 5).map(np.int64))
documents = st.recursive(scalars, lambda inner: st.lists(inner, max_size=5)
                         | st.dictionaries(st.text(max_size=6), inner, max_size=5)
                         | st.tuples(inner, inner), max_leaves=40)


@pytest.mark.slow
@settings(max_examples=400, deadline=None)
@given(documents, st.sampled_from([1, 3, 6, 12, 17]))
def test_json_has_the_bytes_of_the_reference_writer(document, digits):
    assert to_json(document, digits) == reference_json(document, digits)


def test_json_of_report_rows_has_the_bytes_of_the_reference_writer():
    rng = np.random.default_rng(7)
    rows = [{"input": float(x), "pins": {"A": {"x": float(y), "y": -0.0, "magnitude": float("nan")}},
             "target": [float(x), float(y)], "ok": bool(x > 0), "note": None}
            for x, y in rng.normal(size=(500, 2)) * 10.0 ** rng.integers(-8, 8, size=(500, 1))]
    report = {"file": "a.toml", "kinematics": rows, "empty": [], "table": {}, "message": f"x {num(1 / 3)}"}
    for digits in (2, 6, 17):
        assert to_json(report, digits) == reference_json(report, digits)
        assert to_json([report, report], digits) == reference_json([report, report], digits)


def test_json_is_written_in_bounded_pieces():
    from linkcli.io.export import FLUSH_PIECES
    rows = [{"input": k * 0.001, "output": math.sin(k)} for k in range(20_000)]
    sizes = []

    class Recorder(io.StringIO):
        def write(self, text):
            sizes.append(len(text))
            return super().write(text)

    out = Recorder()
    write_json({"kinematics": rows}, 6, out)
    assert out.getvalue() == reference_json({"kinematics": rows}, 6)
    whole = len(out.getvalue())
    assert len(sizes) >= 2 * len(rows) // FLUSH_PIECES and max(sizes) < whole / 4  # never the whole text at once


def reference_csv(rows, digits):
    def flatten(prefix, value, cells):
        if isinstance(value, dict):
            for k, v in value.items():
                flatten(f"{prefix}.{k}" if prefix else str(k), v, cells)
        elif isinstance(value, list):
            names = ("_x", "_y") if len(value) == 2 else tuple(f"_{i + 1}" for i in range(len(value)))
            for suffix, v in zip(names, value):
                flatten(prefix + suffix, v, cells)
        else:
            cells[prefix] = value

    def cell(value):
        if value is None:
            return ""
        if isinstance(value, bool):
            return "true" if value else "false"
        if isinstance(value, float):
            return repr(value) if value != int(value) or abs(value) >= 1e16 else str(int(value))
        return str(value)

    flat = []
    for row in reference_rounded(rows, digits):
        cells: dict = {}
        flatten("", row, cells)
        flat.append(cells)
    columns = list(dict.fromkeys(k for cells in flat for k in cells))
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for cells in flat:
        writer.writerow([cell(cells.get(c)) for c in columns])
    return buffer.getvalue()


@settings(max_examples=200, deadline=None)
@given(st.lists(st.dictionaries(st.sampled_from(["a", "b", "c"]), scalars | st.lists(floats, max_size=3)
                                | st.dictionaries(st.sampled_from(["x", "y"]), floats, max_size=2),
                                max_size=3), min_size=1, max_size=6),
       st.sampled_from([1, 6, 17]))
@pytest.mark.slow
def test_csv_has_the_bytes_of_the_reference_writer(rows, digits):
    assert to_csv(rows, digits) == reference_csv(rows, digits)


# -- the table view: bounded however many rows ---------------------------------------------

def test_a_long_table_formats_a_bounded_number_of_cells(monkeypatch):
    # the table view of a long row table costs the same for 1,000 rows and for 30,000:
    # the cells formatted are counted (report.fmt), not timed
    from linkcli import report as view
    row = {"input": 1.25, "coupler": 2.5, "output": -3.75}
    calls = []
    real = view.fmt
    monkeypatch.setattr(view, "fmt", lambda v, digits=6: calls.append(v) or real(v, digits))
    counts = []
    for n in (1_000, 30_000):
        calls.clear()
        report = {"file": "long.toml", "type": "linkage", "status": "ok", "message": "",
                  "units": {"length": "mm", "angle": "deg"}, "kinematics": [dict(row) for _ in range(3)] * (n // 3)}
        report["kinematics"] += [dict(row)] * (n - len(report["kinematics"]))
        text = view.render_text([report], 6)
        counts.append(len(calls))
        assert f"50 of {n} rows shown; --format csv --table kinematics or --format json gives them all" in text
        assert text.count("\n") < view.MAX_ROWS
    assert counts[0] == counts[1] <= 3 * (view.HEAD_ROWS + view.TAIL_ROWS) + 10


def test_a_table_of_at_most_max_rows_is_shown_whole():
    from linkcli import report as view
    report = {"file": "short.toml", "type": "linkage", "status": "ok", "message": "",
              "units": {"length": "mm", "angle": "deg"},
              "kinematics": [{"input": float(k), "output": 2.0 * k} for k in range(view.MAX_ROWS)]}
    text = view.render_text([report], 6)
    assert "rows shown" not in text
    assert all(f" {2 * k}" in text for k in range(view.MAX_ROWS))


@pytest.mark.slow
def test_a_linkage_of_100000_steps_prints_its_table_cut_and_its_csv_whole(tmp_path):
    problem = tmp_path / "long.toml"
    problem.write_text('type = "linkage"\n[linkage]\nground = 50\ninput = 20\ncoupler = 60\noutput = 45\n'
                       'branch = "open"\n[motion]\ninput_speed = 10\nsteps = 100000\n'
                       '[report]\nsections = ["lengths", "kinematics"]\n')
    code, out, err = run_cli("synth", str(problem))
    assert code == 0, err
    lines = out.splitlines()
    assert "50 of 100000 rows shown; --format csv --table kinematics or --format json gives them all" in lines
    assert len(lines) < 100
    index = next(i for i, line in enumerate(lines) if line.split()[:1] == ["..."])
    assert float(lines[index - 1].split()[0]) == pytest.approx(39 * 360 / 100000)  # row 40 of the head
    assert float(lines[index + 1].split()[0]) == pytest.approx(99990 * 360 / 100000, abs=1e-3)  # tail
    code, out, err = run_cli("synth", str(problem), "--format", "csv")
    assert code == 0
    assert len(out.splitlines()) == 100001


def test_write_csv_streams_to_a_file(tmp_path):
    rows = [{"input": k / 7, "pins": {"A": {"x": k, "y": None}}} for k in range(1000)]
    with open(tmp_path / "t.csv", "w", newline="") as handle:
        write_csv(rows, 6, handle)
    assert (tmp_path / "t.csv").read_text() == reference_csv(rows, 6)
