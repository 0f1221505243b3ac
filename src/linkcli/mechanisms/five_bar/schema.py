"""The five-bar's `[linkage]` and `[motion]` keys (docs/format.md, docs/five_bar.md). Pure
Python (`check` reads it without numpy).

    [linkage]  ground, input, input2, coupler, coupler2 (lengths), branch ("left" |
               "right"), ground_pivot [x, y], ground_angle
    [motion]   inputs = [[phi1, phi2], ...] (angle unit)  or  path = [[x, y], ...] with
               modes = ["+" | "-", "+" | "-"]; input_speeds = [w1, w2] (angle unit per s,
               default [1, 1]); input_accelerations = [a1, a2] (angle unit per s^2,
               default [0, 0]);
    [[motion.phases]]  rows = [first, last] (0-based, inclusive), locked = "input" | "input2"
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from linkcli.io.bounds import ASSEMBLY_RTOL, MAX_LENGTH, bounded_length, bounded_point, refuse_ratio
from linkcli.io.reader import MAX_ARRAY, MISSING, Table, describe
from linkcli.mechanisms.schema import ForceParts, Schema

if TYPE_CHECKING:  # names of annotations only (imported where they are used)
    from linkcli.mechanisms.five_bar.model import FiveBar, Phase

# .model (its dataclasses) is imported inside the functions that build them: every other
# mechanism's [linkage] reads this module for its keys alone (reading.linkage.refuse_foreign)

TOLERANCED = ("ground", "input", "input2", "coupler", "coupler2")  # its lengths, [tolerance] table keys
LINKS = ("input", "input2", "coupler", "coupler2")  # its moving links: [masses], [sections], torques
CARRIED = {"A0": ("ground", "input"), "A": ("input", "coupler"), "P": ("coupler", "coupler2"),
           "B": ("input2", "coupler2"), "B0": ("ground", "input2")}  # each pin -> the bodies it joins
DRIVE_NAMES = ("input", "input2")  # its drives, as [motion] and [dynamics] name them (model.DRIVES)
FOREIGN_LOADS = {"output_torque": "a four-bar's", "output_force": "a slider-crank's",
                 "forces": "a drawn linkage's"}  # [loads] keys of other homes
MOTION_KEYS = ("inputs", "path", "modes", "input_speeds", "input_accelerations", "phases")
MAX_ROWS = MAX_ARRAY
MIN_PATH = 2  # points of a path
ROW_ELEMENTS = 2**23  # tolerance samples x rows: per-row statistics keep every sample's error
TURN_RTOL = 1e-9  # a held drive's angle: equal within this share of a turn


class FiveBarSchema(Schema):
    """The five-bar's vocabulary (mechanisms.schema.Schema): its output is the point P (an
    allowed_error is a distance); a held drive's lock has a play of its own; its loads name its
    links (a torque on any of them) and its one point load acts at P; its [motion] is rows of
    both drives, and its [dynamics] names each drive."""

    name = "five-bar"
    keys = ("ground", "input", "input2", "coupler", "coupler2", "branch", "ground_pivot", "ground_angle")
    joints = ("A0", "A", "P", "B", "B0")
    links = LINKS
    toleranced = TOLERANCED
    plays = {"lock_play": "the angular play of a held drive's lock, taken up when its phase ends"}
    output = "length"
    reported_motion = ("rows", "input_range", "input2_range", "x_range", "y_range")
    class_keys = ("class", "shortest", "longest", "two_shortest_plus_longest", "other_two", "phases")

    def read(self, t: Table, units) -> FiveBar | None:
        return _read(t, units)

    def read_motion(self, root: Table, meta, linkage: FiveBar | None):
        return _read_motion(root, meta, linkage)

    def read_load_case(self, root: Table, kind: str):
        """[loads] (coupler_force at P, gravity, torques by link) and [masses] (input, input2,
        coupler, coupler2) of a five-bar: a model.LoadCase, or None when in error (recorded)."""
        return _read_load_case(root)

    def class_block(self, g: dict, fmt) -> tuple[str, list[tuple[str, object]]]:
        """("Five-bar class", rows): Ting's class, the two shortest and the longest link, the two
        sums, then each phase's four-bar class (its ground: driven pivot to held elbow)."""
        sl, pq = g["two_shortest_plus_longest"], g["other_two"]
        rel = "vs" if sl is None or pq is None else "<" if sl < pq else ("=" if sl == pq else ">")
        rows = [("class", g["class"]), ("shortest", " and ".join(g["shortest"])), ("longest", g["longest"]),
                ("s1 + s2 + l vs p + q", f"{fmt(sl)} {rel} {fmt(pq)}")]
        for ph in g["phases"]:
            first, last = ph["rows"]
            rows.append((f"phase rows {first}..{last} ({ph['locked']} held)",
                         f"four-bar {ph['class']}, {ph['branch']}, ground {fmt(ph['ground'])}"))
        return "Five-bar class (Ting)", rows

    def kinematics_headings(self, rows, length, angle) -> dict[str, str]:
        return {"input": f"input ({angle})", "input2": f"input2 ({angle})", "point": f"P ({length})",
                "dpoint_dinput": f"dP/d input ({length}/{angle})", "dpoint_dinput2": f"dP/d input2 ({length}/{angle})",
                "velocity": f"v P ({length}/s)", "acceleration": f"a P ({length}/s2)", "transmission": f"mu ({angle})",
                "transmission_left": f"mu A ({angle})", "transmission_right": f"mu B ({angle})",
                "margin": f"margin ({angle})"}

    def motion_units(self, length, angle) -> dict[str, str]:
        return {"input_range": angle, "input2_range": angle, "x_range": length, "y_range": length,
                "input_speeds": f"{angle}/s", "input_accelerations": f"{angle}/s2"}

    def force_parts(self, root: Table, kind: str) -> ForceParts:
        """Joints A0, A, P, B, B0; links input, input2, coupler, coupler2; pins A0, A, P, B, B0;
        two drives, input and input2 (each a crank's angle: [dynamics.input], [dynamics.input2]);
        no counterweight rule."""
        return ForceParts(points=dict(CARRIED), links=LINKS, pins=tuple(CARRIED), drives=DRIVE_NAMES)


