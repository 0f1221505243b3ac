"""A designed drawing kept in a result file (`synth --format toml` of a drawn design): its
[linkage] holds `joints`, `links` and `drive` as a problem file's top-level tables do
(sections.drawing_section writes them), beside the distances the report prints (linkcli's
own output: not read back). `analyze` reads the drawing from there, checked as any drawing
(drawn.schema), and analyses it as a linkage file would. Pure Python.
"""

from __future__ import annotations

from linkcli.io.reader import Table
from linkcli.mechanisms.drawn.drawing_tables import drawn_drives, drawn_joints, drawn_links, drawn_motion

KEPT = ("mechanism", "joints", "links", "drive")


def read_kept(t: Table, units, schema):
    """The Drawn of a result's [linkage] (`t`), None when in error (errors recorded); `schema`:
    the drawn home's (drawn.schema.SCHEMA), whose joint keys io.joints reads."""
    from dataclasses import replace

    from linkcli.io.joints import read_joints
    from linkcli.mechanisms.drawn.model import Drawn
    from linkcli.mechanisms.drawn.structure import analyse
    t.allow(*t.keys())  # the distances (the report's own echo: checked below, against the joints);
    # the kept tables when the joints are in error (not read then: not unknown)
    errors = len(t.reader.errors)
    specs = read_joints(t, schema, units)
    joint_table = t.table("joints")
    if specs is None or joint_table is None:
        return None
    joints = drawn_joints(joint_table, specs)
    if joints is None:
        return None
    links = drawn_links(t, joints)
    drives = drawn_drives(t, joints, links, units)
    if len(t.reader.errors) > errors or links is None or drives is None:
        return None
    drawing = Drawn(joints=joints, links=links, drives=drives, designed=True)
    structure = analyse(drawing)
    for problem in structure.problems:
        t.reader.error(("linkage",) + problem.where, problem.expected, raw_got=problem.found)
    if structure.problems or not _echo_agrees(t, drawing):
        return None
    errors = len(t.reader.errors)
    span, points, output = drawn_motion(t.reader.root(), joints, links, drives, units)  # as the problem set them
    if len(t.reader.errors) > errors:
        return None
    return replace(drawing, span=span, points=points, output=output)


def _echo_agrees(t: Table, drawing) -> bool:
    """Whether every other key of the result's [linkage] is a distance the drawing reports
    ("link A-B": two joints of one link, or of the ground) of the joints' value, to the digits
    they are written with: an edited distance would otherwise be ignored, the joints analysed as
    they stand (errors recorded). Written with d significant digits (the most of any of them:
    one precision wrote them all), a value agrees within 10^(1 - d) of itself plus the drawing's
    extent (its joints are written with as many digits)."""
    import math
    reported = drawing.distances()
    extent = max(max(abs(c) for c in j.at) for j in drawing.joints)
    numbers = [v for k, v in t.data.items() if k not in KEPT and isinstance(v, (int, float)) and not isinstance(v, bool)
               and math.isfinite(v)]
    digits = max((_digits(v) for v in numbers), default=1)  # the precision they were written with
    ok = True
    for key in (k for k in t.keys() if k not in KEPT):
        value = t.raw(key)
        if key not in reported:
            t.error(key, "a distance the drawing reports (link A-B: two joints of one link or of the ground) "
                    "or one of: " + ", ".join(KEPT), raw_got=f'"{key}"')
            ok = False
        elif isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            t.error(key, "a number: the distance its joints give (length unit)", value)
            ok = False
        elif abs(value - reported[key]) > 10.0 ** (1 - digits) * (abs(value) + extent):
            t.error(key, f"the distance its joints give, {reported[key]:.6g} (the distances echo the "
                    "joints: edit the joints, then update or delete the distances)", value)
            ok = False
    return ok


def _digits(value: float) -> int:
    """The significant digits of a number as written (its shortest repr: 9.81113 -> 6)."""
    mantissa = repr(abs(float(value))).split("e")[0].replace(".", "").lstrip("0").rstrip("0")
    return max(len(mantissa), 1)
