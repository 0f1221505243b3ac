"""Path generation's design as the Pareto search sees it (linkcli.pareto.space): the full
variable vector of model.Design (lengths, coupler point, placement, timing) on the
least-squares design's branch and turning direction; residuals the coupler point's misses
(length unit), constraints model.Design.constraints as -g / L >= 0."""

from __future__ import annotations

import numpy as np

from linkcli.types.path_generation.robust import PathDesign


class PathSpace(PathDesign):
    """linkcli.pareto.space.Space of a path-generation problem."""

    error_kind = "length"

    def __init__(self, problem, design, best, method: str, budget) -> None:
        super().__init__(problem, design, best, method, budget, True)
        self.full_turn = design.full_turn
        self.groups = np.repeat(np.arange(design.n_targets), 2)

    def _rows(self, x):
        x = np.atleast_2d(np.asarray(x, float))
        return x, np.full(len(x), self.sign), np.full(len(x), self.s)

    def residuals(self, x) -> np.ndarray:
        x, sign, s = self._rows(x)
        return self.design.residuals(x, sign, s, 0.0) * self.design.scale

    def inequalities(self, x) -> np.ndarray:
        x, sign, s = self._rows(x)
        pose, phi = self.design.frame(x, sign, s)
        g = -self.design.constraints(x, pose, phi) / self.design.scale
        return np.where(np.isfinite(g), g, -1e6)


def front(problem, design, best, method: str, budget, found):
    """The front of a path-generation problem (linkcli.pareto.run)."""
    from linkcli.pareto.run import solve_front
    return solve_front(problem, PathSpace(problem, design, best, method, budget), found)