def _read(t: Table, units) -> FiveBar | None:
    """[linkage] of a five-bar: five lengths, an optional branch (without one: "left" for
    inputs, the path's own for a path), the global placement. It must assemble somewhere:
    |A B| ranges over [max(0, ground - input - input2, |input - input2| - ground), ground +
    input + input2] and must overlap [|coupler - coupler2|, coupler + coupler2] over more
    than one value."""
    from linkcli.mechanisms.five_bar.model import SIDES, FiveBar
    lengths = {k: bounded_length(t, k) for k in TOLERANCED}
    branch = t.string("branch", None, choices=SIDES)
    gp = bounded_point(t, "ground_pivot", [0.0, 0.0])
    ga = t.number("ground_angle", 0.0, lo=-MAX_LENGTH, hi=MAX_LENGTH)
    if None in lengths.values() or ("branch" in t and branch is None) or gp is None or ga is None:
        return None
    if refuse_ratio(t, lengths):
        return None
    d, a1, a2, b1, b2 = (lengths[k] for k in TOLERANCED)
    lo, hi = max(0.0, d - a1 - a2, abs(a1 - a2) - d), d + a1 + a2
    reach_lo, reach_hi = abs(b1 - b2), b1 + b2
    gap = min(hi, reach_hi) - max(lo, reach_lo)
    if gap <= ASSEMBLY_RTOL * reach_hi:
        touch = ", which touch at one position only (a structure)" if gap > -ASSEMBLY_RTOL * reach_hi else ""
        t.error(max(lengths, key=lengths.get), "a five-bar that assembles over a range of inputs (|A B|, "
                "from max(0, ground - input - input2, |input - input2| - ground) to ground + input + "
                "input2, meeting |coupler - coupler2| .. coupler + coupler2)",
                raw_got=f"|A B| in [{lo:g}, {hi:g}] and the distal links spanning [{reach_lo:g}, {reach_hi:g}]{touch}")
        return None
    return FiveBar(branch=branch, ground_pivot=tuple(gp), ground_angle=units.to_rad(ga), **lengths)


