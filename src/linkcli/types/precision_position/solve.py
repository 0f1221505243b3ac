"""Precision-position function generation by Freudenstein's equation (numpy only).

Freudenstein (1955), "Approximate synthesis of four-bar linkages", Trans. ASME 77:

    K1 cos(psi) - K2 cos(phi) + K3 = cos(phi - psi),
    K1 = d / a,  K2 = d / c,  K3 = (a^2 - b^2 + c^2 + d^2) / (2 a c)

is linear in K1, K2, K3: three (phi_i, psi_i) pairs give the exact linkage. Four or more
are fitted by Levenberg-Marquardt on the true output-angle error of the assembled linkage
(the linear residual is not the angle error), started from the linear least-squares ratios
and from the exact ratios of three-position subsets, on both branches (starts.py);
the fit that assembles everywhere and travels without a branch change wins. A negative
ratio means that link points the other way (its angle is phi + 180 or psi + 180): the
lengths are reported positive and the note says so. This module must not import scipy.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.errors import SolveInputError
from linkcli.mechanisms.four_bar.kinematics import ground_distance, pose, wrap
from linkcli.mechanisms.four_bar.model import FourBar
from linkcli.solution import Positions, Solution, SolverRecord, Status
from linkcli.types.precision_position.starts import (closure_gap, freudenstein_system, lengths_of, make_starts,
                                              physical_angles, refine, travels)
from linkcli.types.precision_position.system import ILL_CONDITIONED  # one threshold with check
from linkcli.types.precision_position.verdict import verdict
from linkcli.noise import TIE
from linkcli.textnum import num

BRANCHES = ("open", "crossed")
HELD = 1e-6  # rad: an exact fit's closure on a branch within this of psi holds the position


def _position_names(idx) -> str:
    return ", ".join(str(i + 1) for i in idx)


def _bad_positions(problem, expected: str, got: str) -> SolveInputError:
    return SolveInputError(expected, got, path=problem.meta.path, key="positions",
                      line=problem.lines[0] if problem.lines else None)


def _freudenstein_lengths(problem, phi, psi, d, why: str = ""):
    """Signed a and c, and b, of the least-squares (for three pairs exact) ratios of
    Freudenstein's equation; SolveInputError for an infinite link or a coupler that is not real
    (`why` adds to the latter's message)."""
    m, rhs = freudenstein_system(phi, psi)
    k = np.linalg.lstsq(m, rhs, rcond=None)[0]
    a, b2, c = (float(v[0]) for v in lengths_of(k[None, :], d))
    names = _position_names(range(len(phi)))
    if not (math.isfinite(a) and math.isfinite(c)):
        raise _bad_positions(problem, "positions that determine finite input and output links",
                             f"positions {names} give an infinite link")
    if b2 <= 0:
        raise _bad_positions(problem, "positions that a real coupler can join",
                             f"positions {names} need coupler^2 = {b2:.6g} <= 0{why}")
    return a, math.sqrt(b2), c


def tie_order(candidates, cost, converged) -> list[int]:
    """`candidates` by cost, where costs within a relative TIE (linkcli.noise) of the first
    of their group are equal and go converged first, then in start order: several starts
    reach the same minimum, and which of them rounds lowest must not pick the report."""
    ranked = [int(i) for i in np.asarray(candidates)[np.argsort(cost[candidates], kind="stable")]]
    out: list[int] = []
    while ranked:  # a few dozen starts at most
        lead = cost[ranked[0]]
        group = [i for i in ranked if cost[i] <= lead + TIE * abs(lead)]
        out += sorted(group, key=lambda i: (not converged[i], i))
        ranked = [i for i in ranked if i not in group]
    return out


def _orientation_notes(a_turned: bool, c_turned: bool) -> list[str]:
    notes = []
    if a_turned:
        notes.append("Freudenstein ratio K1 < 0: the input link points opposite to the input "
                     "angle (the crank sits at phi + 180); its length is reported positive")
    if c_turned:
        notes.append("Freudenstein ratio K2 < 0: the output link points opposite to the output "
                     "angle (the rocker sits at psi + 180); its length is reported positive")
    return notes


TRAVEL_NOTE = ("branch defect: the input cannot rotate from the first to the last position "
               "without passing a limit position (the linkage would change branch)")


def _infeasible(problem, linkage: FourBar, p, notes) -> Solution:
    """Status INFEASIBLE naming the positions where the loop does not close and by how much:
    |A B0| = rho must lie in [|b - c|, b + c]; the gap is the distance outside (length unit)."""
    bad = np.nonzero(~p.valid)[0]
    gap = closure_gap(linkage.input, linkage.coupler, linkage.output, p.rho)
    unit = problem.meta.units.length
    parts = ", ".join(f"{i + 1} (by {num(gap[i])} {unit})" for i in bad)
    message = (f"the linkage cannot assemble at positions {parts}: the loop misses closing there "
               f"(|A B0| outside [|coupler - output|, coupler + output] = "
               f"[{num(abs(linkage.coupler - linkage.output))}, {num(linkage.coupler + linkage.output)}] {unit})")
    return Solution(status=Status.INFEASIBLE, linkage=linkage, message=message, notes=notes)


def _exact(problem, phi, psi, d):
    """Three positions: the exact Freudenstein linkage, reported on the branch that holds
    the most positions (then the smaller squared error); a position is held by a branch
    whose closure reproduces its psi (error < HELD, or the nearer of the two)."""
    n = len(phi)
    a, b, c = _freudenstein_lengths(problem, phi, psi, d)
    notes = _orientation_notes(a < 0, c < 0)
    phi_phys = phi + (np.pi if a < 0 else 0.0)
    psi_phys = psi + (np.pi if c < 0 else 0.0)
    a, c = abs(a), abs(c)
    errs = {}
    for branch in BRANCHES:
        p = pose(a, b, c, d, phi_phys, branch)
        errs[branch] = np.where(p.valid, np.abs(wrap(p.psi - psi_phys)), np.inf)
    nearest = np.argmin(np.vstack([errs[br] for br in BRANCHES]), axis=0)
    held = {br: [i + 1 for i in range(n) if errs[br][i] < HELD or nearest[i] == j]
            for j, br in enumerate(BRANCHES)}
    branch = min(BRANCHES, key=lambda br: (-len(held[br]), float(np.sum(errs[br] ** 2))))
    message = f"exact through {n} positions"
    if len(held[branch]) < n:
        notes.append("branch defect: positions " + ", ".join(map(str, held["open"]))
                     + " lie on the open branch and " + ", ".join(map(str, held["crossed"]))
                     + " on the crossed branch; the linkage must be disassembled to pass them all")
        message = (f"Freudenstein's equations are met exactly through {n} positions, but no one "
                   f"branch holds all of them: the open branch holds positions "
                   f"{', '.join(map(str, held['open'])) or 'none'} and the crossed branch "
                   f"{', '.join(map(str, held['crossed'])) or 'none'}; reported on the {branch} "
                   f"branch, which misses position(s) "
                   f"{', '.join(str(i) for i in range(1, n + 1) if i not in held[branch])}")
    linkage = FourBar(ground=d, input=a, coupler=b, output=c, branch=branch)
    return linkage, phi_phys, psi_phys, notes, message, SolverRecord("freudenstein", problem.meta.solver.seed, 1, True)


def _least_squares(problem, phi, psi, d):
    """Four or more positions: multi-start Levenberg-Marquardt on the true output-angle
    error (starts.py). The fit reported is, in order: one that assembles at every
    position, then one that travels from the first to the last position without a branch
    change, then the smallest objective (ties: the earlier start, so the result is
    deterministic). When none assembles everywhere, the one whose loop misses closing the
    least is returned for the infeasible message."""
    n = len(phi)
    starts = make_starts(phi, psi, d)
    if not len(starts.x):  # the linear fit raises: no start at all means it fails too
        _freudenstein_lengths(problem, phi, psi, d, why=" (and no three of them give a real coupler)")
    fit = refine(starts, phi, psi, d, problem.meta.solver.budget)
    st = fit.starts
    cost = np.einsum("km,km->k", fit.r, fit.r)
    assembles = np.all(fit.valid, axis=1)
    sweep = float(phi[-1] - phi[0])
    phi_p, psi_p = physical_angles(phi, psi, st.sa, st.sc)
    if np.any(assembles):
        order = tie_order(np.nonzero(assembles)[0], cost, fit.converged)
        chosen = order[0]
        for i in order:  # usually the first passes: a loop over a few candidates
            if travels(*fit.abc[i], d, phi_p[i], sweep):
                chosen = i
                break
    else:  # only where a position has rho = 0 (A on B0): the least closure gap
        a, b, c = (fit.abc[:, i:i + 1] for i in range(3))
        gap = np.sum(closure_gap(a, b, c, ground_distance(a, d, phi_p)), axis=1)
        chosen = np.lexsort((cost, gap))[0]
    a, b, c = (float(v) for v in fit.abc[chosen])
    branch = "open" if st.sign[chosen] < 0 else "crossed"
    notes = _orientation_notes(st.sa[chosen] < 0, st.sc[chosen] < 0)
    phi_phys, psi_phys = phi_p[chosen], psi_p[chosen]
    message = f"least squares over {n} positions, refined on the true output-angle error"
    solver = SolverRecord("freudenstein+lm", problem.meta.solver.seed, int(fit.evaluations),
                          bool(fit.converged[chosen]), starts=int(len(st.x)))
    return FourBar(ground=d, input=a, coupler=b, output=c, branch=branch), phi_phys, psi_phys, \
        notes, message, solver


def solve(problem) -> Solution:
    """The design of the problem's mechanism, by its home's synthesis face
    (mechanisms.synthesis): the four-bar's below (`solve_four_bar`), the slider-crank's in
    slider.py."""
    from linkcli.mechanisms import synthesis
    return synthesis.solve("precision-position", problem)


def solve_four_bar(problem) -> Solution:
    """Freudenstein's positions: exact for three, least squares beyond (module docstring)."""
    phi = np.array(problem.input_angles)
    psi = np.array(problem.output_angles)
    d = problem.ground
    n = len(phi)
    m, _ = freudenstein_system(phi, psi)
    if np.linalg.cond(m) > ILL_CONDITIONED:
        raise _bad_positions(problem, "positions that determine a linkage (Freudenstein's system is singular)",
                             f"positions {_position_names(range(n))} give a singular system")
    solve_n = _exact if n == 3 else _least_squares
    linkage, phi_phys, psi_phys, notes, message, solver = solve_n(problem, phi, psi, d)
    a, b, c, branch = linkage.input, linkage.coupler, linkage.output, linkage.branch
    p = pose(a, b, c, d, phi_phys, branch)
    if not np.all(p.valid):
        return _infeasible(problem, linkage, p, notes)
    err = wrap(p.psi - psi_phys)
    sweep = float(phi[-1] - phi[0])
    if not travels(a, b, c, d, phi_phys, sweep):
        notes.append(TRAVEL_NOTE)
    if any(note.startswith("branch defect") for note in notes):
        message += "; branch defect (see notes)"
    converged = solver.converged
    if not converged:
        budget = problem.meta.solver.budget
        message += (f"; the refinement stopped at its budget ({budget} evaluations) before converging"
                    if budget is not None else "; the refinement reached its iteration limit "
                    "before converging")
    status, message = verdict(Status.OK if converged else Status.NOT_CONVERGED, message, notes, err, n == 3,
                              problem.meta.units)
    return Solution(
        status=status,
        linkage=linkage,
        message=message,
        positions=Positions(kind="angle", input=phi_phys, target=psi_phys, achieved=p.psi, error=err),
        objective=float(err @ err),
        solver=solver,
        notes=notes,
        working_span=(float(phi_phys[0]), sweep),
    )
