"""The five-bar as data (frozen dataclasses, pure Python: `check` reads it without numpy).

Geometry (docs/five_bar.md, SPEC "The five-bar"): local frame with the left ground pivot A0
at the origin and the right one B0 = (ground, 0); left crank A0 A (`input`, angle phi1 at
A0), right crank B0 B (`input2`, phi2 at B0), both counter-clockwise from the x axis
A0 -> B0; left distal link A P (`coupler`), right distal link B P (`coupler2`); the output
point P joins the two distal links. Global placement as the four-bar's: A0 at
`ground_pivot`, the ground line turned by `ground_angle`. Lengths in the file's length
unit, angles in radians.

`branch` (the assembly mode): the side of the line A -> B that P lies on, seen from A,
"left" or "right". A chain's working mode (`modes`, for the inverse kinematics): "+" when
its elbow (A or B) lies to the left of the line from its ground pivot to P, "-" to the
right; ("+", "-") is the common "elbows out" mode of a five-bar whose P is above the ground.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

DRIVES = ("input", "input2")  # the two driven cranks, as [motion] and phases name them
SIDES = ("left", "right")  # branch: P left or right of A -> B
MODES = ("+", "-")  # a chain's elbow left or right of the line from its ground pivot to P
DEFAULT_MODES = ("+", "-")


@dataclass(frozen=True)
class Phase:
    """Rows first..last (inclusive, 0-based) over which the drive `locked` is held still:
    the five-bar works as the four-bar left (a metamorphic phase)."""

    first: int
    last: int
    locked: str  # "input" or "input2"

    @property
    def driven(self) -> str:
        """The drive that moves over the phase."""
        return DRIVES[1 - DRIVES.index(self.locked)]


@dataclass(frozen=True)
class FiveBarMotion:
    """The rows the five-bar goes through ([motion]): either `inputs`, (phi1, phi2) per row
    (rad), or `path`, the points P must pass (global frame, length unit) with each chain's
    working mode `modes` for the inverse kinematics. `speeds` and `accelerations` are the
    drives' (rad/s, rad/s^2; a drive held by a phase stands still on its rows); `phases`
    are the metamorphic phases, in row order."""

    inputs: tuple[tuple[float, float], ...] | None = None
    path: tuple[tuple[float, float], ...] | None = None
    modes: tuple[str, str] = DEFAULT_MODES
    speeds: tuple[float, float] = (1.0, 1.0)
    accelerations: tuple[float, float] = (0.0, 0.0)
    phases: tuple[Phase, ...] = ()

    @property
    def rows(self) -> int:
        return len(self.inputs if self.inputs is not None else self.path)


@dataclass(frozen=True)
class FiveBar:
    """A planar five-bar with two drives and the rows it goes through (docstring above).
    `branch` None: the path's first row decides it (inverse kinematics)."""

    mechanism: ClassVar[str] = "five-bar"  # its home: linkcli.mechanisms
    ground: float
    input: float
    input2: float
    coupler: float
    coupler2: float
    branch: str | None = "left"
    ground_pivot: tuple[float, float] = (0.0, 0.0)
    ground_angle: float = 0.0
    motion: FiveBarMotion | None = None

    @property
    def lengths(self) -> tuple[float, float, float, float, float]:
        """(ground, input, input2, coupler, coupler2)."""
        return (self.ground, self.input, self.input2, self.coupler, self.coupler2)
