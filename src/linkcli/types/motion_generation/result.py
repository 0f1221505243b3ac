"""A motion generator's Solution: the four-bar of a screened candidate (screen.py) with its
positions and error sections, its status (ok, not-converged, infeasible) and message (the
worst transmission deviation, or which defects the candidates have). Shared by the search
(solve) and the front (pareto).
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.four_bar.model import FourBar
from linkcli.solution import Solution, Status
from linkcli.textnum import num

from . import sections
from .screen import DEFECTS

DEFECT_TEXT = {"assembly": "does not reach every pose", "branch": "branch defect", "order": "order defect",
               "grashof": "Grashof class", "transmission": "transmission window", "bounds": "outside the bounds",
               "branch_choice": "not on the branch asked for"}


def solution(problem, poses, scale, p, phi, signs, res, k, feasible, solver, extra, notes, objective,
              weight=None) -> Solution:
    u = problem.meta.units
    weight = weight if weight is not None else (problem.angle_weight or scale)
    gx, gy, gang, d, a, b, c, px, py, cang = (float(v) for v in p)
    branch = "open" if signs[0] < 0 else "crossed"
    fb = FourBar(ground=d, input=a, coupler=b, output=c, branch=branch, coupler_point=(px, py),
                 ground_pivot=(gx, gy), ground_angle=gang, coupler_angle=cang)
    achieved = res["achieved"][k]
    pos, ang = res["position_error"][k], res["angle_error"][k]
    if objective is None:
        objective = float(np.sum(pos ** 2 + (weight * ang) ** 2))
    span_lo, span_w = (float(v[k]) for v in res["span"])
    secs = {"positions": sections.position_rows(phi, poses, achieved, pos, ang, u, max(d, a, b, c)),
            "error": sections.error_section(objective, pos, ang, weight, u, max(d, a, b, c),
                                            problem.meta.reference)}
    secs.update(extra)
    names = [name for name in DEFECTS if bool(res["defects"][name][k])]
    if feasible:
        status = Status.OK if solver.converged else Status.NOT_CONVERGED
        message = (f"{len(poses)} poses: reached in order on the {branch} branch, no branch or order "
                   f"defect; worst transmission deviation from 90 deg over the working span "
                   f"{num(float(u.from_rad(float(res['quality'][k]))))} {u.angle}")
        if not solver.converged:
            message += "; the local polish stopped before meeting its tolerances"
    else:
        status = Status.INFEASIBLE
        message = why(problem, res, names)
    return Solution(status=status, linkage=fb, message=message, positions=None, objective=objective,
                    solver=solver, sections=secs, notes=list(notes), working_span=(span_lo, span_w))


def why(problem, res, names) -> str:
    """Why no candidate is defect-free: how many candidates have each defect, and the
    defects of the one reported."""
    total = len(res["count"])
    counts = [f"{DEFECT_TEXT[name]} {int(np.sum(res['defects'][name]))}" for name in DEFECTS
              if np.any(res["defects"][name])]
    what = "the design" if total == 1 else f"all {total} candidates"
    text = f"no defect-free linkage: {what} " + ("has" if total == 1 else "have") + " defects"
    if total > 1:
        text += f" ({', '.join(counts)})"
    return text + f"; the reported one: {', '.join(DEFECT_TEXT[n] for n in names)}"
