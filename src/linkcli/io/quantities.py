"""Physical quantities a table gives by name: a force or acceleration pair, a link's mass with
its centre and inertia. Pure Python; knows no mechanism (a home names its links and passes them)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from linkcli.io.reader import MISSING, Table

if TYPE_CHECKING:  # names of annotations only (imported where they are used)
    from linkcli.model.loads import LinkMass

MAX_LOAD = 1e12  # N, N m, kg, kg m^2, m/s^2: beyond, no linkage; squares stay finite


def pair(t: Table, key: str, expected: str):
    """Two finite numbers [x, y], each within MAX_LOAD; None when absent or bad."""
    value = t.raw(key)
    if value is MISSING:
        return None
    ok = (isinstance(value, list) and len(value) == 2
          and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
          and all(abs(float(v)) <= MAX_LOAD for v in value))  # nan and inf fail here too
    if not ok:
        t.error(key, expected, value)
        return None
    return tuple(float(v) for v in value)


def amount(t: Table, key: str, default, what: str):
    """A number in [0, MAX_LOAD]; None when missing (without a default) or bad."""
    value = t.number(key, default, what=what)
    if value is not None and not 0.0 <= value <= MAX_LOAD:
        t.error(key, what if value < 0 else f"{what}, at most {MAX_LOAD:g}", value)
        return None
    return value


def link_mass(masses: Table, link: str, point_mass: bool) -> LinkMass | None:
    """{ mass, center, inertia } of one link (a body that only translates, a slider: { mass } only)."""
    from linkcli.model import LinkMass
    t = masses.table(link)
    if t is None:
        return None
    mass = amount(t, "mass", MISSING, "a mass >= 0 (kg)")
    if point_mass:
        return None if mass is None else LinkMass(mass)
    center = mass_center(t)
    inertia = amount(t, "inertia", 0.0, "an inertia >= 0 about the centre (kg m^2)")
    if mass is None or center is None or inertia is None:
        return None
    return LinkMass(mass, tuple(center), inertia)


def mass_center(t: Table):
    """A link's centre of mass [x, y] (length unit, the link's frame; default [0, 0]), each
    coordinate at most MAX_LENGTH in magnitude as every coordinate a file holds (1e308
    made the loads' equations singular); None when bad."""
    from linkcli.io.bounds import MAX_LENGTH
    center = t.number_list("center", [0.0, 0.0], length=2, what="coordinates [x, y] in the link's frame")
    if center is not None and max(abs(v) for v in center) > MAX_LENGTH:
        t.error("center", f"coordinates [x, y] in the link's frame of magnitude at most {MAX_LENGTH:g}",
                raw_got=f"[{center[0]:g}, {center[1]:g}]")
        return None
    return center
