"""Rich tables for a person: one block per problem, one table per section asked for.

The only module that imports rich. Known sections get tailored tables; any other section
a solver adds renders generically (a dict as a key/value table, a list of row dicts as a
table), so new problem types need no change here. Numbers are rounded by export.rounded.
"""

from __future__ import annotations

import sys

from rich import box
from rich.cells import cell_len
from rich.console import Console, Group
from rich.measure import Measurement
from rich.table import Table
from rich.text import Text

from linkcli.io.export import rounded
from linkcli.io.terminal_text import terminal_safe

MAX_TABLE_WIDTH = 400  # columns a table may take when printed to a file or a pipe
MAX_ROWS = 100  # a row table longer than this shows its first HEAD_ROWS and last TAIL_ROWS
HEAD_ROWS, TAIL_ROWS = 40, 10


class Elided(list):
    """The rows of a long row table that the table view shows (the first HEAD_ROWS and the
    last TAIL_ROWS), with how many the table has (`total`) and its name for `--table`
    (`name`, as csv_tables.row_tables names it). `like(rows)` carries both over to rows
    made from these (rounded, escaped, laid out by a type)."""

    def __init__(self, rows, total: int, name: str | None) -> None:
        super().__init__(rows)
        self.total = total
        self.name = name

    def like(self, rows) -> "Elided":
        return Elided(rows, self.total, self.name)


def elided(report: dict) -> dict:
    """The report with every row table longer than MAX_ROWS cut to its first and last rows
    (an Elided list), so that the table view's cost stays bounded however many rows a
    report holds; the other sections are shared, not copied."""
    from linkcli.io.csv_tables import row_tables
    out = dict(report)
    for name, rows in row_tables(report).items():
        if len(rows) <= MAX_ROWS:
            continue
        cut = Elided(rows[:HEAD_ROWS] + rows[-TAIL_ROWS:], len(rows), name)
        section, _, sub = name.partition(".")
        if sub:
            out[section] = {**out[section], sub: cut}
        else:
            out[section] = cut
    return out
STATUS_STYLE = {"ok": "bold green", "infeasible": "bold yellow", "not-converged": "bold red"}
KNOWN = ("file", "title", "type", "status", "message", "units", "linkage", "grashof",
         "transmission", "motion", "kinematics", "positions", "error", "solver", "notes", "forces", "loads", "masses")


def console(file=None, width: int | None = None) -> Console:
    """A console for stdout: the terminal's width when it is one, else 100 columns, no colour."""
    file = file or sys.stdout
    tty = hasattr(file, "isatty") and file.isatty()
    return Console(file=file, width=width if width else (None if tty else 100),
                   no_color=not tty, highlight=False, soft_wrap=False, emoji=False,
                   force_terminal=tty, color_system="auto" if tty else None)


def fmt(v, digits: int = 6) -> str:
    if v is None:
        return "-"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    if isinstance(v, list):
        return "[" + ", ".join(fmt(x, digits) for x in v) + "]"
    return str(v)


def _kv(title: str, rows: list[tuple[str, object]], digits: int) -> Table:
    t = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, show_header=False, pad_edge=False,
              show_edge=False, min_width=cell_len(title))  # a title wider than its rows stays on one line
    t.add_column("key", style="bold")
    t.add_column("value")
    for k, v in rows:
        t.add_row(k, fmt(v, digits))
    return t


def _rows(title: str, rows: list[dict], digits: int, headers: dict | None = None,
          no_wrap: bool = False) -> Table:
    """A row table; a long one (more than MAX_ROWS, or Elided already) shows its first
    and last rows with a "..." row between and a caption saying how to get them all."""
    if not isinstance(rows, Elided) and len(rows) > MAX_ROWS:
        rows = Elided(rows[:HEAD_ROWS] + rows[-TAIL_ROWS:], len(rows), None)
    cols = list(dict.fromkeys(k for r in rows for k in r))
    t = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False, show_edge=False)
    if isinstance(rows, Elided):  # printed under the table by _emit, one line however narrow the table
        where = (f"--format csv --table {rows.name}" if rows.name else "--format csv") + " or --format json"
        t.note = f"{len(rows)} of {rows.total} rows shown; {where} gives them all"
    for c in cols:
        t.add_column((headers or {}).get(c, c.replace("_", " ")), justify="right", no_wrap=no_wrap)
    for i, r in enumerate(rows):
        if isinstance(rows, Elided) and i == len(rows) - TAIL_ROWS:
            t.add_row(*("..." for _ in cols))
        t.add_row(*(fmt(r.get(c), digits) for c in cols))
    return t


