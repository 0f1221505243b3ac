"""Which six-bar? A design over a catalogued topology (`[linkage] topology`, docs/six_bars.md):
every choice of drive and target of the topology (drawn.catalogue.choices; for free timing
only those whose curves or motions go beyond a four-bar's) is searched from its starting
drawings (catalogue.starting_drawings, fitted into the target's bounding box), each joint free
within `reach` x the target's diagonal of its drawn place (a function's ground pivots held where
drawn: `boxes_of`), by the shared search
(solution.design_drawing); the four-bar is searched the same way as the baseline. The best
six-bar is the result: feasible before infeasible, then the least objective, ties to the
catalogue's order. The `topologies` section lists the best of every choice and the baseline.

A choice whose drive reaches the rest through a triad (an Assur group of four links: every
Stephenson II, some Stephenson III) is followed over the population by continuation from each
drawing on its drawn branch (drawn.population_groups), at some TRIAD_COST times a dyad's cost
an evaluation in a search (docs/six_bars.md: 0.54 ms against 0.03 to 0.05 ms on the example):
every choice is searched, and a triad choice's runs are given TRIAD_COST times fewer
evaluations than a choice of dyads, so that its time comes near theirs (a search's starts and
settle spend some 7,000 evaluations whatever its budget: the example's triad choice takes some
10 s of CPU for its two runs, the dyad choice some 4 s).

The budget ([solver] budget, or the shared search's default: `default_total`) is shared by the runs in those
weights (a triad's 1 / TRIAD_COST, a dyad's 1), each run at least MIN_RUN_BUDGET; the seed is the
file's for every run, so the sweep is deterministic.
"""

from __future__ import annotations

import math
from dataclasses import replace

from linkcli.mechanisms.drawn.population import GROUP_COST
from linkcli.solution import Solution, SolverRecord, Status

DRAWINGS = 2  # starting drawings searched per choice
FUNCTION_BOX = (0.0, 0.0, 100.0, 100.0)  # a function's drawings (its error does not depend on the scale)
MIN_RUN_BUDGET = 2_000
TRIAD = "triad"
TRIAD_COST = GROUP_COST  # a triad choice's evaluation over a dyad choice's in a search (module docstring)


def target_box(problem) -> tuple[float, float, float, float]:
    """(x_lo, y_lo, x_hi, y_hi) the starting drawings are fitted into: the path points', the
    poses' origins', or FUNCTION_BOX."""
    if problem.kind == "function":
        return FUNCTION_BOX
    pts = problem.points if problem.kind == "path" else tuple((p[0], p[1]) for p in problem.poses)
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    return min(xs), min(ys), max(xs), max(ys)


def boxes_of(drawing, half: float, kind: str = "path") -> dict:
    """Every joint of a starting drawing free within +-half of its drawn place; a function's
    ground pivots held where drawn (its error is in turns, which no move, turn or scaling of
    the whole drawing changes: with the ground free that would be a flat direction of every
    design, and the optimum's printed places would be where round-off left them)."""
    return {j.name: ((j.at[0] - half, j.at[0] + half), (j.at[1] - half, j.at[1] + half)) for j in drawing.joints
            if not (kind == "function" and j.ground)}


def _timing(problem) -> str:
    """The catalogue's timing for the problem (catalogue.timing_of)."""
    from linkcli.mechanisms.drawn import catalogue
    return catalogue.timing_of(problem.kind, problem.timing)


def runs(problem, total: int) -> list[tuple]:
    """(choice, budget of each of its runs) of the topology's choices and the four-bar's, in
    catalogue order (the baseline last): `total` shared in the weights of the module docstring."""
    from linkcli.mechanisms.drawn import catalogue
    todo = catalogue.choices(problem.topology, problem.kind, _timing(problem)) + catalogue.choices(catalogue.BASELINE,
                                                                                         problem.kind, "prescribed")
    weight = [1.0 / TRIAD_COST if c.plan == TRIAD else 1.0 for c in todo]
    unit = total / (DRAWINGS * sum(weight))
    return [(c, max(MIN_RUN_BUDGET, int(unit * w))) for c, w in zip(todo, weight)]


def default_total(problem) -> int:
    """The sweep's budget without [solver] budget: the shared search's default, and with free
    timing through more than search.FREE_TARGETS targets its share of it (search.free_share: a
    run's batched Levenberg-Marquardt grows with the timing's variables faster than its
    evaluations), as a single drawing's search has."""
    from linkcli.synthesis import search as shared
    if problem.kind == "function":
        return shared.DEFAULT_BUDGET
    n = len(problem.points) if problem.kind == "path" else len(problem.poses)
    return max(1, int(shared.DEFAULT_BUDGET * shared.free_share(problem.timing, n)))


