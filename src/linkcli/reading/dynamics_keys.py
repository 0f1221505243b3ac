"""[springs], [dampers] and [dynamics] (docs/dynamics.md), read and checked in one place for
every problem whose result is a linkage. Returns a `model.dynamics.Dynamics`; no numerics here.

    [springs]   name = { between = [end, end], stiffness = N/length, free_length, preload = N }
                name = { link = "output", stiffness = N m/rad, free_angle }       (torsional)
                name = { links = ["coupler", "output"], stiffness, free_angle }   (between links)
    [dampers]   name = { between = [end, end], coefficient = N s/length }  or  table = [[v, F], ...]
                name = { link = "output", coefficient = N m s/rad }  or  table = [[w, T], ...]
    [dynamics]  drive = { torque = N m } | { torque_speed = [[w, T], ...] }, start = { angle, speed },
                stop = { angle }, duration, steps, marks, friction, friction_speed, dead_point,
                method, flywheel_inertia, fluctuation, mean_speed, balance, counterweights

An end is a point of the linkage by name (a joint, or the coupler point P) or [x, y], an anchor
fixed to the ground (global frame, length unit). The names come from the mechanism's home
(`Schema.force_parts`): shared code never asks which mechanism it holds.
"""

from __future__ import annotations

import difflib
import math

from linkcli.io.reader import MAX_ARRAY, MISSING, Table

TABLES = ("springs", "dampers", "dynamics")
MAX_ELEMENTS = 100  # springs or dampers in one file
MAX_VALUE = 1e12  # N, N m, N/length, kg m^2: beyond, no linkage (as io.quantities.MAX_LOAD)
MAX_ANGLE = 1e6  # angle unit: start, stop, marks, free angles (a thousand turns and more)
MAX_SPEED = 1e9  # angle unit per s
MAX_DURATION = 1e6  # s
MAX_STEPS = 100_000  # output points
MAX_MARKS = 100
MAX_FRICTION = 1.0
DEFAULT_STEPS = 1000
DEFAULT_DURATION = 60.0  # s: the longest run with a stop angle and no duration
DEFAULT_FRICTION_SPEED = 1e-3  # rad/s
DEFAULT_DEAD_POINT = math.radians(1.0)
MAX_DEAD_POINT = math.radians(45.0)
METHODS = ("auto", "DOP853", "RK45", "Radau", "BDF", "LSODA")
DRIVE_KEYS = ("torque", "torque_speed")


