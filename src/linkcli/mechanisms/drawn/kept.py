"""A designed drawing kept in a result file (`synth --format toml` of a drawn design): its
[linkage] holds `joints`, `links` and `drive` as a problem file's top-level tables do
(sections.drawing_section writes them), beside the distances the report prints (linkcli's
own output: not read back). `analyze` reads the drawing from there, checked as any drawing
(drawn.schema), and analyses it as a linkage file would. Pure Python.
"""

from __future__ import annotations

from linkcli.io.reader import Table
from linkcli.mechanisms.drawn.drawing_tables import drawn_drives, drawn_joints, drawn_links

KEPT = ("mechanism", "joints", "links", "drive")


def read_kept(t: Table, units, schema):
    """The Drawn of a result's [linkage] (`t`), None when in error (errors recorded); `schema`:
    the drawn home's (drawn.schema.SCHEMA), whose joint keys io.joints reads."""
    from dataclasses import replace

    from linkcli.io.joints import read_joints
    from linkcli.mechanisms.drawn.model import Drawn
    from linkcli.mechanisms.drawn.structure import analyse
    t.allow(*(k for k in t.keys() if k not in KEPT))  # the distances: the report's own echo
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
    if structure.problems:
        return None
    motion = t.reader.root().table("motion")
    points = ()
    if motion is not None and isinstance(motion.data.get("points"), list):
        names = {j.name for j in joints}
        points = tuple(p for p in motion.raw("points") if isinstance(p, str) and p in names)
    return replace(drawing, points=points)
