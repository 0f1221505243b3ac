"""Path generation of a five-bar (five_bar_design.py; docs/five_bar.md, "Design"): the five
lengths and the ground pivot (and angle) under which the path lies in the workspace of one
pair of working modes with the best worst quality along it (mechanisms.five_bar.synthesis:
1 / condition number, or the transmission angles' sines).

Search, for each mode pair asked (one, or all four with modes = "any"):

1. seeded differential evolution (linkcli.search.evolution, Latin hypercube start, the
   population scored in one batch) over the free variables' unit box, on
   cost = -(worst quality) + PENALTY * (shortfalls: reach, dips into a folded limit, a
   change of assembly mode, the quality floor);
2. the epigraph polish (linkcli.search.kkt.settle): maximize t subject to quality >= t at
   every row (and column), the constraints >= 0 and the box, Newton on the KKT conditions
   of the constraints that bind, to round-off: the maximin optimum balances several rows
   exactly, and its printed digits are the optimum's, not the search's.

The mode pair with the best worst quality wins (values within noise.TIE: the first of
five_bar_design.ALL_MODES). A lower bound of 0 on a length is taken as LOW_SHARE of its upper
bound (a crank of length 0 is a singular five-bar).

Trade-off (minimize = "failure-probability"): for `tradeoff` quality levels from the
optimum q* down to the floor (max_condition / min_transmission, else q* / 2), equally spaced,
the design minimizing the largest first-order error sigma over the rows (synthesis.
first_order_sigma: the RMS of P's error for the [tolerance] lengths and clearance, a smooth
stand-in for the failure probability, which grows with it) subject to quality >= level,
by the same two steps; then each design's failure probability at every row by the
tolerance Monte Carlo (analysis.tolerance, the problem's seed). The reported design is the
row with the smallest largest failure probability (ties: the first, the better quality).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.five_bar import kinematics as kin
from linkcli.mechanisms.five_bar import synthesis as syn
from linkcli.mechanisms.five_bar.model import FiveBar, FiveBarMotion
from linkcli.mechanisms.five_bar.track import solve as solve_track
from linkcli.noise import TIE, first_max, first_min, snap
from linkcli.search import kkt
from linkcli.search.budget import Budget, BudgetSpent
from linkcli.search.evolution import evolve
from linkcli.search.sampling import latin_hypercube
from linkcli.solution import Positions, Solution, SolverRecord, Status
from linkcli.textnum import num

DEFAULT_BUDGET = 1_000_000  # candidate evaluations (each over every row)
PENALTY = 10.0
POPSIZE = 15  # members per free variable
GENERATIONS = 400
LEVEL_GENERATIONS = 200  # a trade-off level's search, from the previous level's design
RETRY_GENERATIONS = 1000  # a search whose polish did not settle goes on this long,
RETRY_TOL = 1e-10  # to this tolerance
DE_TOL = 1e-6
LOW_SHARE = 1e-3
FEASIBLE = 1e-10  # a shortfall this small is round-off
SETTLE_STEP = 3e-6  # unit box: the polish's difference step (kkt.slopes); the conditioning
# bends sharply near isotropic rows, where the usual 3e-4 step's truncation error is 1e-3
AT_BOUND = 1e-4  # unit box: a variable this close to a bound after the search starts on it
ACTIVE = 1e-4  # a constraint this close to 0 binds at the polish's start (the search ends within it)
STEP_TOL = 1e-8  # unit box: a Newton step this small has converged (the slopes' round-off at
# SETTLE_STEP leaves steps of 1e-9; six printed digits need 1e-7)


class Space:
    """The free variables (lo < hi) of the design and the unit box <-> x map."""

    def __init__(self, bounds: dict) -> None:
        lo, hi = [], []
        for k, name in enumerate(syn.VARIABLES):
            a, b = bounds[name]
            if k < 5 and a <= 0.0:
                a = LOW_SHARE * b
            lo.append(a)
            hi.append(b)
        self.lo, self.hi = np.array(lo), np.array(hi)
        self.free = self.hi > self.lo
        self.size = int(self.free.sum())

    def x(self, u: np.ndarray) -> np.ndarray:
        """(N, 8) designs from (N, free) unit-box points."""
        u = np.atleast_2d(u)
        x = np.tile(self.lo, (len(u), 1))
        x[:, self.free] = self.lo[self.free] + u * (self.hi - self.lo)[self.free]
        return x

    def u(self, x: np.ndarray) -> np.ndarray:
        return (np.asarray(x)[self.free] - self.lo[self.free]) / (self.hi - self.lo)[self.free]

    def holding(self, x: np.ndarray, held) -> Space:
        """This space with the variables `held` (indices into VARIABLES) fixed at x's values."""
        if not len(held):
            return self
        out = Space.__new__(Space)
        out.lo, out.hi = self.lo.copy(), self.hi.copy()
        out.lo[held] = out.hi[held] = np.asarray(x)[held]
        out.free = out.hi > out.lo
        out.size = int(out.free.sum())
        return out