def read_dynamics(root: Table, kind: str, has_linkage: bool, units, joints):
    """The file's Dynamics, or None without any of the three tables (or when they hold errors,
    recorded on the reader). `has_linkage`: the type's result is a linkage; `joints`: the
    [joints] specs (pin diameters for friction). The dynamics sections are reported when
    [dynamics] is given (there is no [report] sections name for them)."""
    present = [name for name in TABLES if name in root]
    if not present:
        return None
    masses_given = "masses" in root
    if not has_linkage:  # as [loads]: the types whose linkage takes loads and masses
        from linkcli.registry import NAMES, problem_type
        takers = ", ".join(n for n in NAMES if "forces" in problem_type(n).sections)
        for name in present:
            root.raw(name)
            root.error(name, f"a problem whose result is a linkage that takes [loads] and [masses] "
                       f"({takers}) for [{name}]", raw_got=f'type = "{kind}"')
        return None
    from linkcli.mechanisms import NAMES, schema_of
    from linkcli.mechanisms.schema import mechanism_of
    mechanism = mechanism_of(root)
    parts = schema_of(mechanism).force_parts(root, kind)
    if parts.refused is not None:
        for name in present:
            root.raw(name)
            root.error(name, f"{parts.refused} for [{name}]", raw_got=f'mechanism = "{mechanism}"')
        return None
    from linkcli.model.dynamics import Dynamics
    errors = len(root.reader.errors)
    lines = {}
    springs = _elements(root, "springs", parts, units, lines)
    dampers = _elements(root, "dampers", parts, units, lines)
    t = root.table("dynamics")
    if t is None:
        if "dynamics" not in root:
            for name in present:
                root.error(name, f"a [dynamics] table with start (the simulation [{name}] act in) or "
                           "fluctuation (a flywheel)", raw_got="no [dynamics]")
        return None
    lines["dynamics"] = root.reader.line_of(("dynamics",))
    if parts.drives:
        return _several(root, t, parts, units, lines, springs, dampers, masses_given, joints, errors)
    for key in ("start.angle", "stop.angle", "drive", "fluctuation", "mean_speed", "counterweights",
                "flywheel_inertia", "duration", "friction"):
        lines[key] = root.reader.line_of(("dynamics",) + tuple(key.split(".")))
    drive = _drive(t, units)
    start = _start(t, units)
    stop = _angle_in(t, "stop", units)
    duration = t.number("duration", None, positive=True, hi=MAX_DURATION, what="a time in s")
    steps = t.number("steps", DEFAULT_STEPS, integer=True, lo=2, hi=MAX_STEPS)
    marks = _marks(t, units)
    friction = t.number("friction", 0.0, nonnegative=True, hi=MAX_FRICTION,
                        what="a Coulomb friction coefficient")
    friction_speed = t.number("friction_speed", units.from_rad(DEFAULT_FRICTION_SPEED), positive=True,
                              hi=MAX_SPEED, what="a speed > 0 (angle unit/s)")
    dead_point = t.number("dead_point", units.from_rad(DEFAULT_DEAD_POINT), positive=True,
                          hi=units.from_rad(MAX_DEAD_POINT), what="an angle > 0 (angle unit)")
    method = t.string("method", "auto", choices=METHODS)
    flywheel = t.number("flywheel_inertia", 0.0, nonnegative=True, hi=MAX_VALUE,
                        what="an inertia >= 0 (kg m^2)")
    fluctuation = t.number("fluctuation", None, lo=0.0, hi=1.0,
                           what="a coefficient of speed fluctuation strictly between 0 and 1")
    if fluctuation is not None and not 0.0 < fluctuation < 1.0:
        t.error("fluctuation", "a coefficient of speed fluctuation strictly between 0 and 1", fluctuation)
        fluctuation = None
    mean_speed = _nonzero_speed(t, "mean_speed", units)
    balance = t.boolean("balance", False)
    counterweights, radii = _counterweights(t, parts, mechanism, NAMES, root, kind)
    diameters = _diameters(t, friction, parts, joints)
    if start is None and "start" not in t and fluctuation is None and "fluctuation" not in t \
            and not balance and not counterweights and "balance" not in t and "counterweights" not in t:
        t.error(None, "start = { angle, speed } (a simulation), fluctuation (a flywheel), balance or "
                "counterweights", raw_got="none of them")
    if start is not None:
        if stop is None and duration is None and "stop" not in t and "duration" not in t:
            t.error("duration", "a time in s, or stop = { angle } (when the simulation ends)")
        if stop is not None and stop == start[0]:
            t.error("stop", "a stop angle other than the start angle",
                    raw_got=f"angle = {units.from_rad(stop):g}, the start's")
        if not masses_given and not flywheel:
            t.error("start", "a [masses] table or flywheel_inertia (the simulation needs inertia)",
                    raw_got="neither")
    elif "start" not in t:
        for key in ("stop", "duration", "marks"):
            if key in t:
                t.error(key, "start = { angle, speed } with it (the simulation it belongs to)",
                        raw_got=f"{key} without start")
    if fluctuation is not None and drive is not None and drive.kind != "motor" and mean_speed is None \
            and "mean_speed" not in t:
        t.error("fluctuation", "a torque_speed drive or mean_speed with it (the speed the flywheel "
                "is sized at)", raw_got="neither")
    if mean_speed is not None and fluctuation is None and "fluctuation" not in t:
        t.error("mean_speed", "fluctuation with it (mean_speed sizes the flywheel)",
                raw_got="mean_speed without fluctuation")
    if (springs or dampers) and start is None and fluctuation is None and "start" not in t \
            and "fluctuation" not in t:
        name = "springs" if springs else "dampers"
        root.error(name, f"start or fluctuation in [dynamics] (where [{name}] act)", raw_got="neither")
    if len(root.reader.errors) > errors or None in (drive, steps, friction, friction_speed, dead_point,
                                                      method, flywheel, balance, diameters):
        return None
    if springs is None or dampers is None:
        return None
    if start is not None and stop is None and duration is None:
        return None
    return Dynamics(springs=springs, dampers=dampers, drive=drive, start=start, stop=stop,
                    duration=duration if duration is not None else (DEFAULT_DURATION if start else None),
                    steps=steps, marks=marks or (), friction=friction,
                    friction_speed=units.to_rad(friction_speed), pin_diameters=diameters,
                    dead_point=units.to_rad(dead_point), method=method, flywheel_inertia=flywheel,
                    fluctuation=fluctuation, mean_speed=mean_speed, balance=bool(balance or counterweights),
                    counterweights=bool(counterweights), counterweight_radii=radii, lines=lines)


