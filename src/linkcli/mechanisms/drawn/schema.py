"""The drawn linkage's tables (docs/drawn.md): `[linkage] mechanism = "drawn"` (no other key),
the drawing in `[joints]` (read by io.joints: `at`, `ground`, `slider`, `guide`), `[links]`,
`[drive]`, and its study in `[motion]` (`steps` as any linkage; `span`, `points`, `output`);
`[loads]`/`[masses]` by link and joint name. Every structural error names its joints
(structure.analyse). Pure Python (`check` reads it without numpy).
"""

from __future__ import annotations

import difflib
from typing import TYPE_CHECKING

from linkcli.io.reader import Table, describe
from linkcli.mechanisms.drawn.drawing_tables import drawn_drives, drawn_joints, drawn_links, drawn_motion
from linkcli.mechanisms.schema import ForceParts, Schema

if TYPE_CHECKING:  # names of annotations only (imported where they are used)
    from linkcli.mechanisms.drawn.model import Drawn

# .model (its dataclasses) is imported inside the functions that build them: every other
# mechanism's [linkage] reads this module for its keys alone (reading.linkage.refuse_foreign)



class DrawnSchema(Schema):
    """A drawn linkage's vocabulary (mechanisms.schema.Schema): `[linkage]` holds only
    `mechanism`; the drawing names its own joints, links (each toleranced, and the ground
    between two ground joints or more) and loads (`read_load_case`); a slider block has a play
    in its guide; a tolerance error is a point's deviation."""

    name = "drawn"
    draws = True
    reported_motion = ("dead_points", "links", "sliders", "drives")  # a design's result [motion]: not read back
    plays = {"clearance_slider": "radial play of each slider block in its guide (length unit)"}
    output = "length"
    class_keys = ("class", "mobility", "drives", "links", "sliders", "groups")

    def read(self, t: Table, units) -> Drawn | None:
        return read(t, units)

    def joint_names(self, root: Table) -> tuple[str, ...]:
        """The joint names of the drawing's [joints], unchecked (they are checked where the
        drawing is read); () when it is missing or not a table (`joints = 1`: that error is
        recorded there, once)."""
        joints = root.data.get("joints")
        return tuple(joints) if isinstance(joints, dict) else ()

    def toleranced_names(self, root: Table) -> tuple[str, ...]:
        return toleranced(root)

    def links_designed(self, root: Table) -> bool:
        """A topology without a drawing: each choice's links are the catalogue's (synthesis.sweep)."""
        linkage = root.data.get("linkage")
        return "links" not in root.data and isinstance(linkage, dict) and "topology" in linkage

    def known_lengths(self, linkage) -> dict[str, float]:
        return known_lengths(linkage)

    def read_load_case(self, root: Table, kind: str):
        return read_load_case(root, kind)

    def class_block(self, g: dict, fmt) -> tuple[str, list[tuple[str, object]]]:
        """("Structure", rows): the class, the mobility against the drives, and the plan's groups
        one per row (the Assur groups in solve order)."""
        rows = [("class", g["class"]), ("mobility (drives)", f"{g['mobility']} ({g['drives']})"),
                ("links, sliders", f"{g['links']}, {g['sliders']}")]
        rows += [("solved" if k == 0 else "then", group) for k, group in enumerate(g["groups"])]
        return "Structure", rows

    def kinematics_headings(self, rows, length, angle) -> dict[str, str]:
        """Headings of the nested kinematics columns (flattened by the report): a link's angle
        and rates, a slider's place and rates, a closure's transmission angle, a point's
        coordinates and rates, another drive's value."""
        heads = {"input": f"input ({angle})"}
        units = {("links", "angle"): ("", angle), ("links", "velocity"): (" w", f"{angle}/s"),
                 ("links", "acceleration"): (" a", f"{angle}/s2"), ("sliders", "position"): ("", length),
                 ("sliders", "velocity"): (" v", f"{length}/s"), ("sliders", "acceleration"): (" a", f"{length}/s2")}
        for row in rows[:1]:
            for group, inner in row.items():
                if not isinstance(inner, dict):
                    continue
                for name, value in inner.items():
                    if not isinstance(value, dict):
                        heads[f"{group} {name}"] = f"mu {name} ({angle})" if group == "transmission" else f"{name}"
                        continue
                    for part in value:
                        mark, unit = units.get((group, part), (f" {part}", length if part in ("x", "y") else
                                               f"{length}/s" if part.startswith("v") else f"{length}/s2"))
                        heads[f"{group} {name} {part}"] = f"{name}{mark} ({unit})"
        return heads

    def motion_units(self, length, angle) -> dict[str, str]:
        return {"input_range": angle, "input_speed": f"{angle}/s"}

    def force_parts(self, root: Table, kind: str) -> ForceParts:
        """Points: every joint (carried by the links listing it, "ground" for a ground pivot, its
        slider block for a slider joint); links: every link of [links]; pins: the joints that join
        two bodies or more. Refused unless [drive] has exactly one entry, a link (a turning drive:
        one degree of freedom)."""
        data = root.data
        joints = data.get("joints") if isinstance(data.get("joints"), dict) else {}
        links = data.get("links") if isinstance(data.get("links"), dict) else {}
        points: dict = {}
        for name, spec in joints.items():
            carried = [link for link, held in links.items() if isinstance(held, list) and name in held]
            if isinstance(spec, dict) and spec.get("ground") is True:
                carried.insert(0, "ground")
            if isinstance(spec, dict) and "slider" in spec:
                carried.append(f"{name} (slider block)")
            points[name] = tuple(carried)
        pins = tuple(name for name, carried in points.items() if len(carried) >= 2)
        drive = data.get("drive")
        refused = None
        if isinstance(drive, dict) and (len(drive) != 1 or next(iter(drive)) not in links):
            refused = ("a drawn linkage with one drive, a link turning about its ground joint (one "
                       "degree of freedom)")
        return ForceParts(points=points, links=tuple(links), pins=pins, refused=refused)


