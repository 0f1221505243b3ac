"""The verdict on a precision-position result: a linkage that misses a target is no design.

A position is *missed* when the reported linkage's output angle there is off its target
by more than MISS_FLOOR_RAD = 1e-6 of a half turn (pi * 1e-6 rad = 1.8e-4 deg). The
closed-form (three-position) solution meets its targets to round-off (about 1e-12 rad),
so anything above that floor is a real miss: the position lies on the other branch. A
least-squares fit (four or more positions) has residuals by nature; only its defects
count there. A *defect* is a note starting with "branch defect": the reported branch
does not hold every position, or the input cannot travel from the first position to the
last without passing a limit position (an order defect). Either makes the result
`infeasible` (exit 1); the linkage and its positions table are still reported.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.solution import Status
from linkcli.textnum import num

MISS_FLOOR_RAD = 1e-6 * math.pi  # rad: 1e-6 of a half turn


def missed_positions(error_rad, exact: bool) -> list[int]:
    """1-based positions whose |error| exceeds the noise floor (exact solutions only)."""
    if not exact:
        return []
    return [int(i) + 1 for i in np.nonzero(np.abs(np.asarray(error_rad)) > MISS_FLOOR_RAD)[0]]


def verdict(status: Status, message: str, notes: list[str], error_rad, exact: bool, units):
    """(status, message): INFEASIBLE with the reason appended when a position is missed or
    a branch/order defect is noted; unchanged otherwise."""
    missed = missed_positions(error_rad, exact)
    defect = any(n.startswith("branch defect") for n in notes)
    if not missed and not defect:
        return status, message
    reasons = []
    if missed:
        worst = max(abs(float(error_rad[i - 1])) for i in missed)
        reasons.append(f"position{'s' if len(missed) > 1 else ''} {', '.join(map(str, missed))} "
                       f"missed by up to {num(units.from_rad(worst))} {units.angle} on the reported branch")
    if defect and not missed:
        reasons.append("the linkage cannot pass its positions in one assembly")
    return Status.INFEASIBLE, f"{message}; infeasible: {'; '.join(reasons)}"
