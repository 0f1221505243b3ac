"""Precision positions as the Pareto search sees them (linkcli.pareto.space): the free lengths
(input, coupler, output) of the four-bar, the ground held, on the branch and orientation of
the Freudenstein design; residuals the output-angle errors at the positions (rad).

On a front the positions are targets of the least-squares error, not equalities: a design
that misses them is on the front when it buys a better other objective (three positions
too: the exact design is then the error's anchor). Constraints, as the solver's checks:
assembly at every position on the branch, and travel from the first position to the last
without a limit position (rho = |A B0| within [|b - c|, b + c] at the sweep's ends and at
phi = 0, pi inside it). The box: each length within a factor BOX of the Freudenstein
design's (docs/pareto.md)."""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.four_bar import closure
from linkcli.mechanisms.four_bar.kinematics import TWO_PI, pose, wrap
from linkcli.mechanisms.four_bar.model import FourBar
from linkcli.solution import Positions, Solution, SolverRecord, Status
from linkcli.types.precision_position.starts import travels

BOX = 10.0  # each free length within [x0 / BOX, BOX x0]


class PositionSpace:
    """linkcli.pareto.space.Space of a four-bar precision-position problem."""

    error_kind = "angle"
    full_turn = False

    def __init__(self, problem, found: Solution) -> None:
        fb = found.linkage
        self.problem, self.d, self.branch = problem, float(fb.ground), fb.branch
        self.sign = -1.0 if fb.branch == "open" else 1.0
        self.phi = np.asarray(found.positions.input, dtype=float)
        self.psi = np.asarray(found.positions.target, dtype=float)
        self.sweep = float(self.phi[-1] - self.phi[0])
        self.x0 = np.array([fb.input, fb.coupler, fb.output], dtype=float)
        self.lo, self.hi = self.x0 / BOX, self.x0 * BOX
        self.groups = np.arange(len(self.phi))
        self.method = found.solver.method if found.solver is not None else "freudenstein"

    def _closure(self, x):
        x = np.atleast_2d(np.asarray(x, float))
        a, b, c = (x[:, k:k + 1] for k in range(3))
        return a, b, c, closure.frame(a, b, c, self.d, self.phi[None, :], self.sign)

    def residuals(self, x) -> np.ndarray:
        _, _, _, fr = self._closure(x)
        return wrap(np.arctan2(fr.spsi, fr.cpsi) - self.psi[None, :])

    def inequalities(self, x) -> np.ndarray:
        """Assembly at every position and over the travel, as ((b + c)^2 - rho^2) / d^2 >= 0
        and (rho^2 - (b - c)^2) / d^2 >= 0."""
        a, b, c, fr = self._closure(x)
        d = self.d
        lo, width = (self.phi[0], self.sweep) if self.sweep >= 0 else (self.phi[-1], -self.sweep)
        inside0 = math.fmod(-lo, TWO_PI) % TWO_PI <= width
        inside_pi = math.fmod(math.pi - lo, TWO_PI) % TWO_PI <= width
        extra = [(a - d) ** 2] if inside0 else []
        extra += [(a + d) ** 2] if inside_pi else []
        rho2 = np.concatenate([fr.rho ** 2] + extra, axis=1)
        g = np.concatenate([((b + c) ** 2 - rho2), (rho2 - (b - c) ** 2)], axis=1) / (d * d)
        return np.where(np.isfinite(g), g, -1e6)

    def solution(self, x) -> Solution:
        a, b, c = (float(v) for v in x)
        fb = FourBar(ground=self.d, input=a, coupler=b, output=c, branch=self.branch)
        p = pose(a, b, c, self.d, self.phi, self.branch)
        err = wrap(p.psi - self.psi)
        return Solution(status=Status.OK, linkage=fb, objective=float(err @ err),
                        positions=Positions("angle", self.phi.copy(), self.psi.copy(), p.psi, err),
                        working_span=(float(self.phi[0]), self.sweep))

    def final(self, x) -> Solution:
        """The design checked as the solver checks its own: it assembles at every position on
        its branch and travels between them without a limit position (else infeasible)."""
        sol = self.solution(x)
        a, b, c = (float(v) for v in x)
        p = pose(a, b, c, self.d, self.phi, self.branch)
        n = len(self.phi)
        sol.solver = SolverRecord(self.method, self.problem.meta.solver.seed, 0, True)
        if not np.all(p.valid):
            sol.status = Status.INFEASIBLE
            sol.message = f"the linkage cannot assemble at every position on the {self.branch} branch"
        elif not travels(a, b, c, self.d, self.phi, self.sweep):
            sol.status = Status.INFEASIBLE
            sol.message = ("branch defect: the input cannot rotate from the first to the last position "
                           "without passing a limit position")
        else:
            sol.message = f"{n} positions on the {self.branch} branch, travelled without a limit position"
        return sol


def front(problem, found: Solution) -> Solution:
    """The front of a four-bar precision-position problem (linkcli.pareto.run)."""
    from linkcli.pareto.run import solve_front
    return solve_front(problem, PositionSpace(problem, found), found)
