"""The keys of a drawn linkage's design (docs/drawn_synthesis.md): path-, motion- and
function-generation with `[linkage] mechanism = "drawn"`. Pure Python (`check` reads it
without numpy).

    [linkage]      mechanism = "drawn"; topology = "watt-i" ... | "any six-bar" instead of a
                   drawing: linkcli draws and searches the catalogue's starting designs
                   (synthesis.sweep; docs/six_bars.md)
    [joints], [links], [drive]   the starting design, as for analysis (drawn.schema): one
                   drive, a link turning about its ground joint; every closure a dyad, RRP,
                   RPR or a group of pinned links (a class-III triad: drawn.population_groups;
                   no group carrying a slider)
    [motion]       steps (the kinematics section's rows), points, output (as for analysis)
    [target]       path: joint = "F" (a joint that moves), points, timing, input_angles,
                   direction (as four-bar path generation); motion: link = "name", poses,
                   timing, input_angles, angle_weight (as four-bar motion generation);
                   function: link = "name", output = "<law in phi, phi0, psi0>" or
                   function = "<f(x)>" with x and output_sweep, input_sweep, points,
                   spacing, input_start and output_start (angles from the drawn position:
                   default 0, or free with [bounds])
    [bounds]       a free joint: NAME = { x = [lo, hi], y = [lo, hi] } (a number fixes the
                   coordinate), each box holding the joint's drawn place; input_offset
                   (prescribed timing); input_start, output_start (function generation);
                   with a topology no joint's box but `reach` (every joint free within
                   reach x the target's diagonal of its drawn place; default REACH)
    [constraints]  transmission = [lo, hi] (every closure), drive = "crank" (the driving
                   link turns fully) | "any" (default: it may rock), defect_free
    [objective]    minimize = "error" | "failure-probability" (io.robust_keys), or an array of
                   two or three objectives: a Pareto front (reading.pareto_keys, synthesis.pareto)
"""

from __future__ import annotations

import difflib
from dataclasses import replace

from linkcli.io.bounds import MAX_LENGTH
from linkcli.io.reader import Table, describe

DRIVES = ("any", "crank")
KINDS = {"path-generation": "path", "motion-generation": "motion", "function-generation": "function"}
TARGET_KEYS = {
    "path": ("joint", "points", "timing", "input_angles", "direction"),
    "motion": ("link", "poses", "timing", "input_angles", "angle_weight"),
    "function": ("link", "output", "function", "input_start", "output_start", "input_sweep",
                 "output_sweep", "x", "points", "spacing"),
}
TIMING_BOUNDS = {"path": ("input_offset",), "motion": ("input_offset",),
                 "function": ("input_start", "output_start")}
REACH = 0.2  # a topology's joints: free within REACH x the target's diagonal of their drawn place
FUNCTION_REACH = 0.5  # a function's moving joints (its ground pivots held where drawn: synthesis.sweep):
# a function's error is in turns, so its shapes, not its size, need the room (the dwell of
# problems/six_bar_dwell_sweep.toml: the four-bar's best within 0.2 is 0.030 rad^2, within 0.5 0.0078)
MAX_REACH = 2.0
MIN_REACH = 1e-6  # below, a box is narrower than the search's steps resolve: no joint would move
TRACER = "P"  # a topology's path tracer (drawn.catalogue)
OUTPUT = "output"  # a topology's function output link (drawn.catalogue)


def read_path(root: Table, meta):
    return read(root, meta, "path-generation")


def read_motion(root: Table, meta):
    return read(root, meta, "motion-generation")


def read_function(root: Table, meta):
    return read(root, meta, "function-generation")