def pairs(t: Table, key: str, what: str, min_len: int, limit: float):
    """[[p, q], ...]: min_len .. MAX_ROWS pairs of finite numbers of magnitude <= limit; None
    when missing or bad (one located error)."""
    value = t.raw(key)
    want = f"an array of {min_len} to {MAX_ROWS} {what}"
    if value is MISSING or not isinstance(value, list) or not min_len <= len(value) <= MAX_ROWS:
        t.error(key, want, value)
        return None
    out = []
    for i, item in enumerate(value):
        ok = (isinstance(item, list) and len(item) == 2
              and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in item))
        if ok and all(math.isfinite(v) and abs(v) <= limit for v in item):
            out.append((float(item[0]), float(item[1])))
            continue
        got = ("[" + ", ".join(describe(v) for v in item) + "]"
               if isinstance(item, list) and 0 < len(item) <= 4 else describe(item))
        t.error(f"{key}[{i}]", f"a pair of two finite numbers (at most {limit:g} in magnitude)", raw_got=got)
        return None
    return out


def _modes(t: Table, has_path: bool):
    """modes = ["+"|"-", "+"|"-"] with a path (default ["+", "-"]); refused with inputs."""
    from linkcli.mechanisms.five_bar.model import DEFAULT_MODES, MODES
    if "modes" not in t:
        return DEFAULT_MODES
    value = t.raw("modes")
    if not has_path:
        t.error("modes", 'no modes with inputs (the drive angles decide the elbows; modes choose them for '
                "a path)", raw_got=f"modes = {describe(value)}")
        return None
    if (not isinstance(value, list) or len(value) != 2
            or not all(isinstance(v, str) and v in MODES for v in value)):
        shown = ("[" + ", ".join(describe(v) for v in value) + "]" if isinstance(value, list) and len(value) <= 4
                 else describe(value))
        t.error("modes", 'each chain\'s working mode, two of "+" and "-" (the left chain\'s first): ["+", "-"]',
                raw_got=shown)
        return None
    return (value[0], value[1])


def _rates(t: Table, key: str, default: list[float], unit: str, units):
    """[r1, r2] in the angle unit per s (or s^2), finite: radians out."""
    value = t.number_list(key, default, length=2, what=f"numbers [input, input2] ({unit})")
    if value is None:
        return None
    if max(abs(v) for v in value) > MAX_LENGTH:
        t.error(key, f"numbers of magnitude at most {MAX_LENGTH:g}", raw_got=str(value))
        return None
    return (units.to_rad(value[0]), units.to_rad(value[1]))


def _phases(t: Table, rows: int | None) -> tuple[Phase, ...] | None:
    """[[motion.phases]]: each { rows = [first, last], locked = "input" | "input2" }, within
    the rows, not overlapping; in row order."""
    from linkcli.mechanisms.five_bar.model import DRIVES, Phase
    value = t.raw("phases")
    if value is MISSING:
        return ()
    if not isinstance(value, list) or not all(isinstance(v, dict) for v in value) or len(value) > MAX_ROWS:
        t.error("phases", "an array of tables [[motion.phases]], each { rows = [first, last], locked = "
                '"input" or "input2" }', value)
        return None
    out, bad = [], False
    for i, item in enumerate(value):
        sub = Table(t.reader, t.path + (f"phases[{i}]",), item)
        span = sub.number_list("rows", length=2, what="row numbers [first, last]")
        locked = sub.string("locked", choices=DRIVES)
        if span is not None and not all(float(v).is_integer() for v in span):
            sub.error("rows", "whole row numbers [first, last]", raw_got=str(span))
            span = None
        if span is not None and rows is not None and not 0 <= span[0] <= span[1] <= rows - 1:
            sub.error("rows", f"rows [first, last] with 0 <= first <= last <= {rows - 1} (the {rows} rows of "
                      "[motion], numbered from 0)", raw_got=f"[{span[0]:g}, {span[1]:g}]")
            span = None
        if span is None or locked is None:
            bad = True
            continue
        out.append((Phase(int(span[0]), int(span[1]), locked), i))
    if bad:
        return None
    out.sort(key=lambda p: p[0].first)
    for (a, _), (b, j) in zip(out, out[1:]):
        if b.first <= a.last:
            t.error(f"phases[{j}]", "phases that do not overlap (one drive held at a time)",
                    raw_got=f"rows [{b.first}, {b.last}] and [{a.first}, {a.last}]")
            return None
    return tuple(p for p, _ in out)


