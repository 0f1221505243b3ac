"""`--format csv`: the row tables of a report (kinematics, positions, forces, ...) as CSV.

A row table is a list of row objects: a top-level section (`kinematics`, `positions`) or a
list inside a section (`cylinder.forces`, `forces.rows`); it is named by that key path.
Columns are the rows' keys in order of first appearance, flattened: a nested object gives
`key.sub` columns (`pins.A0.x`), a pair [x, y] gives `key_x`, `key_y`, a longer list
`key_1`, `key_2`, ...; a missing or undefined value is an empty cell. Numbers are rounded
like JSON (`--precision`), so the same report gives the same bytes.
"""

from __future__ import annotations

import csv
import io

from linkcli.io.export import rounded


def _is_rows(value) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(r, dict) for r in value)


def row_tables(report: dict) -> dict[str, list[dict]]:
    """name -> rows of every row table of a report, in report order."""
    out: dict[str, list[dict]] = {}
    for key, value in report.items():
        if _is_rows(value):
            out[key] = value
        elif isinstance(value, dict):
            for sub, inner in value.items():
                if _is_rows(inner):
                    out[f"{key}.{sub}"] = inner
    return out


def _flatten(prefix: str, value, cells: dict) -> None:
    if isinstance(value, dict):
        for k, v in value.items():
            _flatten(f"{prefix}.{k}" if prefix else str(k), v, cells)
    elif isinstance(value, list):
        names = ("_x", "_y") if len(value) == 2 else tuple(f"_{i + 1}" for i in range(len(value)))
        for suffix, v in zip(names, value):
            _flatten(prefix + suffix, v, cells)
    else:
        cells[prefix] = value


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value) if value != int(value) or abs(value) >= 1e16 else str(int(value))
    return str(value)


def to_csv(rows: list[dict], digits: int) -> str:
    """One row table as CSV text (a header line, then one line per row; "\\n" line ends)."""
    flat = []
    for row in rounded(rows, digits):
        cells: dict = {}
        _flatten("", row, cells)
        flat.append(cells)
    columns = list(dict.fromkeys(k for cells in flat for k in cells))
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for cells in flat:
        writer.writerow([_cell(cells.get(c)) for c in columns])
    return buffer.getvalue()
