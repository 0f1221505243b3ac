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

    def like(self, rows) -> Elided:
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
         "transmission", "motion", "kinematics", "positions", "error", "solver", "notes", "forces", "loads", "masses", "strength")


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
        t.add_row(k, Text(fmt(v, digits)))  # a value is text, never rich markup ("[joints]" stays)
    return t


def _flat(row: dict, prefix: str = "") -> dict:
    """A row with nested objects flattened: {"links": {"crank": {"angle": 1}}} ->
    {"links crank angle": 1} (a drawn linkage's kinematics rows)."""
    out = {}
    for k, v in row.items():
        key = f"{prefix} {k}" if prefix else str(k)
        if isinstance(v, dict):
            out.update(_flat(v, key))
        else:
            out[key] = v
    return out


def _rows(title: str, rows: list[dict], digits: int, headers: dict | None = None,
          no_wrap: bool = False) -> Table:
    """A row table; a long one (more than MAX_ROWS, or Elided already) shows its first
    and last rows with a "..." row between and a caption saying how to get them all. Rows
    with nested objects (a drawn linkage's) are flattened, one column per leaf."""
    if not isinstance(rows, Elided) and len(rows) > MAX_ROWS:
        rows = Elided(rows[:HEAD_ROWS] + rows[-TAIL_ROWS:], len(rows), None)
    if any(isinstance(v, dict) for r in rows for v in r.values()):
        flat = [_flat(r) for r in rows]
        rows = rows.like(flat) if isinstance(rows, Elided) else flat
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
        t.add_row(*(Text(fmt(r.get(c), digits)) for c in cols))  # text, never rich markup
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
    err = lu if ("coupler point" in measure or "slider" in measure or "distance" in measure) else au  # a length error
    keys = ("nominal_error", "error_mean", "error_p95", "error_max", "allowed_error")
    out = {k: err for k in keys}
    out.update({"lengths": lu, "clearance": lu, "clearance_slider": lu, "largest_tolerance": lu, "sensitivity": f"{err}/{lu}",
                "lock_play": au})
    return out