def known_lengths(linkage) -> dict[str, float]:
    """Link (and "ground") -> its shortest distance between two joints, for the tolerance
    checks (a tolerance must stay below it)."""
    from linkcli.mechanisms.drawn.model import pair_distances
    out: dict[str, float] = {}
    for body, _, _, d in pair_distances(linkage.joints, linkage.links):
        out[body] = min(out.get(body, d), d)
    return out


def toleranced(root: Table) -> tuple[str, ...]:
    """The [tolerance] lengths keys of this file: "ground" (with two ground joints or more)
    and its links, from the raw tables (unchecked names are checked where they are read)."""
    drawing = root.data.get("linkage") if "status" in root.data else root.data  # a design's result: its [linkage]
    joints = drawing.get("joints") if isinstance(drawing, dict) else None
    links = drawing.get("links") if isinstance(drawing, dict) else None
    grounded = sum(1 for v in joints.values() if isinstance(v, dict) and v.get("ground") is True) \
        if isinstance(joints, dict) else 0
    names = [k for k in links if k] if isinstance(links, dict) else []
    return (("ground",) if grounded >= 2 else ()) + tuple(n for n in names if n != "ground")


def read(t: Table, units) -> Drawn | None:
    """The drawing ([joints], [links], [drive], [motion]) of a `mechanism = "drawn"` [linkage];
    None when in error (every error recorded, structural ones naming the joints)."""
    from linkcli.io.joints import read_joints
    from linkcli.mechanisms.drawn.model import Drawn
    root = t.reader.root()
    errors = len(root.reader.errors)
    if "status" in root.data and isinstance(t.data.get("joints"), dict):
        from linkcli.mechanisms.drawn.kept import read_kept
        return read_kept(t, units, SCHEMA)  # a design's result keeps its drawing in [linkage]
    if "status" in root.data and "joints" not in root.data:  # a result file that keeps no drawing
        t.error("mechanism", "a drawing to analyse: `analyze` reads a drawn linkage from its problem "
                "file (with [joints], [links] and [drive]), not from a result file",
                raw_got='a result file of a drawn linkage')
        t.allow(*t.keys())  # its echo of the links: that one line says it all
        _skip(root)
        return None
    if "topology" in t.data:  # a topology in a file that analyses: that line (and no drawing, nothing more)
        t.raw("topology")
        t.error("topology", 'a drawing ([joints], [links], [drive]) in a type = "linkage" file (a topology is '
                'designed: type = "path-generation", "motion-generation" or "function-generation")',
                raw_got=describe(t.data["topology"]))
        if "joints" not in root.data:
            _skip(root)
            return None
    specs = read_joints(root, SCHEMA, units)  # records a `joints` that is not a table
    joint_table = root.table("joints", required=True) if isinstance(root.data.get("joints", {}), dict) else None
    if specs is None or joint_table is None:
        _skip(root)
        return None
    joints = drawn_joints(joint_table, specs)
    if joints is None:  # a joint in error: [links], [drive] and [motion] name joints, and judged
        # against the drawing without it every link "carries more than the 0 joints" (one bad
        # entry gave eight more lines, each blaming a correct key)
        _skip(root)
        return None
    links = drawn_links(root, joints)
    drives = drawn_drives(root, joints, links, units)
    motion = drawn_motion(root, joints, links or (), drives, units)
    if len(root.reader.errors) > errors or links is None or drives is None or motion is None:
        return None
    span, points, output = motion
    drawing = Drawn(joints=joints, links=links, drives=drives, points=points, span=span, output=output)
    from linkcli.mechanisms.drawn.structure import analyse
    structure = analyse(drawing)
    for problem in structure.problems:
        root.reader.error(problem.where, problem.expected, raw_got=problem.found)
    return None if structure.problems else drawing


