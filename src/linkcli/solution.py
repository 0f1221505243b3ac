"""What a solver returns: a `Solution` whose failure is a status, never an exception."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from linkcli.model import FourBar


class Status(str, Enum):
    OK = "ok"
    INFEASIBLE = "infeasible"
    NOT_CONVERGED = "not-converged"

    @property
    def exit_code(self) -> int:
        return 0 if self is Status.OK else 1


MESSAGES = {
    Status.OK: "solved within every constraint",
    Status.INFEASIBLE: "solved, but a constraint is violated",
    Status.NOT_CONVERGED: "the solver did not converge",
}


@dataclass
class Positions:
    """One row per target. `kind` "angle": target/achieved are output angles (rad), error in
    rad. `kind` "point": target/achieved are (n, 2) coupler points, error a distance.
    `kind` "slider": target/achieved are slider positions, error a length (slider-crank)."""

    kind: str
    input: np.ndarray  # input angle used at each target, rad
    target: np.ndarray
    achieved: np.ndarray
    error: np.ndarray


@dataclass
class Solution:
    status: Status
    linkage: FourBar | None = None
    message: str = ""
    positions: Positions | None = None
    objective: float | None = None  # rad^2 for angle errors, length^2 for paths
    solver: dict = field(default_factory=dict)  # method, seed, evaluations, converged
    sections: dict = field(default_factory=dict)  # extra report sections, output-ready
    notes: list[str] = field(default_factory=list)  # warnings shown with the report
    working_span: tuple[float, float] | None = None  # (start, signed sweep) of the input, rad
