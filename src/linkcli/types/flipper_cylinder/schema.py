"""Schema of `type = "flipper-cylinder"`: a hydraulic cylinder turning a loaded platform.

Tables: [load] (mass, center_of_mass, gravity), [motion] (start, end, table_step),
[bounds] (rod_pivot, base_pivot: each coordinate a number, fixed, or a range),
[cylinder] (bore, rod, dead_length, max_force; all optional), [objective] (minimize,
pareto). When every pivot coordinate is a number the design is only evaluated.
"""

from __future__ import annotations

import math

from linkcli.io.reader import Table
from linkcli.model import FlipperCylinderProblem, Meta

OBJECTIVES = ("peak-force", "cylinder-length")
STANDARD_GRAVITY = 9.80665  # m/s^2
PARETO_POINTS = 8  # rows of the trade-off table for `pareto = true`
MAX_PARETO = 50
MAX_SWEEP = math.pi  # a cylinder line must cross the hinge over a half turn or more
MAX_COORDINATE = 1e9  # length unit: coordinates, diameters, dead length (beyond: overflow)
MAX_MASS = 1e12  # kg
MAX_GRAVITY = 1e6  # m/s^2
MAX_FORCE = 1e15  # N
MAX_ROWS = 10_000  # rows of the force table


def _at_most(t: Table, key: str, value, limit: float, what: str):
    """value, or None after an error when |value| exceeds the limit."""
    if value is not None and abs(value) > limit:
        t.error(key, f"{what} of magnitude at most {limit:g}", t.raw(key))
        return None
    return value


def _point(bounds: Table, key: str):
    """((x_lo, x_hi), (y_lo, y_hi)) of a pivot; a fixed pivot may not sit at the hinge."""
    box = bounds.point_range(key)
    if box is None:
        return None
    (xl, xh), (yl, yh) = box
    sub = bounds.table(key)
    for name, (lo, hi) in (("x", (xl, xh)), ("y", (yl, yh))):
        if max(abs(lo), abs(hi)) > MAX_COORDINATE:
            sub.error(name, f"a coordinate of magnitude at most {MAX_COORDINATE:g}",
                      raw_got=f"{lo:g}" if lo == hi else f"[{lo:g}, {hi:g}]")
            return None
    if xl == xh == 0.0 and yl == yh == 0.0:
        bounds.error(key, "a pivot away from the hinge B = (0, 0) (there the cylinder has no "
                     "moment arm)", raw_got="x = 0, y = 0")
        return None
    return box


def _load(root: Table):
    t = root.table("load", required=True)
    if t is None:
        return None
    mass = _at_most(t, "mass", t.number("mass", positive=True, what="a positive mass (kg)"),
                    MAX_MASS, "a mass (kg)")
    com = t.number_list("center_of_mass", length=2, what="coordinates [x, y]")
    if com is not None and max(abs(v) for v in com) > MAX_COORDINATE:
        t.error("center_of_mass", f"coordinates of magnitude at most {MAX_COORDINATE:g}",
                raw_got=f"[{com[0]:g}, {com[1]:g}]")
        com = None
    elif com is not None and com[0] == 0.0 and com[1] == 0.0:
        t.error("center_of_mass", "a centre of mass off the hinge B = (0, 0) (at the hinge the "
                "load has no moment: no force is needed and every design is equally good)",
                raw_got="[0, 0]")
        com = None
    gravity = _at_most(t, "gravity", t.number("gravity", STANDARD_GRAVITY, positive=True,
                                               what="a positive acceleration of gravity (m/s^2)"),
                       MAX_GRAVITY, "an acceleration of gravity (m/s^2)")
    if mass is None or com is None or gravity is None:
        return None
    return mass, (com[0], com[1]), gravity


def _motion(root: Table, units):
    """start != end (end < start: the platform turns clockwise), |end - start| < 180 deg,
    and the optional table step (radians out)."""
    t = root.table("motion", required=True)
    if t is None:
        return None
    start = t.number("start", 0.0)
    end = t.number("end", what="the platform angle at the end of the sweep")
    step = t.number("table_step", None, positive=True, what="a positive angle step")
    if start is None or end is None:
        return None
    if end == start:
        t.error("end", f"an end angle other than start ({start:g} {units.angle}: the platform turns "
                "counter-clockwise from start to a greater end, clockwise to a smaller one)", t.raw("end"))
        return None
    sweep = abs(units.to_rad(end) - units.to_rad(start))
    if sweep >= MAX_SWEEP * (1.0 - 1e-12):
        half = units.from_rad(math.pi)
        t.error("end", f"a sweep end - start below {half:g} {units.angle} (over a half turn the "
                "cylinder line must pass through the hinge)",
                raw_got=f"end - start = {end - start:g} {units.angle}")
        return None
    if step is not None and abs(end - start) / step > MAX_ROWS:
        t.error("table_step", f"a step of at least {abs(end - start) / MAX_ROWS:g} {units.angle} "
                f"(at most {MAX_ROWS} rows over the sweep)", t.raw("table_step"))
        return None
    return units.to_rad(start), units.to_rad(end), (None if step is None else units.to_rad(step))