def _skip(root: Table) -> None:
    """Without a usable [joints], the other tables of the drawing are not read: known keys."""
    for name in ("links", "drive"):
        if name in root:
            root.raw(name)
    motion = root.data.get("motion")
    if isinstance(motion, dict):
        root.reader.allow(("motion",), ("span", "points", "output", "input_speed"))


def read_load_case(root: Table, kind: str):
    """[loads] (gravity, torques by link, forces by joint) and [masses] (by link; a slider
    joint's block: mass only) of a drawn linkage: a model.LoadCase, or None when absent or
    in error (errors recorded)."""
    from linkcli.io.quantities import MAX_LOAD, link_mass, pair
    from linkcli.model import LoadCase, Loads, Masses
    if "loads" not in root and "masses" not in root:
        return None
    raw_links = root.data.get("links")
    raw_joints = root.data.get("joints")
    kept = root.data.get("linkage")
    if raw_joints is None and isinstance(kept, dict) and "status" in root.data:  # a design's result:
        raw_links, raw_joints = kept.get("links"), kept.get("joints")  # its drawing in [linkage]
    if not (isinstance(raw_joints, dict) and isinstance(raw_links, dict)):  # no drawing to name the
        # links and joints (its absence is its own line; a result file keeps none): judged against
        # nothing, every name was one more line
        for name in ("loads", "masses"):
            if name in root:
                root.raw(name)
        return None
    links, joints = list(raw_links), list(raw_joints)
    sliders = [k for k, v in raw_joints.items() if isinstance(v, dict) and "slider" in v]
    errors = len(root.reader.errors)
    given: dict = {}
    loads = Loads()
    t = root.table("loads")
    if t is not None:
        gravity = pair(t, "gravity", "an acceleration [gx, gy] of two finite numbers (m/s^2)")
        torques = _named(t, "torques", links, "link", lambda sub, k: sub.number(
            k, lo=-MAX_LOAD, hi=MAX_LOAD, what="a torque (N m, counter-clockwise positive)"))
        forces = _named(t, "forces", joints, "joint", lambda sub, k: pair(
            sub, k, "a force [Fx, Fy] of two finite numbers (N, global frame)"))
        loads = Loads(gravity=tuple(gravity or (0.0, 0.0)), torques=tuple(torques.items()),
                      forces=tuple(forces.items()))
        given["loads"] = {"gravity": list(loads.gravity)}
        if torques:
            given["loads"]["torques"] = dict(torques)
        if forces:
            given["loads"]["forces"] = {k: list(v) for k, v in forces.items()}
    masses = Masses()
    m = root.table("masses")
    if m is not None:
        named = {}
        for key in m.keys():
            if key in links:
                value = link_mass(m, key, False)
            elif key in sliders:
                value = link_mass(m, key, True)
            else:
                hint = difflib.get_close_matches(key, links + sliders, n=1, cutoff=0.5)
                extra = f' (did you mean "{hint[0]}"?)' if hint else ""
                m.raw(key)
                m.error(key, f"a link of [links] or a slider joint (its block){extra}",
                        raw_got=f'"{key}", neither')
                continue
            if value is not None:
                named[key] = value
        masses = Masses(named=tuple(named.items()))
        given["masses"] = {k: ({"mass": v.mass} if k in sliders and k not in links
                               else {"mass": v.mass, "center": list(v.center), "inertia": v.inertia})
                           for k, v in named.items()}
    if len(root.reader.errors) > errors:
        return None
    return LoadCase(loads=loads, masses=masses, given=given)


def _named(t: Table, key: str, names: list[str], what: str, read_one) -> dict:
    """A table of `key` by name (links or joints): name -> value; bad entries recorded."""
    sub = t.table(key)
    if sub is None:
        return {}
    out = {}
    for name in list(sub.keys()):
        if name not in names:
            hint = difflib.get_close_matches(name, names, n=1, cutoff=0.5)
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            sub.raw(name)
            sub.error(name, f"a {what} of the drawing{extra}", raw_got=f'"{name}", which the drawing does not have')
            continue
        value = read_one(sub, name)
        if value is not None:
            out[name] = value
    return out


SCHEMA = DrawnSchema()
