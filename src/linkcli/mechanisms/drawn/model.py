"""A drawn linkage as validated data (docs/drawn.md): joints at their drawn places, links as
the joints they carry, drives, and what the motion study reports. Pure Python (`check`
builds it without numpy).

Lengths are in the file's length unit, angles in radians, speeds in rad/s (a turning drive)
or length unit/s (a sliding drive).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

TURN, SLIDE = "turn", "slide"


@dataclass(frozen=True)
class DrawnJoint:
    """A joint at `at` (global frame). `ground`: fixed to the ground. `slider`: the joint is a
    slider block's pin and the block slides on a straight guide through `at` at this angle
    (rad, global, as drawn), fixed to the link `guide` (None: the ground)."""

    name: str
    at: tuple[float, float]
    ground: bool = False
    slider: float | None = None
    guide: str | None = None


@dataclass(frozen=True)
class DrawnLink:
    """A rigid link carrying `joints` (2 or more, in the file's order). Its frame: origin at
    the first joint, x axis towards the second, both as drawn (fixed in the link)."""

    name: str
    joints: tuple[str, ...]


@dataclass(frozen=True)
class Drive:
    """A degree of freedom driven at a constant `speed`: a link turning about its ground
    joint (`kind` "turn", rad/s) or a slider joint moved along its guide ("slide", length
    unit/s)."""

    name: str
    kind: str
    speed: float


@dataclass(frozen=True)
class Drawn:
    """A drawn linkage: the drawing, its drives (the first leads: the study's rows are its
    values; the others move in proportion to their speeds), the points whose paths are
    reported, the span of the leading drive (offsets from its drawn value; None: a full
    turn, or its whole range when it cannot turn fully), and the output the mechanical
    advantage is measured on (a link or a slider joint; None: the last link). A designed drawing
(`designed`, synthesis) is reported with its joints, links and drive."""

    mechanism: ClassVar[str] = "drawn"  # its home: linkcli.mechanisms
    joints: tuple[DrawnJoint, ...]
    links: tuple[DrawnLink, ...]
    drives: tuple[Drive, ...]
    points: tuple[str, ...] = ()
    span: tuple[float, float] | None = None
    output: str | None = None
    designed: bool = False  # a design's drawing: the report's linkage section keeps it (a result
    # file is analysed again: mechanisms.drawn.kept)

    def joint(self, name: str) -> DrawnJoint:
        return next(j for j in self.joints if j.name == name)

    def link(self, name: str) -> DrawnLink:
        return next(k for k in self.links if k.name == name)

    def distances(self) -> dict[str, float]:
        """"link A-B" -> |A B| for every two joints of each link (and of the ground, "ground
        A-B"), as drawn: what a report lists beside the drawing."""
        return {f"{body} {a}-{b}": d for body, a, b, d in pair_distances(self.joints, self.links)}


def pair_distances(joints, links) -> list[tuple[str, str, str, float]]:
    """(body, A, B, |A B|) for every two joints of each link, the ground's first ("ground": its
    ground joints), in the order drawn: a drawing's link lengths (Drawn.distances, the tolerance
    checks' shortest per link, the reader's bounds on them)."""
    import math
    at = {j.name: j.at for j in joints}
    ground = [j.name for j in joints if j.ground]
    return [(body, a, b, math.dist(at[a], at[b]))
            for body, carried in [("ground", ground)] + [(k.name, k.joints) for k in links]
            for i, a in enumerate(carried) for b in carried[i + 1:]]
