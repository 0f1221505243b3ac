"""A drawing's own tables, read the same in a problem file and in a result file that keeps its
design (drawn.kept): the joints' places ([joints], read by io.joints), `[links]` (the joints
each link carries, at distinct places) and `[drive]` (a link turning about its ground joint or
a slider moved along its guide, with its speed). Pure Python (`check` reads them without numpy).
"""

from __future__ import annotations

import difflib
import math
from typing import TYPE_CHECKING

from linkcli.io.bounds import MAX_LENGTH, MAX_RATIO, MIN_LENGTH, over_ratio
from linkcli.io.reader import MISSING, Table, describe

if TYPE_CHECKING:  # names of annotations only (imported where they are used)
    from linkcli.mechanisms.drawn.model import DrawnJoint, DrawnLink, Drive

MAX_LINKS = 100  # a drawing's links: its analysis takes about 10 ms of CPU per link (1 s at the cap)
MAX_DISTANCES = 2000  # distances between two joints of one link (and of the ground), each one reported
MAX_SPEED = 1e9
MAX_SPAN_TURNS = 2.0  # a turning drive's span: at most two turns either way
MIN_SPEED = 1e-9  # a drive's |speed|: below, the speed ratios over- or underflow (a denormal is 0)


def _speed(sub: Table) -> float | None:
    """A drive's `speed` (default 1): a number of magnitude MIN_SPEED to MAX_SPEED; None
    when bad (error recorded on its line)."""
    what = (f"a non-zero number of magnitude {MIN_SPEED:g} to {MAX_SPEED:g} "
            "(angle unit/s for a link, length unit/s for a slider)")
    speed = sub.number("speed", 1.0, lo=-MAX_SPEED, hi=MAX_SPEED, what=what)
    if speed is not None and abs(speed) < MIN_SPEED:
        sub.error("speed", what, speed)
        return None
    return speed


def drawn_joints(t: Table, specs) -> tuple[DrawnJoint, ...] | None:
    """The drawing's joints: each with `at`; `slider` and `ground` exclusive; `guide` only
    with `slider`."""
    from linkcli.mechanisms.drawn.model import DrawnJoint
    out, ok = [], True
    for spec in specs:
        if not spec.name:
            t.error(spec.name, "a joint name of at least one character", raw_got='an empty name ""')
            ok = False
            continue
        if spec.at is None:
            t.error(spec.name, f"at = [x, y]: joint {spec.name}'s place in the drawing (length unit)",
                    raw_got="no at")
            ok = False
            continue
        guide = spec.guide
        if spec.slider is not None and spec.ground:
            t.error(spec.name, f"joint {spec.name} either a ground pivot (ground = true) or a slider on a "
                    "guide (slider = angle)", raw_got="both")
            ok = False
        if guide is not None and spec.slider is None:
            t.error(spec.name, f"slider = angle with guide (joint {spec.name} slides on the guide of "
                    f'link "{guide}" at that angle)', raw_got="a guide without slider")
            ok = False
        out.append(DrawnJoint(spec.name, tuple(spec.at), spec.ground, spec.slider, guide))
    return tuple(out) if ok else None


