"""A design of the shared search: a problem over a population (its home's, or a starting
drawing's for a topology sweep) searched (synthesis.search), checked (synthesis.check) and
reported (synthesis.solution), or handed to its robust (synthesis.robust) or front
(synthesis.pareto) mode.
"""

from __future__ import annotations

import numpy as np

from linkcli.search.budget import Budget
from linkcli.solution import Solution
from linkcli.synthesis import search as shared
from linkcli.synthesis.check import violations
from linkcli.synthesis.model import Model
from linkcli.synthesis.solution import solution


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
    budget = Budget(opts.budget or shared.default_budget(model))
    model.budget = budget
    rng = np.random.default_rng(opts.seed)
    with np.errstate(all="ignore"):
        found, confirmed = shared.search(model, budget, rng)
        if not found:
            x, s = shared.starts.draws(model, rng, 1)
            found = [shared.Candidate(x[0], float(s[0]), False)]
        best = found[0]
        best.x = model.snapped(model.canonical(best.x))  # a function's similarity held: the copy nearest
        # the drawing; round-off printed as 0
        if problem.objective == "failure-probability":
            from linkcli.synthesis.robust import robust
            return robust(problem, model, best, budget, confirmed)
        found = solution(problem, model, best, violations(model, best.x, best.s), budget, confirmed)
        if problem.meta.front is not None:  # a Pareto front from this design (linkcli.pareto)
            from linkcli.synthesis.pareto import front
            return front(problem, model, best, budget, confirmed, found)
        return found
