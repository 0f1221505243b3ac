"""What a solver returns: a `Solution` whose failure is a status, never an exception."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np

from linkcli.model import Linkage


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


@dataclass(frozen=True)
class SolverRecord:
    """How a solver reached its answer: the method, the seed, the objective evaluations
    spent, whether it converged; `starts` (precision positions: the starts polished) and
    `minimize` (the flipper's goal) only where a type has them."""

    method: str
    seed: int | None = None
    evaluations: int = 0
    converged: bool = False
    starts: int | None = None
    minimize: str | None = None

    def report(self) -> dict:
        """The report's `solver` section: method, seed, evaluations, converged, then the
        optional fields a type set, in that order."""
        out = {"method": self.method, "seed": self.seed, "evaluations": self.evaluations,
               "converged": self.converged}
        for key in ("starts", "minimize"):
            value = getattr(self, key)
            if value is not None:
                out[key] = value
        return out


@dataclass
class Solution:
    status: Status
    linkage: Linkage | None = None  # the designed linkage, its home's record (model.Linkage)
    message: str = ""
    positions: Positions | None = None
    objective: float | None = None  # rad^2 for angle errors, length^2 for paths
    solver: SolverRecord | None = None
    # extra report sections, output-ready: each type's own (timing, cylinder, candidates,
    # ...) differ in every row and column, and the report prints them as they are, so a
    # typed form per section would only be converted back to this dict
    sections: dict = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)  # warnings shown with the report
    working_span: tuple[float, float] | None = None  # (start, signed sweep) of the input, rad
    alternatives: list = field(default_factory=list)  # a Pareto front's designs (Solutions), its rows' order
