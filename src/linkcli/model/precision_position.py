"""A precision-position problem (types.precision_position)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # names of annotations only (imported where they are used)
    from linkcli.model import Meta


@dataclass(frozen=True)
class PrecisionPositionProblem:
    """Freudenstein function generation through paired (phi_i, psi_i) positions."""

    meta: Meta
    ground: float | None  # None for a slider-crank (it has no ground link)
    input_angles: tuple[float, ...]
    output_angles: tuple[float, ...]  # slider-crank: slider positions s_i (length unit)
    lines: tuple[int | None, ...] = ()  # line of each position pair, for messages
    input_speed: float = 1.0  # rad/s, [motion] of the kinematics section
    steps: int = 360
    mechanism: str = "four-bar"  # or "slider-crank" ([linkage] mechanism)
