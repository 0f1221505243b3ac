"""flipper-cylinder: place a hydraulic cylinder that turns a loaded platform (docs/format.md).

The statics is linkcli.types.flipper_cylinder.statics: at platform angle t the cylinder force that holds
the platform is F(t) = W(t) L(t) / K(t), W = m g G_x(t), L = |A - C|, K = C x A(t), push
positive. With every pivot coordinate fixed the design is evaluated (method "evaluate");
otherwise linkcli.types.flipper_cylinder.search minimizes the peak force or the closed length
(`[objective] minimize`) within `[solver] budget` designs, and `[objective] pareto` adds
the trade-off table between peak force and closed length. This module turns the design
found into the report: the `cylinder` section (docs/format.md, Output), the `pareto` rows, the
status and its message (the violated limit and by how much).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from linkcli.search.budget import Budget
from linkcli.solution import Solution, SolverRecord, Status
from linkcli.textnum import num
from linkcli.types.flipper_cylinder.search import (
    DEFAULT_BUDGET,
    PARETO_BUDGET,
    PARETO_SHARE,
    SETTLE_EVALUATIONS,
    SETTLE_SHARE,
    TOLERANCE,
    Goal,
    Judge,
    Space,
    optimize,
    pareto,
    settle,
)
from linkcli.types.flipper_cylinder.sections import cylinder_section, facts, pareto_rows
from linkcli.types.flipper_cylinder.statics import Statics

NEGLIGIBLE = 1e-3  # a closed length below this share of the largest pivot bound: the pivots all but meet


# --------------------------------------------------------------------------- the verdict
def verdict(problem, f: dict) -> tuple[Status, str]:
    """Status and message of a design: the violated constraint and by how much, else the peak.
    A cylinder needs a length: closed >= Space.floor (search.MIN_LENGTH times the
    largest pivot bound); where the pivots meet, the force is 0 / 0."""
    u = problem.meta.units
    au = u.angle

    def ang(tau):
        return f"{num(float(u.from_rad(problem.shown_angle(problem.start + tau))))} {au}"

    if f["crosses"]:
        if f.get("zero_length"):
            return Status.INFEASIBLE, (f"the rod pivot passes through the base pivot at platform angle "
                                       f"{ang(f['cross_at'])} (zero cylinder length)")
        return Status.INFEASIBLE, (f"the cylinder line passes through the hinge B at platform angle "
                                   f"{ang(f['cross_at'])}: zero moment arm, the force is unbounded (the "
                                   f"load has a moment of {num(abs(f['load_moment']))} N {u.length} about B "
                                   "there, which no finite cylinder force can balance)")
    problems = []
    floor = Space(problem).floor
    if f["min_length"] < floor * (1.0 - TOLERANCE):
        problems.append(f"the rod pivot comes within {num(f['min_length'])} {u.length} of the base pivot at "
                        f"platform angle {ang(f['closed_at'])}: the pivots must stay at least {num(floor)} "
                        f"{u.length} apart (a cylinder of no length)")
    if problem.dead_length is not None:
        short = f["stroke"] + problem.dead_length - f["min_length"]
        if short > TOLERANCE * max(f["stroke"] + problem.dead_length, 1e-300):
            problems.append(f"closed length {num(f['min_length'])} {u.length} is {num(short)} {u.length} "
                            f"short of stroke + dead_length ({num(f['stroke'] + problem.dead_length)} {u.length})")
    if problem.max_force is not None and f["peak"] > problem.max_force * (1.0 + TOLERANCE):
        over = f["peak"] - problem.max_force
        problems.append(f"peak force {num(f['peak'])} N exceeds max_force {num(problem.max_force)} N "
                        f"by {num(over)} N ({num(100.0 * over / problem.max_force)} %)")
    kind = "push" if f["is_push"] else "pull"
    summary = f"peak force {num(f['peak'])} N ({kind}) at platform angle {ang(f['peak_at'])}"
    if problem.minimize == "cylinder-length":
        summary = (f"closed length {num(f['min_length'])} {u.length} (stroke {num(f['stroke'])} "
                   f"{u.length}); {summary}")
    if problems:
        return Status.INFEASIBLE, "; ".join(problems) + f" ({summary})"
    return Status.OK, summary


# --------------------------------------------------------------------------- trade-off table
# ------------------------------------------------------------------------------------ solve
def solve(problem) -> Solution:
    """Evaluate the design (every pivot fixed) or optimize it; inf and nan are handled as
    values (a design through the hinge), so numpy's warnings are silenced here."""
    with np.errstate(all="ignore"):
        return _solve(problem)


