"""The schema half of the mechanism protocol: what a home declares of the problem-file tables it
owns, as one class (`Schema`), one instance a home (`SCHEMA` in `mechanisms/<package>/schema.py`,
reached by `mechanisms.schema_of(name)`).

linkcli.reading (the problem-file and result-file layer, above the homes) asks it for the
`[linkage]` keys and reads them with it, and for the names its other tables use: the pins of
`[joints]`, the links of `[sections]`, the lengths of `[tolerance]`, the plays besides the pins'
clearance, the load case, the motion a result keeps; the table report asks it for its class
table and the headings and units of its kinematics and motion rows. A home overrides what it does
differently (the drawn linkage names its joints and links in its own drawing; the five-bar's
motion is rows of two drives). Pure Python: `check` reads it without numpy.
"""

from __future__ import annotations

from typing import ClassVar, NamedTuple

from linkcli.io.bounds import MAX_LENGTH
from linkcli.io.quantities import MAX_LOAD, link_mass, pair
from linkcli.io.reader import Table

MAX_STEPS = 100_000  # rows of a motion study
SOLVES_COUPLER_POINT = ("path-generation",)  # types whose result always has a coupler point


class ForceParts(NamedTuple):
    """The names a mechanism's home offers force elements (`Schema.force_parts`): points
    (joint or coupler point -> the links carrying it, "ground" for the frame), links that turn
    (torsional elements), revolute pins (friction: each needs a diameter), `refused`: why
    this linkage has no dynamics (None when it has), the links its counterweights go on
    (none: its home has no balancing rule), and the names of its drives when it has several
    (none: one drive; [dynamics] then names each drive in its per-drive keys)."""

    points: dict
    links: tuple[str, ...]
    pins: tuple[str, ...]
    refused: str | None = None
    counterweighted: tuple[str, ...] = ()  # links that take counterweights (a balancing rule)
    drives: tuple[str, ...] = ()  # several drives: their names ([dynamics] drive, start, stop ...)


