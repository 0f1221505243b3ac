"""The shared search over a home's population (linkcli.synthesis.model.Model), numpy only.

Rounds, each from its own seeded draws (starts.py): the draws completed by their timing are
ranked by their penalized cost and the LM_FIELD best distinct ones enter batched
Levenberg-Marquardt (linkcli.search.levenberg_marquardt, all rows at once, penalty weight
LM_WEIGHT, FIELD_ITERATIONS steps); the POLISHED best distinct rows are polished (POLISH_ITERATIONS
more steps at each of POLISH_WEIGHTS while a constraint is broken), and the round's best is
settled by Newton on the KKT system of the constraints that bind (linkcli.search.kkt), to
round-off. Free timing's sweep, sum(delta) <= 2 pi, is the linear constraint the
Levenberg-Marquardt holds on its plane (as path generation's). Jacobians by forward
differences, the target residuals at the targets and each broken constraint at the drive
value of its worst (the envelope theorem: model.py), so that a Jacobian costs k + 1
evaluations of n + (broken constraints) drive values, not of the whole travel.

Found twice: the search claims its best (status ok) only when a later round's best lands
within CONFIRM of it (another set of draws reaching the same optimum) or it is an exact fit;
it stops at the first confirmation after MIN_ROUNDS rounds, after MAX_STALE rounds that do
not improve the best, or at the budget's end (then not-converged unless confirmed).
Candidates rank by (infeasible, total violation, objective); feasible objectives within TIE
of the best are one optimum, the first found ranked first.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.search import levenberg_marquardt, sampling
from linkcli.search.budget import Budget, BudgetSpent
from linkcli.synthesis import starts
from linkcli.synthesis.model import HUGE, TWO_PI, Model

DEFAULT_BUDGET = 1_000_000  # design evaluations (each at every drive value it needs)
FREE_TARGETS = 20  # free timing beyond this many targets: the default budget shrinks in proportion
ROUND_DRAWS = {"prescribed": 800, "free": 160, "function": 800}  # draws of a round (free timing:
# each with its 288 timing hypotheses)
LM_FIELD = 96  # rows entering the batched Levenberg-Marquardt
FIELD_ROUNDS = 3  # of FIELD_ITERATIONS steps each, the field halving after each
FIELD_ITERATIONS = 20
POLISHED = 2  # distinct rows polished further
POLISH_ITERATIONS = 60
REFINE_MORE = 100  # more polish of a round's unconverged pick near the best
SETTLE_NEAR = 0.5  # relative: a round's best this close to the best so far is settled (a pick the penalized
# polish left short of a binding constraint may be the best's basin)
LM_WEIGHT = 1e2
POLISH_WEIGHTS = (1e3, 1e5, 1e7)
MIN_ROUNDS = 2
MAX_ROUNDS = 12
MAX_STALE = 6
GAUGE_HELD = 4  # home variables the settle holds where a similarity of the drawing is a flat
# direction (model.Model.gauge): the first two joints' x, y fix its place, turn and size
CONFIRM = 1e-6  # relative: a round's best this close to the best found so far confirms it
IMPROVE = 1e-6
TIE = 1e-9
EXACT_RMS = 1e-9  # rms error relative to the targets' scale: an exact fit
NEAR_EXACT_RMS = 1e-6  # ... and one the polish leaves on a flat valley's floor (rounds there agree:
# Jansen's foot path with every moving joint free and free timing, 23 unknowns, ends at 1e-7 to
# 1e-5 of the path's extent, where the Jacobian's condition number is 1e7 and no Newton step gains)
STEP = 1e-7  # forward-difference step, relative to max(|z|, 1e-2 box width, 1e-3 scale)
CURVATURE_STEP = 1e-4  # unit box: the settle's differenced Hessian of the Lagrangian, taken where
# Gauss-Newton's steps stall (kkt curvature="stalled"): a fit that leaves residuals (a six-bar's
# stride: 26 mm^2) has curvature of its own that Gauss-Newton misses, and its settle failed there
MARGIN = 3e-7  # the penalties hold every constraint this far inside (dimensionless): the polish then
# ends feasible, whatever the round-off between its refined extremes and the final check's
SETTLE_SHARE = 2  # a settle spends what the budget has left, and at least 1/SETTLE_SHARE of the whole
# budget when less is left (each of its points is a five-point slope of every variable): unbounded, the
# settles of a Stephenson II triad's sweep at [solver] budget = 30,000 spent 609,592 evaluations and 436
# of its 444 s; the dyads' settles of the examples take 119 to 14,649 (six_bar_dwell_sweep's runs each
# get 27,272 of its 300,000)
NEARLY = 1e-6  # total violation (constraints' units) a penalized polish leaves short of a binding
# constraint: such a pick is settled onto it (the settle is taken when it ends feasible)


def default_budget(model) -> int:
    """The evaluations a search gets without [solver] budget: DEFAULT_BUDGET over the population's
    evaluation cost (Population.evaluation_cost: a triad's ten times a dyad's), and with free
    timing, over n / FREE_TARGETS beyond FREE_TARGETS targets (each target is a timing variable:
    a round's batched Levenberg-Marquardt grows faster than its evaluations; path generation's
    four-bar lowers its own budget alike). A drawn six-bar's 200 free-timing points took 332 s
    on the full budget, 31 s on this one."""
    return max(1, int(DEFAULT_BUDGET / model.pop.evaluation_cost * free_share(model.timing, model.n)))


def free_share(timing: str, n: int) -> float:
    """The default budget's share with `timing` through n targets: FREE_TARGETS / n with free
    timing beyond FREE_TARGETS targets (default_budget; a topology sweep's total alike), else 1."""
    return FREE_TARGETS / n if timing == "free" and n > FREE_TARGETS else 1.0


@dataclass
class Candidate:
    x: np.ndarray
    s: float
    converged: bool
    round: int = 0


class Space:
    """The free variables z of the model's full vector x."""

    def __init__(self, model: Model):
        self.model = model
        self.idx = np.flatnonzero(model.free)
        self.lo, self.hi = model.lo[self.idx], model.hi[self.idx]
        self.base = (model.lo + model.hi) / 2.0
        self.linear = None
        k = model.k_home
        if model.timing == "free" and np.any(self.idx > k):
            self.linear = ((self.idx > k).astype(float), TWO_PI)

    @property
    def k(self) -> int:
        return len(self.idx)

    def full(self, z: np.ndarray) -> np.ndarray:
        x = np.repeat(self.base[None, :], len(z), axis=0)
        x[:, self.idx] = z
        return x

    def steps(self, z: np.ndarray) -> np.ndarray:
        """(N, k) forward steps, into the box."""
        width = self.hi - self.lo
        h = STEP * np.maximum(np.abs(z), np.maximum(1e-2 * width[None, :], 1e-3 * self.model.scale))
        return np.where(z + h > self.hi, -h, h)


class Penalized:
    """The boxed least-squares problems of linkcli.search.levenberg_marquardt: target
    residuals, then weight * max(0, g) of every constraint; each row its direction s."""

    def __init__(self, space: Space, s: np.ndarray, weight: float, budget: Budget, central: bool = False):
        self.space, self.s, self.weight, self.budget = space, s, weight, budget
        self.central = central  # central differences (the polish: a flat valley's floor needs them)
        self.lo, self.hi, self.linear = space.lo, space.hi, space.linear
        self.model = space.model
        self.at = np.zeros((len(s), len(self.model.kinds)))
        self.anchor = np.zeros(self.at.shape, dtype=int)

    def residuals(self, z, rows) -> np.ndarray:
        self.budget.add(len(z))
        ev = self.model.evaluate(self.space.full(z), self.s[rows])
        idx = np.arange(len(self.s))[rows]
        self.at[idx], self.anchor[idx] = ev.at, ev.anchor
        return np.concatenate([ev.r, self.weight * np.maximum(ev.g + MARGIN, 0.0)], axis=1)

    def jacobian(self, z, rows, r0) -> np.ndarray:
        """Forward differences (module docstring)."""
        model, space = self.model, self.space
        idx = np.arange(len(self.s))[rows]
        n, k = z.shape
        m_t = model.m_t
        self.budget.add(n * k * (2 if self.central else 1))
        h = space.steps(z)
        shifted = np.repeat(z[:, None, :], k, axis=1)
        shifted[:, np.arange(k), np.arange(k)] += h
        flat = space.full(shifted.reshape(n * k, k))
        s = np.repeat(self.s[idx], k)
        jac = np.zeros((n, r0.shape[1], k))
        rt = model.targets_at(flat, s).reshape(n, k, m_t)
        if self.central:  # the other side too, where the box leaves room (else forward)
            back = np.repeat(z[:, None, :], k, axis=1)
            room = (z - h >= space.lo) & (z - h <= space.hi)
            back[:, np.arange(k), np.arange(k)] -= np.where(room, h, 0.0)
            rb = model.targets_at(space.full(back.reshape(n * k, k)), s).reshape(n, k, m_t)
            rb = np.where(room[:, :, None], rb, r0[:, None, :m_t])
            span = np.where(room, 2.0 * h, h)
            jac[:, :m_t, :] = np.transpose((rt - rb) / span[:, :, None], (0, 2, 1))
        else:
            jac[:, :m_t, :] = np.transpose((rt - r0[:, None, :m_t]) / h[:, :, None], (0, 2, 1))
        broken = r0[:, m_t:] > 0.0
        some = np.flatnonzero(broken.any(axis=1))
        if len(some):
            xs = flat.reshape(n, k, -1)[some].reshape(len(some) * k, -1)
            g = model.constraints_at(xs, s.reshape(n, k)[some].reshape(-1), np.repeat(self.at[idx][some], k, axis=0),
                                     np.repeat(self.anchor[idx][some], k, axis=0))
            g = self.weight * np.maximum(g + MARGIN, 0.0).reshape(len(some), k, -1)
            slope = (g - r0[some][:, None, m_t:]) / h[some][:, :, None]
            jac[some, m_t:, :] = np.where(broken[some][:, :, None], np.transpose(slope, (0, 2, 1)), 0.0)
        return np.nan_to_num(jac)


def batch_lm(space: Space, z, s, weight: float, iterations: int, budget: Budget, reserve: int = 0,
             enough: float = -1.0, central: bool = False):
    return levenberg_marquardt.batch_lm(Penalized(space, s, weight, budget, central), z, iterations, reserve,
                                        enough)


# ---------------------------------------------------------------- ranking

def rank(model: Model, c: Candidate):
    """(infeasible, total violation, objective) from the exact check (model.check): lengths
    relative to the drawing's size, angles in radians; kept per design (model.ranks)."""
    from linkcli.synthesis.check import violations
    key = (c.x.tobytes(), c.s)
    if key not in model.ranks:
        v = violations(model, c.x, c.s)
        total = sum(amount / model.size if unit == "length" else amount for _, amount, _, unit in v)
        model.ranks[key] = (len(v) > 0, total, objective(model, c))
    return model.ranks[key]


def objective(model: Model, c: Candidate) -> float:
    ev = model.evaluate(c.x[None], np.array([c.s]), refine=False)
    f = float(ev.objective[0])
    return f if math.isfinite(f) else math.inf


def ranked(model: Model, cands: list[Candidate]) -> list[Candidate]:
    ranks = [rank(model, c) for c in cands]
    order = sorted(range(len(cands)), key=lambda i: ranks[i])
    if not order or ranks[order[0]][0]:
        return [cands[i] for i in order]
    top = ranks[order[0]][2]
    tied = [i for i in order if not ranks[i][0] and ranks[i][2] <= top + TIE * abs(top)]
    rest = [i for i in order if i not in set(tied)]
    tied.sort(key=lambda i: (cands[i].round, i))
    return [cands[i] for i in tied + rest]


def exact_objective(model: Model) -> float:
    return model.n * (EXACT_RMS * model.scale) ** 2


def near_exact_objective(model: Model) -> float:
    """An objective this small is an exact fit the polish left on its valley's floor: two
    rounds there found the same optimum (0), whatever their digits below it."""
    return model.n * (NEAR_EXACT_RMS * model.scale) ** 2


# ---------------------------------------------------------------- rounds

def search(model: Model, budget: Budget, rng) -> tuple[list[Candidate], bool]:
    """Rounds until the best is found twice (module docstring): (candidates best first,
    confirmed)."""
    space = Space(model)
    found: list[Candidate] = []
    best = None
    confirmed, stale = False, 0
    exact = exact_objective(model)
    for index in range(MAX_ROUNDS):
        if index and budget.left < ROUND_DRAWS[model.timing] * starts.hypotheses_per_draw(model):
            break
        try:
            new = one_round(model, space, budget, rng, index, best)
        except BudgetSpent:
            break
        found = ranked(model, found + new)[:POLISHED]
        mine = min(rank(model, c) for c in new)
        if not mine[0] and mine[2] <= exact:
            return found, True
        if best is not None:
            k = 1 if best[0] else 2
            better = mine[0] < best[0] or (mine[0] == best[0] and mine[k] < best[k] * (1 - IMPROVE))
            again = mine[0] == best[0] and abs(mine[k] - best[k]) <= CONFIRM * abs(best[k])
            zero = near_exact_objective(model)
            if not mine[0] and not best[0] and max(mine[2], best[2]) <= zero:
                again, better = True, False  # two rounds at an exact fit (its valley's floor): the same optimum
            if better:
                confirmed, stale = False, 0
            else:
                confirmed, stale = confirmed or again, stale + 1
        best = mine if best is None or mine < best else best
        if (confirmed and index + 1 >= MIN_ROUNDS) or stale >= MAX_STALE:
            break
    return found, confirmed


def one_round(model: Model, space: Space, budget: Budget, rng, index: int, best_so_far=None) -> list[Candidate]:
    """Draws, batched Levenberg-Marquardt, polish, settle (module docstring)."""
    x, s = starts.draws(model, rng, ROUND_DRAWS[model.timing])
    if space.k == 0:
        return [Candidate(x[0], float(s[0]), True, index)]
    z = np.clip(x[:, space.idx], space.lo, space.hi)
    budget.add(len(z))
    ev = model.evaluate(space.full(z), s)
    cost = np.sum(ev.r ** 2, axis=1) + np.sum((LM_WEIGHT * np.maximum(ev.g + MARGIN, 0.0)) ** 2, axis=1)
    cost = np.where(np.isfinite(cost), cost, HUGE)
    width = np.where(space.hi > space.lo, space.hi - space.lo, 1.0)
    keep = np.array(sampling.distinct(z / width, np.argsort(cost, kind="stable"), 1e-3, LM_FIELD), dtype=int)
    z, s = z[keep], s[keep]
    exact = exact_objective(model) / model.scale ** 2
    conv = np.zeros(len(z), dtype=bool)
    for _ in range(FIELD_ROUNDS):  # the field halves after each (its best distinct rows)
        z, f, ok = batch_lm(space, z, s, LM_WEIGHT, FIELD_ITERATIONS, budget, enough=exact)
        conv |= ok
        keep = np.array(sampling.distinct(z / width, np.argsort(f, kind="stable"), 1e-3,
                                          max(POLISHED, len(z) // 2)), dtype=int)
        z, s, conv = z[keep], s[keep], conv[keep]
        if f.min() <= exact:
            break
    z, s, conv = z[:POLISHED], s[:POLISHED], conv[:POLISHED]
    z, s, conv = polish(model, space, z, s, conv, budget)
    cands = [Candidate(space.full(z[i:i + 1])[0], float(s[i]), bool(conv[i]), index) for i in range(len(z))]
    cands = ranked(model, cands)
    for i, c in enumerate(cands):  # picks near the best (or nearly feasible and below it): settled
        r = rank(model, c)
        if (best_so_far is None and i == 0) or (best_so_far is not None and r <= _near(best_so_far)) or (
                r[0] and r[1] <= NEARLY and (best_so_far is None or r[2] < best_so_far[2])):
            cands[i] = settled(model, space, refined(model, space, c, budget), budget)
    return ranked(model, cands)


def refined(model: Model, space: Space, c: Candidate, budget: Budget) -> Candidate:
    """A pick the polish left unconverged, polished REFINE_MORE steps further (a long valley:
    one stopped part way would be a second arrival lost)."""
    if c.converged or space.k == 0:
        return c
    z = c.x[space.idx][None]
    z, _, ok = batch_lm(space, z, np.array([c.s]), POLISH_WEIGHTS[-1], REFINE_MORE, budget, central=True)
    out = Candidate(space.full(z)[0], c.s, bool(ok[0]), c.round)
    return out if rank(model, out) <= rank(model, c) else c


def _near(best):
    """A round's pick worth settling: feasible within SETTLE_NEAR of the best so far (or any
    pick while nothing is feasible)."""
    return (best[0], math.inf, math.inf) if best[0] else (False, math.inf, best[2] * (1.0 + SETTLE_NEAR))


def polish(model: Model, space: Space, z, s, conv, budget: Budget):
    """Levenberg-Marquardt at POLISH_WEIGHTS in turn, the rows still breaking a constraint
    going on to the next, stiffer one."""
    from linkcli.synthesis.check import violations
    todo = np.arange(len(z))
    for weight in POLISH_WEIGHTS:
        if not len(todo) or budget.left < len(todo) * (space.k + 1) * 4:
            break
        z[todo], _, ok = batch_lm(space, z[todo], s[todo], weight, POLISH_ITERATIONS, budget, central=True)
        conv[todo] |= ok
        full = space.full(z[todo])
        todo = todo[[bool(violations(model, full[j], s[i])) for j, i in enumerate(todo)]]
    return z, s, conv


# ---------------------------------------------------------------- settle

def settled(model: Model, space: Space, best: Candidate, budget: Budget) -> Candidate:
    """The candidate after Newton on the KKT system of the binding constraints
    (linkcli.search.kkt), when that converges to a feasible point no worse (relative 1e-9)
    within its allowance of evaluations (SETTLE_SHARE)."""
    from linkcli.search import kkt
    f0 = rank(model, best)
    if space.k == 0 or f0[1] > NEARLY or f0[2] <= exact_objective(model):
        return best
    width = np.where(space.hi > space.lo, space.hi - space.lo, 1.0)
    m_t = model.m_t
    k = model.k_home
    order = space.linear

    u0 = np.clip((best.x[space.idx] - space.lo) / width, 0.0, 1.0)
    moving = np.ones(space.k, dtype=bool)
    if model.gauge:  # the drawing's place, turn and size held (model.py): the first two joints'
        moving[np.isin(space.idx, np.arange(GAUGE_HELD))] = False

    def whole(us):
        out = np.repeat(u0[None, :], len(us), axis=0)
        out[:, moving] = us
        return out

    allowance = max(budget.left, budget.total // SETTLE_SHARE)
    spent = 0

    def values(us):
        nonlocal spent
        spent += len(us)
        if spent > allowance:
            raise BudgetSpent
        budget.add(len(us))
        z = space.lo + np.clip(whole(us), 0.0, 1.0) * width
        x = space.full(z)
        ev = model.evaluate(x, np.full(len(us), best.s))
        cols = [ev.r, -ev.g]
        if order is not None:
            cols.append((TWO_PI - x[:, k + 1:].sum(axis=1))[:, None])
        return np.concatenate(cols, axis=1)

    def points(us, gauss_newton: bool):
        v, jac = kkt.slopes_many(values, us)
        return kkt.least_squares_points(v, jac, m_t, gauss_newton)

    try:
        out = kkt.settle(lambda u: points(np.asarray(u, float)[None, :], True)[0], u0[moving],
                         evaluate_many=lambda us: points(us, False), curvature="stalled",
                         hessian_step=CURVATURE_STEP)
    except BudgetSpent:
        return best
    if not out.converged:
        return best
    x = space.full((space.lo + whole(out.u[None])[0] * width)[None])[0]
    cand = Candidate(model.canonical(x), best.s, True, best.round)
    r = rank(model, cand)
    if r[0] or (not f0[0] and r[2] > f0[2] * (1.0 + 1e-9)):
        return best
    return cand
