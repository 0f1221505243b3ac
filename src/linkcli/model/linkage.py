"""A linkage to analyse (types.linkage, and result files read by `analyze`)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class LinkageProblem:
    """Analysis of a given four-bar driven at a constant input speed."""

    meta: Meta
    linkage: FourBar
    input_speed: float = 1.0  # rad/s
    steps: int = 360