def _solve(problem) -> Solution:
    meta = problem.meta
    statics = Statics(problem.mass * problem.gravity, problem.center_of_mass, problem.end - problem.start)
    notes: list[str] = []
    if problem.fixed:
        design, rows = np.array([lo for lo, _ in problem.bounds]), None
        solver, budget, completed = SolverRecord("evaluate", meta.solver.seed, 1, True), 1, True
        if meta.solver.method != "auto":
            notes.append(f'every pivot coordinate is fixed: the design is evaluated, method '
                         f'"{meta.solver.method}" is not used')
    else:
        design, solver, rows, budget, completed = _search(problem, statics, notes)
    solver = replace(solver, minimize=problem.minimize)
    if design is None:
        return Solution(status=Status.NOT_CONVERGED, solver=solver, notes=notes,
                        message=f"the budget of {budget} evaluations is too small to "
                                "judge a design")
    f = facts(problem, statics, design)
    status, message = verdict(problem, f)
    lu = meta.units.length
    if (problem.dead_length is None and not f["crosses"] and not problem.fixed
            and f["min_length"] <= NEGLIGIBLE * max(abs(v) for b in problem.bounds for v in b)):
        notes.append(f"the pivots all but meet at the closed end (closed length {num(f['min_length'])} {lu}): "
                     "without [cylinder] dead_length the least force asks for a cylinder of no length; "
                     "dead_length gives a real one (closed length >= stroke + dead_length)")
    elif (problem.dead_length is None and not f["crosses"] and f["min_length"] < f["stroke"]
          and f["min_length"] >= Space(problem).floor * (1.0 - TOLERANCE)):
        notes.append(f"the closed length {num(f['min_length'])} {lu} is shorter than the stroke "
                     f"{num(f['stroke'])} {lu}: only a telescopic cylinder fits; [cylinder] dead_length "
                     "asks for a single-stage one (closed length >= stroke + dead_length)")
    searched = solver.converged or completed  # not stopped by the budget
    if not problem.fixed and status is Status.INFEASIBLE and searched:
        message = f"no design found within the limits; the nearest: {message}"
    elif not solver.converged:  # an infeasible design may only show that the search stopped early
        status = Status.NOT_CONVERGED
        # no evaluation count here: it differs between machines (solver.evaluations has it)
        message = (f"the search did not converge within its budget ({budget} evaluations); "
                   f"best design found: {message}")
    elif problem.fixed and status is Status.OK:
        message = f"design evaluated over the sweep: {message}"
    sections = {}
    if "cylinder" in meta.sections:
        sections["cylinder"] = cylinder_section(problem, statics, f)
    if rows is not None:
        sections["pareto"] = rows
    objective = f["peak"] if problem.minimize == "peak-force" else f["min_length"]
    return Solution(status=status, message=message, objective=objective if math.isfinite(objective) else None,
                    solver=solver, sections=sections, notes=notes)


def _search(problem, statics: Statics, notes: list[str]):
    """(design or None, solver record, trade-off rows or None, the budget, whether the
    search completed) of the optimizing methods."""
    meta = problem.meta
    method = meta.solver.method
    total = meta.solver.budget or (DEFAULT_BUDGET + (PARETO_BUDGET if problem.pareto else 0))
    share = total - (int(PARETO_SHARE * total) if problem.pareto else 0)
    budget = Budget(total)
    judge = Judge(problem, statics, Space(problem), budget)
    rng = np.random.default_rng(meta.solver.seed)
    goal = Goal("peak") if problem.minimize == "peak-force" else Goal("length", force_cap=problem.max_force)
    polishes = method != "differential-evolution"  # a global method alone is not polished
    reserve = min(SETTLE_EVALUATIONS, share // SETTLE_SHARE) if polishes else 0
    out = optimize(judge, goal, method, share - reserve, rng)
    if polishes:
        with budget.limit(max(0, share - budget.used)):  # the reserve and what the search left
            out = settle(judge, goal, out)
    rows = None
    if problem.pareto and out.best.design is not None:
        found, complete = pareto(problem, judge, out, goal, method, budget.left, rng)
        rows = pareto_rows(problem, statics, found)
        if not complete:
            notes.append(f"the trade-off table has {len(rows)} of the {problem.pareto} rows asked "
                         "for (budget spent, or no shorter cylinder stays within the force limit)")
    solver = SolverRecord(method, meta.solver.seed, budget.used, bool(out.converged))
    return out.best.design, solver, rows, total, bool(out.completed)