# ---------------------------------------------------------------- several drives

ONE_DRIVE_KEYS = ("drive", "start", "stop", "marks", "flywheel_inertia")  # per drive with several
ONE_DRIVE_ONLY = ("fluctuation", "mean_speed", "balance", "counterweights")


def _several(root: Table, t: Table, parts, units, lines, springs, dampers, masses_given, joints, errors):
    """[dynamics] of a linkage of several drives (the five-bar's input and input2): one table per
    drive with its drive law, start, stop, marks and flywheel_inertia; duration, steps, friction,
    friction_speed, dead_point and method for the run. The flywheel (energy method) and
    balancing are one-drive analyses: refused here."""
    from linkcli.model.dynamics import DriveSetup, Dynamics
    names = parts.drives
    listed = ", ".join(names)
    for key in ONE_DRIVE_KEYS:
        if key in t:
            t.raw(key)
            t.error(key, f"{key} per drive, in [dynamics.{names[0]}] and [dynamics.{names[1]}] (a linkage "
                    f"of several drives: {listed})", raw_got=f"{key} in [dynamics]")
    for key in ONE_DRIVE_ONLY:
        if key in t:
            t.raw(key)
            what = "the flywheel (energy method)" if key in ("fluctuation", "mean_speed") else "balancing"
            t.error(key, f"a one-drive linkage for {key}: {what} is computed for one drive, and this "
                    f"linkage has several ({listed})", raw_got=f'{key} = {_said(t.data[key])}')
    known = set(names) | {"duration", "steps", "friction", "friction_speed", "dead_point", "method"} \
        | set(ONE_DRIVE_KEYS) | set(ONE_DRIVE_ONLY)
    for key in list(t.keys()):
        if key not in known:
            hint = difflib.get_close_matches(key, list(names), n=1, cutoff=0.5)
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            t.raw(key)
            t.error(key, f"a drive of the linkage ({listed}){extra} or a key of [dynamics] (duration, steps, "
                    "friction, friction_speed, dead_point, method)", raw_got=f'"{key}"')
    refused = any(key in t for key in ONE_DRIVE_KEYS + ONE_DRIVE_ONLY)
    misnamed = any(key not in known and isinstance(t.data[key], dict) for key in t.keys())
    setups = []
    for name in names:
        d = t.table(name)
        if d is None:
            if misnamed or (refused and not any(n in t for n in names)):  # one problem, one line
                setups.append(None)
                continue
            if name not in t:  # (a value that is not a table: Table.table said so)
                t.error(name, f"a table [dynamics.{name}] with start = {{ angle, speed }} (every drive of a "
                        "linkage of several starts somewhere)", raw_got=f"no [dynamics.{name}]")
            setups.append(None)
            continue
        for key in ("start.angle", "stop.angle", "drive", "flywheel_inertia"):
            lines[f"dynamics.{name}.{key}"] = root.reader.line_of(("dynamics", name) + tuple(key.split(".")))
        drive = _drive(d, units)
        start = _start(d, units)
        if start is None and "start" not in d:
            d.error("start", "the drive's start = { angle, speed } (angle unit, angle unit/s)")
        stop = _angle_in(d, "stop", units)
        if stop is not None and start is not None and stop == start[0]:
            d.error("stop", "a stop angle other than the start angle",
                    raw_got=f"angle = {units.from_rad(stop):g}, the start's")
        marks = _marks(d, units)
        flywheel = d.number("flywheel_inertia", 0.0, nonnegative=True, hi=MAX_VALUE,
                            what="an inertia >= 0 (kg m^2)")
        locked = d.boolean("locked", False)
        if locked:  # held at its start: no law, no speed, nothing of its own to stop or mark
            for key in ("drive", "stop", "marks", "flywheel_inertia"):
                if key in d:
                    d.error(key, f"no {key} on a locked drive (it is held at its start angle)",
                            raw_got=f"{key} with locked = true")
            if start is not None and start[1] != 0.0:
                d.error("start", "a speed of 0 for a locked drive (it is held at its start angle)",
                        raw_got=f"speed = {units.from_rad(start[1]):g}")
        if None in (drive, start, marks, flywheel, locked) or ("stop" in d and stop is None):
            setups.append(None)
            continue
        setups.append(DriveSetup(name, drive, start, stop, marks, flywheel, bool(locked)))
    duration = t.number("duration", None, positive=True, hi=MAX_DURATION, what="a time in s")
    steps = t.number("steps", DEFAULT_STEPS, integer=True, lo=2, hi=MAX_STEPS)
    friction = t.number("friction", 0.0, nonnegative=True, hi=MAX_FRICTION,
                        what="a Coulomb friction coefficient")
    friction_speed = t.number("friction_speed", units.from_rad(DEFAULT_FRICTION_SPEED), positive=True,
                              hi=MAX_SPEED, what="a speed > 0 (angle unit/s)")
    dead_point = t.number("dead_point", units.from_rad(DEFAULT_DEAD_POINT), positive=True,
                          hi=units.from_rad(MAX_DEAD_POINT), what="an angle > 0 (angle unit)")
    method = t.string("method", "auto", choices=METHODS)
    diameters = _diameters(t, friction, parts, joints)
    given = [s for s in setups if s is not None]
    if given and len(given) == len(setups) and all(s.locked for s in given):
        t.error(None, "at least one drive that is not locked (a linkage with every drive held does "
                "not move)", raw_got="every drive locked")
    if duration is None and "duration" not in t and None not in setups \
            and not any(s.stop is not None for s in given):
        t.error("duration", "a time in s, or a drive's stop = { angle } (when the simulation ends)")
    if not masses_given and None not in setups and not any(s.flywheel_inertia for s in given):
        t.error(None, "a [masses] table or a drive's flywheel_inertia (the simulation needs inertia)",
                raw_got="neither")
    if len(root.reader.errors) > errors or None in setups or None in (
            steps, friction, friction_speed, dead_point, method, diameters, springs, dampers):
        return None
    return Dynamics(springs=springs, dampers=dampers, duration=duration if duration is not None else DEFAULT_DURATION,
                    steps=steps, friction=friction, friction_speed=units.to_rad(friction_speed),
                    pin_diameters=diameters, dead_point=units.to_rad(dead_point), method=method,
                    drives=tuple(setups), lines=lines)