def _generic(name: str, section, digits: int, units: dict[str, str] | None = None) -> list:
    """A dict as one key/value table (nested dicts flattened to "key sub"), its lists of
    row dicts as tables of their own; a list of row dicts as a table. `units` maps a key
    to the unit shown beside it."""
    title = name.replace("_", " ").capitalize()
    units = units or {}
    if isinstance(section, list) and section and all(isinstance(r, dict) for r in section):
        return [_rows(title, section, digits)]
    if not isinstance(section, dict):
        return [_kv(title, [(name, section)], digits)]
    flat, tables = [], []
    for k, v in section.items():
        label = k.replace("_", " ") + (f" ({units[k]})" if k in units else "")
        if isinstance(v, dict):
            flat += [(f"{label} {sub.replace('_', ' ')}", x) for sub, x in v.items()]
        elif isinstance(v, list) and v and isinstance(v[0], dict) and k == "curve":
            flat.append((label, f"{len(v)} rows in JSON/TOML output"))  # plot data, not for reading
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            tables.append(_rows(f"{title}: {k.replace('_', ' ')}", v, digits))
        else:
            flat.append((label, v))
    return ([_kv(title, flat, digits)] if flat else []) + tables


def _tolerance_units(section: dict, lu: str, au: str) -> dict[str, str]:
    measure = str(section.get("measure", ""))
    err = lu if ("coupler point" in measure or "slider" in measure) else au  # a length error
    keys = ("nominal_error", "error_mean", "error_p95", "error_max", "allowed_error")
    out = {k: err for k in keys}
    out.update({"lengths": lu, "clearance": lu, "clearance_slider": lu, "largest_tolerance": lu, "sensitivity": f"{err}/{lu}"})
    return out


def _type_tables(kind: str, name: str, section, digits: int, lu: str, au: str) -> list:
    """The tables a problem type lays out itself (`report_tables` of its sections.py);
    empty when the generic layout serves."""
    from linkcli.io.tables import KeyValues
    from linkcli.registry import PACKAGES, problem_type
    if kind not in PACKAGES:
        return []
    blocks = problem_type(kind).module("sections").report_tables(name, section, lu, au)
    cut = [section] if isinstance(section, Elided) else [v for v in section.values()
                                                          if isinstance(v, Elided)] if isinstance(section, dict) else []
    return [_kv(b.title, b.rows, digits) if isinstance(b, KeyValues)
            else _rows(b.title, _as_cut(b.rows, cut), digits, b.headers, no_wrap=b.no_wrap) for b in blocks]


def _as_cut(rows: list, cut: list) -> list:
    """Rows a type laid out one for one from an Elided list of its section (same length)
    are cut the same way: they say so."""
    if isinstance(rows, Elided):
        return rows
    source = next((c for c in cut if len(c) == len(rows)), None)
    return source.like(rows) if source is not None else rows


