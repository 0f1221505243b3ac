"""[joints]: one inline table per joint, read in one place for every use of it.

    [joints]
    A  = { diameter = 8, width = 10, shear = "double", fit = "H7/g6" }   # part sizes
    O2 = { at = [0, 0], ground = true }                                # a drawn linkage's drawing
    S  = { at = [90, 52], slider = 0 }

Part sizes (any mechanism; the names are the mechanism's joints, `joints` of its schema):
`diameter` (pin diameter, length unit), `width` (bearing width, length unit), `shear`
("single" or "double": the pin's shear planes), `fit` (an ISO 286 hole/shaft fit such as
"H7/g6" at the joint's diameter: a clearance fit of ISO 286, standards.iso286; checked here,
its limits drawn where the fit is used). The drawing (a mechanism whose
schema `draws`: any names, the drawing's own): `at` (the joint's place in the
drawn assembly, [x, y] length unit), `ground` (fixed to the ground), `slider` (a slider on
a ground guide through `at`, at this angle, the file's angle unit), `guide` (the link whose
guide the slider runs on, when not the ground's). Pure Python (`check` reads it without
numpy); the mechanism's schema checks what the names mean. A file's [joints] is read once:
a second reader (the drawn linkage's schema, after the file's meta) gets the same joints
and no second set of errors.
"""

from __future__ import annotations

import difflib
import weakref
from dataclasses import dataclass

from linkcli.io.bounds import MAX_LENGTH, bounded_length, bounded_point
from linkcli.io.reader import Table, describe

MAX_JOINTS = 1000
SIZE_KEYS = ("diameter", "width", "shear", "fit")
DRAWING_KEYS = ("at", "ground", "slider", "guide")
SHEAR = ("single", "double")


@dataclass(frozen=True)
class JointSpec:
    """One joint as the file gives it (lengths in the length unit, `slider` in rad)."""

    name: str
    at: tuple[float, float] | None = None
    ground: bool = False
    slider: float | None = None
    guide: str | None = None
    diameter: float | None = None
    width: float | None = None
    shear: str = "single"
    fit: str | None = None
    line: int | None = None

    @property
    def shear_planes(self) -> int:
        return 2 if self.shear == "double" else 1


_READ: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()  # reader -> {mechanism: joints}


def read_joints(root: Table, schema, units) -> tuple[JointSpec, ...] | None:
    """Every joint of [joints] (in file order), () without the table, None when in error
    (errors recorded). `schema` (mechanisms.schema.Schema) is the [linkage] mechanism's whose
    joints they are: its `joints` names them, or its drawing (`draws`). Read once per file and
    mechanism (module docstring)."""
    done = _READ.setdefault(root.reader, {})
    if schema.name not in done:
        done[schema.name] = _read_joints(root, schema, units)
    return done[schema.name]


def _read_joints(root: Table, schema, units) -> tuple[JointSpec, ...] | None:
    t = root.table("joints")
    if t is None:
        return ()
    mechanism = schema.name
    names = None if schema.draws else schema.joints  # a drawing names its own joints
    errors = len(root.reader.errors)
    example = "{ at = [10, 20] }" if names is None else "{ diameter = 8, width = 10 }"  # a drawing's joint: its place
    entries = named_tables(t, names, "joint", mechanism, example)
    if entries is None:
        return None
    out = [_joint(joint, name, drawing=names is None, mechanism=mechanism, units=units,
                  line=root.reader.line_of(("joints", name))) for name, joint in entries]
    if len(root.reader.errors) > errors:
        return None
    return tuple(out)


def named_tables(t: Table, names, kind: str, mechanism: str, example: str):
    """(name, inline table) of each entry of `t` named by one of `names` (None: any name, the
    drawing's own), in file order; a name not among them or an entry that is not a table is
    a located error (with "did you mean"). None when there are over MAX_JOINTS entries."""
    keys = list(t.keys())
    if len(keys) > MAX_JOINTS:
        t.error(None, f"at most {MAX_JOINTS} {kind}s", raw_got=f"{len(keys)} {kind}s")
        t.allow(*keys)  # that one line says it all: not one more per entry, each blamed as unknown
        return None
    out = []
    for name in keys:
        if names is not None and name not in names:
            hint = difflib.get_close_matches(name, names, n=1, cutoff=0.5)
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            t.raw(name)
            t.error(name, f"a {kind} of the {mechanism}: one of {', '.join(names)}{extra}",
                    raw_got=f'{kind} "{name}"')
            continue
        value = t.raw(name)
        if not isinstance(value, dict):  # one line (Table.table would add "expected a table")
            t.error(name, f"an inline table of the {kind}'s keys, e.g. {example}", value)
            continue
        entry = t.table(name)
        out.append((name, entry))
    return out


def _joint(t: Table, name: str, *, drawing: bool, mechanism: str, units, line) -> JointSpec:
    """One joint's keys; the drawing's keys only for a drawn linkage."""
    at, ground, slider, guide = None, False, None, None
    if drawing:
        at = bounded_point(t, "at", None)
        ground = t.boolean("ground", False)
        slider = t.number("slider", None, lo=-MAX_LENGTH, hi=MAX_LENGTH,
                          what="the angle of the slider's ground guide (angle unit)")
        if slider is not None:
            slider = units.to_rad(slider)
        guide = t.string("guide", None, max_len=200)
    else:
        for key in DRAWING_KEYS:
            if key in t:
                t.allow(key)
                t.error(key, f"part sizes for a {mechanism} joint ({', '.join(SIZE_KEYS)}); "
                        f'"{key}" belongs to a drawn linkage (mechanism = "drawn")',
                        raw_got=f"{key} = {describe(t.raw(key))}")
    diameter = _size(t, "diameter", "a pin diameter > 0 (length unit)")
    width = _size(t, "width", "a bearing width > 0 (length unit)")
    shear = t.string("shear", "single", choices=SHEAR)
    fit = t.string("fit", None, max_len=40)
    if fit is not None:
        fit = _checked_fit(t, fit, diameter, units)
    return JointSpec(name=name, at=tuple(at) if at else None, ground=bool(ground), slider=slider, guide=guide,
                     diameter=diameter, width=width, shear=shear or "single", fit=fit, line=line)


def _checked_fit(t: Table, fit: str, diameter, units):
    """The fit when it is an ISO 286 clearance fit at the joint's diameter (a running joint
    needs clearance); None after recording why not (standards.iso286.clearance_fit_problem)."""
    from linkcli.standards.iso286 import clearance_fit_problem
    if diameter is None:
        if "diameter" not in t:
            t.error("diameter", "a pin diameter > 0 (length unit): the nominal size of the fit", raw_got=f'fit "{fit}" and no diameter')
        return None
    problem = clearance_fit_problem(fit, diameter * units.mm_per_length)
    if problem is not None:
        t.error("fit", problem[0], raw_got=problem[1])
        return None
    return fit


def _size(t: Table, key: str, what: str):
    """A pin's length within [MIN_LENGTH, MAX_LENGTH] (`io.bounds.bounded_length`); None when
    absent or bad (error recorded)."""
    return bounded_length(t, key, None, what)