def _said(value) -> str:
    return "true" if value is True else "false" if value is False else repr(value)


# ---------------------------------------------------------------- [springs], [dampers]

def _elements(root: Table, name: str, parts, units, lines: dict):
    """Every entry of [springs] or [dampers], in file order; () without the table, None when in
    error."""
    t = root.table(name)
    if t is None:
        return None if name in root else ()
    keys = list(t.keys())
    if len(keys) > MAX_ELEMENTS:
        t.error(None, f"at most {MAX_ELEMENTS} {name}", raw_got=f"{len(keys)} {name}")
        return None
    example = ('{ between = ["A0", "B"], stiffness = 2, free_length = 40 }' if name == "springs"
               else '{ link = "output", coefficient = 0.5 }')
    out, ok = [], True
    for key in keys:
        entry = t.table(key)
        if entry is None:
            t.error(key, f"an inline table of the {name[:-1]}'s keys, e.g. {example}", t.raw(key))
            ok = False
            continue
        lines[f"{name}.{key}"] = root.reader.line_of((name, key))
        element = _spring(entry, key, parts, units) if name == "springs" else _damper(entry, key, parts, units)
        if element is None:
            ok = False
        else:
            out.append(element)
    return tuple(out) if ok else None


def _where(t: Table, name: str, parts, units):
    """(kind, ends, links) of an element: `between` (linear), `link` or `links` (torsional or
    rotary); None when in error."""
    from linkcli.model.dynamics import LINEAR, TORSIONAL
    given = [k for k in ("between", "link", "links") if k in t]
    if len(given) != 1:
        t.error(None, 'one of between = [end, end] (linear), link = "name" or links = ["a", "b"] '
                "(torsional)", raw_got="none" if not given else " and ".join(given))
        for key in given:
            t.raw(key)
        return None
    key = given[0]
    if key == "between":
        ends = _ends(t, parts)
        return None if ends is None else (LINEAR, ends, ())
    if key == "link":
        link = _link(t, "link", t.raw("link"), parts)
        return None if link is None else (TORSIONAL, None, (link,))
    value = t.raw("links")
    if not (isinstance(value, list) and len(value) == 2):
        t.error("links", 'two link names ["first", "second"]', value)
        return None
    links = [_link(t, "links", v, parts) for v in value]
    if None in links:
        return None
    if links[0] == links[1]:
        t.error("links", "two different links", value)
        return None
    return TORSIONAL, None, tuple(links)


