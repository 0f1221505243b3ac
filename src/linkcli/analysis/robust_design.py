"""Designs that minimize failure (`[objective] minimize = "failure-probability"`, path and
function generation; docs/tolerance.md).

Starting from the type's least-squares design x0, the design x (the type's own variables:
lengths, coupler point, placement, timing or start angles) minimizing the largest failure
probability over the targets,

    min_x max_j p_j(x),  p_j = P(a made linkage misses target j by more than allowed_error,
                               or cannot assemble there on the design's branch),

subject to the type's constraints (Grashof class, transmission window, travel ...) and to
the defect-free probability D(x) = P(a made linkage assembles on the design's branch at every
target and travels between them) >= `[constraints] defect_free`: the seed study's
probabilistic synthesis (the largest failure probability over the trajectory points
minimized, reliability and defect-free motion as probabilistic constraints; on random
link lengths and kinematic reliability see also Rao & Bhatti 2001, "Probabilistic approach
to manipulator kinematics and dynamics", Reliability Engineering & System Safety 72).

The made linkages are the [tolerance] table's (lengths, general tolerances at each design's
own lengths, clearance or fits); the probabilities are Monte Carlo shares on common random
numbers (SEARCH_SAMPLES of the study's draws, the same at every design), each sample's
failure indicator smoothed (logistic, bandwidth SMOOTH allowed_error) so that p_j is smooth
in x. The minimax is solved in its epigraph form, min z subject to p_j(x) <= z and the type's
constraints g(x) >= 0, by SLSQP in the unit box of the free variables with forward
differences (one pass over the common draws per variable), in rounds within a trust box
around the current design (far from it the smoothed shares saturate at 1, where a full
quadratic step would be lost): a round that lowers the largest share is taken and the box
doubles when the step reached its edge; one that does not quarters the box. D(x) is then checked on the same
draws; when the design found falls below the limit, the largest step from x0 towards it that
meets it is taken (bisection). A design no better than x0 on the exact shares of the common
draws is not taken.

Both designs are then verified by a fresh Monte Carlo (another seed stream, `samples` of
[tolerance]): per target the failure share, its largest with the Wilson 95 % interval, the
defect-free share and the share failing anywhere. The robust design is the answer; the
`robust` section reports both side by side.
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np

from linkcli.analysis.made_parts import parts as made_parts
from linkcli.analysis.made_parts import scales
from linkcli.analysis.tolerance import VERIFY_STREAM, Draws, clearance_terms, plan_of, wilson
from linkcli.errors import SolveInputError

SEARCH_SAMPLES = 5000
SMOOTH = 0.1  # bandwidth of the smoothed failure indicator, a share of allowed_error
PASS_BUDGET = 3000  # passes over the common draws the search may spend
FD_STEP = 1e-5  # in output_scales: the outputs move 1e-5 allowed_error
MAX_ITERATIONS = 100  # SLSQP's, each round
MAX_ROUNDS = 40
TRUST_START = 1.0  # the first box's half width, in output_scales (outputs move ~ allowed_error)
SETTLE = 1e-7  # a step (or box) this small (output_scales) ends the rounds
FTOL = 1e-12
FEASIBLE = 1e-9  # the type's constraints, relative


class Adapter(Protocol):
    """A synthesis type's view of its design for the robust search: the free variables'
    least-squares values `x0` and bounds `lo`, `hi`; `solution(x)` the linkage with its
    targets (a Solution: linkage, positions, working_span); `inequalities(x)` the type's
    constraints as g >= 0 (scaled to order 1); `final(x)` the type's full Solution."""

    x0: np.ndarray
    lo: np.ndarray
    hi: np.ndarray

    def solution(self, x: np.ndarray): ...

    def inequalities(self, x: np.ndarray) -> np.ndarray: ...

    def final(self, x: np.ndarray): ...


class Study:
    """The common draws and what a design's made linkages do on them."""

    def __init__(self, problem, adapter: Adapter, n: int, stream=()):
        from linkcli.mechanisms import of
        self.problem, self.adapter = problem, adapter
        tol = problem.meta.tolerance
        self.allowed = float(tol.allowed_error)
        model = of(adapter.solution(adapter.x0).linkage).tolerance_model(problem, adapter.solution(adapter.x0))
        if getattr(model, "deviations", None) is None:
            raise SolveInputError("a mechanism whose tolerance model gives each target's deviation "
                                  'for minimize = "failure-probability"', "one that does not",
                                  path=problem.meta.path, key="objective.minimize")
        self.parts = made_parts(model, problem)
        self.plan = plan_of(model, self.parts, n, tol.distribution)
        self.draws = Draws(int(problem.meta.solver.seed), self.plan, stream, keep=True)
        self.terms = {}
        self.passes = 0

    def deviations(self, x: np.ndarray) -> np.ndarray:
        """(n, M) each common sample's deviation at each target (inf: fails there)."""
        from linkcli.mechanisms import of
        sol = self.adapter.solution(x)
        model = of(sol.linkage).tolerance_model(self.problem, sol)
        tol = self.problem.meta.tolerance
        parts = self.parts.with_scale(scales(model, self.problem, tol.lengths, tol.general,
                                             ("tolerance.lengths", tol.lines.get("lengths"))))
        out = []
        for start, ch in self.draws:
            if start not in self.terms:  # the plays' offsets do not depend on the design
                self.terms[start] = clearance_terms(model, ch, parts)
            terms, jammed = self.terms[start]
            dev = model.deviations(ch.u * parts.scale[None, :], terms)
            if jammed is not None:
                dev = np.where(jammed[:, None], np.inf, dev)
            out.append(dev)
        self.passes += 1
        return np.concatenate(out)

    def smoothed(self, dev: np.ndarray) -> np.ndarray:
        """(M,) the targets' smoothed failure shares."""
        z = np.clip((dev - self.allowed) / (SMOOTH * self.allowed), -40.0, 40.0)
        return np.mean(np.where(np.isfinite(dev), 1.0 / (1.0 + np.exp(-z)), 1.0), axis=0)