def drawn_links(root: Table, joints) -> tuple[DrawnLink, ...] | None:
    """[links]: name = [joints it carries] (2 or more, each once, at distinct places)."""
    from linkcli.mechanisms.drawn.model import DrawnLink
    t = root.table("links", required=True)
    if t is None:
        return None
    names = {j.name: j for j in joints or ()}
    keys = list(t.keys())
    if len(keys) > MAX_LINKS:
        t.error(None, f"at most {MAX_LINKS} links (the analysis of a drawing takes about 10 ms per link)",
                raw_got=f"{len(keys)} links")
        t.allow(*keys)  # that one line says it all: not one more per link, each blamed as unknown
        return None
    if not keys:
        t.error(None, "at least one link = [its joints]", raw_got="an empty table")
        return None
    out, ok = [], True
    for name in keys:
        value = t.raw(name)
        where = f"link {name}" if name else "a link"
        if not name:
            t.error(name, "a link name of at least one character", raw_got='an empty name ""')
            ok = False
            continue
        if name == "ground":
            t.error(name, "a link name other than ground (the ground is implicit: [tolerance] lengths, "
                    "[masses] and the report call it ground)", raw_got='a link named "ground"')
            ok = False
            continue
        if name in names and names[name].slider is not None:
            t.error(name, f"a link name that no slider joint has ([drive], [masses] and [motion] output "
                    f'name a slider joint for its block: "{name}" would name both)',
                    raw_got=f'link "{name}", also the name of slider joint {name}')
            ok = False
            continue
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            t.error(name, f"an array of the joint names {where} carries, e.g. [\"A\", \"B\"]", value)
            ok = False
            continue
        if len(value) < 2:
            t.error(name, f"{where} carrying two joints or more", raw_got=f"{len(value)} joint"
                    + ("" if len(value) == 1 else "s") + (f" ({value[0]})" if value else ""))
            ok = False
            continue
        if len(value) > len(names) or len(value) > 10_000:
            t.error(name, f"{where} carrying at most the {len(names)} joints of the drawing",
                    raw_got=f"{len(value)} joints")
            ok = False
            continue
        unknown = [v for v in value if v not in names]
        if joints is not None and unknown:
            hint = difflib.get_close_matches(unknown[0], list(names), n=1, cutoff=0.5)
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            t.error(name, f"joints of [joints]{extra}", raw_got=f'"{unknown[0]}", which [joints] does not have')
            ok = False
            continue
        twice = [v for i, v in enumerate(value) if v in value[:i]]
        if twice:
            t.error(name, f"each joint once in {where}", raw_got=f"{twice[0]} twice")
            ok = False
            continue
        if joints is None:
            continue
        same = _same_place(value, names)
        if same:
            t.error(name, f"the joints of {where} at distinct places (a link has length)",
                    raw_got=f"{same[0]} and {same[1]} both at {list(names[same[0]].at)}")
            ok = False
            continue
        grounded = [v for v in value if names[v].ground]
        if len(grounded) > 1:
            t.error(name, f"{where} with one ground joint at most (the ground is implicit)",
                    raw_got=f"ground joints {', '.join(grounded)}: {where} is part of the ground")
            ok = False
            continue
        out.append(DrawnLink(name, tuple(value)))
    if not ok or joints is None:
        return None
    if _too_many_distances(root, t, joints, out) or _distances_out_of_bounds(t, joints, out):
        return None
    return _carried(root, t, joints, tuple(out))


def _distances_out_of_bounds(t: Table, joints, links) -> bool:
    """A located error (and True) where a distance between two joints of one link or of the
    ground -- the drawing's link lengths -- lies outside [MIN_LENGTH, MAX_LENGTH], or the
    longest is over MAX_RATIO times the shortest: the limits a four-bar's lengths have
    (io.bounds; links of 2e-10 mm, or 1e12 times apart, were analysed as given)."""
    from linkcli.mechanisms.drawn.model import pair_distances
    distances: dict[str, float] = {}
    owner: dict[str, str] = {}
    pair: dict[str, tuple[str, str]] = {}
    for body, a, b, d in pair_distances(joints, links):
        key = f"{body} {a}-{b}"
        distances[key], owner[key], pair[key] = d, body, (a, b)
    bad = False
    for key, value in distances.items():
        if not MIN_LENGTH <= value <= MAX_LENGTH:
            where = owner[key]
            path = (*t.path[:-1], "joints", pair[key][1]) if where == "ground" else (*t.path, where)
            t.reader.error(path, f"a distance within [{MIN_LENGTH:g}, {MAX_LENGTH:g}] "
                    f"between two joints of {'the ground' if where == 'ground' else 'link ' + where} (as a "
                    "four-bar's lengths: beyond, squares of lengths lose their precision)",
                    raw_got=f"{'-'.join(pair[key])} = {value:g}")
            bad = True
    if bad or not distances:
        return bad
    extremes = over_ratio(distances)
    if extremes:
        longest, shortest = extremes
        where = owner[longest]
        path = (*t.path[:-1], "joints", pair[longest][1]) if where == "ground" else (*t.path, where)
        t.reader.error(path, f"a linkage whose longest distance between two joints of one link is at most {MAX_RATIO:g} "
                "times its shortest (beyond, double precision cannot resolve its angles)",
                raw_got=f"{longest} = {distances[longest]:g} and {shortest} = {distances[shortest]:g}, "
                f"{distances[longest] / distances[shortest]:.7g} times")
        return True
    return False