class Schema:
    """One mechanism's vocabulary and readers.

    Class attributes: `name` (the `[linkage] mechanism` value); `keys` (its `[linkage]` keys);
    `joints` (its pins as `[joints]` names them), `links` (its moving links as `[sections]`
    names them), `toleranced` (the `[tolerance] lengths` keys); `draws`: the home is a drawing
    that names its own joints and links (`[joints]` holds the drawing, and names in other tables
    are checked against it where it is analysed; `joint_names` and `toleranced_names` read them
    from the file); `plays` (`[tolerance]` keys of plays besides the pins' clearance -> what each is);
    `output` ("angle" or "length": what an `allowed_error` measures); `reported_motion` (its own
    keys a result's `[motion]` may hold); `masses` (`[masses]` key -> model.Masses field),
    `point_masses` (bodies that only translate: a mass, no centre or inertia) and `output_load`
    (its `[loads]` key on the output and what it is) for the default load-case reader;
    `class_keys` (the keys of its class section, in order)."""

    name: ClassVar[str]
    keys: ClassVar[tuple[str, ...]] = ()
    draws: ClassVar[bool] = False
    joints: ClassVar[tuple[str, ...]] = ()
    links: ClassVar[tuple[str, ...]] = ()
    toleranced: ClassVar[tuple[str, ...]] = ()
    plays: ClassVar[dict[str, str]] = {}
    output: ClassVar[str] = "angle"
    reported_motion: ClassVar[tuple[str, ...]] = ()
    masses: ClassVar[dict[str, str]] = {}
    point_masses: ClassVar[tuple[str, ...]] = ()
    output_load: ClassVar[tuple[str, str] | tuple[()]] = ()
    class_keys: ClassVar[tuple[str, ...]] = ()

    # ------------------------------------------------------------ [linkage] and [motion]
    def read(self, t: Table, units):
        """The home's linkage record from its `[linkage]` table; None when in error (recorded)."""
        raise NotImplementedError

    def read_motion(self, root: Table, meta, linkage):
        """[motion] of a linkage file whose one drive turns at a constant speed: (linkage,
        input_speed rad/s, steps), or None when a value is bad (errors recorded)."""
        speed, steps = read_drive_motion(root)
        if speed is None or steps is None:
            return None
        return linkage, meta.units.to_rad(speed), steps

    # ------------------------------------------------------------ names other tables use
    def joint_names(self, root: Table) -> tuple[str, ...]:
        """The joints of this file's linkage (a drawing's: as its [joints] names them)."""
        return self.joints

    def toleranced_names(self, root: Table) -> tuple[str, ...]:
        """The `[tolerance] lengths` keys of a table of tolerances per link."""
        return self.toleranced

    def links_designed(self, root: Table) -> bool:
        """Whether the file names no links because its design draws them (a drawn topology):
        `[tolerance] lengths` then applies to whichever links the design has (this default: no)."""
        return False

    def known_lengths(self, linkage) -> dict[str, float]:
        """Link -> the length a tolerance on it must stay below."""
        return {k: getattr(linkage, k) for k in self.toleranced}

    # ------------------------------------------------------------ [loads] and [masses]
    def read_load_case(self, root: Table, kind: str):
        """[loads] (coupler_force, the home's `output_load`, gravity) and [masses] (by
        `masses` key) of a problem of type `kind`: a model.LoadCase, or None when they hold
        errors (recorded). Keys another home uses instead are named as such."""
        from linkcli.mechanisms import NAMES, schema_of
        from linkcli.model import LoadCase, Loads, Masses
        others = {name: schema_of(name) for name in NAMES if name != self.name}
        errors = len(root.reader.errors)
        given: dict = {}
        loads = Loads()
        t = root.table("loads")
        if t is not None:
            force = pair(t, "coupler_force", "a force [Fx, Fy] of two finite numbers (N)")
            gravity = pair(t, "gravity", "an acceleration [gx, gy] of two finite numbers (m/s^2)")
            right, what = self.output_load
            for name, other in others.items():
                wrong = other.output_load[0] if other.output_load else right
                if wrong != right and wrong in t:
                    t.raw(wrong)
                    t.error(wrong, f"{right} ({what}) on a {self.name}; {wrong} is a {name}'s",
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
            links = tuple(self.masses)
            foreign = [k for other in others.values() for k in other.masses if k not in links]
            for other in dict.fromkeys(foreign):
                if other in m:
                    m.raw(other)
                    m.error(other, f"masses of {', '.join(links)} on a {self.name}", raw_got=f"a mass for {other}")
            point = self.point_masses
            read = {link: link_mass(m, link, link in point) for link in links if link in m}
            masses = Masses(**{self.masses[link]: v for link, v in read.items()})
            given["masses"] = {link: {"mass": v.mass, "center": list(v.center), "inertia": v.inertia}
                               if link not in point else {"mass": v.mass}
                               for link, v in read.items() if v is not None}
        if len(root.reader.errors) > errors:
            return None
        return LoadCase(loads=loads, masses=masses, given=given)

    # ------------------------------------------------------------ [springs], [dampers], [dynamics]
    def force_parts(self, root: Table, kind: str) -> ForceParts:
        """The names force elements and the forward dynamics may use on this linkage (points,
        turning links, pins, counterweighted links), or why it has no dynamics (`refused`)."""
        return ForceParts(points={}, links=(), pins=(),
                          refused=f"a one-drive linkage: the dynamics of a {self.name} are not modelled")

    # ------------------------------------------------------------ the table report
    def class_block(self, section: dict, fmt) -> tuple[str, list[tuple[str, object]]]:
        """(title, rows) of its class section in the table report."""
        return "Class", [(k.replace("_", " "), v) for k, v in section.items()]

    def kinematics_headings(self, rows: list[dict], length: str, angle: str) -> dict[str, str]:
        """Column -> heading with its unit, for the kinematics rows of this home's report
        (`length`, `angle`: the file's units)."""
        return {"input": f"input ({angle})"}

    def motion_units(self, length: str, angle: str) -> dict[str, str]:
        """The unit of each `motion` entry of this home's report that has one."""
        return {"input_speed": f"{angle}/s"}


def read_drive_motion(root: Table) -> tuple[float | None, int | None]:
    """[motion] of a kinematics study: input_speed (angle unit per second, non-zero,
    default 1) and steps (2 .. MAX_STEPS, default 360); None for a value in error."""
    mot = root.table("motion")
    speed, steps = 1.0, 360
    if mot is not None:
        speed = mot.number("input_speed", 1.0, lo=-MAX_LENGTH, hi=MAX_LENGTH,
                           what="a non-zero number (angle unit per second)")
        if speed == 0.0:
            mot.error("input_speed", "a non-zero number (angle unit per second)", 0.0)
            speed = None
        steps = mot.number("steps", 360, integer=True, lo=2, hi=MAX_STEPS)
    return speed, steps


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


def coupler_point_headings(length: str) -> dict[str, str]:
    """Headings of the coupler point's kinematics columns (the four-bar's and the slider-crank's)."""
    return {"coupler_point_x": f"P x ({length})", "coupler_point_y": f"P y ({length})",
            "coupler_point_vx": f"P vx ({length}/s)", "coupler_point_vy": f"P vy ({length}/s)",
            "coupler_point_ax": f"P ax ({length}/s2)", "coupler_point_ay": f"P ay ({length}/s2)"}