def shares(dev: np.ndarray, allowed: float) -> dict:
    """Exact shares of one set of deviations: per target, the largest, defect-free, any."""
    fails = ~np.isfinite(dev) | (dev > allowed)
    per = fails.mean(axis=0)
    return {"per_target": per, "largest": float(per.max()), "at": int(np.argmax(per)),
            "count": int(fails[:, int(np.argmax(per))].sum()),
            "defect_free": float(np.mean(np.all(np.isfinite(dev), axis=1))),
            "anywhere": float(np.mean(np.any(fails, axis=1)))}


def output_scales(study: Study, x0: np.ndarray, free: np.ndarray) -> np.ndarray:
    """Per free variable, the change that moves some target's nominal output by the allowed
    error (a central difference of the outputs; the variables' natural step)."""
    ad = study.adapter
    out0 = np.asarray(ad.solution(x0).positions.achieved, dtype=float).reshape(-1)
    scale = np.empty(int(free.sum()))
    for i, k in enumerate(np.flatnonzero(free)):
        h = 1e-7 * max(abs(x0[k]), ad.hi[k] - ad.lo[k], 1e-300)
        up, down = x0.copy(), x0.copy()
        up[k] += h
        down[k] -= h
        slope = (np.asarray(ad.solution(up).positions.achieved, dtype=float).reshape(-1)
                 - np.asarray(ad.solution(down).positions.achieved, dtype=float).reshape(-1)) / (2 * h)
        worst = float(np.max(np.abs(slope))) if slope.size and np.all(np.isfinite(slope)) else 0.0
        scale[i] = study.allowed / worst if worst > 0 else ad.hi[k] - ad.lo[k]
    del out0
    return scale


def search(study: Study, defect_free: float):
    """(x, iterations, how, converged): the robust design (module docstring)."""
    from scipy.optimize import minimize
    ad = study.adapter
    free = ad.hi > ad.lo
    if not free.any():
        return ad.x0.copy(), 0, "nothing free to choose: the given design", True
    scale = output_scales(study, ad.x0, free)
    lo_all = (ad.lo[free] - ad.x0[free]) / scale  # the box in the scaled variables (x0 at 0)
    hi_all = (ad.hi[free] - ad.x0[free]) / scale

    def design(y):
        x = ad.x0.copy()
        x[free] = np.clip(ad.x0[free] + y * scale, ad.lo[free], ad.hi[free])
        return x

    cache: dict = {}

    def values(y):
        key = y.tobytes()
        if key not in cache:
            if study.passes >= PASS_BUDGET:
                raise _Spent
            x = design(y)
            cache[key] = (study.smoothed(study.deviations(x)), np.asarray(ad.inequalities(x), dtype=float))
        return cache[key]

    def jacobian(y):
        p0, g0 = values(y)
        jp, jg = np.zeros((len(p0), len(y))), np.zeros((len(g0), len(y)))
        for k in range(len(y)):  # one pass over the common draws per free variable
            step = FD_STEP if y[k] + FD_STEP <= hi_all[k] else -FD_STEP
            moved = y.copy()
            moved[k] += step
            p1, g1 = values(moved)
            jp[:, k], jg[:, k] = (p1 - p0) / step, (g1 - g0) / step
        return jp, jg

    k = int(free.sum())
    y = np.zeros(k)
    best, radius, iterations = float(values(y)[0].max()), TRUST_START, 0
    message, converged = "the minimax optimum (SLSQP in a trust region)", False
    for _ in range(MAX_ROUNDS):  # SLSQP within a box around y: the smoothed shares saturate
        lo, hi = np.maximum(y - radius, lo_all), np.minimum(y + radius, hi_all)  # far away, a flat 1
        cons = [{"type": "ineq", "fun": lambda w: w[k] - values(w[:k])[0],
                 "jac": lambda w: np.hstack([-jacobian(w[:k])[0], np.ones((len(values(w[:k])[0]), 1))])},
                {"type": "ineq", "fun": lambda w: values(w[:k])[1],
                 "jac": lambda w: np.hstack([jacobian(w[:k])[1], np.zeros((len(values(w[:k])[1]), 1))])}]
        try:
            res = minimize(lambda w: w[k], np.append(y, best), jac=lambda w: np.eye(k + 1)[k], method="SLSQP",
                           bounds=list(zip(lo, hi)) + [(0.0, 1.0)], constraints=cons,
                           options={"maxiter": MAX_ITERATIONS, "ftol": FTOL})
            iterations += int(res.nit)
            step = np.clip(res.x[:k], lo, hi)
            p_new, g_new = values(step)
        except _Spent:
            message = f"the search stopped at its budget ({PASS_BUDGET} passes over the common draws)"
            break
        if float(p_new.max()) < best and np.all(g_new >= -FEASIBLE):
            moved = float(np.max(np.abs(step - y)))
            y, best = step, float(p_new.max())
            if moved >= 0.5 * radius:
                radius = 2.0 * radius
            elif moved <= SETTLE:
                converged = True
                break
        elif float(np.max(np.abs(step - y))) <= SETTLE:
            converged = True  # SLSQP stays where it started: a minimax point
            break
        else:
            radius *= 0.25
            if radius < SETTLE:
                converged = True
                break
    else:
        message = f"the search stopped after {MAX_ROUNDS} rounds"
    x = design(y)
    how = message
    if np.any(np.asarray(ad.inequalities(x)) < -FEASIBLE):
        x, how = ad.x0.copy(), "no design found that keeps the constraints: the least-squares design"
    exact0 = shares(study.deviations(ad.x0), study.allowed)
    exact = shares(study.deviations(x), study.allowed)
    if exact["defect_free"] < defect_free <= exact0["defect_free"]:
        x, how = _towards(study, ad.x0, x, defect_free), how + "; stepped back to meet defect_free"
        exact = shares(study.deviations(x), study.allowed)
    if exact["largest"] > exact0["largest"]:
        x, how = ad.x0.copy(), "no design with a lower largest failure share: the least-squares design"
    return x, iterations, how, converged