def _type_tables(kind: str, name: str, section, digits: int, lu: str, au: str) -> list:
    """The tables a problem type lays out itself (`report_tables` of its sections.py);
    empty when the generic layout serves."""
    from linkcli.analysis.dynamics.layout import SECTIONS  # [dynamics]
    from linkcli.analysis.dynamics.layout import report_tables as dynamics_tables
    from linkcli.io.tables import KeyValues
    from linkcli.registry import PACKAGES, problem_type
    if name in SECTIONS:
        blocks = dynamics_tables(name, section, lu, au)
    elif kind not in PACKAGES:
        return []
    else:
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
    iu = _input_unit(r, lu, au)  # the leading drive's values: an angle, or a length for a sliding drive
    at_input = "at input" if iu == au else f"at input ({iu})"
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
        parts.append(_kv("Link lengths", _linkage_rows(r["linkage"], lu, au), digits))
    if "grashof" in r:
        parts.append(_class_table(r["grashof"], digits))
    if "transmission" in r and r["transmission"] and "input_at_min" not in r["transmission"]:  # over rows (a five-bar's)
        parts.extend(_generic("transmission", r["transmission"], digits, _angle_units(r["transmission"], au)))
    elif "transmission" in r and r["transmission"]:
        tr = r["transmission"]
        t = Table(title=f"Transmission angle ({au})", title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False, show_edge=False)
        for c in ("over", "min", at_input, "max", at_input):
            t.add_column(c, justify="right" if c != "over" else "left")
        t.add_row("input's range of motion", fmt(tr["min"], digits), fmt(tr["input_at_min"], digits),
                  fmt(tr["max"], digits), fmt(tr["input_at_max"], digits))
        if "working_min" in tr:
            t.add_row("working range (targets)", fmt(tr["working_min"], digits),
                      fmt(tr["working_input_at_min"], digits), fmt(tr["working_max"], digits),
                      fmt(tr["working_input_at_max"], digits))
        for joint, c in tr.get("closures", {}).items():  # a drawn linkage: every closure
            t.add_row(f"closure at {joint} ({', '.join(c['links'])})", fmt(c["min"], digits),
                      fmt(c["input_at_min"], digits), fmt(c["max"], digits), fmt(c["input_at_max"], digits))
        parts.append(t)
    if "motion" in r:
        units = _motion_units(lu, au)
        if iu != au:
            units["input_range"] = iu
        motion = r["motion"]
        flat = {k: v for k, v in motion.items() if not isinstance(v, (dict, list)) or k in units}
        parts.append(_kv("Motion", [(k.replace("_", " ") + (f" ({units[k]})" if k in units else ""), v)
                                    for k, v in flat.items()], digits))
        for k, v in motion.items():  # a drawn linkage's ranges per link, slider and drive
            if k in flat:
                continue
            table = [{"name": name, **inner} for name, inner in v.items()] if isinstance(v, dict) else v
            if table and all(isinstance(x, dict) for x in table):
                parts.append(_rows(f"Motion: {k.replace('_', ' ')}", table, digits))
    if "positions" in r:
        parts.append(_rows("Positions", r["positions"], digits, _position_heads(r, lu, au)))
    if "error" in r:
        parts.append(_kv("Error", [(k.replace("_", " "), v) for k, v in r["error"].items()], digits))
    if "kinematics" in r:
        heads = _kinematics_heads(r["kinematics"], lu, au)
        if iu != au:
            heads["input"] = f"input ({iu})"
        parts.append(_rows("Kinematics", r["kinematics"], digits, heads))
    if "loads" in r:
        units = {"coupler_force": "N", "output_torque": "N m", "output_force": "N", "gravity": "m/s2",
                 "torques": "N m", "forces": "N"}
        parts.append(_kv("Loads", [(f"{k.replace('_', ' ')} {name} ({units[k]})", x) for k, v in r["loads"].items()
                                   if isinstance(v, dict) for name, x in v.items()]
                         + [(f"{k.replace('_', ' ')} ({units[k]})", v) for k, v in r["loads"].items()
                            if not isinstance(v, dict)], digits))
    if "masses" in r:
        units = {"mass": "kg", "center": lu, "inertia": "kg m2"}
        parts.append(_kv("Masses", [(f"{link} {k} ({units[k]})", v) for link, props in r["masses"].items()
                                    for k, v in props.items()], digits))
    if "forces" in r:
        parts.extend(_forces(r["forces"], digits, au))
    if "strength" in r:
        parts.extend(_strength(r["strength"], digits, lu, au))
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


def _input_unit(r: dict, lu: str, au: str) -> str:
    """The unit of the leading drive's values (`input` columns, `input_range`): the length unit
    when a drawn linkage's first drive slides (motion.drives' `kind`), else the angle unit."""
    drives = r.get("motion", {}).get("drives") if isinstance(r.get("motion"), dict) else None
    first = next(iter(drives.values()), None) if isinstance(drives, dict) and drives else None
    return lu if isinstance(first, dict) and first.get("kind") == "slide" else au


def _kinematics_heads(rows: list[dict], lu: str, au: str) -> dict[str, str]:
    """Headings of the kinematics columns, with their units: what each mechanism's schema
    declares of its own columns (mechanisms.schema.Schema.kinematics_headings), in the order of
    mechanisms.NAMES (a report holds rows, not a linkage: any home's columns are known)."""
    from linkcli.mechanisms import NAMES, schema_of
    heads: dict[str, str] = {}
    for name in NAMES:
        heads.update(schema_of(name).kinematics_headings(rows, lu, au))
    return heads


def _linkage_rows(lk: dict, lu: str, au: str) -> list[tuple[str, object]]:
    """The linkage section in its own order: text as it is, numbers and coordinates in the
    length unit, `*_angle` keys in the angle unit."""
    rows = []
    for key, value in lk.items():
        if isinstance(value, dict):  # a designed drawing (a drawn linkage's): one row per entry
            rows += _drawing_rows(key, value, lu, au)
            continue
        label = key.replace("_", " ")
        if not isinstance(value, str):
            label += f" ({au})" if key.endswith("_angle") else f" ({lu})"
        rows.append((label, value))
    return rows


