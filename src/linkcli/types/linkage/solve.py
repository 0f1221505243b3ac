"""`type = "linkage"`: nothing to solve; the given four-bar or slider-crank is the solution."""

from __future__ import annotations

from linkcli.mechanisms.four_bar.kinematics import input_arcs
from linkcli.solution import Solution, SolverRecord, Status


def solve(problem) -> Solution:
    fb = problem.linkage
    if hasattr(fb, "abe"):  # a slider-crank: the schema refused one that never assembles
        return Solution(status=Status.OK, linkage=fb, message="given linkage",
                        solver=SolverRecord("analysis", problem.meta.solver.seed, 0, True))
    if input_arcs(*fb.abcd) == []:
        return Solution(status=Status.INFEASIBLE, linkage=fb,
                        message="the linkage cannot assemble at any input angle "
                                "(rho = |A B0| never lies within [|b - c|, b + c])")
    return Solution(status=Status.OK, linkage=fb, message="given linkage",
                    solver=SolverRecord("analysis", problem.meta.solver.seed, 0, True))
