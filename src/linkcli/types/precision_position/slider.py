"""precision-position with `[linkage] mechanism = "slider-crank"`: a slider-crank through
(crank angle phi_i, slider position s_i) pairs (numpy only).

The synthesis is types/precision_position/slider_synthesis.synthesize: three pairs exactly through
the linear equation 2a s cos(phi) + 2ae sin(phi) - (a^2 + e^2 - b^2) = s^2 (SPEC), more by
least squares on the true slider error. The verdict follows the four-bar's
(types/precision_position/verdict.py): an exact fit whose reported branch misses a position
by more than MISS_RTOL of the linkage's size, or any branch defect (the branch does not
hold every position, or the crank cannot travel from the first to the last position
without a limit position) is `infeasible` (exit 1); linkage and positions are still
reported.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.solution import Positions, Solution, SolverRecord, Status
from linkcli.textnum import num
from linkcli.types.precision_position.slider_synthesis import synthesize

MISS_RTOL = 1e-6  # relative to max(crank, rod, |offset|): an exact fit meets its targets to ~1e-12


def _size(linkage) -> float:
    return max(linkage.input, linkage.coupler, abs(linkage.offset))


def solve(problem) -> Solution:
    phi = np.array(problem.input_angles, dtype=float)
    s = np.array(problem.output_angles, dtype=float)
    line = problem.lines[0] if problem.lines else None
    fit = synthesize(phi, s, path=problem.meta.path, line=line)
    n = len(phi)
    linkage = fit.linkage
    unit = problem.meta.units.length
    notes = list(fit.notes)
    message = (f"exact through {n} positions" if fit.exact
               else f"least squares over {n} positions, refined on the true slider error")
    err = np.asarray(fit.error, dtype=float)
    assembles = np.isfinite(fit.achieved)
    reasons = []
    if not np.all(assembles):
        bad = ", ".join(str(i + 1) for i in np.nonzero(~assembles)[0])
        reasons.append(f"the slider-crank cannot assemble at position(s) {bad}")
    tol = MISS_RTOL * _size(linkage)
    missed = [i + 1 for i in range(n) if fit.exact and assembles[i] and abs(err[i]) > tol]
    if missed:
        worst = max(abs(float(err[i - 1])) for i in missed)
        reasons.append(f"position{'s' if len(missed) > 1 else ''} {', '.join(map(str, missed))} missed by up "
                       f"to {num(worst)} {unit} on the reported branch")
    defect = any(note.startswith("branch defect") for note in notes)
    if defect:
        message += "; branch defect (see notes)"
        if not reasons:
            reasons.append("the slider-crank cannot pass its positions in one assembly")
    status = Status.OK if fit.converged else Status.NOT_CONVERGED
    if not fit.converged:
        message += "; the refinement reached its iteration limit before converging"
    if reasons:
        status = Status.INFEASIBLE
        message += "; infeasible: " + "; ".join(reasons)
    finite = np.where(np.isfinite(err), err, 0.0)
    objective = float(finite @ finite) if np.all(assembles) else math.inf
    return Solution(
        status=status, linkage=linkage, message=message,
        positions=Positions(kind="slider", input=np.asarray(fit.input_angles), target=s,
                            achieved=np.asarray(fit.achieved), error=err),
        objective=objective if math.isfinite(objective) else None,
        solver=SolverRecord(fit.method, problem.meta.solver.seed, int(fit.iterations), bool(fit.converged),
                            starts=int(fit.starts)),
        notes=notes,
        working_span=(float(fit.input_angles[0]), float(phi[-1] - phi[0])),
    )