def _drawing_rows(key: str, entries: dict, lu: str, au: str) -> list[tuple[str, object]]:
    """A designed drawing's joints (`joint J (unit)`: its place, and ground, slider angle and
    guide where they apply), links (`link L`: its joints) and drive (`drive L`: its speed)."""
    rows = []
    for name, entry in entries.items():
        if key == "joints":
            what = ", ground" if entry.get("ground") else ""
            what += f", slider at {entry['slider']:.6g} {au}" if "slider" in entry else ""
            what += f" on {entry['guide']}" if "guide" in entry else ""
            rows.append((f"joint {name}{what} ({lu})", list(entry["at"])))
        elif key == "links":
            rows.append((f"link {name}", ", ".join(entry)))
        else:
            rows.append((f"{key} {name} ({au}/s)", entry.get("speed")))
    return rows


def _class_table(g: dict, digits: int) -> Table:
    """The class section as its mechanism lays it out (mechanisms.of_class_section), else key by key."""
    from linkcli.mechanisms import of_class_section
    schema = of_class_section(g)
    if schema is None:
        return _kv("Class", [(k.replace("_", " "), v) for k, v in g.items()], digits)
    title, rows = schema.class_block(g, lambda v: fmt(v, digits))
    return _kv(title, rows, digits)


def _motion_units(lu: str, au: str) -> dict[str, str]:
    """The unit of each Motion row that has one (time ratio, steps and yes/no have none): what
    each mechanism's schema declares (Schema.motion_units), in the order of mechanisms.NAMES."""
    from linkcli.mechanisms import NAMES, schema_of
    units: dict[str, str] = {}
    for name in NAMES:
        units.update(schema_of(name).motion_units(lu, au))
    return units


def _angle_units(section: dict, au: str) -> dict[str, str]:
    """Units of a transmission section over rows: its angles; row numbers and the condition
    number have none."""
    return {k: au for k, v in section.items()
            if isinstance(v, float) and not k.startswith("row") and not k.startswith("condition")}


def _position_heads(r: dict, lu: str, au: str) -> dict[str, str]:
    """Positions column headings with units: the input is an angle; target, achieved and
    error are points or slider positions (length) for path generation and a slider-crank,
    output angles for a four-bar's function, poses (x, y, angle) for motion generation,
    with a position error (length) and an angle error."""
    from linkcli.mechanisms import DEFAULT, schema_of
    mechanism = r.get("linkage", {}).get("mechanism", DEFAULT)
    length_output = schema_of(mechanism).output == "length" and r["type"] != "function-generation"
    # a slider's position (a function's output is an angle, whatever the mechanism)
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
    others = [k[:-len("_torque")] for k in forces if k.endswith("_torque") and k != "input_torque"]
    parts: list = []
    for drive in ["input"] + others:
        torque = forces[f"{drive}_torque"]
        rows = [("peak (N m)", torque["peak"]), (f"at input ({au})", torque["at_input"])]
        rows += [(f"at {k} ({au})", torque[f"at_{k}"]) for k in others if f"at_{k}" in torque]
        rows.append(("rms (N m)", torque["rms"]))
        if "dead_points" in forces and drive == ("input" if not others else others[-1]):
            rows.append(("dead points (rows left out)", forces["dead_points"]))
        parts.append(_kv("Input torque" if drive == "input" else f"{drive.capitalize()} torque", rows, digits))
    cycle = [{"pin": name, **{k: v for k, v in pin.items() if k not in ("x", "y")}}
             for name, pin in forces["pins"].items()]
    parts.append(_rows("Pin forces over the cycle (N, magnitude)", cycle, digits))
    heads = {"input": f"input ({au})", **{k: f"{k} ({au})" for k in others},
             "input_torque": "torque (N m)" if not others else "input torque (N m)",
             **{f"{k}_torque": f"{k} torque (N m)" for k in others}, "mechanical_advantage": "MA"}
    table = []
    for row in forces["rows"]:
        line = {"input": row["input"], **{k: row[k] for k in others}, "input_torque": row["input_torque"],
                **{f"{k}_torque": row[f"{k}_torque"] for k in others}}
        for name, pin in row["pins"].items():
            line[name] = pin["magnitude"]
            heads[name] = f"|{name}| (N)"
        if "mechanical_advantage" in row:
            line["mechanical_advantage"] = row["mechanical_advantage"]
        table.append(line)
    parts.append(_rows("Forces", _as_cut(table, [forces["rows"]] if isinstance(forces["rows"], Elided) else []),
                       digits, heads))
    return parts


