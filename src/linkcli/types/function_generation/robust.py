"""Function generation's design as analysis.robust_design sees it ([objective] minimize =
"failure-probability"): the free lengths and start angles of model.Model, on the
least-squares design's branch; the targets are the law's at each design's start angles."""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.four_bar.model import FourBar
from linkcli.solution import Positions, Solution, Status
from linkcli.types.function_generation.model import BRANCH_SIGN, Model


class FunctionDesign:
    """analysis.robust_design.Adapter of a function-generation problem."""

    def __init__(self, problem, model: Model, search, converged: bool, found_twice: bool):
        self.problem, self.model, self.search = problem, model, search
        self.converged, self.found_twice = converged, found_twice
        best = search.answer()
        self.branch, self.sign = best.branch, BRANCH_SIGN[best.branch]
        self.x0 = np.array(best.v, dtype=float)
        self.lo, self.hi = model.lo.copy(), model.hi.copy()

    def solution(self, v: np.ndarray) -> Solution:
        """The linkage of v with the law's targets at its evaluation points."""
        _, det = self.model.evaluate(v[None], self.sign, detail=True)
        a, b, c, d = (float(x[0, 0]) for x in det["lengths"])
        fb = FourBar(ground=d, input=a, coupler=b, output=c, branch=self.branch)
        phi0 = float(det["phi0"][0, 0])
        return Solution(status=Status.OK, linkage=fb, working_span=(phi0, self.problem.input_sweep),
                        positions=Positions("angle", det["phi"][0], det["target"][0],
                                            kin.wrap(det["psi"][0]), kin.wrap(det["err"][0])))

    def inequalities(self, v: np.ndarray) -> np.ndarray:
        return self.model.inequalities(v[None], self.sign)[0]

    def final(self, v: np.ndarray) -> Solution:
        """The type's own Solution of v (as its final polish puts its answer in the search)."""
        from linkcli.types.function_generation.result import build_solution
        from linkcli.types.function_generation.search import Best
        batch = self.model.evaluate(v[None], self.sign)
        self.search.feasible = {self.branch: Best(float(batch.f[0]), float(batch.violation[0].max()),
                                                  float(batch.penalized[0]), self.model.units(v[None])[0],
                                                  self.branch, v.copy())}  # the answer is this design
        return build_solution(self.problem, self.model, self.search, self.converged, self.found_twice)


def robust(problem, model: Model, search, converged: bool, found_twice: bool) -> Solution:
    """The design minimizing the largest failure probability (analysis.robust_design)."""
    from linkcli.analysis.robust_design import robust as minimize_failure
    adapter = FunctionDesign(problem, model, search, converged, found_twice)
    return minimize_failure(problem, adapter, adapter.final(adapter.x0))
