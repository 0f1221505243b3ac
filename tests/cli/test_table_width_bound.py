"""The table view's shortcut (linkcli.report._surely_fits): a table it calls narrow enough is
never wider than the console by rich's own measure (_width), which print_table then skips.
The reference is rich's Measurement of the same table, on real reports and on made-up
tables with markup, styled text, wide characters, fixed and minimum column widths."""

from __future__ import annotations

import io
import json

import pytest
from conftest import run_cli
from rich.console import Console
from rich.table import Table
from rich.text import Text

from linkcli.report import _surely_fits, _width, render


def _console(width: int) -> Console:
    return Console(file=io.StringIO(), width=width, no_color=True, highlight=False, emoji=False)


def _tables(path: str) -> list[Table]:
    code, out, err = run_cli("synth", path, "--format", "json")
    assert code in (0, 1), err
    return [p for p in render(json.loads(out), 6).renderables
            if isinstance(p, Table) and not getattr(p, "is_head", False)]


def _made_up() -> list[Table]:
    tables = []
    cells = ["1", "[bold]x[/bold]", "\\[not markup]", "[42.8878, 143.707]", "漢字の幅", "a much longer cell text",
             Text("styled", style="bold"), Text("two words"), "-"]
    for k in range(len(cells)):
        for box_on in (True, False):
            t = Table(title="a title", show_edge=k % 2 == 0, pad_edge=k % 3 == 0, box=None if not box_on else Table().box,
                      min_width=[None, 10, 60][k % 3])
            t.add_column("key", min_width=[None, 5, 30][(k + 1) % 3])
            t.add_column("a header of words", width=[None, 3, 12][k % 3])
            t.add_column("漢字")
            for j in range(3):
                t.add_row(cells[(k + j) % len(cells)], cells[(k + 2 * j) % len(cells)], cells[(k * j) % len(cells)])
            tables.append(t)
    return tables


def _check(tables: list[Table], width: int) -> int:
    """Assert the bound at `width`; how many tables it calls narrow enough."""
    con = _console(width)
    sure = 0
    for table in tables:
        if _surely_fits(con, table):
            sure += 1
            assert _width(con, table) <= con.width
    return sure


def test_made_up_tables_at_every_width_near_their_own():
    tables = _made_up()
    assert sum(_check(tables, width) for width in range(20, 101)) > 0


@pytest.mark.parametrize("width", [40, 80, 100, 140])
def test_report_tables_called_narrow_enough_fit_by_richs_measure(width):
    tables = _tables("problems/firedoor.toml") + _tables("problems/firedoor_motion.toml")
    sure = _check(tables, width)
    if width >= 100:
        assert sure > 0  # the shortcut is taken, not only sound


def test_every_fire_door_table_is_known_to_fit_100_columns():
    con = _console(100)
    assert all(_surely_fits(con, t) for t in _tables("problems/firedoor.toml"))


def test_a_wide_table_is_left_to_richs_measure():
    con = _console(80)
    wide = [t for t in _tables("problems/firedoor_motion.toml") if _width(con, t) > 80]
    assert wide and not any(_surely_fits(con, t) for t in wide)