def _link(t: Table, key: str, value, parts):
    choices = ("ground",) + tuple(parts.links)
    if not isinstance(value, str) or value not in choices:
        hint = difflib.get_close_matches(value, choices, n=1, cutoff=0.5) if isinstance(value, str) else []
        extra = f' (did you mean "{hint[0]}"?)' if hint else ""
        t.error(key, f"a link that turns: one of {', '.join(parts.links)}{extra}", value)
        return None
    if value == "ground" and key == "link":
        t.error(key, f"a link that turns: one of {', '.join(parts.links)}", value)
        return None
    return value


def _ends(t: Table, parts):
    """`between`: two ends, each a point name or a ground anchor [x, y], on two different
    links."""
    from linkcli.io.bounds import MAX_LENGTH
    from linkcli.model.dynamics import End
    value = t.raw("between")
    expected = 'two ends ["A", "B"]: point names or ground anchors [x, y]'
    if not (isinstance(value, list) and len(value) == 2):
        t.error("between", expected, value)
        return None
    ends, carried = [], []
    for item in value:
        if isinstance(item, str):
            if item not in parts.points:
                hint = difflib.get_close_matches(item, list(parts.points), n=1, cutoff=0.5)
                extra = f' (did you mean "{hint[0]}"?)' if hint else ""
                t.error("between", f"points of the linkage: {', '.join(parts.points)}{extra}, or [x, y]",
                        raw_got=f'"{item}"')
                return None
            ends.append(End(point=item))
            carried.append(set(parts.points[item]))
        elif (isinstance(item, list) and len(item) == 2
              and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in item)
              and all(abs(float(v)) <= MAX_LENGTH for v in item)):
            ends.append(End(at=(float(item[0]), float(item[1]))))
            carried.append({"ground"})
        else:
            t.error("between", expected, value)
            return None
    common = carried[0] & carried[1]
    if common:
        link = sorted(common)[0]
        def said(end):
            return f'"{end.point}"' if end.point else f"[{end.at[0]:g}, {end.at[1]:g}]"
        t.error("between", "ends on two different links (an element between points of one link "
                "never stretches)", raw_got=f"{said(ends[0])} and {said(ends[1])}, both on {link}")
        return None
    return tuple(ends)


def _spring(t: Table, name: str, parts, units):
    from linkcli.io.bounds import MAX_LENGTH
    from linkcli.model.dynamics import LINEAR, Spring
    where = _where(t, name, parts, units)
    if where is None:  # its numbers are still checked, as a linear spring's when it has `between`
        where = (LINEAR if "between" in t else "torsional", None, ())
        t.allow("free_length", "free_angle", "preload")
    kind, ends, links = where
    linear = kind == LINEAR
    stiffness = t.number("stiffness", positive=True, hi=MAX_VALUE,
                         what="a stiffness > 0 (N per length unit)" if linear else "a stiffness > 0 (N m per rad)")
    if linear:
        free = t.number("free_length", nonnegative=True, hi=MAX_LENGTH, what="a length >= 0 (length unit)")
        preload = t.number("preload", 0.0, lo=-MAX_VALUE, hi=MAX_VALUE, what="a force (N, tension +)")
        _refuse(t, "free_angle", "free_length (a linear spring)")
    else:
        free = t.number("free_angle", lo=-MAX_ANGLE, hi=MAX_ANGLE, what="an angle (angle unit)")
        free = None if free is None else units.to_rad(free)
        preload = 0.0
        _refuse(t, "free_length", "free_angle (a torsional spring)")
        _refuse(t, "preload", "no preload on a torsional spring (its free_angle sets it)")
    if None in (stiffness, free, preload) or (ends is None and not links):
        return None
    return Spring(name=name, kind=kind, stiffness=stiffness, free=free, ends=ends, links=links,
                  preload=preload)


