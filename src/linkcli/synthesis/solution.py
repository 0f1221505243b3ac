"""The Solution of a design of the shared search (synthesis.design), reported as the type
reports a four-bar's design: the designed linkage, positions, error, timing, the solver
record and the status -- ok (feasible, found twice or an exact fit), not-converged (feasible,
not confirmed), infeasible (the broken constraints named, each by how much:
synthesis.check).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.columns import angle_out
from linkcli.solution import Positions, Solution, SolverRecord, Status
from linkcli.synthesis import search as shared
from linkcli.synthesis.model import TWO_PI, Model
from linkcli.textnum import num

METHOD = "multistart-lm+kkt"


def _amount(name_unit: str, amount: float, u) -> str:
    if name_unit == "angle":
        return f"{num(u.from_rad(amount))} {u.angle}"
    return f"{num(amount)} {u.length}"


# ---------------------------------------------------------------- the Solution

def solution(problem, model: Model, best, bad, budget, confirmed: bool) -> Solution:
    """The Solution of the design `best` (search.Candidate) with its violations `bad`."""
    from linkcli.mechanisms.drawn.solved import drive_start
    u = problem.meta.units
    x, s = best.x, best.s
    linkage = model.pop.linkage(x)
    ev = model.evaluate(x[None], np.array([s]), refine=False)
    q = ev.q[0]
    objective = float(ev.objective[0])
    exact = objective <= shared.exact_objective(model)
    floor = objective <= shared.near_exact_objective(model)  # an exact fit on a flat valley's floor
    converged = ((bool(best.converged) or floor) and confirmed) or exact
    motion = model.pop.kinematics(x[None], q[None])
    sections, notes = {}, []
    if model.kind == "path":
        pts = motion.points[0, :, 0, :]
        err = np.hypot(*(pts - model.targets).T)
        positions = Positions(kind="point", input=q, target=model.targets.copy(), achieved=pts, error=err)
    elif model.kind == "function":
        drawn = model.pop.drawn_angles(model.pop.places(x[None]))[0, 0]
        psi = motion.angles[0, :, 0] - drawn
        target = model.law(x[None])[0]
        err = np.mod(psi - target + math.pi, TWO_PI) - math.pi
        positions = Positions(kind="angle", input=q, target=target, achieved=target + err, error=err)
    else:
        positions = None
        sections.update(_motion_sections(problem, model, x, q, motion, objective))
    first, last = float(q[0]), float(q[-1])
    monotone = bool(np.all(np.diff(q) >= 0) or np.all(np.diff(q) <= 0))
    span = (first, last - first) if monotone else (float(q.min()), float(q.max() - q.min()))
    start = drive_start(linkage, None, linkage.drives[0])
    timing = {"timing": model.timing if model.kind != "function" else "prescribed",
              "direction": ("ccw" if span[1] >= 0 else "cw") if monotone else "reverses",
              "first_input": angle_out(u, first), "input_sweep": float(u.from_rad(abs(span[1]))),
              "drawn_drive_angle": float(u.from_rad(start))}
    k = model.k_home
    if model.timing == "prescribed" and model.free[k]:
        offset = float(x[k])  # free over a turn or more: the one in (-180, 180] deg (bounds of +-1e6 deg
        # printed -541667 for 133.333 deg plus turns, a third of a degree lost to the 6 digits)
        full = model.hi[k] - model.lo[k] >= 2.0 * math.pi * (1.0 - 1e-12)
        timing["input_offset"] = angle_out(u, offset) if full else float(u.from_rad(offset))
    if model.kind == "function":
        timing["input_start"] = float(u.from_rad(float(x[k])))
        timing["output_start"] = float(u.from_rad(float(x[k + 1])))
    sections["timing"] = timing
    names = {v[0] for v in bad}
    sections["defects"] = {"assembles": "assembly" not in names, "branch_defect": "branch" in names,
                           "drive_defect": "drive" in names, "order_defect": "order" in names}
    solver = SolverRecord(METHOD, problem.meta.solver.seed, budget.used, converged)
    n = model.n
    what = {"path": f"joint {problem.joint}", "motion": f"link {problem.link}",
            "function": f"link {problem.link}"}[model.kind]
    if bad:
        status = Status.INFEASIBLE
        message = "; ".join(f"{name}: {msg} (by {_amount(unit, amt, u)})" for name, amt, msg, unit in bad)
    else:
        status = Status.OK if converged else Status.NOT_CONVERGED
        turn = ("the driving link turns fully" if model.crank else
                "it moves from its drawn position through every target without a dead point")
        message = (f"{n} targets of {what}: every closure closes on its drawn side at every target and "
                   f"{turn}")
        if not converged:
            message += ("; the search's rounds ended at different optima and none was found again: "
                        "another seed or a larger budget may end lower")
    notes += _reach_note(problem, model, x, positions)
    if model.pop.held:
        held = model.pop.held
        notes.append(f"joint{'s' if len(held) > 1 else ''} {', '.join(held)} held where drawn, though given a box: "
                     f"on one link alone and not the target, {'their places change' if len(held) > 1 else 'its place changes'}"
                     " no target and no constraint")
    return Solution(status=status, linkage=linkage, message=message, positions=positions,
                    objective=objective, solver=solver, sections=sections, notes=notes,
                    working_span=span)


def _motion_sections(problem, model: Model, x, q, motion, objective) -> dict:
    """motion generation's `positions` and `error` (types.motion_generation.sections)."""
    from linkcli.types.motion_generation.sections import error_section, position_rows
    u = problem.meta.units
    size = float(model.pop.size(x[None])[0]) or 1.0
    origins = motion.origins[0, :, 0, :]
    angles = motion.angles[0, :, 0]
    achieved = np.concatenate([origins, angles[:, None]], axis=1)
    pos = np.hypot(*(origins - model.targets[:, :2]).T)
    ang = np.mod(angles - model.targets[:, 2] + math.pi, TWO_PI) - math.pi
    ref = problem.meta.reference
    return {"positions": position_rows(q, model.targets, achieved, pos, ang, u, size),
            "error": error_section(objective, pos, ang, model.weight, u, size, ref)}


def _reach_note(problem, model: Model, x, positions) -> list[str]:
    """A fit that misses a target by more than a tenth of the targets' scale: the free
    coordinates at their box's edge (a wider box may let the design reach further)."""
    if positions is None or positions.kind != "point":
        return []
    worst = float(np.max(positions.error)) if len(positions.error) else 0.0
    if not worst > 0.1 * model.scale:
        return []
    tight = [model.names[j] for j in range(model.k_home)
             if model.free[j] and min(x[j] - model.lo[j], model.hi[j] - x[j]) <= 1e-6 * (model.hi[j] - model.lo[j])]
    msg = (f"the best fit misses a target by {num(worst)} {problem.meta.units.length} "
           f"({num(100 * worst / model.scale)} % of the targets' extent)")
    return [msg + (f"; at the edge of its box: {', '.join(tight)}" if tight else "")]
