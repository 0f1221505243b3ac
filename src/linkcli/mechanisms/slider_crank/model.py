"""The slider-crank as data (a frozen dataclass, pure Python: `check` reads it without numpy)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

BRANCHES = ("open", "crossed")  # the slider at a cos(phi) plus (open) or minus (crossed) the root (docs/format.md)


@dataclass(frozen=True)
class SliderCrank:
    """An offset slider-crank: lengths in the length unit; coupler_point (px, py) in the
    coupler frame (origin A, x along A -> B), as the four-bar's (the conventions of docs/format.md)."""

    mechanism: ClassVar[str] = "slider-crank"
    input: float
    coupler: float
    offset: float
    branch: str = "open"
    coupler_point: tuple[float, float] | None = None

    @property
    def abe(self) -> tuple[float, float, float]:
        """(crank, rod, offset)."""
        return self.input, self.coupler, self.offset
