"""The four-bar as data (a frozen dataclass, pure Python: `check` reads it without numpy)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

LINKS = ("ground", "input", "coupler", "output")
BRANCHES = ("open", "crossed")


@dataclass(frozen=True)
class FourBar:
    """A planar four-bar (the conventions of docs/format.md). Lengths in the length unit, angles in radians."""

    mechanism: ClassVar[str] = "four-bar"
    ground: float
    input: float
    coupler: float
    output: float
    branch: str = "open"
    coupler_point: tuple[float, float] | None = None
    ground_pivot: tuple[float, float] = (0.0, 0.0)
    ground_angle: float = 0.0
    coupler_angle: float | None = None  # motion generation: the body's x axis from A -> B, rad

    @property
    def abcd(self) -> tuple[float, float, float, float]:
        """Seed-paper letters: a = input, b = coupler, c = output, d = ground."""
        return (self.input, self.coupler, self.output, self.ground)
