"""Reports on an 80 to 120 column terminal (issue 28): no line wider than the terminal, no
number cut or folded (a wide row table prints in blocks of columns, its key column
repeated), whole headings, the status on the first line of a long title; pipes and files
keep one row per line."""

from __future__ import annotations

import io
import json
import re

import pytest
from conftest import run_cli
from rich.console import Console

from linkcli.report import _emit, print_table, render

NUMBER = re.compile(r"^-?\d+(\.\d+)?(e[-+]\d+)?$")


def _report(*args: str) -> dict:
    code, out, err = run_cli("synth", *args, "--format", "json")
    assert code in (0, 1), err
    return json.loads(out)


def _terminal(report: dict, width: int) -> str:
    buf = io.StringIO()
    con = Console(file=buf, width=width, force_terminal=True, color_system=None)
    _emit(con, render(report, 6))
    return buf.getvalue()


def _blocks(text: str, title: str) -> list[list[list[str]]]:
    """The row blocks of the table `title` (and its continuations): each a list of cell rows."""
    lines = text.splitlines()
    blocks, current = [], None
    for line in lines:
        if line.startswith(title):
            current = []
            blocks.append(current)
        elif current is not None and re.match(r"^\s*-?\d", line):
            current.append(line.split())
        elif current is not None and current and not line.startswith(" "):
            current = None
    return blocks


@pytest.mark.parametrize("width", [80, 100, 120])
def test_a_wide_kinematics_table_prints_in_blocks_with_every_digit(width):
    report = _report("problems/firedoor_motion.toml")
    text = _terminal(report, width)
    assert max(len(line) for line in text.splitlines()) <= width
    assert "…" not in text
    blocks = _blocks(text, "Kinematics")
    assert len(blocks) >= 2  # 14 columns do not fit 120
    rows = report["kinematics"]
    cells = [[] for _ in rows]
    for block in blocks:
        assert len(block) == len(rows)
        for k, line in enumerate(block):
            assert float(line[0]) == pytest.approx(rows[k]["input"])  # the key column in each block
            cells[k] += line[1:]
    for k, row in enumerate(rows):  # every value, whole, in the order of the columns
        assert all(NUMBER.match(c) for c in cells[k])
        assert [float(c) for c in cells[k]] == pytest.approx([v for key, v in row.items() if key != "input"],
                                                            rel=1e-5, abs=1e-9)


def test_in_a_pipe_the_wide_table_keeps_one_row_per_line():
    columns = len(_report("problems/firedoor_motion.toml")["kinematics"][0])
    code, out, err = run_cli("synth", "problems/firedoor_motion.toml")
    assert code == 0
    rows = [line for line in out.splitlines() if re.match(r"^\s+\d+\s+\d", line)]
    assert len(rows) == 36 and all(len(r.split()) == columns for r in rows)


def test_the_trade_off_headings_are_whole_on_a_terminal(tmp_path):
    problem = tmp_path / "pareto.toml"
    problem.write_text(open("problems/flipper.toml").read().replace("[objective]", "[objective]\npareto = 4"))
    text = _terminal(_report(str(problem)), 80)
    assert "closed length" in text and "peak force (N)" in text
    assert "…" not in text and max(len(line) for line in text.splitlines()) <= 80


@pytest.mark.parametrize("width", [80, 100])
def test_a_long_title_keeps_type_and_status_on_its_first_line(tmp_path, width):
    problem = tmp_path / "titled.toml"
    problem.write_text('title = "' + "A very long title of a fire-door closer designed for a test " * 2 + '"\n'
                       + open("problems/firedoor.toml").read().replace("title =", "# title ="))
    text = _terminal(_report(str(problem)), width)
    first = text.splitlines()[0]
    assert first.rstrip().endswith("precision-position  ok")
    assert max(len(line) for line in text.splitlines()) <= width


def test_bench_summary_prints_in_blocks_on_a_terminal():
    from linkcli import bench
    rows = [{"problem": "problems/bench/firedoor.toml", "method": "auto", "budget": None, "seed": s,
             "seconds": 0.001 * (s + 1), "evaluations": 1, "objective": 0.0, "best_known": 0.0, "gap": 0.0,
             "status": "ok"} for s in range(3)]
    table = bench._table("reliability over the seeds (within 1e-6 of the best known)", bench.summary(rows),
                         bench.SUMMARY_COLUMNS, 4)
    buf = io.StringIO()
    print_table(Console(file=buf, width=80, force_terminal=True, color_system=None), table)
    text = buf.getvalue()
    assert max(len(line) for line in text.splitlines()) <= 80
    for column in bench.SUMMARY_COLUMNS:  # every heading, whole or wrapped at its words
        assert all(word in text for word in column.split())
    assert text.count("firedoor") >= 2  # the key column repeated in each block
