"""A motion-generation problem (types.motion_generation)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar


@dataclass(frozen=True)
class MotionGenerationProblem:
    """A body guided through poses (docs/format.md, motion-generation). Poses (x, y, angle)
    in the length unit and radians, global frame; pivots as given ((x, y) pairs: A0 and B0
    global, or A and B in the body frame), bounds like PathGenerationProblem."""

    mechanism: ClassVar[str] = "four-bar"  # the mechanism designed (its home's synthesis face)
    meta: Meta
    poses: tuple[tuple[float, float, float], ...]
    timing: str  # "free" or "prescribed"
    input_angles: tuple[float, ...] | None  # prescribed timing: one per pose, rad
    angle_weight: float | None  # length; None: the poses' characteristic length
    ground_pivots: tuple[tuple[float, float], tuple[float, float]] | None
    moving_pivots: tuple[tuple[float, float], tuple[float, float]] | None
    lengths: dict  # "ground", "input", "coupler", "output" -> (lo, hi)
    ground_pivot: tuple[tuple[float, float], tuple[float, float]]
    ground_angle: tuple[float, float]  # rad
    input_offset: tuple[float, float] | None = None  # prescribed timing: rad
    grashof: str = "any"
    transmission: tuple[float, float] | None = None  # window on mu, rad
    branch: str = "either"
    lines: dict = field(default_factory=dict)  # key -> line of the file, for messages
