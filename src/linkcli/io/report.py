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
    t = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, show_header=False, pad_edge=False, show_edge=False)
    t.add_column("key", style="bold")
    t.add_column("value")
    for k, v in rows:
        t.add_row(k, fmt(v, digits))
    return t


def _rows(title: str, rows: list[dict], digits: int, headers: dict | None = None,
          no_wrap: bool = False) -> Table:
    cols = list(dict.fromkeys(k for r in rows for k in r))
    t = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False, show_edge=False)
    for c in cols:
        t.add_column((headers or {}).get(c, c.replace("_", " ")), justify="right", no_wrap=no_wrap)
    for r in rows:
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
            for sub, x in v.items():  # a list of row dicts inside is a table of its own
                if isinstance(x, list) and x and all(isinstance(r, dict) for r in x):
                    tables.append(_rows(f"{title}: {label} {sub.replace('_', ' ')}", x, digits))
                else:
                    flat.append((f"{label} {sub.replace('_', ' ')}", x))
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
    return [_kv(b.title, b.rows, digits) if isinstance(b, KeyValues)
            else _rows(b.title, b.rows, digits, b.headers, no_wrap=b.no_wrap) for b in blocks]


def render(report: dict, digits: int = 6) -> Group:
    """One problem's block."""
    r = terminal_safe(rounded(report, digits))
    lu, au = r["units"]["length"], r["units"]["angle"]
    parts: list = []
    head = Text()
    head.append(r.get("title") or r["file"], style="bold")
    if r.get("title"):
        head.append(f"  ({r['file']})")
    head.append(f"  {r['type']}  ")
    head.append(r["status"], style=STATUS_STYLE.get(r["status"], "bold"))
    parts.append(head)
    parts.append(Text(r["message"]))
    if "linkage" in r:
        parts.append(_kv("Link lengths", _linkage_rows(r["linkage"], lu, au), digits))
    if "grashof" in r:
        parts.append(_class_table(r["grashof"], digits))
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


def _linkage_rows(lk: dict, lu: str, au: str) -> list[tuple[str, object]]:
    """The linkage section in its own order: text as it is, numbers and coordinates in the
    length unit, `*_angle` keys in the angle unit."""
    rows = []
    for key, value in lk.items():
        label = key.replace("_", " ")
        if not isinstance(value, str):
            label += f" ({au})" if key.endswith("_angle") else f" ({lu})"
        rows.append((label, value))
    return rows


def _class_table(g: dict, digits: int) -> Table:
    """The class section as its mechanism lays it out (mechanisms.layout_of), else key by key."""
    from linkcli.mechanisms import layout_of
    layout = layout_of(g)
    if layout is None:
        return _kv("Class", [(k.replace("_", " "), v) for k, v in g.items()], digits)
    title, rows = layout.class_block(g, lambda v: fmt(v, digits))
    return _kv(title, rows, digits)


def _motion_units(lu: str, au: str) -> dict[str, str]:
    """The unit of each Motion row that has one (time ratio, steps and yes/no have none)."""
    return {"input_range": au, "output_range": au, "output_swing": au, "slider_range": lu,
            "stroke": lu, "input_speed": f"{au}/s"}


def _position_heads(r: dict, lu: str, au: str) -> dict[str, str]:
    """Positions column headings with units: the input is an angle; target, achieved and
    error are points or slider positions (length) for path generation and a slider-crank,
    output angles for a four-bar's function, poses (x, y, angle) for motion generation,
    with a position error (length) and an angle error."""
    from linkcli.mechanisms import module
    mechanism = r.get("linkage", {}).get("mechanism", "four-bar")
    length_output = module(mechanism, "schema").OUTPUT == "length"  # a slider's position
    unit = lu if r["type"] == "path-generation" or length_output else au
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
    parts.append(_rows("Forces", table, digits, heads))
    return parts


def _compact(table: Table) -> None:
    """Fix each column at its longest cell or header word (headers wrap at words, cells
    never)."""
    for column in table.columns:
        words = str(column.header).split() or [""]
        column.width = max([cell_len(str(c)) for c in column.cells] + [cell_len(w) for w in words])


def _width(con: Console, table: Table) -> int:
    """The width the table takes when nothing limits it (rich's own measure)."""
    return Measurement.get(con, con.options.update_width(MAX_TABLE_WIDTH), table).maximum


def _emit(con: Console, group: Group) -> None:
    """Print a report part by part. A table never shows a truncated number: one wider than
    the console is laid out compactly (headers wrap at words, cells never), and if it still
    does not fit it is printed wider (a file or a pipe: one row per line, every digit) or,
    on a terminal, folds its cells onto a second line."""
    for part in group.renderables:
        if isinstance(part, Table):
            if _width(con, part) > con.width:
                _compact(part)
                need = _width(con, part)
                if need > con.width:
                    if con.is_terminal:
                        for column in part.columns:
                            column.width, column.overflow = None, "fold"
                    else:
                        width, con.width = con.width, need
                        con.print(part)
                        con.width = width
                        continue
        con.print(part)


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