def render(report: dict, digits: int = 6) -> Group:
    """One problem's block."""
    r = terminal_safe(rounded(elided(report), digits))
    lu, au = r["units"]["length"], r["units"]["angle"]
    parts: list = []
    name = Text()
    name.append(r.get("title") or r["file"], style="bold")
    if r.get("title"):
        name.append(f"  ({r['file']})")
    status = Text(f"{r['type']}  ")
    status.append(r["status"], style=STATUS_STYLE.get(r["status"], "bold"))
    # one line when it fits; else the title wraps in its column and the type and status
    # stay on the first line (_emit prints it as it is)
    head = Table.grid(padding=(0, 2))
    head.add_column(overflow="fold")  # a long file name folds, never cut with an ellipsis
    head.add_column(no_wrap=True)
    head.add_row(name, status)
    head.is_head = True
    parts.append(head)
    parts.append(Text(r["message"]))
    if "linkage" in r:
        lk = r["linkage"]
        slider = lk.get("mechanism") == "slider-crank"  # input, coupler, offset: no ground or output
        rows = [("mechanism", "slider-crank")] if slider else []
        rows += [(f"{k} ({lu})", lk[k]) for k in (("input", "coupler", "offset") if slider
                                                  else ("ground", "input", "coupler", "output"))]
        rows.append(("branch", lk["branch"]))
        if "coupler_point" in lk:
            rows.append((f"coupler point ({lu})", lk["coupler_point"]))
            if "ground_pivot" in lk:  # a slider-crank has its crank pivot at the origin
                rows += [(f"ground pivot ({lu})", lk["ground_pivot"]),
                         (f"ground angle ({au})", lk["ground_angle"])]
            if "coupler_angle" in lk:
                rows.append((f"coupler angle ({au})", lk["coupler_angle"]))
        parts.append(_kv("Link lengths", rows, digits))
    if "grashof" in r:
        g = r["grashof"]
    if "grashof" in r and "crank_plus_offset" in g:  # a slider-crank: turns fully iff a + |e| <= b
        a_e, b = g["crank_plus_offset"], g["coupler"]
        rel = "<" if a_e < b else ("=" if a_e == b else ">")
        parts.append(_kv("Class", [("class", g["class"]),
                                   ("input + |offset| vs coupler", f"{fmt(a_e, digits)} {rel} {fmt(b, digits)}")],
                         digits))
    elif "grashof" in r:
        sl, pq = g["s_plus_l"], g["p_plus_q"]
        rel = "vs" if sl is None or pq is None else "<" if sl < pq else ("=" if sl == pq else ">")
        parts.append(_kv("Grashof", [("class", g["class"]), ("shortest", g["shortest"]),
                                     ("longest", g["longest"]),
                                     ("s + l vs p + q", f"{fmt(g['s_plus_l'], digits)} {rel} {fmt(g['p_plus_q'], digits)}")],
                         digits))
    if "transmission" in r:
        tr = r["transmission"]
        t = Table(title=f"Transmission angle ({au})", title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False, show_edge=False)
        for c in ("over", "min", "at input", "max", "at input"):
            t.add_column(c, justify="right" if c != "over" else "left")
        t.add_row("input's range of motion", fmt(tr["min"], digits), fmt(tr["input_at_min"], digits),
                  fmt(tr["max"], digits), fmt(tr["input_at_max"], digits))
        if "working_min" in tr:
            t.add_row("working range (targets)", fmt(tr["working_min"], digits),
                      fmt(tr["working_input_at_min"], digits), fmt(tr["working_max"], digits),
                      fmt(tr["working_input_at_max"], digits))
        parts.append(t)
    if "motion" in r:
        units = _motion_units(lu, au)
        parts.append(_kv("Motion", [(k.replace("_", " ") + (f" ({units[k]})" if k in units else ""), v)
                                    for k, v in r["motion"].items()], digits))
    if "positions" in r:
        parts.append(_rows("Positions", r["positions"], digits, _position_heads(r, lu, au)))
    if "error" in r:
        parts.append(_kv("Error", [(k.replace("_", " "), v) for k, v in r["error"].items()], digits))
    if "kinematics" in r:
        heads = {"input": f"input ({au})", "coupler": f"coupler ({au})", "output": f"output ({au})",
                 "transmission": f"mu ({au})", "coupler_velocity": f"w coupler ({au}/s)",
                 "output_velocity": f"w output ({au}/s)", "coupler_acceleration": f"a coupler ({au}/s2)",
                 "output_acceleration": f"a output ({au}/s2)",
                 "slider": f"slider ({lu})", "slider_velocity": f"v slider ({lu}/s)",
                 "slider_acceleration": f"a slider ({lu}/s2)",
                 "coupler_point_x": f"P x ({lu})", "coupler_point_y": f"P y ({lu})",
                 "coupler_point_vx": f"P vx ({lu}/s)", "coupler_point_vy": f"P vy ({lu}/s)",
                 "coupler_point_ax": f"P ax ({lu}/s2)", "coupler_point_ay": f"P ay ({lu}/s2)"}
        parts.append(_rows("Kinematics", r["kinematics"], digits, heads))
    if "loads" in r:
        units = {"coupler_force": "N", "output_torque": "N m", "output_force": "N", "gravity": "m/s2"}
        parts.append(_kv("Loads", [(f"{k.replace('_', ' ')} ({units[k]})", v) for k, v in r["loads"].items()],
                         digits))
    if "masses" in r:
        units = {"mass": "kg", "center": lu, "inertia": "kg m2"}
        parts.append(_kv("Masses", [(f"{link} {k} ({units[k]})", v) for link, props in r["masses"].items()
                                    for k, v in props.items()], digits))
    if "forces" in r:
        parts.extend(_forces(r["forces"], digits, au))
    for name, section in r.items():
        if name not in KNOWN:
            units = _tolerance_units(section, lu, au) if name == "tolerance" else None
            parts.extend(_type_tables(r["type"], name, section, digits, lu, au)
                         or _generic(name, section, digits, units))
    if "solver" in r:
        parts.append(_kv("Solver", [(k.replace("_", " "), v) for k, v in r["solver"].items()], digits))
    for note in r.get("notes", []):
        parts.append(Text(f"warning: {note}", style="yellow"))
    return Group(*parts)


