"""The search behind flipper-cylinder: designs judged on the sweep, a global stage, local
SLSQP on the epigraph form, and the force/size trade-off (scipy imported lazily).

Design variables: the free coordinates among (A_x, A_y, C_x, C_y), scaled to [0, 1] over
their bounds. Designs are compared by Deb's feasibility rules (Deb 2000: a feasible design
beats an infeasible one; infeasible ones compare by their violation): the cylinder line
through the hinge inside the sweep, the dead length (closed >= stroke + dead_length, i.e.
2 L_closed - L_open >= dead), the force limit, a cap on the closed length.

- `peak` goal: minimize P(x) = max over the sweep of |F(t; x)|. P is the maximum of smooth
  functions; at the optimum it usually balances two angles (a push at one end of the sweep
  against a pull at the other), where it is not differentiable, so a smooth local method on
  P stalls. Local stage: the epigraph form

      minimize z  subject to  z s K(t_k) - W(t_k) L(t_k) >= 0,  z s K(t_k) + W(t_k) L(t_k) >= 0

  at angles t_k (both ends and about every 2 deg), s = sign K held from the start point:
  with F = W L / K these say |F(t_k)| <= z, written without the pole at K = 0. SLSQP (Kraft
  1988) solves it with analytic gradients; an exchange step (semi-infinite programming,
  Hettich & Kortanek 1993) adds the angles of the design's refined maxima and solves again
  until no maximum between the angles exceeds z.
- `length` goal: minimize the closed length min(L(start), L(end)) subject to |F(t)| <=
  max_force. L is monotone over a feasible sweep, so the local stage holds the end at which
  the cylinder is closed (L_closed <= L_open) and its objective is smooth.

Methods: `auto` = a seeded Latin-hypercube sample, differential evolution (Storn & Price
1997; scipy, one vectorized call per generation), then SLSQP from the best design of each
family (the cylinder line on either side of the hinge) and from one design per basin of
the sample (multi-level single linkage), then SLSQP from random perturbations of the best
design (monotonic basin hopping, Leary 2000); `differential-evolution` = the global stage
alone; `slsqp` = the sample, then SLSQP from the same kind of starts. A budget counts
designs evaluated (one per design, whatever the number of angles); a refined peak counts
one. A length goal with no design within its force cap in the global stage first finds the
least peak force: the start of the length search when it is within the cap, otherwise the
answer (infeasible by the least excess). Every goal keeps the pivots apart (closed length
>= MIN_LENGTH times the largest pivot bound): where they meet the force is 0 / 0.

The trade-off table (`pareto`): for closed lengths from that of the least-force design down
to the shortest cylinder within the force limit, the least peak force (the epigraph search
with a cap on the closed length).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.search.budget import Budget, BudgetSpent
from linkcli.search.evolution import evolve
from linkcli.search.sampling import distinct, latin_hypercube
from linkcli.types.flipper_cylinder.statics import Statics

DEFAULT_BUDGET = 4000  # designs evaluated by the optimizing methods
PARETO_BUDGET = 2000  # added to the default budget when the trade-off table is asked for
PARETO_SHARE = 0.4  # share of a given budget that the trade-off table may spend
GLOBAL_SHARE = 0.6  # share of the optimizing budget that the global stage spends
MAX_STARTS = 8  # local searches after the global stage
SEPARATION = 0.25  # distance in the unit box between two starts of local searches
BASIN_RADIUS = 0.3  # unit box: a sample design starts a local search if none better is closer
SAMPLE_MAX = 400  # designs of the Latin-hypercube sample that seeds the local searches
LOCAL_ITERATIONS = 100
LOCAL_MIN_SHARE = 20  # evaluations a local search is given at least (fewer starts otherwise)
LOCAL_STRIDE = 4  # the local search's constraint angles: every 4th angle of the sweep grid
HOPS = 6  # perturbed restarts of the local search from the best design (basin hopping)
HOP_STEPS = (0.05, 0.15, 0.3)  # their step sizes in the unit box, in turn
EXCHANGE_ROUNDS = 20  # an interior peak that moves with the design may need ten or more
EXCHANGE_SPREAD = 0.1  # neighbours of an added maximum, in grid steps
EXCHANGE_GAP = 1e-8  # relative: stop when the refined peak exceeds the peak at the angles by less
FEASIBLE = 1e-9  # relative violation a search still counts as feasible
TOLERANCE = 1e-6  # relative: a reported design meets max_force and dead_length within this
MARGIN = 1e-7  # relative: SLSQP aims this far inside max_force and dead_length
BIG = 1e30  # penalty base: worse than any feasible design
SETTLE_EVALUATIONS = 400  # the final KKT polish's reserve in the budget, at most,
SETTLE_SHARE = 10  # and at most this fraction (1/10) of the optimizing share
MIN_LENGTH = 1e-6  # relative to the largest pivot bound: the shortest cylinder (the pivots never meet)


# ------------------------------------------------------------------ design space
class Space:
    """Free coordinates of (A_x, A_y, C_x, C_y), each scaled to [0, 1] over its bounds."""

    def __init__(self, problem) -> None:
        b = np.array(problem.bounds, dtype=float)
        self.lo, self.hi = b[:, 0], b[:, 1]
        self.free = np.nonzero(self.hi > self.lo)[0]
        self.width = (self.hi - self.lo)[self.free]
        g = problem.center_of_mass
        self.scale = max(float(np.max(np.abs(b))), math.hypot(*g), 1e-300)  # length scale
        self.floor = MIN_LENGTH * max(float(np.max(np.abs(b))), 1e-300)  # shortest cylinder allowed

    @property
    def size(self) -> int:
        return len(self.free)

    def full(self, y) -> np.ndarray:
        """Unit coordinates (S, n_free) -> designs (S, 4)."""
        y = np.atleast_2d(np.asarray(y, dtype=float))
        p = np.tile(self.lo, (len(y), 1))
        p[:, self.free] = self.lo[self.free] + y * self.width
        return p

    def unit(self, p) -> np.ndarray:
        p = np.atleast_2d(np.asarray(p, dtype=float))
        return np.clip((p[:, self.free] - self.lo[self.free]) / self.width, 0.0, 1.0)


@dataclass
class Best:
    """The best design seen, by Deb's rules (lower violation first, then lower objective)."""

    design: np.ndarray | None = None
    objective: float = math.inf
    violation: float = math.inf

    def offer(self, design, objective: float, violation: float) -> None:
        v = 0.0 if violation <= FEASIBLE else violation
        if (v, objective) < (0.0 if self.violation <= FEASIBLE else self.violation, self.objective):
            self.design = np.array(design, dtype=float)
            self.objective = float(objective)
            self.violation = float(violation)


