"""[loads] and [masses] (docs/loads.md), read and checked in
one place for every problem whose result is a linkage (and for result files read by
`analyze`). Returns a `LoadCase`; no numerics here.

    [loads]   coupler_force = [Fx, Fy]  N at the coupler point, global frame
              output_torque = T         N m on the output link, counter-clockwise + (four-bar)
              output_force  = F         N on the slider along +x (slider-crank)
              gravity       = [gx, gy]  m/s^2, acts on the masses
    [masses]  input / coupler / output (slider-crank: slider) =
              { mass = kg, center = [x, y] (length unit, the link's own frame), inertia = kg m^2 }
"""

from __future__ import annotations

from linkcli.io.reader import MISSING, Table

MAX_LOAD = 1e12  # N, N m, kg, kg m^2, m/s^2: beyond, no linkage; squares stay finite
SOLVES_COUPLER_POINT = ("path-generation",)  # types whose result always has a coupler point


def mechanism_of(root: Table) -> str:
    """The mechanism [linkage] names (`mechanism`, default mechanisms.DEFAULT; the [linkage]
    reader checks the key itself: an unknown one is taken as the default here)."""
    from linkcli.mechanisms import DEFAULT, NAMES
    link = root.data.get("linkage")
    mechanism = link.get("mechanism") if isinstance(link, dict) else None
    return mechanism if mechanism in NAMES else DEFAULT


def has_coupler_point(root: Table, kind: str) -> bool:
    """The linkage the forces act on has a coupler point: the type solves for one, or its
    [linkage] table gives one."""
    link = root.data.get("linkage")
    return kind in SOLVES_COUPLER_POINT or (isinstance(link, dict) and "coupler_point" in link)


def refuse_loads(root: Table, kind: str, types_with_linkage: tuple[str, ...]) -> None:
    """[loads] or [masses] on a type whose result is not a linkage: one located line each."""
    for name in ("loads", "masses"):
        if name in root:
            root.raw(name)  # known (refused here, not again as an unknown key)
            root.error(name, f"a problem whose result is a linkage ({', '.join(types_with_linkage)}) "
                       f"for [{name}]", raw_got=f'type = "{kind}", which has no linkage')


def read_loads(root: Table, kind: str) -> LoadCase | None:
    """The load case of a problem, or None when it has neither [loads] nor [masses] (or when
    they hold errors, recorded on the reader)."""
    if "loads" not in root and "masses" not in root:
        return None
    from linkcli.mechanisms import NAMES, module
    from linkcli.model import LoadCase, Loads, Masses
    mechanism = mechanism_of(root)
    own = module(mechanism, "schema")
    if own.MASSES is None:  # a home whose loads are named by its own drawing reads them itself
        return own.read_load_case(root, kind)
    others = {name: module(name, "schema") for name in NAMES if name != mechanism}
    errors = len(root.reader.errors)
    given: dict = {}
    loads = Loads()
    t = root.table("loads")
    if t is not None:
        force = pair(t, "coupler_force", "a force [Fx, Fy] of two finite numbers (N)")
        gravity = pair(t, "gravity", "an acceleration [gx, gy] of two finite numbers (m/s^2)")
        right, what = own.OUTPUT_LOAD
        for name, other in others.items():
            wrong = other.OUTPUT_LOAD[0] if other.OUTPUT_LOAD else right
            if wrong != right and wrong in t:
                t.raw(wrong)
                t.error(wrong, f"{right} ({what}) on a {mechanism}; {wrong} is a {name}'s",
                        raw_got=f"{wrong} = {t.data[wrong]!r}")
        value = t.number(right, 0.0, lo=-MAX_LOAD, hi=MAX_LOAD)
        if force is not None and any(force) and not has_coupler_point(root, kind):
            if kind == "linkage":
                t.error("coupler_force", "a coupler_point in [linkage] (the point the force acts at)",
                        raw_got="a linkage without a coupler_point")
            else:
                t.error("coupler_force", "a linkage with a coupler point (the point the force acts "
                        "at): apply the load as output_torque, or analyse the result as a "
                        'type = "linkage" file with a coupler_point',
                        raw_got=f'a {kind} result, which has no coupler point')
        loads = Loads(coupler_force=tuple(force or (0.0, 0.0)), gravity=tuple(gravity or (0.0, 0.0)),
                      **{right: value or 0.0})
        given["loads"] = {k: list(v) if isinstance(v, tuple) else v
                          for k, v in (("coupler_force", loads.coupler_force), (right, value or 0.0),
                                       ("gravity", loads.gravity))}
    masses = Masses()
    m = root.table("masses")
    if m is not None:
        links = tuple(own.MASSES)
        foreign = [k for other in others.values() for k in (other.MASSES or ()) if k not in links]
        for other in dict.fromkeys(foreign):
            if other in m:
                m.raw(other)
                m.error(other, f"masses of {', '.join(links)} on a {mechanism}", raw_got=f"a mass for {other}")
        point = own.POINT_MASSES
        read = {link: link_mass(m, link, link in point) for link in links if link in m}
        masses = Masses(**{own.MASSES[link]: v for link, v in read.items()})
        given["masses"] = {link: {"mass": v.mass, "center": list(v.center), "inertia": v.inertia}
                           if link not in point else {"mass": v.mass}
                           for link, v in read.items() if v is not None}
    if len(root.reader.errors) > errors:
        return None
    return LoadCase(loads=loads, masses=masses, given=given)


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


def _amount(t: Table, key: str, default, what: str):
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
    mass = _amount(t, "mass", MISSING, "a mass >= 0 (kg)")
    if point_mass:
        return None if mass is None else LinkMass(mass)
    center = mass_center(t)
    inertia = _amount(t, "inertia", 0.0, "an inertia >= 0 about the centre (kg m^2)")
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