class Goal:
    """What one search optimizes: the worst quality (sigma None), or the largest first-order
    error over sigma_ref (sigma = (length variances, pin variance)) with the quality at least
    `level`; the path, the modes, the assembly mode kept (`side`: None, the first row's)."""

    def __init__(self, problem, path, modes, measure, side=None, level=None, sigma=None, sigma_ref=1.0):
        self.problem, self.path, self.modes, self.measure = problem, path, modes, measure
        self.side, self.level, self.sigma, self.sigma_ref = side, level, sigma, sigma_ref

    def along(self, x):
        return syn.along(x, self.path, self.modes, self.measure)

    def score(self, x):
        """(objective to minimize (N,), shortfall (N,))."""
        a = self.along(x)
        short = a.violation(self.side)
        if self.level is not None:
            short = short + np.maximum(0.0, self.level - a.quality).sum(axis=(1, 2))
        if self.sigma is None:
            return -a.worst(), short
        s = syn.first_order_sigma(a.pose, *self.sigma) / self.sigma_ref
        return np.where(np.isfinite(s), s, 1e6).max(axis=1), short

    def constraints(self, x, t):
        """(N, m) the epigraph's constraints (>= 0) at designs x and level t (N,)."""
        a = self.along(x)
        side = np.sign(a.side[:, :1]) if self.side is None else self.side
        n = len(x)
        if self.sigma is None:
            top = (a.quality - t[:, None, None]).reshape(n, -1)
        else:
            s = syn.first_order_sigma(a.pose, *self.sigma) / self.sigma_ref
            top = np.concatenate([(t[:, None] - s), (a.quality - self.level).reshape(n, -1)], axis=1)
        return np.concatenate([top, a.reach.reshape(n, -1), a.dips.reshape(n, -1), side * a.side], axis=1)


