"""`type = "linkage"`: nothing to solve; the given linkage is the solution."""

from __future__ import annotations

from linkcli import mechanisms
from linkcli.solution import Solution, SolverRecord, Status


def solve(problem) -> Solution:
    linkage = problem.linkage
    mech = mechanisms.of(linkage)
    record = SolverRecord("analysis", problem.meta.solver.seed, 0, True)
    why = mech.infeasible()  # rows of its motion it cannot reach (a five-bar's), named
    if why is not None:
        return Solution(status=Status.INFEASIBLE, linkage=linkage, message=why, solver=record)
    if mech.study() is None:  # the schemas refuse such linkages; a hand-made problem may not
        return Solution(status=Status.INFEASIBLE, linkage=linkage, message=mech.NO_ASSEMBLY)
    return Solution(status=Status.OK, linkage=linkage, message="given linkage", solver=record)