@dataclass
class Goal:
    """What a search minimizes: `peak` (the peak force) or `length` (the closed length,
    with `force_cap` on the peak), optionally with a cap on the closed length."""

    kind: str
    force_cap: float | None = None
    length_cap: float | None = None


@dataclass
class Outcome:
    best: Best
    converged: bool
    archive: Archive | None = None  # every design of the global stage
    completed: bool = False  # a search ran to its own end (not stopped by the budget)


class Archive:
    """Every design a global stage judged, to pick distinct starts for the local searches."""

    def __init__(self) -> None:
        self.parts: list[tuple] = []

    def add(self, p, obj, viol, fam) -> None:
        self.parts.append((np.array(p), np.array(obj), np.array(viol), np.array(fam)))

    def columns(self):
        return tuple(np.concatenate([part[i] for part in self.parts]) for i in range(4))

    def best(self) -> Best:
        out = Best()
        if self.parts:
            p, obj, viol, _ = self.columns()
            i = _order(obj, viol)[0]
            out.offer(p[i], obj[i], viol[i])
        return out

    def leaders(self) -> list[np.ndarray]:
        """The best design of each family (the cylinder line on either side of the hinge;
        for a length goal also either closed end), best family first; feasible ones only,
        unless none is."""
        if not self.parts:
            return []
        p, obj, viol, fam = self.columns()
        order = _order(obj, viol)
        if viol[order[0]] > FEASIBLE:
            return [p[order[0]]]
        order = order[viol[order] <= FEASIBLE]
        firsts = dict.fromkeys(fam[order].tolist())
        return [p[order[np.argmax(fam[order] == f)]] for f in firsts]

    def basins(self, space: Space, radius: float) -> list[np.ndarray]:
        """Designs with no better design (Deb's rules) within `radius` in the unit box: one
        per basin of the sample, best first (the start rule of multi-level single linkage,
        Rinnooy Kan & Timmer 1987; an infeasible basin leads SLSQP towards feasibility).
        Vectorized over the pairs of a sample of at most a few hundred."""
        if not self.parts:
            return []
        p, obj, viol, _ = self.columns()
        order = _order(obj, viol)
        y = space.unit(p[order])
        near = np.linalg.norm(y[:, None, :] - y[None, :, :], axis=2) <= radius
        better_near = np.tril(near, -1).any(axis=1)  # a better design (earlier in order) close by
        return [p[i] for i in order[~better_near]]


