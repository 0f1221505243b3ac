"""A path generator's candidate and the Solution made of it: `violations` (every constraint a
design breaks, checked with the exact kinematics: Grashof class, transmission window,
assembly at every target, no dead point between the first and last target, order within one
turn) and `solution` (the four-bar, its positions, status and message). Shared by the
multistart (solve), the robust design (robust) and the front (pareto).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.four_bar.model import FourBar
from linkcli.noise import snap
from linkcli.solution import Positions, Solution, SolverRecord, Status
from linkcli.textnum import num
from linkcli.types.path_generation.model import N_LINK, SHORTEST, Design, rho2_extremes

EXACT_RMS = 1e-9  # rms error, relative to the targets' extent, that ends the rounds
ANGLE_VIOLATIONS = ("transmission", "order")  # violations measured in radians (others: length)


@dataclass
class Candidate:
    """One finished candidate: full vector, branch sign (-1 open, +1 crossed), turning
    direction (+1 ccw, -1 cw) and whether its local search converged."""

    x: np.ndarray
    sign: float
    s: float
    converged: bool
    round: int = 0  # the multistart round that found it


def exact_objective(design: Design) -> float:
    """An objective this small is an exact fit: rms error EXACT_RMS of the targets' extent."""
    return design.n_targets * (EXACT_RMS * design.scale) ** 2


def violations(design: Design, x, sign, s) -> list[tuple[str, float, str]]:
    """Every constraint the candidate breaks, checked with the exact kinematics:
    (constraint, amount, message). Amounts in the length unit, or radians for angles."""
    dd, a, b, c = (float(v) for v in x[:4])
    out = []
    phi = design.input_angles(x[None], np.array([s]))[0]
    if design.grashof != "any":
        cls = kin.GRASHOF_CLASSES[int(kin.grashof_code(a, b, c, dd))]
        if cls != design.grashof:
            links = np.array([dd, a, b, c])
            if design.grashof in SHORTEST:
                k = SHORTEST[design.grashof]
                rest = [j for j in range(4) if j != k]
                amt = max(links[k] + links[j] - sum(links[o] for o in rest if o != j) for j in rest)
            else:
                srt = np.sort(links)
                amt = srt[1] + srt[2] - srt[0] - srt[3]
            out.append(("grashof", max(float(amt), 0.0), f"the linkage is {cls}, not {design.grashof}"))
    lo_span, width = float(phi.min()), float(phi.max() - phi.min())
    if design.window is not None:
        lo, hi = (0.0, kin.TWO_PI) if design.full_turn else (lo_span, lo_span + width)
        mn, _, mx, _ = kin.transmission_extremes(a, b, c, dd, lo, hi)
        over = "the full turn" if design.full_turn else "the targets' span"
        if mn < design.window[0] - 1e-12:
            out.append(("transmission", design.window[0] - mn, f"the smallest transmission angle over {over} "
                        f"is below the window"))
        if mx > design.window[1] + 1e-12:
            out.append(("transmission", mx - design.window[1], f"the largest transmission angle over {over} "
                        f"is above the window"))
    p = kin.pose(a, b, c, dd, phi, "open" if sign < 0 else "crossed")
    if not np.all(p.valid):
        bad = np.flatnonzero(~p.valid)
        short = float(np.max(np.maximum(abs(b - c) - p.rho, p.rho - (b + c))[bad]))
        out.append(("assembly", short, "the linkage cannot assemble at target"
                    + ("s " if len(bad) > 1 else " ") + ", ".join(str(i + 1) for i in bad)))
    if not design.full_turn or kin.input_arcs(a, b, c, dd) is not None:
        r2_min, r2_max = rho2_extremes(np.array([a]), np.array([dd]), np.array([lo_span]),
                                       np.array([width]))
        over = max(abs(b - c) - math.sqrt(r2_min[0]), math.sqrt(r2_max[0]) - (b + c))
        if over > 1e-12 * (b + c):
            out.append(("branch", over, "the input passes a dead point between the first and "
                        "the last target (the linkage would change branch)"))
    if design.timing == "free":
        steps = x[N_LINK + 1:]
        if np.any(steps < 0) or steps.sum() > kin.TWO_PI * (1 + 1e-12):
            out.append(("order", float(max(steps.sum() - kin.TWO_PI, -steps.min())),
                        "the targets are not reached in order within one turn of the input"))
    return out


# ---------------------------------------------------------------- the Solution

