"""Path generation's design as analysis.robust_design sees it ([objective] minimize =
"failure-probability"): the full variable vector of model.Design (lengths, coupler point,
placement, timing) on the least-squares design's branch and turning direction."""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.four_bar.model import FourBar
from linkcli.solution import Positions, Solution, Status
from linkcli.types.path_generation.model import N_LINK, Design


class PathDesign:
    """analysis.robust_design.Adapter of a path-generation problem."""

    def __init__(self, problem, design: Design, best, method: str, budget, confirmed: bool):
        self.problem, self.design, self.method = problem, design, method
        self.budget, self.confirmed = budget, confirmed
        self.sign, self.s = best.sign, best.s
        self.x0 = design.wrapped(best.x[None])[0]
        self.lo, self.hi = design.lo.copy(), design.hi.copy()

    def _at(self, x):
        return x[None], np.array([self.sign]), np.array([self.s])

    def solution(self, x: np.ndarray) -> Solution:
        """The linkage of x with its targets and input angles."""
        x1, sign, s = self._at(x)
        pts, _, phi = self.design.points(x1, sign, s)
        pts, phi = pts[0], phi[0]
        d, a, b, c, px, py, gx, gy, gamma = (float(v) for v in x[:N_LINK])
        fb = FourBar(ground=d, input=a, coupler=b, output=c, branch="open" if self.sign < 0 else "crossed",
                     coupler_point=(px, py), ground_pivot=(gx, gy), ground_angle=gamma)
        err = np.hypot(*(pts - self.design.targets).T)
        monotone = bool(np.all(np.diff(phi) >= 0) or np.all(np.diff(phi) <= 0))
        span = ((float(phi[0]), float(phi[-1] - phi[0])) if monotone
                else (float(phi.min()), float(phi.max() - phi.min())))
        return Solution(status=Status.OK, linkage=fb, working_span=span,
                        positions=Positions("point", phi, self.design.targets.copy(), pts, err))

    def inequalities(self, x: np.ndarray) -> np.ndarray:
        """The type's constraints (model.Design.constraints, g <= 0 feasible) as -g / L >= 0."""
        x1, sign, s = self._at(x)
        pose, phi = self.design.frame(x1, sign, s)
        return -self.design.constraints(x1, pose, phi)[0] / self.design.scale

    def final(self, x: np.ndarray) -> Solution:
        from linkcli.types.path_generation.result import Candidate, solution, violations
        bad = violations(self.design, x, self.sign, self.s)
        return solution(self.problem, self.design, Candidate(x.copy(), self.sign, self.s, True), bad,
                        self.method, self.budget, self.confirmed)


def robust(problem, design: Design, best, method: str, budget, confirmed: bool) -> Solution:
    """The design minimizing the largest failure probability (analysis.robust_design)."""
    from linkcli.analysis.robust_design import robust as search
    adapter = PathDesign(problem, design, best, method, budget, confirmed)
    return search(problem, adapter, adapter.final(adapter.x0))
