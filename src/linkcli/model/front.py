"""[objective] minimize = [...] of a synthesis that reports a Pareto front (reading.pareto_keys;
linkcli.pareto): the objectives in the order asked, how many designs the front is sampled at,
and an optional reference point for its hypervolume."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Front:
    """Two or three objectives, each a name of linkcli.pareto.objectives (`error`,
    `max-error`, `transmission`, `size`, `link-ratio`, `torque`, `pin-force`,
    `failure-probability`), the first the one each design minimizes; `points`: the designs
    the front is sampled at (its epsilon levels); `reference_point`: one value per
    objective, in the report's units, or None (the rule of linkcli.pareto.hypervolume)."""

    objectives: tuple[str, ...]
    points: int = 20
    reference_point: tuple[float, ...] | None = None
    line: int | None = None  # the line of `minimize`, for messages
