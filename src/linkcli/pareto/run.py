"""A synthesis type's front, start to end: anchors, levels, points, rows, the `front` section
and the Solution the report shows (the knee's design). docs/pareto.md; the steps are
linkcli.pareto.front's."""

from __future__ import annotations

import math

import numpy as np

from linkcli.pareto import front as fr
from linkcli.pareto.hypervolume import KNEE_RULE, hypervolume, knee, reference_point
from linkcli.pareto.objectives import Measure, unit_of
from linkcli.pareto.scalarized import Scalarized
from linkcli.pareto.spread import map_levels
from linkcli.search.budget import Budget
from linkcli.solution import SolverRecord, Status

METHOD = "epsilon-constraint"


def solve_front(problem, space, found) -> object:
    """The Solution of a front problem: `space` the type's hook (linkcli.pareto.space) built
    from its least-squares answer `found` (a Solution, the error anchor)."""
    spec = problem.meta.front
    names = spec.objectives
    measure = Measure(problem, space, names)
    budget = Budget(10**12)
    with np.errstate(all="ignore"):
        anchors = _anchors(measure, space, budget)
        values = np.array([p.values for p in anchors])
        scales = fr.scales_of(values)
        t_scale = max(1.0, 2.0 * float(values[:, 0].max()) / scales[0])
        tasks = [fr.Task(measure, 0, scales, t_scale, levels, start, k)
                 for k, (levels, start) in enumerate(fr.chains(fr.levels(values, spec.points, scales),
                                                               [p.x for p in anchors]))]
        solved = map_levels(fr.solve_chain, tasks)
    ends: dict = {}
    for chain, used in solved:
        budget.add(used)
        for index, point in chain:
            ends.setdefault(index, [])
            if point is not None:
                ends[index].append(point)
    best = [fr.best_of(ends[index], 0, scales[0]) for index in sorted(ends)]
    with np.errstate(all="ignore"):  # each level's best end settled (the chains' other ends never are)
        settled = map_levels(fr.settle_point, [fr.Settle(measure, 0, scales, t_scale, p) for p in best if p is not None])
    points = []
    for point, used in settled:
        budget.add(used)
        points.append(point)
    # the first objective's anchor is a row; another's, unless its end level's point stands for it
    points = [a for k, a in enumerate(anchors) if k == 0 or not fr.refines(a, k, points, scales)] + points
    return _report(problem, space, measure, points, scales, budget, found)


def _anchors(measure: Measure, space, budget: Budget) -> list:
    """Each objective's anchor: x0 for `error`, else the objective minimized from x0."""
    out = []
    x0 = np.asarray(space.x0, float)
    for k, name in enumerate(measure.names):
        if name == "error":
            out.append(fr.Point(x0.copy(), measure.values(x0), -1 - k, True, True))
            continue
        out.append(_minimize(measure, k, {}, None, x0, budget, -1 - k))
    return out


def _minimize(measure, primary: int, eps: dict, scales, x, budget: Budget, start: int) -> fr.Point:
    """Objective `primary` minimized from design x, the levels `eps` held."""
    scales = np.ones(len(measure.names)) if scales is None else scales
    v0 = measure.values(x)
    problem = Scalarized(measure, primary, eps, scales, budget)
    if problem.epigraph:
        scales = scales.copy()
        scales[primary] = max(abs(float(v0[primary])), 1e-300) if math.isfinite(v0[primary]) else 1.0
        problem.scales = scales
        problem.t_scale = 2.0
    with budget.limit(fr.POINT_BUDGET):
        xe, certified = fr.polish_from(problem, x)
        if certified:
            xe, _ = fr.settle(problem, xe)
    ve = measure.values(xe)
    if not (np.all(np.isfinite(ve)) and ve[primary] <= v0[primary] and _holds(measure, eps, ve)):
        return fr.Point(np.asarray(x, float).copy(), v0, start, False, True)  # no better: stays
    return fr.Point(xe, ve, start, certified, True)


def _holds(measure, eps: dict, values) -> bool:
    return all(values[k] <= level * (1 + 1e-9) + 1e-300 for k, level in eps.items())


def _report(problem, space, measure: Measure, points: list, scales, budget: Budget, found):
    """Finish, filter and order the points (linkcli.pareto.front, 4.); the knee's Solution."""
    units = problem.meta.units
    names = measure.names
    finished = []
    for p in points:
        sol = space.final(p.x)
        if sol.status is not Status.OK:
            continue
        values = measure.snapped(measure.values(p.x), sol)
        if not np.all(np.isfinite(values)):
            continue
        finished.append((p, sol, values))
    if not finished:
        found.message = (f"no design of the front passes every constraint of the file: the "
                         f"least-squares design is reported ({found.message})")
        found.status = Status.INFEASIBLE if found.status is Status.OK else found.status
        return found
    kept = fr.non_dominated(finished, np.array([v for _, _, v in finished]), scales)
    tol = fr.TIE * np.asarray(scales)
    kept.sort(key=lambda item: tuple(np.round(item[2] / np.maximum(tol, 1e-300)).tolist()))
    values = np.array([v for _, _, v in kept])
    ref = (np.array(problem.meta.front.reference_point, dtype=float)
           if problem.meta.front.reference_point is not None else reference_point(values))
    at = knee(values)
    rows = []
    for (p, sol, v) in kept:
        from linkcli.mechanisms import of
        rows.append({"objectives": {name: float(x) for name, x in zip(names, v)},
                     "linkage": of(sol.linkage).lengths_section(units),
                     "certified": bool(p.certified), "confirmed": bool(p.confirmed or p.start < 0)})
    section = {
        "objectives": list(names),
        "units": {name: unit_of(name, units, space.error_kind) for name in names},
        "method": METHOD,
        "rows": rows,
        "hypervolume": hypervolume(values, ref),
        "reference_point": [float(v) for v in ref],
        "knee": {"index": at, "rule": KNEE_RULE},
    }
    main = kept[at][1]
    uncertified = [i for i, row in enumerate(rows) if not row["certified"]]
    evaluations = (found.solver.evaluations if found.solver is not None else 0) + budget.used
    main.solver = SolverRecord(f"{METHOD} ({found.solver.method if found.solver else 'type'})",
                               problem.meta.solver.seed, int(evaluations), not uncertified)
    main.sections = {**main.sections, "front": section}
    main.alternatives = [sol for _, sol, _ in kept]
    if uncertified:
        main.status = Status.NOT_CONVERGED
        main.message = (f"front of {len(rows)} designs, each within every constraint; the polish of rows "
                        f"{', '.join(str(i) for i in uncertified)} stopped before a KKT point: "
                        "a lower first objective may exist there")
    else:
        main.message = (f"front of {len(rows)} designs, each within every constraint and a KKT point of "
                        f"its level; the report shows the knee (row {at}): " + (main.message or ""))
    return main