def _held(t: Table, inputs, phases, units) -> bool:
    """Forward rows hold a phase's locked drive at its first row's angle (within TURN_RTOL
    of a turn): else one located error, False."""
    from linkcli.mechanisms.five_bar.model import DRIVES
    turn = units.from_rad(2.0 * math.pi)
    for ph in phases:
        k = DRIVES.index(ph.locked)
        held = inputs[ph.first][k]
        for r in range(ph.first + 1, ph.last + 1):
            gap = abs(inputs[r][k] - held) % turn
            if min(gap, turn - gap) > TURN_RTOL * turn:
                t.error(f"inputs[{r}]", f"{ph.locked} held at {held:g} {units.angle} over the phase of rows "
                        f"{ph.first}..{ph.last} (locked = \"{ph.locked}\")",
                        raw_got=f"{ph.locked} = {inputs[r][k]:g} {units.angle} at row {r}")
                return False
    return True


def _read_motion(root: Table, meta, linkage: FiveBar | None):
    """[motion] of a five-bar (module docstring): (the linkage with its motion, the left
    drive's speed rad/s, the rows) or None (errors recorded)."""
    from linkcli.mechanisms.five_bar.model import FiveBarMotion
    units = meta.units
    t = root.table("motion")
    if t is None:
        if "motion" not in root:
            root.error("motion", "a [motion] table with inputs = [[phi1, phi2], ...] or path = [[x, y], ...] "
                       "(the rows the five-bar goes through)")
        return None
    has_inputs, has_path = "inputs" in t, "path" in t
    inputs = path = None
    if has_inputs and has_path:
        t.raw("inputs")
        t.raw("path")
        t.error("path", "either inputs (forward kinematics) or path (inverse kinematics), not both",
                raw_got="both")
    elif has_inputs:
        inputs = pairs(t, "inputs", "drive angles [input, input2] (angle unit)", 1, MAX_LENGTH)
    elif has_path:
        path = pairs(t, "path", "points [x, y] of P (length unit)", MIN_PATH, MAX_LENGTH)
    else:
        t.error("inputs", "inputs = [[phi1, phi2], ...] (drive angles) or path = [[x, y], ...] (points of P)")
    modes = _modes(t, has_path)
    speeds = _rates(t, "input_speeds", [1.0, 1.0], f"{units.angle}/s", units)
    accelerations = _rates(t, "input_accelerations", [0.0, 0.0], f"{units.angle}/s^2", units)
    rows = len(inputs) if inputs is not None else (len(path) if path is not None else None)
    phases = _phases(t, rows)
    if inputs is not None and phases and not _held(t, inputs, phases, units):
        return None
    if None in (modes, speeds, accelerations, phases) or (inputs is None and path is None):
        return None
    tol = meta.tolerance
    if tol is not None and tol.samples * rows > ROW_ELEMENTS:
        root.reader.error(("tolerance", "samples"), f"at most {ROW_ELEMENTS // rows} samples with {rows} rows "
                          f"(samples x rows <= {ROW_ELEMENTS}: the per-row statistics keep every sample's "
                          "error at every row)", tol.samples)
        return None
    if linkage is None:
        return None
    motion = FiveBarMotion(
        inputs=None if inputs is None else tuple((units.to_rad(a), units.to_rad(b)) for a, b in inputs),
        path=None if path is None else tuple(path), modes=modes, speeds=speeds,
        accelerations=accelerations, phases=phases)
    branch = linkage.branch if linkage.branch is not None or path is not None else "left"
    from dataclasses import replace
    return replace(linkage, branch=branch, motion=motion), speeds[0], rows