def _motion_units(lu: str, au: str) -> dict[str, str]:
    """The unit of each Motion row that has one (time ratio, steps and yes/no have none)."""
    return {"input_range": au, "output_range": au, "output_swing": au, "slider_range": lu,
            "stroke": lu, "input_speed": f"{au}/s"}


def _position_heads(r: dict, lu: str, au: str) -> dict[str, str]:
    """Positions column headings with units: the input is an angle; target, achieved and
    error are points or slider positions (length) for path generation and a slider-crank,
    output angles for a four-bar's function, poses (x, y, angle) for motion generation,
    with a position error (length) and an angle error."""
    slider = r.get("linkage", {}).get("mechanism") == "slider-crank"
    unit = lu if r["type"] == "path-generation" or slider else au
    heads = {"input": f"input ({au})", "position_error": f"position error ({lu})",
             "angle_error": f"angle error ({au})"}
    if r["type"] == "motion-generation":
        heads.update({k: f"{k} ({lu}, {lu}, {au})" for k in ("target", "achieved")})
    else:
        heads.update({k: f"{k} ({unit})" for k in ("target", "achieved", "error")})
    return heads


def _forces(forces: dict, digits: int, au: str) -> list:
    """The forces section: the input torque, the load cycle per pin (magnitudes; the x/y
    components are in JSON/TOML) and the rows with one column of magnitudes per pin."""
    torque = forces["input_torque"]
    rows = [("peak (N m)", torque["peak"]), (f"at input ({au})", torque["at_input"]),
            ("rms (N m)", torque["rms"])]
    if "dead_points" in forces:
        rows.append(("dead points (rows left out)", forces["dead_points"]))
    parts: list = [_kv("Input torque", rows, digits)]
    cycle = [{"pin": name, **{k: v for k, v in pin.items() if k not in ("x", "y")}}
             for name, pin in forces["pins"].items()]
    parts.append(_rows("Pin forces over the cycle (N, magnitude)", cycle, digits))
    heads = {"input": f"input ({au})", "input_torque": "torque (N m)", "mechanical_advantage": "MA"}
    table = []
    for row in forces["rows"]:
        line = {"input": row["input"], "input_torque": row["input_torque"]}
        for name, pin in row["pins"].items():
            line[name] = pin["magnitude"]
            heads[name] = f"|{name}| (N)"
        line["mechanical_advantage"] = row["mechanical_advantage"]
        table.append(line)
    parts.append(_rows("Forces", _as_cut(table, [forces["rows"]] if isinstance(forces["rows"], Elided) else []),
                       digits, heads))
    return parts