def solve(problem) -> Solution:
    opts = problem.meta.solver
    budget = Budget(opts.budget or DEFAULT_BUDGET)
    path = np.asarray(problem.points, dtype=float)
    space = Space(problem.bounds)
    side = {"left": 1.0, "right": -1.0}.get(problem.branch)
    tried, converged = [], True
    try:
        for i, modes in enumerate(problem.modes):
            signs = tuple(1.0 if m == "+" else -1.0 for m in modes)
            goal = Goal(problem, path, signs, problem.maximize, side=side, level=problem.floor)
            found = search(goal, space, budget, [opts.seed, i])
            tried.append((modes, found))
    except BudgetSpent:
        converged = False
    record = SolverRecord("differential-evolution+kkt", opts.seed, budget.used, converged)
    usable = [(m, f) for m, f in tried if f is not None and f[2] <= FEASIBLE]
    if not usable:
        why = ("the budget ran out before a design was found" if not tried else
               "no design within the bounds keeps the whole path inside the workspace of modes "
               + ", ".join(m[0] + m[1] for m, _ in tried) + " without crossing a singularity"
               + ("" if problem.floor is None else " at the quality floor"))
        return Solution(status=Status.INFEASIBLE, message=why, solver=record)
    worst = np.array([f[1] for _, f in usable])
    pick = int(first_max(worst))
    modes, (x, quality, _, settled) = usable[pick]
    converged = converged and settled
    linkage = _linkage(problem, x, modes)
    sections = {"design": _design_section(problem, linkage, usable, pick)}
    if problem.minimize is not None:
        try:
            table, best, settled = tradeoff(problem, space, budget, path, modes, x, quality, linkage)
            converged = converged and settled
        except BudgetSpent:
            table, best = None, None
            converged = False
        if table is not None:
            sections["tradeoff"] = table
            if best is not None:
                linkage = best
                sections["design"] = _design_section(problem, linkage, usable, pick, chosen="failure-probability")
    record = SolverRecord("differential-evolution+kkt", opts.seed, budget.used, converged)
    return _solution(problem, linkage, sections, record)


def search(goal: Goal, space: Space, budget: Budget, seed, start=None, generations: int = GENERATIONS):
    """(x, worst quality, shortfall, settled) of the best design for `goal`: differential
    evolution, then the polish; when the polish does not settle (the search stopped too far
    from the optimum's binding set), the evolution goes on from its best for RETRY_GENERATIONS
    more at a tighter tolerance and the polish starts again from there."""
    k = space.size
    rng = np.random.default_rng(seed)

    def cost(u):
        budget.spend(len(u))
        f, short = goal.score(space.x(u))
        return f + PENALTY * short

    if k == 0:
        x = space.x(np.zeros((1, 0)))
        f, short = goal.score(x)
        return x[0], _quality(goal, x[0]), float(short[0]), True
    for rounds, tol in ((generations, DE_TOL), (RETRY_GENERATIONS, RETRY_TOL)):
        init = latin_hypercube(rng, POPSIZE * k, k)
        if start is not None:
            init[0] = np.clip(space.u(start), 0.0, 1.0)
        found = evolve(cost, [(0.0, 1.0)] * k, rounds, init=init, rng=rng, tol=tol)
        if found is None:
            raise BudgetSpent
        x = space.x(found.x)[0]
        kept = goal
        if goal.side is None:  # the assembly mode the search found, kept from here on
            kept = Goal(goal.problem, goal.path, goal.modes, goal.measure,
                        side=float(np.sign(goal.along(x[None]).side[0, 0]) or 1.0), level=goal.level,
                        sigma=goal.sigma, sigma_ref=goal.sigma_ref)
        x, settled = _settle(kept, space, budget, x)
        if settled:
            break
        start = x
    _, short = kept.score(x[None])
    return x, _quality(kept, x), float(short[0]), settled


def _quality(goal: Goal, x) -> float:
    """The worst quality (or, for a sigma goal, minus the largest sigma) of one design."""
    return float(goal.along(x[None]).worst()[0])


def _settle(goal: Goal, space: Space, budget: Budget, x0):
    """The epigraph polish (module docstring) from x0: (x, converged); x0 back when the
    polish fails or ends worse. The variables the search left within AT_BOUND of a bound
    start on it; when the polish does not settle (a degenerate set of binding constraints,
    as the mirror rows of a symmetric path give, makes the multiplier of such a bound come
    out of the wrong sign and releases it), it runs again with them held there."""
    u = space.u(x0)
    u = np.where(u < AT_BOUND, 0.0, np.where(u > 1.0 - AT_BOUND, 1.0, u))  # on the bound it leans on
    x0 = space.x(u)[0]
    f0, short0 = goal.score(x0[None])
    on = (u == 0.0) | (u == 1.0)
    for held in ((), np.flatnonzero(space.free)[on]) if on.any() else ((),):
        part = space.holding(x0, held)
        x, ok = _polish(goal, part, budget, x0)
        if ok:
            f1, short1 = goal.score(x[None])
            if (float(short1[0]) <= max(FEASIBLE, float(short0[0]))
                    and float(f1[0]) <= float(f0[0]) + TIE * abs(float(f0[0]))):
                return x, True
    return x0, False


