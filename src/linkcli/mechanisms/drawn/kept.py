"""A designed drawing kept in a result file (`synth --format toml` of a drawn design): its
[linkage] holds `joints`, `links` and `drive` as a problem file's top-level tables do
(sections.drawing_section writes them), beside the distances the report prints (linkcli's
own output: not read back). `analyze` reads the drawing from there, checked as any drawing
(drawn.schema), and analyses it as a linkage file would. Pure Python.
"""

from __future__ import annotations

from linkcli.io.reader import Table

KEPT = ("mechanism", "joints", "links", "drive")


def read_kept(t: Table, units):
    """The Drawn of a result's [linkage] (`t`), None when in error (errors recorded)."""
    from dataclasses import replace

    from linkcli.io.joints import read_joints
    from linkcli.mechanisms.drawn.model import Drawn
    from linkcli.mechanisms.drawn.schema import SCHEMA, _drawn_joints, _drives, _links
    from linkcli.mechanisms.drawn.structure import analyse
    t.allow(*(k for k in t.keys() if k not in KEPT))  # the distances: the report's own echo
    errors = len(t.reader.errors)
    specs = read_joints(t, SCHEMA, units)
    joint_table = t.table("joints")
    if specs is None or joint_table is None:
        return None
    joints = _drawn_joints(joint_table, specs)
    if joints is None:
        return None
    links = _links(t, joints)
    drives = _drives(t, joints, links, units)
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
