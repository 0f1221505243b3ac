"""The reference pages name every problem type the registry knows (issue 28: format.md's
`type` row, its [solver] and [report] tables and plots.md's table listed 5 of 7): a new type
that is not documented fails here. And `bench --help` names only options bench has."""

from __future__ import annotations

import re

import pytest

from conftest import ROOT, run_cli
from linkcli.registry import NAMES


def _row(text: str, first_cell: str) -> str:
    return next(line for line in text.splitlines() if line.startswith(f"| {first_cell} |"))


def _table_after(text: str, heading: str) -> str:
    start = text.index(heading)
    return text[start:text.index("\n\n", text.index("|---", start))]


def test_format_md_type_row_lists_every_type():
    row = _row((ROOT / "docs" / "format.md").read_text(), "`type`")
    assert set(re.findall(r"`([a-z-]+)`", row)) >= set(NAMES)


@pytest.mark.parametrize("heading", ["| type | methods | default budget |", "| type | allowed sections | default |"])
def test_format_md_per_type_tables_have_a_row_for_every_type(heading):
    table = _table_after((ROOT / "docs" / "format.md").read_text(), heading)
    first_cells = {cell.strip() for line in table.splitlines()[2:] for cell in line.split("|")[1].split(",")}
    assert first_cells >= set(NAMES)


def test_plots_md_has_a_row_for_every_type():
    table = _table_after((ROOT / "docs" / "plots.md").read_text(), "| type | position drawn | beside it |")
    named = set(re.findall(r"`([a-z-]+)`", "\n".join(line.split("|")[1] for line in table.splitlines()[2:])))
    assert named >= set(NAMES)


def test_every_type_has_a_template_named_by_new():
    code, out, err = run_cli("new", "no-such-type")
    assert code == 2
    listed = set(err.split("one of: ")[1].split("; found")[0].split(", "))
    assert listed == set(NAMES) | {"five-bar", "drawn"}  # and the mechanisms with a template of their own


def test_bench_help_names_only_its_own_options():
    code, out, err = run_cli("bench", "--help")
    assert code == 0 and "--table" not in out