def _cylinder(root: Table):
    """bore, rod, dead_length, max_force (each None when not given)."""
    t = root.table("cylinder")
    if t is None:
        return {}
    out = {"bore": t.number("bore", None, positive=True, what="a positive bore diameter"),
           "rod": t.number("rod", None, positive=True, what="a positive rod diameter"),
           "dead_length": t.number("dead_length", None, nonnegative=True,
                                   what="a dead length >= 0"),
           "max_force": t.number("max_force", None, positive=True, what="a positive force (N)")}
    for key in ("bore", "rod", "dead_length"):
        out[key] = _at_most(t, key, out[key], MAX_COORDINATE, "a length")
    out["max_force"] = _at_most(t, "max_force", out["max_force"], MAX_FORCE, "a force (N)")
    if out["rod"] is not None:
        if "bore" not in t:
            t.error("rod", "a bore beside the rod (the pull acts on the annulus between them)",
                    raw_got=f"rod = {out['rod']:g} without a bore")
            out["rod"] = None
        elif out["bore"] is not None and out["rod"] >= out["bore"]:
            t.error("rod", f"a rod diameter smaller than the bore ({out['bore']:g})", t.raw("rod"))
            out["rod"] = None
    return out


def _objective(root: Table, has_max_force: bool, fixed: bool):
    t = root.table("objective")
    if t is None:
        return "peak-force", 0
    minimize = t.string("minimize", "peak-force", choices=OBJECTIVES)
    raw = t.raw("pareto", False)
    pareto = 0
    if isinstance(raw, bool):
        pareto = PARETO_POINTS if raw else 0
    else:
        pareto = t.number("pareto", integer=True, lo=2, hi=MAX_PARETO,
                          what="true, false or a number of points") or 0
    if minimize == "cylinder-length" and not has_max_force and not fixed:
        t.error("minimize", 'max_force in [cylinder] with minimize = "cylinder-length" (the '
                "shortest cylinder needs a force limit)", minimize)
    if pareto and fixed:
        t.error("pareto", "a free pivot coordinate (a range in [bounds]) for the trade-off "
                "table", raw_got=f"{str(raw).lower()} with every pivot fixed")
        pareto = 0
    return minimize, pareto


def parse(root: Table, meta: Meta) -> FlipperCylinderProblem | None:
    load = _load(root)
    motion = _motion(root, meta.units)
    bounds = root.table("bounds", required=True)
    rod_pivot = _point(bounds, "rod_pivot") if bounds else None
    base_pivot = _point(bounds, "base_pivot") if bounds else None
    cylinder = _cylinder(root)
    fixed = (rod_pivot is not None and base_pivot is not None
             and all(lo == hi for lo, hi in rod_pivot + base_pivot))
    cyl_table = root.data.get("cylinder")
    has_max_force = isinstance(cyl_table, dict) and "max_force" in cyl_table
    minimize, pareto = _objective(root, has_max_force, fixed)
    if fixed and (rod_pivot[0][0], rod_pivot[1][0]) == (base_pivot[0][0], base_pivot[1][0]):
        bounds.error("base_pivot", "a base pivot apart from the rod pivot at the start position "
                     "(zero cylinder length)",
                     raw_got=f"x = {base_pivot[0][0]:g}, y = {base_pivot[1][0]:g}, the rod pivot")
        return None
    if None in (load, motion, rod_pivot, base_pivot, minimize):
        return None
    mass, com, gravity = load
    start, end, step = motion
    clockwise = end < start
    if clockwise:  # solved as its mirror image in x (see FlipperCylinderProblem)
        start, end, com = -start, -end, (-com[0], com[1])
        rod_pivot, base_pivot = (_mirror_x(b) for b in (rod_pivot, base_pivot))
    return FlipperCylinderProblem(
        meta=meta, mass=mass, center_of_mass=com, gravity=gravity, start=start, end=end,
        rod_pivot=rod_pivot, base_pivot=base_pivot, minimize=minimize, pareto=pareto,
        table_step=step, clockwise=clockwise, **cylinder)


def _mirror_x(bounds):
    """((x lo, hi), (y lo, hi)) mirrored in the vertical line through the hinge: x -> -x."""
    (x_lo, x_hi), y = bounds
    return (-x_hi, -x_lo), y
