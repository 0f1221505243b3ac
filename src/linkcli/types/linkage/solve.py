"""`type = "linkage"`: nothing to solve; the given linkage is the solution."""

from __future__ import annotations

from linkcli import mechanisms
from linkcli.solution import Solution, SolverRecord, Status


def solve(problem) -> Solution:
    linkage = problem.linkage
    mech = mechanisms.of(linkage)
    study = mech.study()
    if study is None:  # the schemas refuse such linkages; a hand-made problem may not
        return Solution(status=Status.INFEASIBLE, linkage=linkage, message=mech.NO_ASSEMBLY)
    if study.shortfall:  # the asked motion stops at a dead point: the rows reached are reported
        return Solution(status=Status.INFEASIBLE, linkage=linkage, message=study.shortfall,
                        solver=SolverRecord("analysis", problem.meta.solver.seed, 0, True))
    return Solution(status=Status.OK, linkage=linkage, message="given linkage",
                    solver=SolverRecord("analysis", problem.meta.solver.seed, 0, True))