SCHEMA = FiveBarSchema()


def _read_load_case(root: Table):
    """[loads] and [masses] of a five-bar (docs/five_bar.md, Loads):

        [loads]   coupler_force = [Fx, Fy]   N at P (on the coupler, the left distal link)
                  gravity = [gx, gy]         m/s^2
                  torques = { input2 = T }   N m on a link, counter-clockwise positive
        [masses]  input, input2, coupler, coupler2 = { mass, center, inertia } (each link's
                  frame: input A0 -> A, input2 B0 -> B, coupler A -> P, coupler2 B -> P)

    Keys of another home's [loads] are named as such; a link that is not the five-bar's gets a
    "did you mean"."""
    import difflib

    from linkcli.io.quantities import MAX_LOAD, link_mass, pair
    from linkcli.model import LoadCase, Loads, Masses
    errors = len(root.reader.errors)
    given: dict = {}
    loads = Loads()
    t = root.table("loads")
    if t is not None:
        force = pair(t, "coupler_force", "a force [Fx, Fy] of two finite numbers (N, at P)")
        gravity = pair(t, "gravity", "an acceleration [gx, gy] of two finite numbers (m/s^2)")
        for key, whose in FOREIGN_LOADS.items():
            if key in t:
                t.raw(key)
                t.error(key, "torques = { link = T } (N m on input, input2, coupler or coupler2) and "
                        f"coupler_force (N at P) on a five-bar; {key} is {whose}",
                        raw_got=f"{key} = {describe(t.data[key])}")
        torques = {}
        sub = t.table("torques")
        if sub is not None:
            for name in list(sub.keys()):
                if name not in LINKS:
                    hint = difflib.get_close_matches(name, LINKS, n=1, cutoff=0.5)
                    extra = f' (did you mean "{hint[0]}"?)' if hint else ""
                    sub.raw(name)
                    sub.error(name, f"a link of the five-bar: {', '.join(LINKS)}{extra}", raw_got=f'"{name}"')
                    continue
                value = sub.number(name, lo=-MAX_LOAD, hi=MAX_LOAD, what="a torque (N m, counter-clockwise positive)")
                if value is not None:
                    torques[name] = value
        loads = Loads(coupler_force=tuple(force or (0.0, 0.0)), gravity=tuple(gravity or (0.0, 0.0)),
                      torques=tuple(torques.items()))
        given["loads"] = {"coupler_force": list(loads.coupler_force), "gravity": list(loads.gravity)}
        if torques:
            given["loads"]["torques"] = dict(torques)
    masses = Masses()
    m = root.table("masses")
    if m is not None:
        named = {}
        for key in list(m.keys()):
            if key not in LINKS:
                hint = difflib.get_close_matches(key, LINKS, n=1, cutoff=0.5)
                extra = f' (did you mean "{hint[0]}"?)' if hint else ""
                m.raw(key)
                m.error(key, f"masses of input, input2, coupler, coupler2 on a five-bar{extra}",
                        raw_got=f"a mass for {key}")
                continue
            value = link_mass(m, key, False)
            if value is not None:
                named[key] = value
        masses = Masses(named=tuple((k, named[k]) for k in LINKS if k in named))
        given["masses"] = {k: {"mass": v.mass, "center": list(v.center), "inertia": v.inertia}
                           for k, v in masses.named}
    if len(root.reader.errors) > errors:
        return None
    return LoadCase(loads=loads, masses=masses, given=given)