def _strength(strength: dict, digits: int, lu: str, au: str) -> list:
    """The strength section: material and the weakest part, one row per pin and per link
    (factors, stresses in MPa), and the stresses over the cycle."""
    material = strength["material"]
    rows = [("material", material["name"])] if "name" in material else []
    rows += [(f"{k.replace('_', ' ')} (MPa)", material[k])
             for k in ("ultimate", "yield_strength", "endurance", "modulus")]
    rows += [("fatigue criterion", strength["criterion"]), ("required factor", strength["required"])]
    critical = strength.get("critical")
    if critical:
        rows += [("weakest part", critical["part"]), ("its factor", critical["factor"]),
                 ("failure mode", critical["mode"]), (f"at input ({au})", critical["at_input"])]
    if strength.get("unchecked"):
        rows.append(("not checked", ", ".join(strength["unchecked"])))
    parts: list = [_kv("Strength", rows, digits)]
    heads = {"diameter": f"d ({lu})", "width": f"w ({lu})", "force_max": "|F| max (N)",
             "force_min": "|F| min (N)", "shear_max": "tau max (MPa)",
             "bearing_max": "bearing (MPa)", "at_input": f"at input ({au})",
             "shear_alternating": "tau a (MPa)", "shear_mean": "tau m (MPa)",
             "static_factor": "static n", "bearing_factor": "bearing n",
             "fatigue_factor": "fatigue n", "factor": "n", "length": f"length ({lu})",
             "tension": "tension (N)", "tension_at": f"at ({au})", "compression": "compression (N)",
             "compression_at": f"at ({au})", "bending": "M max (N m)", "bending_at": f"at ({au})",
             "stress_max": "sigma max (MPa)", "alternating": "sigma a (MPa)", "mean": "sigma m (MPa)",
             "buckling_load": "P cr (N)", "buckling_factor": "buckling n"}
    if strength["pins"]:
        parts.append(_rows("Pins: shear and bearing", strength["pins"], digits, heads))
    if strength["links"]:
        parts.append(_rows("Links: axial, bending, buckling", strength["links"], digits, heads))
    table, cycle_heads = [], {"input": f"input ({au})"}
    for row in strength["rows"]:
        line = {"input": row["input"]}
        for name, value in row.get("pins", {}).items():
            line[f"pin {name}"] = value
            cycle_heads[f"pin {name}"] = f"tau {name} (MPa)"
        for name, value in row.get("links", {}).items():
            line[f"link {name}"] = value
            cycle_heads[f"link {name}"] = f"sigma {name} (MPa)"
        table.append(line)
    parts.append(_rows("Stress over the cycle (pin shear, link's largest fibre stress)", table,
                       digits, cycle_heads))
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


def _surely_fits(con: Console, table: Table) -> bool:
    """True when the table cannot be wider than the console, by a bound that costs a pass
    over the cells' text: each column at most its longest header or cell plus both its
    paddings, plus a rule or edge between and around the columns, and the table's own
    min_width. rich's measure (_width) is never more than that (markup and emoji codes
    only shorten a cell), so a False from here only means "measure it": the result of
    print_table is the same, and the common case skips a measure of every cell
    (tests/cli/test_table_width_bound.py holds the bound against rich's measure)."""
    if table.width is not None or not table.columns:
        return False
    _, right, _, left = table.padding
    pad = left + right
    total = len(table.columns) + 2  # rules between columns, the two edges (box or not)
    for column in table.columns:
        texts = [column.header] + list(column.cells)
        if not column.cells or not all(isinstance(t, (str, Text)) for t in texts):
            return False  # an empty column is measured as wide as allowed; other renderables vary
        plain = [t if isinstance(t, str) else t.plain for t in texts]
        if any("\t" in p or "\n" in p for p in plain):
            return False
        widest = column.width if column.width is not None else max(cell_len(p) for p in plain)
        total += max(widest, column.min_width or 0) + pad
    return max(total, table.min_width or 0) <= con.width


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
    if (isinstance(part, Table) and not getattr(part, "is_head", False) and not _surely_fits(con, part)
            and _width(con, part) > con.width):
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