def read(root: Table, meta, type_name: str):
    """The DrawnDesignProblem of a design file; None after recording every error found."""
    from linkcli.mechanisms.drawn.schema import read as read_drawing
    from linkcli.mechanisms.schema import read_drive_motion as read_steps
    from linkcli.model import DrawnDesignProblem
    from linkcli.reading.robust_keys import read_objective
    kind = KINDS[type_name]
    u = meta.units
    if meta.solver.method != "auto":  # the shared search is the one strategy of a drawn design
        root.reader.error(("solver", "method"), 'method = "auto" for a drawn linkage (the shared search: '
                          "docs/drawn_synthesis.md)", raw_got=f'"{meta.solver.method}"')
    link_t = root.table("linkage")
    topology, drawing = None, None
    if link_t is not None and "topology" in link_t:
        from linkcli.mechanisms.drawn.topology import read_topology
        link_t.allow("topology")
        topology = read_topology(link_t) or False
    else:
        drawing = read_drawing(link_t, u)
    _, steps = read_steps(root)
    drawing = drawing if drawing is None else _one_turning_drive(root, drawing)
    if topology is not None:
        _refuse_unnamed_tables(root)
    tgt = root.table("target", required=True)
    if tgt is not None:
        tgt.allow(*TARGET_KEYS[kind])
    bnd = root.table("bounds")
    boxes, reach = (), REACH
    if topology is not None:
        reach = _reach(bnd, kind)
    elif drawing is not None:
        boxes = _boxes(bnd, drawing, kind)
    elif bnd is not None:  # the drawing has an error of its own: its joints' boxes are not checked against it
        bnd.allow(*bnd.keys())
    drive, window = _constraints(root, u)
    robust = read_objective(root, meta)
    front_ok, front = _front(root, meta, kind, topology)  # [objective] minimize = [...]: a Pareto front
    meta = replace(meta, front=front) if front is not None else meta
    fields = None
    if tgt is not None and (drawing is not None or topology):
        fields = {"path": _path_target, "motion": _motion_target, "function": _function_target}[kind](
            tgt, bnd, drawing, u)
    if topology is not None and fields is not None and topology:
        fields = _topology_timing(kind, fields)
        from linkcli.mechanisms.drawn import catalogue
        why = catalogue.empty_reason(topology, kind, catalogue.timing_of(kind, fields.get("timing", "prescribed")))
        if why:  # no catalogued drawing to search (the sweep would find none): said where the topology is
            link_t.error("topology", "a topology with a choice the design can search", raw_got=why)
            topology = False
    if (None in (boxes, drive, fields, robust, steps, reach) or window is False or topology is False or not front_ok
            or (drawing is None and topology is None)):
        return None
    lines = {".".join(k): root.reader.line_of(k) for k in (("target",), ("bounds",), ("constraints",))}
    return DrawnDesignProblem(meta=meta, kind=kind, drawing=drawing, boxes=boxes, drive=drive,
                              transmission=window, steps=steps, lines=lines, objective=robust[0],
                              defect_free=robust[1], topology=topology, reach=reach, **fields)


NAMED_TABLES = ("loads", "masses", "sections", "material", "strength")  # keyed by the drawing's links and joints


def _refuse_unnamed_tables(root: Table) -> None:
    """[loads], [masses], [sections], [material], [strength] with [linkage] topology: one line each.
    They name the drawing's links and joints, which a topology's file has not (each choice is
    drawn by the search): they were read against nothing and dropped without a word. The
    design found is a result file that takes them (docs/format.md, result files)."""
    for name in NAMED_TABLES:
        if name in root:
            value = root.raw(name)
            root.error(name, f"no [{name}] with [linkage] topology (its links and joints are the design "
                       f"found: add [{name}] to the design's result file and analyze it)",
                       raw_got=f"a [{name}] table" if isinstance(value, dict) else describe(value))


def _front(root: Table, meta, kind: str, topology):
    """(ok, Front or None) of [objective] minimize = [...] (reading.pareto_keys): the
    objectives the kind measures (motion generation: no [loads] or [tolerance], so no
    torque, pin-force or failure-probability); not with a topology (a front is one
    drawing's: docs/pareto.md)."""
    from linkcli.reading.pareto_keys import KEYS, OBJECTIVES, is_front, read_front
    if topology is not None and is_front(root):
        t = root.table("objective")
        t.allow(*KEYS)
        t.error("minimize", "a drawn linkage's joints for a Pareto front (a front is one drawing's; "
                "with [linkage] topology, design each catalogued drawing on its own)",
                raw_got="[linkage] topology")
        return False, None
    if kind == "motion":
        from linkcli.types.motion_generation.schema import OBJECTIVES as MOTION
        return read_front(root, meta, MOTION)
    return read_front(root, meta, OBJECTIVES)


