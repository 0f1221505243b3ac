"""Units: lengths stay in the file's unit; angles are radians inside, the file's unit outside."""

from __future__ import annotations

import math
from dataclasses import dataclass

LENGTH_TO_MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4}
ANGLE_UNITS = ("deg", "rad")


@dataclass(frozen=True)
class Units:
    length: str = "mm"
    angle: str = "deg"

    def to_rad(self, value: float) -> float:
        """An angle in the file's unit, in radians."""
        return math.radians(value) if self.angle == "deg" else float(value)

    def from_rad(self, value):
        """An angle (or array of angles) in radians, in the file's unit."""
        if self.angle == "deg":
            return value * (180.0 / math.pi)
        return value

    def angles_to_rad(self, value):
        """Angles (a number or a numpy array) in the file's unit, in radians, as
        value / (180/pi): the inverse of from_rad, for the values a plot reads back from
        a report (to_rad, math.radians, may differ from it in the last bit)."""
        if self.angle == "deg":
            return value / (180.0 / math.pi)
        return value

    @property
    def mm_per_length(self) -> float:
        return LENGTH_TO_MM[self.length]
