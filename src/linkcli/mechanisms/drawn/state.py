"""The state of a drawn linkage over rows: every body's pose and every joint's place, with
their rates when asked (drawn.solver fills it op by op; drawn.groups solves its groups on
it). numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class State:
    """Poses of every body and places of every joint over n rows, with rates when asked
    (`rates`). theta/omega/alpha: (n,); origin/origin_v/origin_a, pos/vel/acc: (n, 2)."""

    n: int
    q: np.ndarray
    rates: bool
    theta: dict = field(default_factory=dict)
    omega: dict = field(default_factory=dict)
    alpha: dict = field(default_factory=dict)
    origin: dict = field(default_factory=dict)
    origin_v: dict = field(default_factory=dict)
    origin_a: dict = field(default_factory=dict)
    pos: dict = field(default_factory=dict)
    vel: dict = field(default_factory=dict)
    acc: dict = field(default_factory=dict)
    valid: np.ndarray | None = None
    failed: dict = field(default_factory=dict)  # op index -> rows where that op failed first
