"""A drawn linkage's design as the Pareto search sees it (linkcli.pareto.space): the shared
search's full variable vector (synthesis.model.Model: each free joint's x, y within its box,
then the timing) in the turning direction of the least-squares design; residuals the target
misses in the model's own weighting, in report units (path: P_k - T_k; motion: O_k - T_k and
w dtheta_k, length unit; function: dpsi_k, rad), so that error = sum r^2 is the report's
objective; constraints the model's (each closure's assembly margin and transmission window,
the worst over the drive's travel, dimensionless) as -g >= 0, and the sweep within one turn.
Each front design is finished by the search's own exact check on the fine grid
(check.violations)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from linkcli.solution import Solution, Status
from linkcli.synthesis.model import HUGE, Model
from linkcli.synthesis.robust import SharedDesign


class DrawnSpace(SharedDesign):
    """linkcli.pareto.space.Space of a drawn design (path, motion or function generation)."""

    def __init__(self, problem, model: Model, best, budget, confirmed: bool) -> None:
        super().__init__(problem, model, best, budget, confirmed)
        n = model.n
        self.error_kind = "angle" if model.kind == "function" else "length"
        self.full_turn = bool(model.crank)
        self.groups = {"path": np.repeat(np.arange(n), 2),
                       "motion": np.concatenate([np.repeat(np.arange(n), 2), np.arange(n)]),
                       "function": np.arange(n)}[model.kind]

    def __getstate__(self):
        state = dict(self.__dict__)
        state["budget"] = None  # the search's count stays in the process that reports it
        return state

    def _directions(self, x) -> np.ndarray:
        return np.full(len(x), float(self.best.s))

    def residuals(self, x) -> np.ndarray:
        """(N, m_t): the model's target residuals times its scale (report units)."""
        x = np.atleast_2d(np.asarray(x, float))
        m = self.model
        q = m.inputs(x, self._directions(x))
        with np.errstate(all="ignore"):
            motion = m.pop.kinematics(x, q)
            r, _ = m.target_residuals(x, motion, q)
        r = r * m.scale
        return np.where(np.isfinite(r), r, HUGE)

    def inequalities(self, x) -> np.ndarray:
        """The model's constraints g <= 0 as -g >= 0 (dimensionless), the sweep's too."""
        x = np.atleast_2d(np.asarray(x, float))
        m = self.model
        with np.errstate(all="ignore"):
            out = -m.evaluate(x, self._directions(x)).g
        if m.timing == "free":
            k = m.k_home
            out = np.concatenate([out, (2.0 * np.pi - np.sum(x[:, k + 1:], axis=1))[:, None]], axis=1)
        return np.where(np.isfinite(out), out, -HUGE)

    def solution(self, x) -> Solution:
        """The linkage of x and its drive's travel over the targets (cheap: no sections); a
        drive that does not turn fully: the linkage's span the travel from the drawn position
        through the targets (the model's constraints' travel), which the home's study covers."""
        x = np.asarray(x, float)
        q = self.model.inputs(x[None], np.array([float(self.best.s)]))[0]
        monotone = bool(np.all(np.diff(q) >= 0) or np.all(np.diff(q) <= 0))
        span = ((float(q[0]), float(q[-1] - q[0])) if monotone
                else (float(q.min()), float(q.max() - q.min())))
        linkage = self.model.pop.linkage(x)
        if not self.full_turn:  # the home studies its linkage's span: the travel over the targets
            linkage = replace(linkage, span=(min(0.0, float(q.min())), max(0.0, float(q.max()))))
        return Solution(status=Status.OK, linkage=linkage, working_span=span)

    def final(self, x) -> Solution:
        """The search's Solution of x: its exact check on the fine grid decides the status
        (a front design is a certified point of its level: `converged`)."""
        from linkcli.synthesis.check import violations
        from linkcli.synthesis.search import Candidate
        from linkcli.synthesis.solution import solution
        x = np.asarray(x, float).copy()
        c = Candidate(x, self.best.s, True)
        return solution(self.problem, self.model, c, violations(self.model, x, self.best.s), self.budget, True)


def front(problem, model: Model, best, budget, confirmed: bool, found):
    """The front of a drawn design (linkcli.pareto.run), from the search's design `best`."""
    from linkcli.pareto.run import solve_front
    return solve_front(problem, DrawnSpace(problem, model, best, budget, confirmed), found)
