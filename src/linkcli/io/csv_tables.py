"""`--format csv`: the row tables of a report (kinematics, positions, forces, ...) as CSV.

A row table is a list of row objects: a top-level section (`kinematics`, `positions`) or a
list inside a section (`cylinder.forces`, `forces.rows`); it is named by that key path.
Columns are the rows' keys in order of first appearance, flattened: a nested object gives
`key.sub` columns (`pins.A0.x`), a pair [x, y] gives `key_x`, `key_y`, a longer list
`key_1`, `key_2`, ...; a missing or undefined value is an empty cell. Numbers are rounded
like JSON (`--precision`), so the same report gives the same bytes.
"""

from __future__ import annotations

import io

from linkcli.io.export import rounded_leaf


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


def _text(value, digits: int) -> str:
    """One cell: a number rounded like JSON (a whole number without ".0"), true/false, a
    string with its wrapped numbers rounded, empty for None or a non-finite number."""
    value = rounded_leaf(value, digits)
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value) if value != int(value) or abs(value) >= 1e16 else str(int(value))
    return str(value)


def _cells(prefix: str, value, cells: dict, digits: int | None, fmt: str) -> None:
    """The cells of one row (or of a value inside it), by column name, rounded as they
    are flattened (no rounded copy of the rows is made); `digits` None: the column names
    alone (every cell None)."""
    if isinstance(value, dict):
        for k, v in value.items():
            name = f"{prefix}.{k}" if prefix else str(k)
            if isinstance(v, (dict, list, tuple)):
                _cells(name, v, cells, digits, fmt)
            elif digits is None:
                cells[name] = None
            elif type(v) is float and -1e308 < v < 1e308:  # the common leaf, inlined (export.round_sig)
                v = float(format(v, fmt)) + 0.0
                cells[name] = repr(v) if v != int(v) or abs(v) >= 1e16 else str(int(v))
            else:
                cells[name] = _text(v, digits)
    elif isinstance(value, (list, tuple)):
        names = ("_x", "_y") if len(value) == 2 else tuple(f"_{i + 1}" for i in range(len(value)))
        for suffix, v in zip(names, value):
            _cells(prefix + suffix, v, cells, digits, fmt)
    else:
        cells[prefix] = None if digits is None else _text(value, digits)


def write_csv(rows: list[dict], digits: int, file) -> None:
    """One row table as CSV (a header line, then one line per row; "\\n" line ends),
    written to `file` as it is made: the columns (their first appearance over all rows)
    in a first pass that formats nothing, then each row formatted and written, so the
    cells of 100,000 rows are never held at once."""
    import csv  # here, not at the top: the table view reads row_tables alone
    fmt = f".{digits}g"
    names: dict = {}
    for row in rows:
        _cells("", row, names, None, fmt)
    columns = list(names)
    writer = csv.writer(file, lineterminator="\n")
    writer.writerow(columns)
    for start in range(0, len(rows), 1000):
        block = []
        for row in rows[start:start + 1000]:
            cells: dict = {}
            _cells("", row, cells, digits, fmt)
            block.append([cells.get(c, "") for c in columns])
        writer.writerows(block)


def to_csv(rows: list[dict], digits: int) -> str:
    """`write_csv` as text."""
    buffer = io.StringIO()
    write_csv(rows, digits, buffer)
    return buffer.getvalue()
