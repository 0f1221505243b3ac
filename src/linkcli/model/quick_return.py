"""A quick-return problem (types.quick_return)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # names of annotations only (imported where they are used)
    from linkcli.model import Meta


@dataclass(frozen=True)
class QuickReturnProblem:
    """A crank-rocker or slider-crank designed by its time ratio (SPEC section 2,
    quick-return). Lengths in the length unit, angles in radians."""

    meta: Meta
    mechanism: str  # "crank-rocker" or "slider-crank"
    time_ratio: float  # K >= 1
    swing: float | None = None  # crank-rocker: rocker swing, rad, in (0, pi)
    stroke: float | None = None  # slider-crank: slider stroke
    scale: tuple[str, float] | None = None  # crank-rocker: ("ground" | "output", length)
    offset: float | None = None  # slider-crank: given (signed) offset; None: free
    bounds: dict = field(default_factory=dict)  # "parameter" | a length -> (lo, hi)
    transmission: tuple[float, float] | None = None  # window on mu over the full turn, rad
    lines: dict = field(default_factory=dict)  # key ("swing", "linkage.offset", ...) -> line