def _compact(table: Table) -> None:
    """Fix each column at its longest cell or header word (headers wrap at words, cells
    never; a no_wrap column's header stays whole)."""
    for column in table.columns:
        words = ([str(column.header)] if column.no_wrap else str(column.header).split()) or [""]
        column.width = max([cell_len(str(c)) for c in column.cells] + [cell_len(w) for w in words])


def _width(con: Console, table: Table) -> int:
    """The width the table takes when nothing limits it (rich's own measure)."""
    return Measurement.get(con, con.options.update_width(MAX_TABLE_WIDTH), table).maximum


def _blocks(con: Console, table: Table) -> list[Table]:
    """A row table too wide for the terminal as several tables of its columns, each as wide
    as fits, the first column (the row's key: input angle, parameter, problem) repeated
    in each, as wide tables are printed in blocks; no number is cut or folded. A single
    column wider than the terminal still folds."""
    def block(columns, title) -> Table:
        t = Table(title=title, title_justify="left", box=table.box, pad_edge=False, show_edge=False,
                  min_width=min(cell_len(title), con.width))  # the title on one line when it fits
        for c in columns:
            t.add_column(c.header, justify=c.justify, no_wrap=c.no_wrap, width=c.width)
        for cells in zip(*(list(c.cells) for c in columns)):
            t.add_row(*cells)
        return t

    key, rest = table.columns[0], table.columns[1:]
    title = str(table.title or "")
    out: list[Table] = []
    group: list = []
    for column in rest:
        trial = block([key] + group + [column], title)
        if group and _width(con, trial) > con.width:
            out.append(block([key] + group, title if not out else f"{title} (continued)"))
            group = []
        group.append(column)
    out.append(block([key] + group, title if not out else f"{title} (continued)"))
    for t in out:
        if _width(con, t) > con.width:  # one column alone is too wide: fold its cells
            for column in t.columns:
                column.width, column.overflow = None, "fold"
    return out


def print_table(con: Console, part) -> None:
    """Print one part of a report (or any rich table, e.g. bench's). A table never shows a
    truncated number: one wider than the console is laid out compactly (headers wrap at
    words, cells never); if it still does not fit it is printed wider (a file or a pipe:
    one row per line, every digit) or, on a terminal, a row table in blocks of columns
    (_blocks) and a key/value table with its cells folded onto a second line."""
    if isinstance(part, Table) and not getattr(part, "is_head", False) and _width(con, part) > con.width:
        _compact(part)
        need = _width(con, part)
        if need > con.width:
            if not con.is_terminal:
                width, con.width = con.width, need
                con.print(part)
                con.width = width
                _note(con, part)
                return
            if part.show_header and len(part.columns) > 2:
                for piece in _blocks(con, part):
                    con.print(piece)
                _note(con, part)
                return
            for column in part.columns:
                column.width, column.overflow = None, "fold"
    con.print(part)
    _note(con, part)


def _emit(con: Console, group: Group) -> None:
    """Print a report part by part (print_table)."""
    for part in group.renderables:
        print_table(con, part)


def _note(con: Console, part) -> None:
    """The line a table carries under it (an elided row table's "50 of N rows shown"), on
    one line of its own."""
    note = getattr(part, "note", None)
    if note:
        con.print(Text(note, no_wrap=True, overflow="ignore"), crop=False)


def print_reports(reports: list[dict], digits: int, file=None) -> None:
    con = console(file)
    for i, rep in enumerate(reports):
        if i:
            con.print()
        _emit(con, render(rep, digits))


def render_text(reports: list[dict], digits: int) -> str:
    """Plain text of the tables (for --out with the table format)."""
    import io
    buf = io.StringIO()
    con = Console(file=buf, width=100, no_color=True, highlight=False, emoji=False, color_system=None)
    for i, rep in enumerate(reports):
        if i:
            con.print()
        _emit(con, render(rep, digits))
    return buf.getvalue()
