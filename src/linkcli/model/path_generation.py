"""A path-generation problem (types.path_generation)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar


@dataclass(frozen=True)
class PathGenerationProblem:
    """A coupler point through target points (docs/format.md, path-generation).

    Every bound is (lo, hi); lo == hi fixes the value. Lengths in the length unit (a
    length's lo may be 0: the solver keeps it strictly positive), angles in radians.
    `input_angles` (prescribed timing) are measured in the local frame from A0 -> B0."""

    mechanism: ClassVar[str] = "four-bar"  # the mechanism designed (its home's synthesis face)
    meta: Meta
    points: tuple[tuple[float, float], ...]  # targets, global frame
    timing: str  # "prescribed" or "free"
    input_angles: tuple[float, ...] | None  # prescribed timing: one per point, rad
    direction: str  # free timing: "ccw", "cw" or "either" (the solver picks)
    lengths: dict  # "ground", "input", "coupler", "output" -> (lo, hi)
    coupler_point: tuple[tuple[float, float], tuple[float, float]]  # (x lo, hi), (y lo, hi)
    ground_pivot: tuple[tuple[float, float], tuple[float, float]]
    ground_angle: tuple[float, float]  # rad
    input_offset: tuple[float, float] | None = None  # prescribed timing: rad, added to every angle
    grashof: str = "any"  # a class of mechanisms.four_bar.kinematics.GRASHOF_CLASSES (not change-point) or "any"
    transmission: tuple[float, float] | None = None  # window on mu, rad
    branch: str = "either"  # "open", "crossed" or "either"
    lines: dict = field(default_factory=dict)  # key -> line of the file, for messages
    objective: str = "error"  # [objective] minimize: "error" or "failure-probability" (robust design)
    defect_free: float = 0.99  # [constraints] defect_free: least share of made linkages that assemble