def _reach(bnd: Table | None, kind: str):
    """[bounds] of a topology: `reach` and the timing keys, no joint's box (the joints are the
    catalogue's, drawn anew for each choice); None after an error."""
    default = FUNCTION_REACH if kind == "function" else REACH
    if bnd is None:
        return default
    ok = True
    for key in list(bnd.keys()):
        if key in TIMING_BOUNDS[kind] or key == "reach":
            continue
        bnd.raw(key)
        bnd.error(key, f"no joint's box with [linkage] topology (each starting drawing's joints are free "
                  f"within reach x the target's diagonal of their drawn place: reach = {default:g} unless "
                  f"given) or one of: reach, {', '.join(TIMING_BOUNDS[kind])}", raw_got=f'"{key}"')
        ok = False
    what = f"a fraction of the target's diagonal in [{MIN_REACH:g}, {MAX_REACH:g}]"
    reach = bnd.number("reach", default, lo=MIN_REACH, hi=MAX_REACH, what=what) if "reach" in bnd else default
    return reach if ok else None


def _topology_timing(kind: str, fields: dict) -> dict:
    """A topology's drawings are drawn at a drive angle of linkcli's choosing: prescribed
    input angles keep their spacing with the offset free over a full turn (unless [bounds]
    input_offset narrows it)."""
    import math
    if kind != "function" and fields["timing"] == "prescribed" and fields["input_offset"] is None:
        fields = dict(fields, input_offset=(-math.pi, math.pi))
    return fields


# ---------------------------------------------------------------- the drawing

def _one_turning_drive(root: Table, drawing):
    """The drawing when it has one drive turning a link (synthesis measures its angle), and
    every group one the population solves (no slider in a group); else None (error
    recorded, located)."""
    from linkcli.mechanisms.drawn.model import TURN
    from linkcli.mechanisms.drawn.structure import analyse
    drives = drawing.drives
    if len(drives) != 1 or drives[0].kind != TURN:
        found = (f"{len(drives)} drives ({', '.join(d.name for d in drives)})" if len(drives) != 1
                 else f"slider {drives[0].name} moved along its guide")
        root.reader.error(("drive",), "one drive turning a link about its ground joint (a design measures "
                          "its targets by that link's angle)", raw_got=found)
        return None
    group = closed_form_problem(analyse(drawing))
    if group is not None:
        root.reader.error(("links", group[0]), "a drawing whose closures are dyads, RRP, RPR or groups of "
                          "pinned links (what a design can run over a whole population)",
                          raw_got=f"links {', '.join(group)} closed together with a slider "
                                  "(a group of more than two links carrying a slider)")
        return None
    return drawing


def _boxes(bnd: Table | None, drawing, kind: str):
    """((joint, ((x lo, x hi), (y lo, y hi))), ...) in file order: each box holds the
    joint's drawn place; None after an error."""
    from linkcli.types.path_generation.schema import point_range
    if bnd is None:
        return ()
    names = [j.name for j in drawing.joints]
    timing = TIMING_BOUNDS[kind]
    out, ok = [], True
    for key in list(bnd.keys()):
        if key in timing:
            continue  # read with the target (it depends on the timing)
        if key not in names:
            hint = difflib.get_close_matches(key, names + list(timing), n=1, cutoff=0.5)
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            bnd.raw(key)
            bnd.error(key, f"a joint of [joints] (its box: {{ x = [lo, hi], y = [lo, hi] }}) or one of: "
                      f"{', '.join(timing)}{extra}", raw_got=f'"{key}", which the drawing does not have')
            ok = False
            continue
        box = point_range(bnd, key, None)  # each end a coordinate of at most MAX_MAGNITUDE (1e9)
        if box is None:
            ok = False
            continue
        at = drawing.joint(key).at
        sub = bnd.table(key)
        for c, (lo, hi), v in zip("xy", box, at):
            if not lo <= v <= hi:
                sub.error(c, f"a range holding {key}'s drawn {c} = {v:g} (the box of a free joint holds its "
                          "drawn place: the starting design)", raw_got=f"[{lo:g}, {hi:g}]" if lo < hi else f"{lo:g}")
                ok = False
        out.append((key, box))
    return tuple(out) if ok else None


def _constraints(root: Table, u):
    """(drive, window): window None without one, False after an error; drive None after one."""
    from linkcli.types.path_generation.schema import transmission_window
    con = root.table("constraints")
    if con is None:
        return "any", None
    con.allow("transmission", "drive", "defect_free")  # defect_free: io.robust_keys
    drive = con.string("drive", "any", choices=DRIVES)
    window, ok = transmission_window(con, u)
    return drive, (window if ok else False)