def _too_many_distances(root: Table, t: Table, joints, links) -> bool:
    """A located error (and True) when the links (and the ground) have more than
    MAX_DISTANCES distances between two of their joints: the report lists each (a plate of
    990 joints listed 490,000 of them), blamed on the body with the most."""
    ground = sum(1 for j in joints if j.ground)
    bodies = [("ground", ground)] + [(k.name, len(k.joints)) for k in links]
    total = sum(k * (k - 1) // 2 for _, k in bodies)
    if total <= MAX_DISTANCES:
        return False
    name, most = max(bodies, key=lambda b: b[1])
    what = (f"at most {MAX_DISTANCES} distances between two joints of one link or of the ground "
            f"(the report lists each: a plate of 63 joints has 1953)")
    found = f"{total:,} distances ({'the ground has' if name == 'ground' else f'link {name} carries'} {most} joints)"
    if name == "ground":
        root.table("joints").error(None, what, raw_got=found)
    else:
        t.error(name, what, raw_got=found)
    return True


def _same_place(value, names) -> tuple[str, str] | None:
    seen: dict[tuple[float, float], str] = {}
    for v in value:
        at = tuple(names[v].at)
        if at in seen:
            return seen[at], v
        seen[at] = v
    return None


def _carried(root: Table, t: Table, joints, links) -> tuple[DrawnLink, ...] | None:
    """Every joint on a link; a slider's guide link lists it and the block is pinned to
    another link."""
    jt = root.table("joints")
    on = {j.name: [k.name for k in links if j.name in k.joints] for j in joints}
    ok = True
    for joint in joints:
        if not on[joint.name]:
            jt.error(joint.name, f"joint {joint.name} on a link (listed in [links])", raw_got="a joint on no link")
            ok = False
        elif joint.guide is not None:
            if joint.guide not in {k.name for k in links}:
                hint = difflib.get_close_matches(joint.guide, [k.name for k in links], n=1, cutoff=0.5)
                extra = f' (did you mean "{hint[0]}"?)' if hint else ""
                jt.error(joint.name, f"guide = a link of [links]{extra}", raw_got=f'guide = "{joint.guide}"')
                ok = False
            elif joint.guide not in on[joint.name]:
                jt.error(joint.name, f"link {joint.guide} listing {joint.name} (the link whose guide it "
                         "slides on carries it)", raw_got=f"{joint.guide} without {joint.name}")
                ok = False
            elif on[joint.name] == [joint.guide]:
                jt.error(joint.name, f"slider {joint.name} pinned to a link besides its guide's {joint.guide}",
                         raw_got=f"only {joint.guide} lists {joint.name}")
                ok = False
    return links if ok else None


def drawn_drives(root: Table, joints, links, units) -> tuple[Drive, ...] | None:
    """[drive]: one entry per degree of freedom, a link turning about its ground joint
    (speed: angle unit/s) or a slider joint moved along its guide (length unit/s)."""
    from linkcli.mechanisms.drawn.model import SLIDE, TURN, Drive
    t = root.table("drive", required=True)
    if t is None or joints is None:
        return None
    named = links is not None  # without valid links, only the speeds are checked here
    link_names = {k.name: k for k in links or ()}
    sliders = {j.name for j in joints if j.slider is not None}
    grounded = {j.name for j in joints if j.ground}
    keys = list(t.keys())
    if not keys:
        t.error(None, "at least one drive: a link = { speed = ... } or a slider joint = { speed = ... }",
                raw_got="an empty table")
        return None
    out, ok = [], True
    for name in keys:
        is_link, is_slider = name in link_names, name in sliders
        sub = t.table(name)
        if sub is None:
            ok = False
            continue
        speed = _speed(sub)
        if not named:
            continue
        if is_link and is_slider:
            t.error(name, f'a drive naming one link or one slider joint ("{name}" is both)',
                    raw_got=f'"{name}", a link and a slider joint')
            ok = False
            continue
        if not (is_link or is_slider):
            choices = list(link_names) + sorted(sliders)
            hint = difflib.get_close_matches(name, choices, n=1, cutoff=0.5)
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            what = ("a link of [links] turning about its ground joint, or a slider joint moved along "
                    f"its guide{extra}")
            t.error(name, what, raw_got=f'"{name}", neither' + (
                " (a joint, but not a slider)" if name in {j.name for j in joints} else ""))
            ok = False
            continue
        if is_link:
            pivots = [j for j in link_names[name].joints if j in grounded]
            if not pivots:
                t.error(name, f"a driven link with a ground pivot (link {name} turns about it)",
                        raw_got=f"link {name} on joints {', '.join(link_names[name].joints)}, none on the ground")
                ok = False
                continue
        if speed is None:
            ok = False
            continue
        if is_link:
            out.append(Drive(name, TURN, units.to_rad(speed)))
        else:
            out.append(Drive(name, SLIDE, speed))
    return tuple(out) if ok else None


def drawn_motion(root: Table, joints, links, drives, units):
    """[motion] of a drawn linkage (a drawing's, or a design's result: drawn.kept): span,
    points, output (steps is read with every linkage); (span, points, output), the errors
    recorded on the reader."""
    from linkcli.mechanisms.drawn.model import TURN
    t = root.table("motion")
    if t is None:
        return None, (), None
    if "input_speed" in t:
        t.raw("input_speed")
        t.error("input_speed", "the drives' speeds in [drive] (a drawn linkage: link = { speed = ... })",
                raw_got=f"input_speed = {describe(t.data['input_speed'])} in [motion]")
    names = {j.name for j in joints or ()}
    span = None
    if "span" in t:
        lead = drives[0] if drives else None
        turning = lead is not None and lead.kind == TURN
        limit = units.from_rad(MAX_SPAN_TURNS * 2 * math.pi) if turning else MAX_LENGTH
        unit = units.angle if turning else units.length
        value = t.number_list("span", length=2, what=f"numbers [lo, hi] ({unit}, from the drawn position)")
        if value is not None:
            lo, hi = value
            if not lo < hi:
                t.error("span", "[lo, hi] with lo < hi", raw_got=str(value))
            elif max(abs(lo), abs(hi)) > limit:
                t.error("span", f"offsets of at most {limit:g} {unit} from the drawing", raw_got=str(value))
            elif lead is not None:
                span = (units.to_rad(lo), units.to_rad(hi)) if turning else (float(lo), float(hi))
    points = ()
    raw = t.raw("points", MISSING)
    if raw is not MISSING:
        if not isinstance(raw, list) or not all(isinstance(v, str) for v in raw) or len(raw) > len(names) + 1:
            t.error("points", "an array of joint names (the joints whose paths are reported)", raw)
        else:
            bad = [v for v in raw if v not in names]
            if bad and joints is not None:
                hint = difflib.get_close_matches(bad[0], sorted(names), n=1, cutoff=0.5)
                extra = f' (did you mean "{hint[0]}"?)' if hint else ""
                t.error("points", f"joints of [joints]{extra}", raw_got=f'"{bad[0]}", which [joints] does not have')
            else:
                points = tuple(dict.fromkeys(raw))
    output = None
    value = t.raw("output", MISSING)
    if value is not MISSING:
        choices = [k.name for k in links] + [j.name for j in joints or () if j.slider is not None]
        if not isinstance(value, str) or value not in choices:
            hint = difflib.get_close_matches(value, choices, n=1, cutoff=0.5) if isinstance(value, str) else []
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            t.error("output", f"a link or a slider joint (whose motion the mechanical advantage is "
                    f"measured on){extra}", value)
        else:
            output = value
    _steps_within_cells(t, joints, links, points)
    return span, points, output


MAX_CELLS = 3_000_000  # the kinematics table's rows x columns (a Watt six-bar tracing a point, 28 columns x
# 100,000 rows: 12 s, 0.7 GB as JSON; 67 links x 100,000 rows took 90 s, 3.6 GB and wrote 917 MB)


def _steps_within_cells(t: Table, joints, links, points) -> None:
    """[motion] steps of a drawing within MAX_CELLS of its kinematics table: rows x columns, the
    columns counted as 3 per link and slider (angle or place and their rates), 6 per traced
    point, 1 per joint (closures' transmission angles and the drives): a located line naming
    the most steps this drawing takes."""
    from linkcli.mechanisms.schema import MAX_STEPS
    steps = t.data.get("steps")  # its own range is read_drive_motion's line
    if not isinstance(steps, int) or isinstance(steps, bool) or not 2 <= steps <= MAX_STEPS or not joints or not links:
        return
    sliders = sum(1 for j in joints if j.slider is not None)
    columns = 3 * (len(links) + sliders) + 6 * len(points) + len(joints)
    if steps * columns > MAX_CELLS:
        t.error("steps", f"at most {MAX_CELLS // columns:,} steps for this drawing (its kinematics table's rows x "
                f"columns within {MAX_CELLS:,}; {columns} columns: 3 a link and a slider, 6 a traced point, 1 a "
                "joint)", steps)