def _damper(t: Table, name: str, parts, units):
    from linkcli.model.dynamics import LINEAR, Damper
    where = _where(t, name, parts, units)
    failed = where is None
    if failed:  # its numbers are still checked
        where = (LINEAR if "between" in t else "torsional", None, ())
    kind, ends, links = where
    linear = kind == LINEAR
    if ("coefficient" in t) == ("table" in t):
        t.error(None, "one of coefficient or table", raw_got="both" if "coefficient" in t else "neither")
        t.allow("coefficient", "table")
        return None
    if "coefficient" in t:
        c = t.number("coefficient", positive=True, hi=MAX_VALUE,
                     what="a damping coefficient > 0 (N s per length unit)" if linear
                     else "a damping coefficient > 0 (N m s per rad)")
        return None if c is None or failed else Damper(name=name, kind=kind, coefficient=c, ends=ends,
                                                       links=links)
    rows = _table(t, "table", f"a table [[speed, force], ...] of 2 to {MAX_ARRAY} rows ("
                  + ("length unit/s, N)" if linear else "angle unit/s, N m)"))
    if rows is None:
        return None
    scale = 1.0 if linear else units.to_rad(1.0)
    rows = [(v * scale, f) for v, f in rows]
    problem = _damper_table_problem(rows)
    if problem is not None:
        t.error("table", "speeds strictly increasing and forces rising with speed, each of its speed's "
                "sign (a damper takes energy: no force at rest)", raw_got=problem)
        return None
    return None if failed else Damper(name=name, kind=kind, table=tuple(rows), ends=ends, links=links)


def _damper_table_problem(rows) -> str | None:
    for (v0, f0), (v1, f1) in zip(rows, rows[1:]):
        if not v1 > v0:
            return f"speed {v1:g} after {v0:g}"
        if f1 < f0:
            return f"force {f1:g} after {f0:g}"
    for v, f in rows:
        if f * v < 0 or (v == 0 and f != 0):
            return f"force {f:g} at speed {v:g}"
    return None


def _refuse(t: Table, key: str, instead: str) -> None:
    if key in t:
        t.raw(key)
        t.error(key, instead, raw_got=f"{key} = {t.data[key]!r}")


def _table(t: Table, key: str, expected: str, min_rows: int = 2):
    """An array of [a, b] rows of finite numbers within MAX_VALUE; None when bad."""
    value = t.raw(key)
    if value is MISSING:
        t.error(key, expected)
        return None
    ok = (isinstance(value, list) and min_rows <= len(value) <= MAX_ARRAY
          and all(isinstance(r, list) and len(r) == 2
                  and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in r)
                  and all(abs(float(v)) <= MAX_VALUE for v in r) for r in value))
    if not ok:
        t.error(key, expected, value)
        return None
    return [(float(a), float(b)) for a, b in value]


# ---------------------------------------------------------------- [dynamics]

def _drive(t: Table, units):
    from linkcli.model.dynamics import FREE, MOTOR, TORQUE, Drive
    d = t.table("drive")
    if d is None:
        return None if "drive" in t else Drive(FREE)
    given = [k for k in DRIVE_KEYS if k in d]
    if len(given) != 1:
        d.error(None, "one of torque = T (N m) or torque_speed = [[speed, torque], ...]",
                raw_got="both" if len(given) == 2 else "neither")
        d.allow(*DRIVE_KEYS)
        return None
    if given[0] == "torque":
        torque = d.number("torque", lo=-MAX_VALUE, hi=MAX_VALUE, what="a torque (N m, counter-clockwise +)")
        return None if torque is None else Drive(TORQUE, torque=torque)
    rows = _table(d, "torque_speed", f"a table [[speed, torque], ...] of 2 to {MAX_ARRAY} rows "
                  "(angle unit/s, N m)")
    if rows is None:
        return None
    for (w0, _), (w1, _) in zip(rows, rows[1:]):
        if not w1 > w0:
            d.error("torque_speed", "speeds strictly increasing (a torque-speed curve is monotonic in "
                    "speed)", raw_got=f"speed {w1:g} after {w0:g}")
            return None
    return Drive(MOTOR, curve=tuple((units.to_rad(w), tq) for w, tq in rows))