def pick_starts(space: Space, candidates: list[np.ndarray]) -> list[np.ndarray]:
    """The candidates in order, skipping any within SEPARATION of one taken; at most
    MAX_STARTS."""
    if not candidates:
        return []
    rows = space.unit(np.vstack(candidates))
    return [candidates[i] for i in distinct(rows, range(len(candidates)), SEPARATION, MAX_STARTS, norm=2)]


def _order(obj, viol) -> np.ndarray:
    """Indices best first by Deb's rules: feasible by objective, then by violation."""
    return np.lexsort((obj, np.where(viol > FEASIBLE, viol, 0.0)))


# ---------------------------------------------------------------------- judging designs
class Judge:
    """Objective and violation of designs on the sweep grid (vectorized over designs)."""

    def __init__(self, problem, statics: Statics, space: Space, budget: Budget) -> None:
        self.problem = problem
        self.statics = statics
        self.space = space
        self.budget = budget
        self.dead = problem.dead_length

    def assess(self, p, goal: Goal):
        """(objective, violation, family) for designs p (S, 4) on the grid; spends S."""
        self.budget.spend(len(p))
        statics = self.statics
        sing = statics.singular(p)  # where the cylinder line meets the hinge: shared by the three
        force = statics.forces(p, sing=sing)[0]
        crosses, tau0 = sing["blocked"], sing["tau0"]
        peak = _grid_peak(force)
        crosses = crosses | ~np.isfinite(peak)  # no finite force somewhere: as bad as a crossing
        ls, le = statics.end_lengths(p)
        closed, opened, _ = statics.lengths(p, sing=sing)
        # a crossing nearer the middle of the sweep violates more: the search moves it out
        weight = 1.0 + np.minimum(tau0, statics.sweep - tau0).clip(0) / statics.sweep
        obj, viol = self.score(goal, crosses, peak, closed, opened, cross_weight=weight)
        k0 = statics.terms(p, np.array([0.0]))[0][:, 0]
        by_end = goal.kind == "length" or goal.length_cap is not None  # closed at start or at end
        family = (k0 > 0).astype(int) + (2 * (ls > le) if by_end else 0)
        return obj, viol, family

    def score(self, goal: Goal, crosses, peak, closed, opened, cross_weight=1.0, shortest=None):
        """(objective, violation) of designs from their facts, scalars or arrays (S,): a
        crossing (no finite force somewhere) costs `cross_weight`; the pivots kept apart
        (`shortest`, default the closed length, against the floor), the dead length, the
        force and length caps add their relative excess."""
        scale = self.space.scale
        viol = np.where(crosses, cross_weight, 0.0)
        viol = viol + np.maximum(0.0, self.space.floor - (closed if shortest is None else shortest)) / scale
        if self.dead is not None:
            viol = viol + np.maximum(0.0, opened - closed + self.dead - closed) / scale
        if goal.force_cap is not None:
            viol = viol + np.where(crosses, 0.0, _excess(peak, goal.force_cap))
        if goal.length_cap is not None:
            viol = viol + np.maximum(0.0, closed - goal.length_cap) / scale
        obj = np.where(crosses, math.inf, peak) if goal.kind == "peak" else closed
        return obj, viol

    @staticmethod
    def penalized(obj, viol):
        return np.where(viol > FEASIBLE, BIG * (1.0 + viol), np.minimum(obj, BIG))


def _grid_peak(force) -> np.ndarray:
    """Largest |F| of each row (S, N); a row holding nan (no finite force at some angle)
    gets inf, the worst value (np.max, not np.nanmax: no warning, and nan never hides)."""
    a = np.abs(np.asarray(force, dtype=float))
    return np.max(np.where(np.isnan(a), np.inf, a), axis=-1)