def _moving_joint(tgt: Table, drawing):
    name = tgt.string("joint")
    if name is None:
        return None
    names = [j.name for j in drawing.joints]
    if name not in names:
        hint = difflib.get_close_matches(name, names, n=1, cutoff=0.5)
        extra = f' (did you mean "{hint[0]}"?)' if hint else ""
        tgt.error("joint", f"a joint of [joints]{extra}", raw_got=f'"{name}", which the drawing does not have')
        return None
    if drawing.joint(name).ground:
        tgt.error("joint", "a joint that moves (the path of a ground pivot is a point)",
                  raw_got=f'"{name}", a ground joint')
        return None
    return name


def _moving_link(tgt: Table, drawing):
    name = tgt.string("link")
    if name is None:
        return None
    links = [k.name for k in drawing.links]
    if name not in links:
        hint = difflib.get_close_matches(name, links, n=1, cutoff=0.5)
        extra = f' (did you mean "{hint[0]}"?)' if hint else ""
        why = "the ground, which does not move" if name == "ground" else "which [links] does not have"
        tgt.error("link", f"a link of [links]{extra}", raw_got=f'"{name}", {why}')
        return None
    return name


# ---------------------------------------------------------------- targets

def _timing(tgt: Table, bnd: Table | None, n: int | None, u, item: str):
    """(timing, input_angles, input_offset, direction) of a path or motion target; None after an
    error."""
    from linkcli.types.path_generation.schema import DIRECTIONS, angle_range, read_input_angles
    timing = tgt.string("timing", "prescribed" if "input_angles" in tgt else "free",
                        choices=("prescribed", "free"))
    if timing is None:
        return None
    direction = "either"
    if timing == "free":
        direction = tgt.string("direction", "either", choices=DIRECTIONS) if "direction" in tgt else "either"
    elif "direction" in tgt:
        tgt.error("direction", 'no direction with timing = "prescribed" (the input angles set it)',
                  raw_got=describe(tgt.raw("direction")))
        direction = None  # the angles and the offset still read: a key left unread would be blamed as unknown
    angles = read_input_angles(tgt, timing, n, u, item=item) if n is not None else None
    offset = None
    if bnd is not None and "input_offset" in bnd:
        if timing == "free":
            bnd.error("input_offset", 'no input_offset with timing = "free" (every input angle is free)',
                      raw_got=describe(bnd.raw("input_offset")))
            return None
        offset = angle_range(bnd, "input_offset", None, u)
        if offset is None:
            return None
    if direction is None or angles is None:
        return None
    return timing, (angles if timing == "prescribed" else None), offset, direction


def _named_by_topology(tgt: Table, key: str, name: str | None, what: str):
    """A topology's target joint or link is the catalogue's: `key` absent or `name` (None:
    each choice names its own, and the key is refused). "" stands for "each choice's"."""
    if key not in tgt:
        return name if name is not None else ""
    value = tgt.string(key)
    if value is None:
        return None
    if name is None or value != name:
        tgt.error(key, f"no {key} with [linkage] topology ({what})" if name is None
                  else f'{key} = "{name}" or none with [linkage] topology ({what})', raw_got=f'"{value}"')
        return None
    return value


def _path_target(tgt: Table, bnd, drawing, u):
    from linkcli.types.path_generation.schema import MAX_FREE_POINTS, _points
    joint = (_moving_joint(tgt, drawing) if drawing is not None else
             _named_by_topology(tgt, "joint", TRACER, f"the tracer is {TRACER}, on the link each choice names"))
    points = _points(tgt)
    timing = _timing(tgt, bnd, len(points) if points is not None else None, u, "point")
    if timing is not None and points is not None and timing[0] == "free" and len(points) > MAX_FREE_POINTS:
        tgt.error("points", f"at most {MAX_FREE_POINTS} points with free timing (each point adds an input "
                  "angle to the unknowns)", raw_got=f"an array of {len(points)}")
        return None
    if joint is None or points is None or timing is None:
        return None
    return dict(joint=joint, points=tuple(points), timing=timing[0], input_angles=timing[1],
                input_offset=timing[2], direction=timing[3])


def _motion_target(tgt: Table, bnd, drawing, u):
    from linkcli.types.motion_generation.schema import _poses
    link = (_moving_link(tgt, drawing) if drawing is not None else
            _named_by_topology(tgt, "link", None, "the guided body is the link each choice names"))
    poses = _poses(tgt, u)
    timing = _timing(tgt, bnd, len(poses) if poses is not None else None, u, "pose")
    weight = tgt.number("angle_weight", None, positive=True, hi=MAX_LENGTH, what="a positive length") \
        if "angle_weight" in tgt else None
    if link is None or poses is None or timing is None or ("angle_weight" in tgt and weight is None):
        return None
    return dict(link=link or None, poses=tuple(poses), timing=timing[0], input_angles=timing[1],
                input_offset=timing[2], direction=timing[3], angle_weight=weight)


