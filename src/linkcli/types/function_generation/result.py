"""A function generator's Solution: the best design of a search (search.Search.answer) as a
four-bar with its positions, its violated constraints described (each by how much), its
status and message, the notes on bounds and printed digits, and its target and structural
error sections. Shared by the search (solve), the robust design (robust) and the front (pareto).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.errors import SolveInputError
from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.four_bar.model import FourBar
from linkcli.solution import Positions, Solution, SolverRecord, Status
from linkcli.textnum import num
from linkcli.types.function_generation.model import BRANCH_SIGN, GRASHOF_MARGIN, STARTS, Model
from linkcli.types.function_generation.printed_digits import digits_note
from linkcli.types.function_generation.search import FEASIBLE, Search
from linkcli.types.function_generation.sections import structural_error, target_section

AT_BOUND = 1e-6  # a free value this close to a bound (unit box) is "at" it (a note)


def build_solution(problem, model: Model, search: Search, converged: bool,
                   found_twice: bool = True) -> Solution:
    best = search.answer()
    sign = BRANCH_SIGN[best.branch]
    v = best.v[None, :]
    batch, det = model.evaluate(v, sign, detail=True)
    a, b, c, d = (float(x[0, 0]) for x in model.lengths(v))
    fb = FourBar(ground=d, input=a, coupler=b, output=c, branch=best.branch)
    u = problem.meta.units
    phi0, psi0 = float(det["phi0"][0, 0]), float(det["psi0"][0, 0])
    err = det["err"][0]
    target = det["target"][0]
    positions = Positions(kind="angle", input=det["phi"][0], target=target,
                          achieved=kin.wrap(det["psi"][0]), error=kin.wrap(err))
    check_law_finite(problem, model, batch.violation[0], det, u)
    violations = describe_violations(problem, model, batch.violation[0], det, u)
    solver = SolverRecord(solver_name(problem.meta.solver.method, model.n_variables), problem.meta.solver.seed,
                          search.evaluations.used, bool(converged))
    if violations:
        status, message = Status.INFEASIBLE, "; ".join(violations)
    elif not found_twice:
        status = Status.NOT_CONVERGED
        message = ("the best linkage found meets every constraint, but within the budget "
                   f"({search.budget} evaluations) no second local search ended at it, or the "
                   "local searches found a different minimum nearly every time (too few to rule "
                   "out a lower one): another seed or a larger budget may end lower")
    elif not converged:
        status = Status.NOT_CONVERGED
        # no evaluation count here: it differs between machines (solver.evaluations has it)
        message = (f"the solver stopped before converging (budget {search.budget} "
                   "evaluations); the best linkage found meets every constraint")
    else:
        status = Status.OK
        message = (f"optimized over {len(model.t)} points on the {best.branch} branch; "
                   "within every constraint")
    notes = bound_notes(problem, model, best.u)
    if status is not Status.INFEASIBLE:  # do the printed digits hold? (printed_digits)
        note = digits_note(problem, model, v, sign, FEASIBLE,
                           lambda viol, one: describe_violations(problem, model, viol, one, u))
        if note:
            notes.append(note)
    sections = {}
    if "positions" in problem.meta.sections:
        sections["target"] = target_section(problem, phi0, psi0, u)
    if "error" in problem.meta.sections:
        sections["structural_error"] = structural_error(problem, model, (a, b, c, d), (phi0, psi0), sign, u)
    return Solution(status=status, linkage=fb, message=message, positions=positions,
                    objective=float(batch.f[0]), solver=solver, sections=sections,
                    notes=notes,
                    working_span=(phi0, problem.input_sweep))


def solver_name(method: str, n: int) -> str:
    if n == 0:
        return "evaluation (no free variable)"
    return {"auto": "levenberg-marquardt+gauss-newton+slsqp"}.get(method, method)


def check_law_finite(problem, model: Model, viol, det, u) -> None:
    """A law that is still not finite at some point of the best design found (its start
    angles defined) is bad input, not an infeasible design: an overflow, a pole or a
    logarithm of a negative number over every design the search could reach."""
    if dict(zip(model.names, viol))["law"] <= FEASIBLE:
        return
    phi0, psi0 = float(det["phi0"][0, 0]), float(det["psi0"][0, 0])
    if not (math.isfinite(phi0) and math.isfinite(psi0)):
        return  # no start angles (no extended dead-centre): that violation is reported
    target, phi = det["target"][0], det["phi"][0]
    bad = np.flatnonzero(~np.isfinite(target))
    k = int(bad[0])
    raise SolveInputError("a law finite at every evaluation point of some design within the bounds",
                     f"{target[k]:.6g} at {len(bad)} of {len(target)} points of the best design "
                     f"found, first at phi = {float(u.from_rad(float(kin.wrap(phi[k])))):.6g} {u.angle} "
                     f"(point {k + 1})",
                     path=problem.meta.path, line=problem.lines.get("law"),
                     key=problem.lines.get("law_key"))


def describe_violations(problem, model: Model, viol, det, u) -> list[str]:
    """One phrase per violated constraint, with the amount in the file's units."""
    out = []
    names = dict(zip(model.names, viol))
    lu, au = u.length, u.angle
    scale = model.scale
    if names["extended"] > FEASIBLE:
        out.append(f"no extended dead-centre: input + coupler misses the range |output - ground| .. "
                   f"output + ground by {num(names['extended'] * scale)} {lu}")
    if names["travel"] > FEASIBLE:
        out.append(f"travel: the input meets a dead point within the sweep (coupler and output are "
                   f"{num(names['travel'] * scale)} {lu} short of assembling)")
    where = "over the full turn" if model.full_turn else "over the sweep"
    window = problem.transmission
    if names["transmission_low"] > FEASIBLE:
        mu = float(det["mu"][0][0, 0])
        out.append(f"transmission: mu falls to {num(u.from_rad(mu))} {au} {where}, "
                   f"{num(u.from_rad(names['transmission_low']))} {au} below the minimum "
                   f"{num(u.from_rad(window[0]))}")
    if names["transmission_high"] > FEASIBLE:
        mu = float(det["mu"][1][0, 0])
        out.append(f"transmission: mu reaches {num(u.from_rad(mu))} {au} {where}, "
                   f"{num(u.from_rad(names['transmission_high']))} {au} above the maximum "
                   f"{num(u.from_rad(window[1]))}")
    if names["grashof"] > FEASIBLE:
        found = kin.GRASHOF_CLASSES[int(kin.grashof_code(*(float(x[0, 0]) for x in det["lengths"])))]
        what = (f"not a {problem.grashof} but a {found}" if found != problem.grashof
                else f"a {found} within {GRASHOF_MARGIN:g} of a change-point")
        out.append(f"grashof: {what} (an inequality misses by {num(names['grashof'] * scale)} {lu})")
    if names["law"] > FEASIBLE:
        out.append(f"law: the target is not finite at {round(names['law'] * len(model.t))} of "
                   f"{len(model.t)} points")
    return out


def bound_notes(problem, model: Model, unit) -> list[str]:
    """A free length or start angle that ends on its bound: widening the bound may help."""
    notes = []
    u = problem.meta.units
    for i, name in enumerate(model.variables):
        lo, hi = model.lo[i], model.hi[i]
        at = "lower" if unit[i] <= AT_BOUND else ("upper" if unit[i] >= 1 - AT_BOUND else None)
        if at is None:
            continue
        bound = lo if at == "lower" else hi
        shown = f"{num(u.from_rad(bound))} {u.angle}" if name in STARTS else f"{num(bound)} {u.length}"
        notes.append(f"{name} ends at its {at} bound ({shown}): a wider [bounds].{name} may lower the objective")
    return notes