def sweep(problem) -> Solution:
    """The best six-bar of `problem`'s topology, with the `topologies` table (module docstring)."""
    from linkcli.analysis.tolerance_report import with_links
    from linkcli.errors import SolveInputError
    from linkcli.mechanisms.drawn import catalogue
    from linkcli.mechanisms.drawn.schema import known_lengths
    from linkcli.synthesis.design import design_drawing
    opts = problem.meta.solver
    todo = runs(problem, opts.budget or default_total(problem))
    if not any(c.topology != catalogue.BASELINE for c, _ in todo):
        why = catalogue.empty_reason(problem.topology, problem.kind, _timing(problem))
        raise SolveInputError("a topology with a choice the design can search",
                              why or f"{problem.topology} offers no choice for this design",
                              path=problem.meta.path, key="linkage.topology")
    box = target_box(problem)
    half = problem.reach * math.hypot(box[2] - box[0], box[3] - box[1])
    if problem.kind == "function":
        half = problem.reach * math.hypot(FUNCTION_BOX[2], FUNCTION_BOX[3])
    best_of: dict = {}
    used = 0
    for index, (choice, budget) in enumerate(todo):
        run_problem = replace(problem, meta=replace(problem.meta, solver=replace(opts, budget=budget)))
        for drawing in catalogue.starting_drawings(choice, box, seed=opts.seed or 0, count=DRAWINGS):
            joint = "P" if problem.kind == "path" else None
            link = choice.target if problem.kind != "path" else None
            sol = design_drawing(with_links(run_problem, known_lengths(drawing)), drawing,
                                 boxes_of(drawing, half, problem.kind), joint=joint, link=link)
            used += sol.solver.evaluations if sol.solver else 0
            if choice.label not in best_of or _rank(sol, index) < _rank(best_of[choice.label][0], index):
                best_of[choice.label] = (sol, index)
    six = [best_of[c.label] for c, _ in todo if c.topology != catalogue.BASELINE]
    best, _ = min(six, key=lambda item: _rank(*item))
    rows = [_row(c, budget, best_of[c.label][0], problem) for c, budget in todo]
    converged = best.solver.converged if best.solver else False
    solver = SolverRecord(best.solver.method if best.solver else "multistart-lm+kkt", opts.seed, used, converged)
    sections = dict(best.sections)
    sections["topologies"] = {"topology": problem.topology, "reach": problem.reach, "rows": rows}
    chosen = next(r for r in rows if best_of[r["choice"]][0] is best)
    notes = list(best.notes) + [_baseline_note(rows, chosen)]
    return replace(best, solver=solver, sections=sections, notes=[n for n in notes if n],
                   message=f"{chosen['choice']}: {best.message}")


def _rank(sol: Solution, index: int) -> tuple:
    """Feasible (ok, then not-converged) before infeasible; then the least objective; then the
    catalogue's order."""
    order = {Status.OK: 0, Status.NOT_CONVERGED: 0, Status.INFEASIBLE: 1}[sol.status]
    objective = sol.objective if sol.objective is not None and math.isfinite(sol.objective) else math.inf
    return order, objective, index


def _row(choice, budget: int, sol: Solution, problem) -> dict:
    """One row of the topologies table: the choice, the budget of each of its runs, its best
    design's status and error."""
    row = {"choice": choice.label, "topology": choice.topology, "budget": budget, "status": sol.status.value,
           "objective": sol.objective, "max_error": None}
    if sol.positions is not None and len(sol.positions.error):
        worst = max(abs(float(e)) for e in sol.positions.error)
        row["max_error"] = problem.meta.units.from_rad(worst) if sol.positions.kind == "angle" else worst
    elif "error" in sol.sections:
        row["max_error"] = sol.sections["error"].get("max_position_error")
    return row


def _baseline_note(rows: list[dict], chosen: dict) -> str:
    """How the chosen six-bar compares with the best four-bar."""
    four = [r for r in rows if r["topology"] == "four-bar" and r["objective"] is not None]
    if not four or chosen["objective"] is None:
        return ""
    base = min(four, key=lambda r: (r["status"] == "infeasible", r["objective"]))
    return (f"best six-bar: {chosen['choice']} ({chosen['status']}, objective {chosen['objective']:.6g}); "
            f"best four-bar: objective {base['objective']:.6g} ({base['status']})")
