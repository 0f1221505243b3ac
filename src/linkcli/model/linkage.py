"""A linkage to analyse (types.linkage, and result files read by `analyze`)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class LinkageProblem:
    """Analysis of a given linkage of any mechanism, driven at a constant input speed (or, for
    the five-bar, through its rows)."""

    meta: Meta
    linkage: Linkage  # its home's record (model.Linkage)
    input_speed: float = 1.0  # rad/s
    steps: int = 360