def _function_target(tgt: Table, bnd, drawing, u):
    """The law of a link's angle (function generation's keys; the start angles measured from the
    drawn position, default 0, or free with [bounds])."""
    from linkcli.types.function_generation import schema as fg
    link = (_moving_link(tgt, drawing) if drawing is not None else
            _named_by_topology(tgt, "link", OUTPUT, f"the output link is {OUTPUT}"))
    if link and drawing is not None and any(d.name == link for d in drawing.drives):
        tgt.error("link", "a link the drive turns through the linkage, not the driving link (its angle is "
                  "the drive's: no design changes it)", raw_got=f'"{link}", the driving link')
        link = None
    form_law = fg.read_law(tgt)
    sweep = fg.read_sweep(tgt, "input_sweep", u)
    points = tgt.number("points", fg.DEFAULT_POINTS, integer=True, lo=2, hi=fg.MAX_POINTS)
    spacing = tgt.string("spacing", "uniform", choices=fg.SPACINGS)
    function = fg.read_function_keys(tgt, form_law[0] if form_law else None, u)
    free = ("output_start",) if drawing is None and form_law is not None and form_law[0] == "function" else ()
    starts = _starts(tgt, bnd, u, free)
    if None in (link, form_law, sweep, points, spacing, function, starts):
        return None
    form, law = form_law
    given, bounds = starts
    t = fg.fractions(points, spacing)
    output_sweep, x_range = function
    shape: tuple = ()
    if form == "function":
        shape = fg.function_shape(tgt, law, x_range, t)
        if shape is None:
            return None
    elif not bounds:
        if not fg.check_law_at_points(tgt, law, given, sweep, t, u):
            return None
    elif not fg.check_law_for_some_start(tgt, law, given, bounds, sweep, t, u):
        return None
    return dict(link=link or None, law=law, form=form, input_sweep=sweep, fractions=t,
                input_start=given.get("input_start"), output_start=given.get("output_start"),
                start_bounds=bounds, output_sweep=output_sweep, x_range=x_range, shape=shape)


def _starts(tgt: Table, bnd: Table | None, u, free: tuple[str, ...] = ()):
    """(given, bounds) of input_start and output_start: given in [target] (angle), free in
    [bounds] (range), never both; absent: 0 (the drawn position, the link's drawn angle), or
    free over a turn for the keys in `free` (a topology's function form: its law is a shape,
    placed at an output start of the search's choosing; the input start stays the drawn
    position, the drawings' free crank pins placing it)."""
    import math

    from linkcli.types.path_generation.schema import angle_range
    given, bounds, ok = {}, {}, True
    for key in ("input_start", "output_start"):
        in_tgt, in_bnd = key in tgt, bnd is not None and key in bnd
        if in_tgt and in_bnd:
            bnd.raw(key)
            bnd.error(key, "a start angle either given in [target] or bounded in [bounds], not both",
                      raw_got=f"target.{key} = {describe(tgt.raw(key))} and bounds.{key} = {describe(bnd.data[key])}")
            ok = False
        elif in_bnd:
            r = angle_range(bnd, key, None, u)
            if r is None:
                ok = False
            elif r[0] == r[1]:
                given[key] = r[0]
            else:
                bounds[key] = r
        elif in_tgt:
            value = tgt.number(key, lo=-MAX_LENGTH, hi=MAX_LENGTH, what=f"an angle ({u.angle}) from the drawn position")
            if value is None:
                ok = False
            else:
                given[key] = u.to_rad(value)
        elif key in free:
            bounds[key] = (-math.pi, math.pi)
        else:
            given[key] = 0.0
    return (given, bounds) if ok else None


def closed_form_problem(structure) -> tuple[str, ...] | None:
    """The links of the first group the population cannot solve (drawn.population_groups:
    a group carrying a slider's guide or block), or None: dyads, RRP, RPR and pinned groups
    (a class-III triad and the like, by continuation from the drawing) all run over a
    population."""
    from linkcli.mechanisms.drawn.structure import Group, unsupported
    groups = [op for op in structure.plan if isinstance(op, Group) and unsupported(structure, op)]
    return groups[0].links if groups else None
