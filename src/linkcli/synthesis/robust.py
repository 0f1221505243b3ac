"""A design of the shared search as analysis.robust_design sees it ([objective] minimize =
"failure-probability", path and function generation): the full variable vector of
synthesis.model.Model (the home's variables and the timing) with the least-squares design's
turning direction; its made linkages are the home's tolerance model's at the targets."""

from __future__ import annotations

import numpy as np

from linkcli.synthesis.model import Model


class SharedDesign:
    """analysis.robust_design.Adapter of a problem over a home's population."""

    def __init__(self, problem, model: Model, best, budget, confirmed: bool):
        self.problem, self.model, self.best = problem, model, best
        self.budget, self.confirmed = budget, confirmed
        self.x0 = np.array(best.x, dtype=float)
        self.lo, self.hi = model.lo.copy(), model.hi.copy()

    def solution(self, x: np.ndarray):
        """The design x with its targets (a Solution: linkage, positions, working span)."""
        from linkcli.synthesis.search import Candidate
        from linkcli.synthesis.solution import solution
        return solution(self.problem, self.model, Candidate(x.copy(), self.best.s, True), [], self.budget,
                        self.confirmed)

    def inequalities(self, x: np.ndarray) -> np.ndarray:
        """The model's constraints g <= 0 as -g >= 0 (dimensionless), the sweep's too."""
        ev = self.model.evaluate(x[None], np.array([self.best.s]))
        out = -ev.g[0]
        if self.model.timing == "free":
            k = self.model.k_home
            out = np.append(out, 2.0 * np.pi - float(np.sum(x[k + 1:])))
        return out

    def final(self, x: np.ndarray):
        from linkcli.synthesis.check import violations
        from linkcli.synthesis.search import Candidate
        from linkcli.synthesis.solution import solution
        c = Candidate(x.copy(), self.best.s, self.best.converged)
        return solution(self.problem, self.model, c, violations(self.model, x, self.best.s), self.budget,
                        self.confirmed)


def robust(problem, model: Model, best, budget, confirmed: bool):
    """The design minimizing the largest failure probability (analysis.robust_design)."""
    from linkcli.analysis.robust_design import robust as minimize_failure
    adapter = SharedDesign(problem, model, best, budget, confirmed)
    return minimize_failure(problem, adapter, adapter.final(adapter.x0))