def _excess(peak, cap: float):
    """Relative excess of the peak over the force cap, >= 0; a peak that is not finite
    (nan included) gives BIG (Python's max(0, nan) would give 0 and look feasible)."""
    peak = np.asarray(peak, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.where(np.isfinite(peak), np.maximum(0.0, peak - cap) / cap, BIG)


# ---------------------------------------------------------------------------- global stage
def _evolve(judge: Judge, goal: Goal, share: int, rng) -> Outcome:
    """Differential evolution on the penalized grid objective (seeded, Latin-hypercube
    start), one vectorized call per generation; every design it judges joins the archive."""
    space = judge.space
    dim = space.size
    pop = int(max(5, min(10 * dim, share // 6)))
    generations = max(0, share // pop - 1)
    archive = Archive()

    def energy(rows):  # rows (S, dim) of the unit box
        p = space.full(rows)
        obj, viol, fam = judge.assess(p, goal)
        archive.add(p, obj, viol, fam)
        return judge.penalized(obj, viol)

    if share < pop:
        return _sample(judge, goal, share, rng)
    init = latin_hypercube(rng, pop, dim)
    converged = False
    if generations == 0:
        try:
            energy(init)
        except BudgetSpent:
            pass
    else:
        out = evolve(energy, [(0.0, 1.0)] * dim, generations, init=init, rng=rng, tol=1e-6,
                     mutation=(0.5, 1.0), recombination=0.9)
        converged = out is not None and out.converged
    return Outcome(archive.best(), converged, archive)


def _sample(judge: Judge, goal: Goal, n: int, rng) -> Outcome:
    """A seeded Latin-hypercube sample, judged in one vectorized call."""
    archive = Archive()
    n = min(n, judge.budget.left)
    if n > 0:
        p = judge.space.full(latin_hypercube(rng, n, judge.space.size))
        archive.add(p, *judge.assess(p, goal))
    return Outcome(archive.best(), False, archive)


# ----------------------------------------------------------------------------- local stage
class Epigraph:
    """The smooth local problem at a fixed set of angles, for SLSQP (see the module doc).

    Variables v: the free unit coordinates, then (goal `peak`) z / F_s. Constraints >= 0:
    the force pairs z s K -/+ W L at every angle, the dead length, the length cap; each
    scaled to order one. Every new v evaluates one design (spends one).
    """

    def __init__(self, judge: Judge, goal: Goal, tau: np.ndarray, start, margin: float = MARGIN) -> None:
        self.judge, self.goal, self.tau = judge, goal, tau
        self.margin = margin  # relative: how far inside max_force and dead_length to aim
        statics, space = judge.statics, judge.space
        self.w = statics.moment(tau)
        self.end_index = 1  # tau[0] = 0 and tau[1] = sweep: local_angles puts the ends first
        p0 = np.asarray(start, dtype=float)
        k0, _, l0, _ = statics.gradients(p0, tau)
        kref = k0[0] if abs(k0[0]) >= abs(k0[self.end_index]) else k0[self.end_index]  # K(0) may be 0
        self.sign = 1.0 if kref >= 0 else -1.0
        self.closed_at_end = bool(l0[self.end_index] < l0[0])
        self.uses_length = goal.kind == "length" or goal.length_cap is not None
        with np.errstate(divide="ignore", invalid="ignore"):
            peak0 = float(_grid_peak(self.w * l0 / k0))
        if goal.kind == "peak":
            self.fs = peak0 if math.isfinite(peak0) and peak0 > 0 else max(statics.weight * space.scale, 1e-300)
        else:
            self.fs = goal.force_cap * (1.0 - margin) if goal.force_cap else None
        self.ns = (self.fs or 1.0) * space.scale ** 2
        self.best = Best()
        self._cache: tuple[bytes, tuple] | None = None
        self.z0 = (peak0 / self.fs) * (1.0 + 1e-9) if goal.kind == "peak" and math.isfinite(peak0) else 1.0

    def x0(self, start) -> np.ndarray:
        y = self.judge.space.unit(start)[0]
        return np.append(y, self.z0) if self.goal.kind == "peak" else y

    def bounds(self):
        b = [(0.0, 1.0)] * self.judge.space.size
        return b + [(0.0, None)] if self.goal.kind == "peak" else b

    def _compute(self, v):
        key = np.asarray(v, dtype=float).tobytes()
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1]
        judge, goal, space = self.judge, self.goal, self.judge.space
        judge.budget.spend(1)
        n = space.size
        p = space.full(v[:n])[0]
        k, dk, length, dl = judge.statics.gradients(p, self.tau)
        dk = dk[:, space.free] * space.width
        dl = dl[:, space.free] * space.width
        peak_kind = goal.kind == "peak"
        z = v[n] * self.fs if peak_kind else self.fs
        cons, jac = [], []
        if z is not None:
            sk, sdk = self.sign * k, self.sign * dk
            for s in (-1.0, 1.0):  # z s K - W L >= 0 and z s K + W L >= 0
                cons.append((z * sk + s * self.w * length) / self.ns)
                g = (z * sdk + s * self.w[:, None] * dl) / self.ns
                if peak_kind:
                    g = np.column_stack([g, self.fs * sk / self.ns])
                jac.append(g)
        i_s, i_e = 0, self.end_index
        ls, le, dls, dle = length[i_s], length[i_e], dl[i_s], dl[i_e]
        lc, lo_, dlc, dlo = (le, ls, dle, dls) if self.closed_at_end else (ls, le, dls, dle)
        rows = []  # (value, gradient over the free coordinates), lengths / scale
        dead = None if judge.dead is None else judge.dead + self.margin * space.scale
        floor = space.floor * (1.0 + MARGIN / MIN_LENGTH)  # the pivots stay apart, 10 % inside
        if self.uses_length:
            rows.append((lo_ - lc, dlo - dlc))  # this end stays the closed one
            rows.append((lc - floor, dlc))
            if dead is not None:
                rows.append((2 * lc - lo_ - dead, 2 * dlc - dlo))
            if goal.length_cap is not None:
                rows.append((goal.length_cap - lc, -dlc))
        else:
            rows.append((ls - floor, dls))
            rows.append((le - floor, dle))
            if dead is not None:
                rows.append((2 * ls - le - dead, 2 * dls - dle))
                rows.append((2 * le - ls - dead, 2 * dle - dls))
        for val, g in rows:
            cons.append(np.array([val / space.scale]))
            g = (g / space.scale)[None, :]
            jac.append(np.column_stack([g, [[0.0]]]) if peak_kind else g)
        if peak_kind:
            f, df = v[n], np.append(np.zeros(n), 1.0)
        else:
            f, df = lc / space.scale, np.append(dlc / space.scale, [])
        out = (float(f), df, np.concatenate(cons), np.vstack(jac))
        self._offer(p, k, length, lc, lo_)
        self._cache = (key, out)
        return out

    def _offer(self, p, k, length, lc, lo_) -> None:
        """Record the design by its true objective and violation at these angles (lc is the
        end the model keeps closed, lo_ the other: the floor holds for the shorter)."""
        crosses = not (np.sign(k[0]) * np.sign(k[self.end_index]) > 0)
        if crosses:  # unless the load has no moment where the line crosses the hinge
            crosses = bool(self.judge.statics.crossing(p[None, :])[0][0])
        with np.errstate(divide="ignore", invalid="ignore"):
            peak = float(_grid_peak(self.w * length / k))
        crosses = crosses or not math.isfinite(peak)
        obj, viol = self.judge.score(self.goal, crosses, peak, lc, lo_, shortest=min(lc, lo_))
        self.best.offer(p, float(obj), float(viol))

    def fun(self, v):
        return self._compute(v)[0]

    def grad(self, v):
        return self._compute(v)[1]

    def cons(self, v):
        return self._compute(v)[2]

    def cons_jac(self, v):
        return self._compute(v)[3]


def local_angles(statics: Statics) -> np.ndarray:
    """The angles a local search starts with: both ends first, then every LOCAL_STRIDE-th
    grid angle (about 2 deg); the exchange rounds add the true maxima between them."""
    inner = statics.grid[LOCAL_STRIDE:-1:LOCAL_STRIDE]
    return np.concatenate([[0.0, statics.sweep], inner[inner < statics.sweep]])


def _local(judge: Judge, goal: Goal, start, share: int) -> Outcome:
    """SLSQP on the epigraph form from `start`, with exchange rounds: the refined maxima of
    the design found join the angles until none exceeds the value reached on them. SLSQP's
    "positive directional derivative for linesearch" (mode 8: rounding noise at a tight
    optimum) is retried once from the design reached; the same objective again (within
    1e-8) counts as converged."""
    from scipy.optimize import minimize
    statics = judge.statics
    budget = judge.budget
    outer_cap = budget.cap
    budget.cap = min(outer_cap, budget.used + share)
    tau = local_angles(statics)
    design = np.asarray(start, dtype=float)
    best = Best()
    converged, completed = False, False
    rounds, retries, stalled_at = 0, 1, math.inf
    try:
        while rounds < EXCHANGE_ROUNDS:
            ep = Epigraph(judge, goal, tau, design)
            try:
                res = minimize(ep.fun, ep.x0(design), jac=ep.grad, method="SLSQP", bounds=ep.bounds(),
                               constraints=[{"type": "ineq", "fun": ep.cons, "jac": ep.cons_jac}],
                               options={"maxiter": min(LOCAL_ITERATIONS, max(1, budget.left)),
                                        "ftol": 1e-12})
                mode = int(res.status)
            except BudgetSpent:
                mode = -1
            if ep.best.design is None:
                completed = mode != -1
                break
            design = ep.best.design
            budget.spend(1)
            pk = statics.peaks(design[None, :])
            refined = float(pk["peak"][0])
            obj, viol = _refined_score(judge, goal, design, refined)
            best.offer(design, obj, viol)
            if mode == 8:  # line search found no descent: retry once; the same value twice is an optimum
                if retries > 0:
                    retries, stalled_at = retries - 1, obj
                    continue
                if abs(obj - stalled_at) <= 1e-8 * max(abs(obj), 1e-300):
                    mode = 0
            if mode != 0:
                completed = mode != -1
                break
            limit = ep.best.objective if goal.kind == "peak" else goal.force_cap
            if limit is None or refined <= limit * (1.0 + EXCHANGE_GAP):
                converged, completed = viol <= FEASIBLE, True
                break
            extra = np.array([pk[k + "_at"][0] for k in ("push", "pull") if pk[k][0] > 0])
            if len(extra):  # each maximum with two close neighbours: it may move a little
                h = EXCHANGE_SPREAD * (statics.grid[1] - statics.grid[0])
                extra = np.clip(np.concatenate([extra, extra - h, extra + h]), 0.0, statics.sweep)
            tau = np.concatenate([tau, extra])
            rounds += 1
    except BudgetSpent:
        pass
    finally:
        budget.cap = outer_cap
    return Outcome(best, converged, completed=completed)


def _refined_score(judge: Judge, goal: Goal, design, peak: float) -> tuple[float, float]:
    """(objective, violation) of one design with its refined peak (no budget spent)."""
    p = design[None, :]
    statics = judge.statics
    sing = statics.singular(p)
    crosses = bool(sing["blocked"][0]) or not math.isfinite(peak)  # nan: no finite force, the worst
    closed, opened = (float(x[0]) for x in statics.lengths(p, sing=sing)[:2])
    obj, viol = judge.score(goal, crosses, peak, closed, opened)
    return float(obj), float(viol)


# --------------------------------------------------------------------------- final polish
def settle(judge: Judge, goal: Goal, outcome: Outcome) -> Outcome:
    """The final polish (linkcli.search.kkt) of the best design: Newton on the KKT system
    of the epigraph form (`Epigraph`, at the local search's angles and the design's own
    peak angles) with the constraints that bind held as equalities, to machine precision:
    forces that balance at the optimum (a push at one end against a pull at the other)
    come out equal to round-off, so that the tie rule, not the path, names the peak. The
    polished design replaces the found one when it meets every limit and is as good within a relative
    1e-9 (its refined score). It spends within the budget's current cap (`_search` keeps a
    reserve for it, SETTLE_EVALUATIONS at most)."""
    best = outcome.best
    if best.design is None or best.violation > FEASIBLE or judge.space.size == 0:
        return outcome
    from linkcli.search import kkt
    statics = judge.statics
    pk = statics.peaks(best.design[None, :])
    tau = np.concatenate([local_angles(statics), [float(pk["push_at"][0]), float(pk["pull_at"][0])]])
    tau = np.unique(np.clip(tau, 0.0, statics.sweep))
    tau = np.concatenate([[0.0, statics.sweep], tau[(tau > 0.0) & (tau < statics.sweep)]])  # the ends first
    ep = Epigraph(judge, goal, tau, best.design, margin=0.0)  # on the limits themselves
    n = judge.space.size
    # the unit box of the polish: the free coordinates, and (peak goal) z / (2 F_s)
    half = 0.5 if goal.kind == "peak" else 1.0

    def values(w):
        v = np.append(w[:n], w[n:] / half)
        f, df, c, a = ep._compute(v)
        a = a.copy()
        df = np.array(df, dtype=float)
        if goal.kind == "peak":
            df[n:] /= half
            a[:, n:] /= half
        return kkt.Point(f, df, c, a)

    try:
        out = kkt.settle(values, np.append(ep.x0(best.design)[:n], ep.x0(best.design)[n:] * half),
                         active_tol=100.0 * MARGIN)  # the local search aims MARGIN inside
    except BudgetSpent:
        return outcome
    if not out.converged:
        return outcome
    design = judge.space.full(np.clip(out.u[:n], 0.0, 1.0))[0]
    try:
        polished = _rescore(judge, goal, design)
    except BudgetSpent:
        return outcome
    (v0, f0), (v1, f1) = _key(best), _key(polished)
    if v1 <= v0 and f1 <= f0 + 1e-9 * abs(f0):
        return Outcome(polished, True, outcome.archive, outcome.completed)
    return outcome


# ------------------------------------------------------------------------------ strategy
def _key(best: Best) -> tuple[float, float]:
    return (best.violation if best.violation > FEASIBLE else 0.0, best.objective)


def _rescore(judge: Judge, goal: Goal, design) -> Best:
    """A design with its refined peak (one evaluation)."""
    judge.budget.spend(1)
    best = Best()
    peak = float(judge.statics.peaks(design[None, :])["peak"][0])
    best.offer(design, *_refined_score(judge, goal, design, peak))
    return best


def optimize(judge: Judge, goal: Goal, method: str, share: int, rng) -> Outcome:
    """One search for `goal` within `share` evaluations (global stage, then local searches
    unless the method is differential evolution alone); the best design has its refined
    objective. Outcome.best.design is None only when the share is too small to evaluate.

    A length goal whose global stage finds no design within its force cap first looks for
    the least peak force (the same limits otherwise): when that stays within the cap, the
    length searches start from it; when it does not, it is the answer, infeasible by the
    least possible excess over max_force."""
    budget = judge.budget
    outer = budget.cap
    base = budget.used
    stop = min(outer, base + share)
    found: list[Outcome] = []
    if stop - base < 2:  # no room for a search: the centre of the bounds, judged once
        result = Outcome(Best(), False)
        if stop > base:
            budget.spend(1)
            centre = judge.space.full(np.full(judge.space.size, 0.5))[0]
            peak = float(judge.statics.peaks(centre[None, :])["peak"][0])
            result.best.offer(centre, *_refined_score(judge, goal, centre, peak))
        budget.cap = outer
        return result
    budget.cap = stop - 1  # one evaluation kept for the final refined score
    try:
        sample = None
        if method == "differential-evolution":
            glob = _evolve(judge, goal, budget.left, rng)
        else:
            size = share // (5 if method == "slsqp" else 10)  # a fifth, a tenth of the share
            sample = _sample(judge, goal, int(min(max(size, min(20, share // 4), 5), SAMPLE_MAX)), rng)
            glob = sample if method == "slsqp" else _evolve(
                judge, goal, min(int(GLOBAL_SHARE * share) - (budget.used - base), budget.left), rng)
        if method != "differential-evolution":
            candidates = glob.archive.leaders() + (sample.archive.basins(judge.space, BASIN_RADIUS)
                                                   if sample.archive else [])
            starts = pick_starts(judge.space, candidates)[:max(1, budget.left // LOCAL_MIN_SHARE)]
            least = None
            if goal.kind == "length" and goal.force_cap is not None and not _any_feasible(glob, sample):
                least = _least_force(judge, goal, starts)
                if least is not None and least.best.violation <= FEASIBLE:
                    starts = [least.best.design] + starts[:1]  # within the cap: shorten from here
                elif least is not None:
                    found.append(least)
                    starts = []
            for i, start in enumerate(starts):
                local = _local(judge, goal, start, budget.left // (len(starts) - i))
                if local.best.design is not None:
                    found.append(local)
            if found and least is None:
                found += _hop(judge, goal, min(found, key=lambda o: _key(o.best)), rng)
            if found and budget.left >= LOCAL_MIN_SHARE:
                found = _confirm(judge, goal, found)
        budget.cap = stop
        if found:
            result = min(found, key=lambda o: _key(o.best))
            result.completed = any(o.completed for o in found)
            return result
        alone = method == "differential-evolution"
        result = Outcome(Best(), glob.converged, completed=alone and glob.converged)
        best = glob.best if glob.best.design is not None else (sample.best if sample else Best())
        if best.design is not None and budget.left > 0:
            result.best = _rescore(judge, goal, best.design)
        return result
    finally:
        budget.cap = outer


def _hop(judge: Judge, goal: Goal, best: Outcome, rng) -> list[Outcome]:
    """Monotonic basin hopping (Leary 2000): local searches from random perturbations of
    the best feasible design, steps of HOP_STEPS in the unit box in turn, the best design
    moving on whenever a search improves on it. Two local minima a few per cent of the
    bounds apart, which the global stage and the spread-out starts can take for one, are
    told apart this way."""
    budget, space = judge.budget, judge.space
    out: list[Outcome] = []
    for i in range(HOPS):
        if best.best.violation > FEASIBLE or budget.left < 2 * LOCAL_MIN_SHARE:
            break
        y = space.unit(best.best.design)[0]
        y = np.clip(y + HOP_STEPS[i % len(HOP_STEPS)] * rng.standard_normal(len(y)), 0.0, 1.0)
        local = _local(judge, goal, space.full(y)[0], budget.left // (HOPS - i))
        if local.best.design is not None:
            out.append(local)
            if _key(local.best) < _key(best.best):
                best = local
    return out


def _confirm(judge: Judge, goal: Goal, found: list[Outcome]) -> list[Outcome]:
    """When the best design comes from a local search that ended without converging (SLSQP
    can pass the best point on its way to a failed line search), one more local search
    from it; a converged result as good within 1e-9 relative takes its place."""
    best = min(found, key=lambda o: _key(o.best))
    if best.converged:
        return found
    again = _local(judge, goal, best.best.design, judge.budget.left)
    if again.converged and again.best.design is not None:
        (v0, f0), (v1, f1) = _key(best.best), _key(again.best)
        if v1 <= v0 and f1 <= f0 + 1e-9 * abs(f0):
            return [o for o in found if o is not best] + [again]
    return found + [again]


def _any_feasible(*outcomes) -> bool:
    """Whether a global stage judged any design that meets every limit."""
    for out in outcomes:
        if out is not None and out.archive is not None and out.archive.parts:
            if np.any(out.archive.columns()[2] <= FEASIBLE):
                return True
    return False


def _least_force(judge: Judge, goal: Goal, starts) -> Outcome | None:
    """The least peak force within the limits of `goal` other than its force cap (SLSQP
    epigraph searches from `starts`, within half of the budget left), scored for `goal`:
    feasible exactly when that force stays within the cap."""
    budget = judge.budget
    sub = Goal("peak", length_cap=goal.length_cap)
    stop = budget.used + budget.left // 2
    runs = []
    for i, start in enumerate(starts):
        local = _local(judge, sub, start, max(0, stop - budget.used) // (len(starts) - i))
        if local.best.design is not None:
            runs.append(local)
    if not runs:
        return None
    best = min(runs, key=lambda o: _key(o.best)).best
    out = Outcome(Best(), False, completed=any(o.completed for o in runs))
    out.best.offer(best.design, *_refined_score(judge, goal, best.design, best.objective))
    return out


# --------------------------------------------------------------------------- trade-off table
def pareto(problem, judge: Judge, main: Outcome, goal: Goal, method: str, share: int, rng):
    """Rows (least peak force first) of the best peak force for closed lengths from that of
    the least-force design down to the shortest cylinder whose peak stays within
    max_force (or within twice the least peak force without max_force): each row an SLSQP
    epigraph search with a cap on the closed length, warm-started from the next shorter
    row and from the least-force design. Returns (designs, complete)."""
    budget = judge.budget
    outer = budget.cap
    budget.cap = min(outer, budget.used + share)
    n = problem.pareto
    designs: list[np.ndarray] = []
    try:
        hi = main.best if goal.kind == "peak" else optimize(judge, Goal("peak"), method, share // 4, rng).best
        if hi.design is None or hi.violation > FEASIBLE:
            return [], False
        cap_f = problem.max_force
        if cap_f is None or cap_f <= hi.objective * (1.0 + 1e-6):
            cap_f = 2.0 * hi.objective
        if goal.kind == "length" and cap_f == problem.max_force and main.best.violation <= FEASIBLE:
            lo = main.best
        else:
            lo = optimize(judge, Goal("length", force_cap=cap_f), method, share // 4, rng).best
        l_hi = closed_length(judge, hi.design)
        if lo.design is None or lo.violation > FEASIBLE or closed_length(judge, lo.design) >= l_hi:
            return [hi.design], False
        l_lo = closed_length(judge, lo.design)
        caps = np.linspace(l_lo, l_hi, n)
        designs = [lo.design]
        for i, cap in enumerate(caps[1:-1]):
            row_goal = Goal("peak", length_cap=float(cap))
            runs = 2 * (n - 2 - i)
            best = None
            for start in (designs[-1], hi.design):
                local = _local(judge, row_goal, start, budget.left // runs)
                runs -= 1
                if local.best.design is not None and (best is None or _key(local.best) < _key(best)):
                    best = local.best
            if best is not None and best.violation <= FEASIBLE:
                designs.append(best.design)
        designs.append(hi.design)
        return designs[::-1], len(designs) == n
    except BudgetSpent:
        return designs[::-1], False
    finally:
        budget.cap = outer


def closed_length(judge: Judge, design) -> float:
    return float(judge.statics.lengths(np.asarray(design, dtype=float)[None, :])[0][0])