def _start(t: Table, units):
    s = t.table("start")
    if s is None:
        return None
    angle = s.number("angle", lo=-MAX_ANGLE, hi=MAX_ANGLE, what="the drive's angle (angle unit)")
    speed = s.number("speed", 0.0, lo=-MAX_SPEED, hi=MAX_SPEED, what="the drive's speed (angle unit/s)")
    if angle is None or speed is None:
        return None
    return units.to_rad(angle), units.to_rad(speed)


def _angle_in(t: Table, key: str, units):
    s = t.table(key)
    if s is None:
        return None
    angle = s.number("angle", lo=-MAX_ANGLE, hi=MAX_ANGLE, what="the drive's angle (angle unit)")
    return None if angle is None else units.to_rad(angle)


def _marks(t: Table, units):
    if "marks" not in t:
        return ()
    value = t.number_list("marks", max_len=MAX_MARKS, what="angles (angle unit)")
    if value is None:
        return None
    if any(abs(v) > MAX_ANGLE for v in value):
        t.error("marks", f"angles of magnitude at most {MAX_ANGLE:g}", t.raw("marks"))
        return None
    return tuple(units.to_rad(v) for v in value)


def _nonzero_speed(t: Table, key: str, units):
    value = t.number(key, None, lo=-MAX_SPEED, hi=MAX_SPEED, what="a non-zero speed (angle unit/s)")
    if value == 0.0:
        t.error(key, "a non-zero speed (angle unit/s)", value)
        return None
    return None if value is None else units.to_rad(value)


def _counterweights(t: Table, parts, mechanism, names, root, kind):
    """`counterweights`: true (at radii equal to the links' lengths) or a table of radii per link
    (length unit); only on a home with a balancing rule. (flag, radii)."""
    from linkcli.io.bounds import MAX_LENGTH
    from linkcli.mechanisms import schema_of
    value = t.raw("counterweights", False)
    if value is False:
        return False, ()
    allowed = parts.counterweighted
    if not allowed:
        having = [n for n in names if schema_of(n).force_parts(root, kind).counterweighted]
        t.error("counterweights", f"a linkage with a counterweight rule ({', '.join(having)}) for "
                "counterweights; balance = true gives the shaking force and moment of any linkage",
                raw_got=f'mechanism = "{mechanism}"')
        return None, ()
    if value is True:
        return True, ()
    if not isinstance(value, dict) or not value:
        t.error("counterweights", "true, false, or a table of radii { " + ", ".join(
            f"{k} = r" for k in allowed) + " } (length unit)", value)
        return None, ()
    sub = t.table("counterweights")
    radii = []
    for link in list(sub.keys()):
        if link not in allowed:
            hint = difflib.get_close_matches(link, allowed, n=1, cutoff=0.5)
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            sub.raw(link)
            sub.error(link, f"a link that takes a counterweight: {', '.join(allowed)}{extra}",
                      raw_got=f'"{link}"')
            return None, ()
        r = sub.number(link, positive=True, hi=MAX_LENGTH, what="a radius > 0 (length unit)")
        if r is None:
            return None, ()
        radii.append((link, r))
    return True, tuple(radii)


def _diameters(t: Table, friction, parts, joints):
    """Pin diameters (pin -> length unit) for friction: every pin of the linkage needs one."""
    if not friction:
        return ()
    sizes = {j.name: j.diameter for j in (joints or ()) if j.diameter is not None}
    missing = [p for p in parts.pins if p not in sizes]
    if missing:
        t.error("friction", f"a [joints] diameter for every pin with friction ({', '.join(parts.pins)}: "
                "the friction circle's radius)", raw_got=f"none for {', '.join(missing)}")
        return None
    return tuple((p, sizes[p]) for p in parts.pins)
