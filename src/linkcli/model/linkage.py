"""A linkage to analyse (types.linkage, and result files read by `analyze`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # names of annotations only (imported where they are used)
    from linkcli.model import Linkage, Meta


@dataclass(frozen=True)
class LinkageProblem:
    """Analysis of a given linkage of any mechanism, driven at a constant input speed (or, for
    the five-bar, through its rows)."""

    meta: Meta
    linkage: Linkage  # its home's record (model.Linkage)
    input_speed: float = 1.0  # rad/s
    steps: int = 360
