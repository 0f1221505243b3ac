"""Function generation as the Pareto search sees it (linkcli.pareto.space): the free lengths
and start angles of model.Model on the least-squares design's branch; residuals the output
angle's errors at the evaluation points (rad), constraints Model.inequalities (g >= 0)."""

from __future__ import annotations

import numpy as np

from linkcli.types.function_generation.robust import FunctionDesign


class FunctionSpace(FunctionDesign):
    """linkcli.pareto.space.Space of a function-generation problem. `final` needs the type's
    search record, which stays in the process that built the space (it does not pickle: the
    levels solved elsewhere need only the other members)."""

    error_kind = "angle"

    def __init__(self, problem, model, search, converged: bool, found_twice: bool) -> None:
        super().__init__(problem, model, search, converged, found_twice)
        self.full_turn = model.full_turn
        self.groups = np.arange(len(model.t))

    def __getstate__(self):
        state = dict(self.__dict__)
        state["search"] = None
        return state

    def residuals(self, v) -> np.ndarray:
        v = np.atleast_2d(np.asarray(v, float))
        err = self.model.evaluate(v, self.sign).err
        return np.where(np.isfinite(err), err, 1e6)

    def inequalities(self, v) -> np.ndarray:
        return self.model.inequalities(np.atleast_2d(np.asarray(v, float)), self.sign)

    def final(self, v):
        """The type's Solution of v, its status from its own constraint checks (ok: within
        every constraint; the search that found it is the front's, certified there)."""
        self.converged = self.found_twice = True
        return super().final(np.asarray(v, float))


def front(problem, model, search, found):
    """The front of a function-generation problem (linkcli.pareto.run)."""
    from linkcli.pareto.run import solve_front
    return solve_front(problem, FunctionSpace(problem, model, search, True, True), found)