class _Spent(Exception):
    """The search's pass budget is spent."""


def _towards(study: Study, x0, x1, defect_free: float, steps: int = 30):
    """The point x0 + s (x1 - x0) with the largest s in [0, 1] whose defect-free share on
    the common draws is at least the limit (x0's is)."""
    lo, hi = 0.0, 1.0
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        if shares(study.deviations(x0 + mid * (x1 - x0)), study.allowed)["defect_free"] >= defect_free:
            lo = mid
        else:
            hi = mid
    return x0 + lo * (x1 - x0)


def robust(problem, adapter: Adapter, least_squares):
    """The robust design's Solution, with the `robust` section beside the least-squares one."""
    tol = problem.meta.tolerance
    n = min(tol.samples, SEARCH_SAMPLES)
    with np.errstate(all="ignore"):
        study = Study(problem, adapter, n)
        x, iterations, how, converged = search(study, problem.defect_free)
        check = Study(problem, adapter, tol.samples, VERIFY_STREAM)
        before = shares(check.deviations(adapter.x0), check.allowed)
        after = shares(check.deviations(x), check.allowed)
    sol = adapter.final(x)
    rows = [_row("least squares", least_squares, before, tol.samples, problem),
            _row("robust", sol, after, tol.samples, problem)]
    sol.sections["robust"] = {
        "objective": "largest failure probability over the targets",
        "defect_free_min": float(problem.defect_free),
        "designs": rows,
        "search_samples": n,
        "check_samples": tol.samples,
        "search": how,
    }
    from linkcli.solution import Status
    if after["defect_free"] < problem.defect_free and sol.status is not Status.INFEASIBLE:
        sol.status = Status.INFEASIBLE
        sol.message = (f"defect-free share {after['defect_free']:.6g} of the fresh check below "
                       f"[constraints] defect_free = {problem.defect_free:g}")
    elif not converged and sol.status is Status.OK:
        sol.status = Status.NOT_CONVERGED
        sol.message = (f"{how}: its design fails less often than the least-squares one (largest "
                       f"failure share {after['largest']:.6g} against {before['largest']:.6g} on a fresh "
                       "check), but the search did not settle: a lower one may exist")
    sol.sections["robust"]["converged"] = bool(converged)
    return sol


def _row(name: str, sol, s: dict, n: int, problem) -> dict:
    from linkcli.mechanisms import of
    lo, hi = wilson(s["count"], n)
    units = problem.meta.units
    pos = sol.positions
    err = float(np.max(np.abs(pos.error))) if pos is not None and len(pos.error) else math.nan
    kind_angle = pos is not None and pos.kind == "angle"
    row = {"design": name, **{k: v for k, v in of(sol.linkage).lengths_section(units).items()
                              if k in ("ground", "input", "coupler", "output")},
           "error_max": float(units.from_rad(err)) if kind_angle else err,
           "largest_failure_probability": s["largest"], "largest_ci95": [lo, hi],
           "at_target": s["at"] + 1, "defect_free": s["defect_free"], "failure_anywhere": s["anywhere"]}
    return row