def _polish(goal: Goal, space: Space, budget: Budget, x0):
    """kkt.settle of the epigraph over `space` from x0 (on its bounds): (x, converged)."""
    k = space.size
    f0, _ = goal.score(x0[None])
    t0 = float(-f0[0]) if goal.sigma is None else float(f0[0])  # maximize t, or minimize s

    def values(w):
        budget.spend(len(w))
        x = space.x(w[:, :k])
        t = w[:, k]
        c = goal.constraints(x, t)
        return np.concatenate([c, (-t if goal.sigma is None else t)[:, None]], axis=1)

    def evaluate(w):
        v, jac = kkt.slopes(values, w, SETTLE_STEP)
        return kkt.Point(float(v[-1]), jac[-1], v[:-1], jac[:-1])

    u0 = np.append(space.u(x0), np.clip(t0, 0.0, 1.0))
    out = kkt.settle(evaluate, u0, active_tol=ACTIVE, multipliers=True, step_tol=STEP_TOL)
    if not out.converged or out.worst > FEASIBLE:
        return x0, False
    return space.x(out.u[:k])[0], True


def _linkage(problem, x, modes, side=None) -> FiveBar:
    """The FiveBar of a design (the path and modes as its motion), its branch the side of
    A -> B that P takes at the first row."""
    path = tuple(problem.points)
    lengths = [float(v) for v in x[:5]]
    probe = FiveBar(*lengths, branch=None, ground_pivot=(float(x[5]), float(x[6])), ground_angle=float(x[7]),
                    motion=FiveBarMotion(path=path, modes=modes))
    track = solve_track(probe)
    return FiveBar(*lengths, branch="left" if track.side > 0 else "right", ground_pivot=probe.ground_pivot,
                   ground_angle=probe.ground_angle, motion=probe.motion)


def _design_section(problem, linkage, usable, pick, chosen="quality") -> dict:
    """measure, modes, the worst condition number and transmission along the path, each mode
    pair's best worst quality when several were tried, and what chose the design."""
    track = solve_track(linkage)
    p = track.pose
    kappa = kin.condition(p)
    margin = np.min(np.stack([np.minimum(m, np.pi - m) for m in p.transmissions()]), axis=0)
    u = problem.meta.units
    k, j = int(first_max(kappa)), int(first_min(margin))
    out = {"maximize": problem.maximize, "chosen_by": chosen,
           "modes": list(linkage.motion.modes), "worst_condition": float(kappa[k]), "row_at_worst_condition": k,
           "worst_transmission": float(u.from_rad(margin[j])), "row_at_worst_transmission": j}
    if problem.floor is not None and problem.maximize == "conditioning":
        out["max_condition"] = 1.0 / problem.floor
    elif problem.floor is not None:
        out["min_transmission"] = float(u.from_rad(math.asin(min(problem.floor, 1.0))))
    if len(usable) > 1 or len(problem.modes) > 1:
        out["mode_pairs"] = [{"modes": m[0] + m[1], "worst_quality": f[1]} for m, f in usable]
    return out