def solution(problem, design: Design, best: Candidate, bad, method, budget,
             confirmed: bool = True) -> Solution:
    u = problem.meta.units
    x, sign, s = design.wrapped(best.x[None])[0], best.sign, best.s
    dd, a, b, c, px, py, gx, gy, gamma = (float(v) for v in x[:N_LINK])
    branch = "open" if sign < 0 else "crossed"
    fb = FourBar(ground=dd, input=a, coupler=b, output=c, branch=branch, coupler_point=(px, py),
                 ground_pivot=(gx, gy), ground_angle=gamma)
    pts, pose, phi = design.points(x[None], np.array([sign]), np.array([s]))
    pts, phi = pts[0], phi[0]
    err = np.hypot(pts[:, 0] - design.targets[:, 0], pts[:, 1] - design.targets[:, 1])
    objective = float(np.sum(err * err))
    first, last = float(phi[0]), float(phi[-1])
    monotone = bool(np.all(np.diff(phi) >= 0) or np.all(np.diff(phi) <= 0))
    span = (first, last - first) if monotone else (float(phi.min()), float(phi.max() - phi.min()))
    direction = ("ccw" if span[1] >= 0 else "cw") if monotone else "reverses"
    timing = {"timing": design.timing, "direction": direction,
              "first_input": float(u.from_rad(snap(float(kin.wrap(first)), 1.0))),
              "input_sweep": float(u.from_rad(abs(span[1])))}
    if design.timing == "prescribed" and design.free[N_LINK]:
        timing["input_offset"] = float(u.from_rad(float(x[N_LINK])))
    names = {v[0] for v in bad}
    defects = {"assembles": "assembly" not in names, "branch": branch,
               "branch_defect": "branch" in names,
               "order_defect": "order" in names}
    notes = _notes(problem, design, x) + _reach_note(problem, design, x, err)
    exact = objective <= exact_objective(design)  # an exact fit: nothing to add
    converged = (bool(best.converged) and confirmed) or exact
    solver = SolverRecord(method, problem.meta.solver.seed, budget.used, converged)
    n = design.n_targets
    if bad:
        status = Status.INFEASIBLE
        message = "; ".join(f"{name}: {msg} (by {_amount(name, amt, u, problem)})" for name, amt, msg in bad)
    else:
        status = Status.OK if converged else Status.NOT_CONVERGED
        order = ("at the prescribed input angles" if design.timing == "prescribed"
                 else f"in order within one turn ({timing['direction']}, input sweep "
                      f"{num(timing['input_sweep'])} {u.angle})")
        message = (f"{n} targets, {design.timing} timing: assembles at every target on the {branch} "
                   f"branch, without a branch change, and reaches them {order}")
        if not converged and not confirmed:
            message += ("; the search's rounds ended at different optima and none was found "
                        "again: another seed or a larger budget may end lower")
        elif not converged and budget.left < max(1, budget.cap // 10):
            message += "; the search stopped at its budget before the polish converged"
        elif not converged:
            message += ("; the local polish reached its iteration limit before meeting its "
                        "tolerances (a long, flat valley: another seed or method may end lower)")
    return Solution(
        status=status, linkage=fb, message=message,
        positions=Positions(kind="point", input=phi, target=design.targets.copy(), achieved=pts, error=err),
        objective=objective, solver=solver, sections={"timing": timing, "defects": defects},
        notes=notes, working_span=span,
    )


def _amount(name: str, amount: float, u, problem) -> str:
    if name in ANGLE_VIOLATIONS:
        return f"{num(u.from_rad(amount))} {u.angle}"
    return f"{num(amount)} {u.length}"


def _reach_note(problem, design: Design, x, err) -> list[str]:
    """A fit that misses a target by more than a tenth of the targets' extent: name the
    bounds the linkage presses against (a wider one may let it reach further)."""
    worst = float(np.max(err)) if len(err) else 0.0
    if not worst > 0.1 * design.scale:
        return []
    names = ("ground", "input", "coupler", "output", "coupler_point.x", "coupler_point.y",
             "ground_pivot.x", "ground_pivot.y")
    tight = [names[j] for j in range(len(names))
             if design.free[j] and min(x[j] - design.lo[j], design.hi[j] - x[j]) <= 1e-6 * (design.hi[j] - design.lo[j])]
    u = problem.meta.units.length
    msg = (f"the best fit misses a target by {num(worst)} {u} ({num(100 * worst / design.scale)} % of the "
           "targets' extent)")
    return [msg + (f"; at its bound: {', '.join(tight)}" if tight else "")]


def _notes(problem, design: Design, x) -> list[str]:
    """A length that ended on a lower bound of 0 raised to MIN_LENGTH."""
    out = []
    for j, name in enumerate(("ground", "input", "coupler", "output")):
        lo = problem.lengths[name][0]
        if lo == 0.0 and design.free[j] and x[j] <= design.lo[j] * (1 + 1e-9):
            out.append(f"{name} sits at the smallest length allowed ({num(design.lo[j])} "
                       f"{problem.meta.units.length}): its lower bound 0 is kept strictly positive")
    return out
