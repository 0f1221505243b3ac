"""The shared search's entry point and its Solution: a problem over its home's population
(the face's `population(problem)`), searched (search.py), checked against every constraint
on the fine grid (`violations`), reported as the type reports a four-bar's design: the
designed linkage, positions, error, timing, the solver record and the status -- ok (feasible,
found twice or an exact fit), not-converged (feasible, not confirmed), infeasible (the broken
constraints named, each by how much).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.search.budget import Budget
from linkcli.solution import Positions, Solution, SolverRecord, Status
from linkcli.synthesis import search as shared
from linkcli.synthesis.model import TWO_PI, Model
from linkcli.textnum import num

METHOD = "multistart-lm+kkt"


def solve(problem) -> Solution:
    """The design of a problem whose home offers a population (mechanisms.synthesis); with
    a topology, the sweep over its catalogued drawings (synthesis.sweep)."""
    from linkcli.mechanisms import synthesis
    if getattr(problem, "topology", None):
        from linkcli.synthesis.sweep import sweep
        return sweep(problem)
    return design(problem, synthesis.face(problem.mechanism).population(problem))


def design_drawing(problem, drawing, boxes: dict | None = None, joint: str | None = None,
                   link: str | None = None) -> Solution:
    """`problem` (a DrawnDesignProblem: its targets, timing, constraints, [solver]) solved from
    another starting drawing -- the callable a topology sweep runs once per catalogued drawing.
    `boxes`: {joint: ((x lo, x hi), (y lo, y hi))} of its free joints (each holding its drawn
    place; None: the problem's own); `joint` / `link`: its target joint or link when the
    drawing names them otherwise. The drawing is checked as a file's would be (structure, one
    turning drive, groups the population solves): SolveInputError (exit 2) naming what is wrong."""
    from dataclasses import replace

    from linkcli.errors import SolveInputError
    from linkcli.mechanisms.drawn.population import DrawnPopulation
    from linkcli.mechanisms.drawn.structure import analyse
    from linkcli.synthesis.schema import closed_form_problem
    structure = analyse(drawing)
    names = {j.name: j for j in drawing.joints}
    boxes = dict(problem.boxes) if boxes is None else dict(boxes)
    joint = joint if joint is not None else problem.joint
    link = link if link is not None else problem.link
    bad = ([f"{p.where}: {p.found}" for p in structure.problems]
           + ([f"links {', '.join(closed_form_problem(structure))} closed together with a slider"]
              if not structure.problems and closed_form_problem(structure) else [])
           + [f"box of {j} (not a joint of the drawing)" for j in boxes if j not in names]
           + [f"box of {j} not holding its drawn place" for j, ((xl, xh), (yl, yh)) in boxes.items()
              if j in names and not (xl <= names[j].at[0] <= xh and yl <= names[j].at[1] <= yh)]
           + ([f"target joint {joint}"] if joint is not None and (joint not in names or names[joint].ground) else [])
           + ([f"target link {link}"] if link is not None and link not in {k.name for k in drawing.links} else []))
    if bad:
        raise SolveInputError("a starting drawing the design can start from", "; ".join(bad),
                              path=problem.meta.path, key="linkage")
    problem = replace(problem, drawing=drawing, boxes=tuple(boxes.items()), joint=joint, link=link)
    population = DrawnPopulation(drawing, structure, problem.free, boxes,
                                 traced=(joint,) if joint else (), followed=(link,) if link else ())
    return design(problem, population)


def design(problem, population) -> Solution:
    """Search `population` for `problem`'s target (the shared search; `design_drawing` builds
    the population of a drawing)."""
    model = Model(problem, population)
    opts = problem.meta.solver
    budget = Budget(opts.budget or shared.DEFAULT_BUDGET)
    model.budget = budget
    rng = np.random.default_rng(opts.seed)
    with np.errstate(all="ignore"):
        found, confirmed = shared.search(model, budget, rng)
        if not found:
            x, s = shared.starts.draws(model, rng, 1)
            found = [shared.Candidate(x[0], float(s[0]), False)]
        best = found[0]
        best.x = model.canonical(best.x)  # a function's similarity held: the copy nearest the drawing
        if problem.objective == "failure-probability":
            from linkcli.synthesis.robust import robust
            return robust(problem, model, best, budget, confirmed)
        found = solution(problem, model, best, violations(model, best.x, best.s), budget, confirmed)
        if problem.meta.front is not None:  # a Pareto front from this design (linkcli.pareto)
            from linkcli.synthesis.pareto import front
            return front(problem, model, best, budget, confirmed, found)
        return found


# ---------------------------------------------------------------- the exact check

def violations(model: Model, x, s) -> list[tuple[str, float, str, str]]:
    """Every constraint the design breaks on the fine grid (FINE deg over its travel):
    (constraint, amount, message, unit: "length" | "angle")."""
    ev, order = model.check(np.asarray(x, dtype=float), float(s))
    out = []
    bad_targets = [k + 1 for k in np.flatnonzero(~ev.valid[0])]
    over = "the full turn" if model.crank else "the travel from the drawn position through the targets"
    for m, (kind, closure) in enumerate(model.kinds):
        g = float(ev.g[0, m])
        if not g > shared.FEASIBLE:
            continue
        at = f"{num(math.degrees(float(ev.at[0, m])))} deg"
        if kind == "transmission":
            side = "below" if m < len(model.kinds) - len(model.pop.closures) else "above"
            out.append(("transmission", g, f"the transmission angle at {closure} is {side} the window over "
                        f"{over} (at drive angle {at})", "angle"))
        elif bad_targets and ev.anchor[0, m] >= 0:
            out.append(("assembly", g * model.size, f"the closure at {closure} cannot close at target"
                        + ("s " if len(bad_targets) > 1 else " ") + ", ".join(map(str, bad_targets))
                        + " on its drawn side", "length"))
        elif model.crank:
            out.append(("drive", g * model.size, f"the driving link cannot turn fully: the closure at {closure} "
                        f"locks (a dead point near drive angle {at})", "length"))
        else:
            out.append(("branch", g * model.size, f"the closure at {closure} locks between the drawn position "
                        f"and the targets (near drive angle {at}): the linkage would change branch", "length"))
    if order > 0:
        out.append(("order", order, "the targets are not reached in order within one turn of the drive", "angle"))
    return out


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
              "first_input": float(u.from_rad(first)), "input_sweep": float(u.from_rad(abs(span[1]))),
              "drawn_drive_angle": float(u.from_rad(start))}
    k = model.k_home
    if model.timing == "prescribed" and model.free[k]:
        timing["input_offset"] = float(u.from_rad(float(x[k])))
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