def _solution(problem, linkage: FiveBar, sections: dict, record: SolverRecord) -> Solution:
    track = solve_track(linkage)
    px, py = track.to_global(track.pose.px, track.pose.py)
    target = np.asarray(problem.points, dtype=float)
    achieved = np.stack([px, py], axis=1)
    error = np.hypot(*(achieved - target).T)
    scale = max(linkage.lengths)
    positions = Positions("point", track.pose.phi1, target, achieved, snap(error, scale))
    objective = float(np.sum(error * error))
    if track.defects:
        return Solution(status=Status.INFEASIBLE, linkage=linkage, message="; ".join(track.defects),
                        positions=positions, objective=objective, solver=record, sections=sections)
    status = Status.OK if record.converged else Status.NOT_CONVERGED
    message = ("the path in the workspace of modes " + "".join(linkage.motion.modes)
               + f", worst condition number {num(sections['design']['worst_condition'])}")
    return Solution(status=status, linkage=linkage, message=message, positions=positions, objective=objective,
                    solver=record, sections=sections)


# ---------------------------------------------------------------- the trade-off

def tradeoff(problem, space, budget, path, modes, x_best, quality, linkage):
    """(rows, the linkage of the row with the smallest largest failure probability, whether
    every level's polish settled)."""
    from linkcli.analysis.tolerance import monte_carlo_rows, wilson
    from linkcli.mechanisms.five_bar.tolerance import Model
    tol = problem.meta.tolerance
    sigma = syn.variances(tol)
    signs = tuple(1.0 if m == "+" else -1.0 for m in modes)
    side = 1.0 if linkage.branch == "left" else -1.0
    base = Goal(problem, path, signs, problem.maximize, side=side)
    ref = float(np.max(syn.first_order_sigma(base.along(x_best[None]).pose, *sigma)))
    floor = problem.floor if problem.floor is not None else quality / 2.0
    levels = quality - (quality - floor) * np.arange(problem.tradeoff) / (problem.tradeoff - 1)
    rows, designs, start, settled = [], [], x_best, True
    u = problem.meta.units
    for i, level in enumerate(levels):
        if i == 0:
            x = x_best
        else:
            goal = Goal(problem, path, signs, problem.maximize, side=side, level=float(level), sigma=sigma,
                        sigma_ref=ref if ref > 0 else 1.0)
            found = search(goal, space, budget, [problem.meta.solver.seed, 100 + i], start=start,
                           generations=LEVEL_GENERATIONS)
            if found is None or found[2] > FEASIBLE:
                continue
            x, settled = found[0], settled and found[3]
        start = x
        fb = _linkage(problem, x, modes)
        track = solve_track(fb)
        if track.defects:
            continue
        model = Model(track, u)
        scale = model.column_scale(tol.lengths)
        draws = monte_carlo_rows(model, scale, tol.clearance, 0.0, tol.samples, problem.meta.solver.seed,
                                 tol.distribution)
        bad = ~draws.row_ok | (draws.dev > tol.allowed_error)
        fails = bad.sum(axis=0)
        r = int(first_max(fails))
        k = int(fails[r])
        a = base.along(x[None])
        s = syn.first_order_sigma(a.pose, *sigma)[0]
        kappa = kin.condition(a.pose)[0]
        margin = np.min(np.stack([np.minimum(m, np.pi - m) for m in a.pose.transmissions()]), axis=0)[0]
        limit = ({"max_condition": float(1.0 / level)} if problem.maximize == "conditioning" else
                 {"min_transmission": float(u.from_rad(math.asin(min(float(level), 1.0))))})
        rows.append({**limit, "worst_condition": float(np.max(kappa)),
                     "worst_transmission": float(u.from_rad(np.min(margin))),
                     "sigma_max": float(np.max(s)), "largest_failure_probability": k / tol.samples,
                     "largest_failure_probability_ci95": list(wilson(k, tol.samples)), "row": int(model.rows[r]),
                     "ground": fb.ground, "input": fb.input, "input2": fb.input2, "coupler": fb.coupler,
                     "coupler2": fb.coupler2, "ground_pivot": list(fb.ground_pivot),
                     "ground_angle": float(u.from_rad(fb.ground_angle))})
        designs.append(fb)
    if not rows:
        return None, None, settled
    fail = np.array([r["largest_failure_probability"] for r in rows])
    best = int(first_min(fail))
    return rows, designs[best], settled
