"""Function generation by optimization (docs/format.md; seed: the crank-rocker case).

The objective and the constraints are in model.py (numpy, vectorized over
candidates and points). Design variables: every length not fixed in [linkage] (within
[bounds]) and the free start angles, mapped to the unit box: lengths on a log scale
(lengths are ratios: bounds [0.02, 20] put 0.5 mid-box, where a linear map squeezes it
into the first 2.5 %), angles linearly. Each branch asked for (`either`: open, then
crossed) is solved in turn with its share of the budget, and the best result that meets
every constraint wins.

Freudenstein designs: unless the start is the extended dead-centre, the start angles
(given, or a grid over their bounds) fix the target angles at the points, and
Freudenstein's equation, linear in its three ratios, gives a design per start pair by
least squares (Model.freudenstein). The best of them seed the searches.

Strategies, by `[solver] method`:
- `auto`: the `slsqp` multistart below on 60 % of each branch's evaluations, then rounds
  of seeded scipy differential evolution with `vectorized=True` (one call
  scores the whole population at every point) on the exact L1 penalty
  f + W * sum(violations), each followed by the local polish (linkcli.search.polish: Gauss-Newton
  SQP steps, then SLSQP with the constraints explicit) from its best; the first round's
  population holds the best Freudenstein designs, and the best SEED_POLISHES of those
  are polished too; rounds stop when one no longer improves on the best found and two
  local searches from different starts have ended at it (else: not-converged);
- `slsqp`: SLSQP alone (search.polish stage 2) from the best distinct points of a seeded
  Latin hypercube sample and of the Freudenstein designs;
- `differential-evolution`, `dual-annealing`: the scipy global method alone, on the penalty.
The local polish works in a linear unit box (the valleys are straighter in the lengths
than in their logarithms). Gradients are central differences, the 2n shifted candidates
in one vectorized call (forward differences, n candidates, for the Gauss-Newton model).
Every candidate evaluated counts against `[solver] budget` (default 4000 per variable);
the answer is the best candidate seen that meets every constraint (else the least
violating one, status infeasible, the message naming each violated constraint and by
how much). A result that meets them all but whose local search did not converge (a
spent budget) is status not-converged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.errors import SolveInputError
from linkcli.types.function_generation.printed_digits import digits_note
from linkcli.model import FourBar, FunctionGenerationProblem
from linkcli.solution import Positions, Solution, SolverRecord, Status
from linkcli.search import kkt, linalg
from linkcli.search import polish as local_polish
from linkcli.search import sampling
from linkcli.search.budget import Budget, BudgetSpent
from linkcli.search.evolution import evolve
from linkcli.search.sampling import latin_hypercube
from linkcli.types.function_generation.model import BRANCH_SIGN, GRASHOF_MARGIN, STARTS, Batch, Model
from linkcli.types.function_generation.sections import structural_error, target_section
from linkcli.textnum import num

DEFAULT_BUDGET_PER_VARIABLE = 4000  # default budget: this many candidates per design variable
POPULATION_PER_VARIABLE = 10  # differential evolution population size per variable
MIN_POPULATION = 8
DE_TOL = 0.01  # scipy's relative spread of the population's energies at convergence (auto)
DE_ALONE_TOL = 1e-6  # the same for differential evolution without a polish
POLISH_SHARE = 0.5  # of a round's budget kept for the local polish (auto)
MULTISTART_SAMPLE = 20  # slsqp: Latin hypercube points per variable
MULTISTART_STARTS = 4  # slsqp: local searches per branch
MULTISTART_SHARE = 0.6  # auto: share of a branch's evaluations for the slsqp multistart first
SEED_PAIRS = 256  # start-angle pairs fitted by Freudenstein's equation (free starts)
MAX_ROUNDS = 6  # auto: differential evolution rounds at most, per branch
ROUND_GENERATIONS = 5  # auto: a further round needs the budget for this many generations
IMPROVE = 1e-6  # relative: a round that gains less has not improved the best
CONFIRM = 1e-6  # relative: a second polish ending this close to the best has found it again
REPEATS = 2  # local searches that ended in a minimum found before, at least (Search.confirmed)
EXACT_RMS = 1e-9  # rad: an rms error this small is an exact fit (round-off)
SEED_POLISHES = 3  # auto: Freudenstein designs polished besides the first round's best
SEED_POLISH_STEPS = 60  # auto: a seed's polish gets this many Gauss-Newton steps' evaluations
DISTINCT = 0.15  # slsqp: starts differ by this much in some variable (unit box)
STEP = 1e-7  # central-difference step in the unit box
FEASIBLE = 1e-8  # largest violation (rad, or fraction of L) accepted as feasible
SETTLE_EVALUATIONS = 1000  # the final KKT polish's reserve in the budget, at most,
SETTLE_SHARE = 20  # and at most this fraction (1/20) of it
SETTLED = ("auto", "slsqp")  # methods whose result is polished (a global method alone is not)
SETTLE_GAIN = 1e-6  # relative: the polished design (on its constraints) may be this much
# above a best one that used the FEASIBLE allowance
AT_BOUND = 1e-6  # a free value this close to a bound (unit box) is "at" it (a note)


# ---------------------------------------------------------------- counting and the best seen

@dataclass
class Best:
    f: float
    worst: float  # largest violation
    penalized: float
    u: np.ndarray  # unit box of the global search
    branch: str
    v: np.ndarray  # design values


class Search:
    """Counts every candidate against the budget and keeps the best seen per branch."""

    def __init__(self, model: Model, budget: int, branches: tuple[str, ...]) -> None:
        self.model = model
        self.evaluations = Budget(budget)
        self.budget = int(budget)  # as asked
        self.branches = branches
        self.feasible: dict[str, Best] = {}
        self.least: dict[str, Best] = {}
        self.ends: dict[str, list[float]] = {}  # per branch: the best feasible f of each polish
        self._session: float = math.nan  # best feasible f of the polish under way (nan: none)

    @property
    def left(self) -> int:
        return self.evaluations.left

    def run(self, u: np.ndarray, branch: str) -> Batch:
        """Evaluate candidates (unit box, (N, n)) on one branch: N evaluations."""
        u = np.clip(np.atleast_2d(np.asarray(u, dtype=float)), 0.0, 1.0)
        return self.run_values(self.model.values(u), branch, u)

    def run_values(self, v: np.ndarray, branch: str, u: np.ndarray | None = None) -> Batch:
        """Evaluate candidates given by their design values (N, n): N evaluations."""
        self.evaluations.spend(len(v))
        batch = self.model.evaluate(v, BRANCH_SIGN[branch])
        self._record(self.model.units(v) if u is None else u, v, batch, branch)
        return batch

    def _record(self, u, v, batch: Batch, branch: str) -> None:
        worst = batch.violation.max(axis=1)
        ok = worst <= FEASIBLE
        if ok.any():
            i = int(np.argmin(np.where(ok, batch.f, np.inf)))
            if not math.isnan(self._session):
                self._session = min(self._session, float(batch.f[i]))
            best = self.feasible.get(branch)
            if best is None or batch.f[i] < best.f:
                self.feasible[branch] = Best(float(batch.f[i]), float(worst[i]), float(batch.penalized[i]),
                                             u[i].copy(), branch, v[i].copy())
        i = int(np.argmin(batch.penalized))
        best = self.least.get(branch)
        if best is None or batch.penalized[i] < best.penalized:
            self.least[branch] = Best(float(batch.f[i]), float(worst[i]), float(batch.penalized[i]),
                                      u[i].copy(), branch, v[i].copy())

    def begin_polish(self) -> None:
        self._session = math.inf

    def end_polish_uncounted(self) -> None:
        self._session = math.nan  # a polish going on from the best confirms nothing

    def end_polish(self, branch: str) -> None:
        """Record where the polish just run ended (its best feasible f), if anywhere feasible."""
        if math.isfinite(self._session):
            self.ends.setdefault(branch, []).append(self._session)
        self._session = math.nan

    def confirmed(self, branch: str) -> bool:
        """Two local searches from different starts ended at the branch's best (within
        CONFIRM, relative, and round-off of an exact fit): the optimum found again; and
        the searches have begun to repeat themselves: n searches ended in w distinct
        minima with n - w >= REPEATS. (Boender & Rinnooy Kan, Bayesian stopping rules for
        multistart global optimization, Math. Programming 37, 1987: the expected number of
        minima w (n - 1) / (n - w - 2) exists only from n = w + 3; three searches that
        found 0.2023 twice and 6.08 once have seen too little to rule out a lower basin,
        as log_generator_grashof's 0.1072 on a small budget.)"""
        best = self.feasible.get(branch)
        if best is None:
            return False
        if best.f <= len(self.model.t) * EXACT_RMS ** 2:  # an exact fit: nothing lower to find
            return True
        ends = sorted(self.ends.get(branch, []))
        tol = CONFIRM * abs(best.f) + 1e-20
        if sum(f <= best.f + tol for f in ends) < 2:
            return False
        distinct = sum(1 for i, f in enumerate(ends) if i == 0 or f - ends[i - 1] > CONFIRM * abs(f) + 1e-20)
        return len(ends) - distinct >= REPEATS

    def answer(self) -> Best:
        """The best feasible candidate of any branch, else the least violating one."""
        if self.feasible:
            return min(self.feasible.values(), key=lambda b: (b.f, b.branch))
        return min(self.least.values(), key=lambda b: (b.penalized, b.branch))

    def start_of(self, branch: str) -> np.ndarray | None:
        """Where a local search on a branch starts: its best feasible or least penalized
        candidate, whichever is lower on the penalized objective."""
        cands = [b for b in (self.feasible.get(branch), self.least.get(branch)) if b is not None]
        return min(cands, key=lambda b: b.penalized).u if cands else None


# ---------------------------------------------------------------- local stage

class Local:
    """One branch as the problem of search.polish: values and slopes at points of the unit
    box, counted against the budget (and a local cap) and cached (SLSQP asks for values
    and slopes separately). The local unit box is linear in every variable (lengths too,
    unlike the global search's log scale): the valleys of these objectives are
    straighter in the lengths than in their logarithms, and Gauss-Newton needs several
    times fewer steps there."""

    def __init__(self, search: Search, branch: str, evaluations: int) -> None:
        self.search = search
        self.model = search.model
        self.n_variables = self.model.n_variables
        self.weight = self.model.weight
        self.branch = branch
        self.sign = BRANCH_SIGN[branch]
        self.stop = min(search.evaluations.used + evaluations, search.evaluations.total)
        self.cache: dict = {}

    def _batch(self, uu: np.ndarray):
        if self.search.evaluations.used + len(uu) > self.stop:
            raise BudgetSpent
        v = self.model.linear_values(uu)
        batch = self.search.run_values(v, self.branch)
        cons = self.model.inequalities(v, self.sign)
        fv = batch.f + self.model.weight * batch.violation[:, -1]  # a non-finite law stays penalized
        return batch, fv, cons

    def value(self, u: np.ndarray):
        """(f, constraint values, residuals, law violation) at u: one evaluation."""
        u = np.clip(u, 0.0, 1.0)
        key = (u.tobytes(), False)
        if key not in self.cache:
            batch, fv, cons = self._batch(u[None, :])
            self.cache[key] = (float(fv[0]), cons[0], batch.err[0], float(batch.violation[0, -1]))
        return self.cache[key]

    def slope(self, u: np.ndarray, central: bool = True):
        """(gradient of f, Jacobian of the constraints, Jacobian of the residuals) at u by
        central differences about a point at least STEP inside the box: 2n evaluations;
        or (central=False, for the Gauss-Newton model) by forward differences from u,
        stepping inwards at the upper bound: n evaluations besides the value at u."""
        n = self.model.n_variables
        if not central:
            u = np.clip(u, 0.0, 1.0)
            key = (u.tobytes(), "forward")
            if key not in self.cache:
                f0, c0, r0, _ = self.value(u)
                h = np.where(u > 1.0 - STEP, -STEP, STEP)
                batch, fv, cons = self._batch(u + np.diag(h))
                self.cache[key] = ((fv - f0) / h, ((cons - c0) / h[:, None]).T,
                                   ((batch.err - r0) / h[:, None]).T)
            return self.cache[key]
        u = np.clip(u, STEP, 1.0 - STEP)
        key = (u.tobytes(), True)
        if key not in self.cache:
            batch, fv, cons = self._batch(u + np.vstack([np.eye(n), -np.eye(n)]) * STEP)
            h2 = 2.0 * STEP
            self.cache[key] = ((fv[:n] - fv[n:]) / h2, ((cons[:n] - cons[n:]) / h2).T,
                               ((batch.err[:n] - batch.err[n:]) / h2).T)
        return self.cache[key]


def polish(search: Search, u0: np.ndarray, branch: str, evaluations: int,
           gauss_newton_first: bool = True, independent: bool = True) -> bool:
    """The local solver of search.polish on one branch from u0 (unit box of the global
    search), within `evaluations`; True if it converged. Where it ends counts towards
    confirming the best (Search.confirmed) unless it went on from the best itself
    (`independent` false)."""
    local = Local(search, branch, evaluations)
    model = search.model
    search.begin_polish() if independent else search.end_polish_uncounted()
    try:
        return local_polish.polish(local, model.linear_units(model.values(u0))[0], gauss_newton_first)
    except BudgetSpent:
        return False
    finally:
        search.end_polish(branch)


# ---------------------------------------------------------------- global stage

def check_law(model: Model, u: np.ndarray) -> None:
    """SolveInputError when the law is undefined at every point for every sampled candidate
    on every branch (the law, not the linkage, is then at fault). A law undefined at some
    points only (a domain that holds part of the sweeps) is left to the search, which
    penalizes those points (check_law_finite judges the linkage it ends with). Not an
    evaluation of the objective: the linkage is not assembled."""
    p = model.problem
    if p.form == "function":
        return
    values = model.values(u)
    a, b, c, d = model.lengths(values)
    for sign in sorted({BRANCH_SIGN[b_] for b_ in (("open", "crossed") if p.branch == "either" else (p.branch,))}):
        with np.errstate(all="ignore"):
            phi0, psi0, _ = model.start(values, a, b, c, d, sign)
            phi = phi0 + model.t * p.input_sweep
            target = model.target(phi, phi0, psi0)
        sane = np.isfinite(phi0[:, 0]) & np.isfinite(psi0[:, 0])  # else the lengths overflowed
        if not sane.any() or np.isfinite(target[sane]).any():
            return
    i = int(np.argmax(sane))
    k = int(np.argmin(np.isfinite(target[i])))
    phi = phi[i:i + 1]
    value = float(target[i, k])
    shown = "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    u_ = p.meta.units
    raise SolveInputError("a law finite at every evaluation point of some linkage within the bounds",
                     f"{shown} at phi = {u_.from_rad(float(phi[0, k])):.6g} {u_.angle} "
                     f"(and at every point for every sampled linkage)", path=p.meta.path,
                     line=p.lines.get("law"), key=p.lines.get("law_key"))


def population_size(n: int, evaluations: int) -> int:
    """POPULATION_PER_VARIABLE * n, smaller when the budget allows fewer than two generations."""
    size = max(MIN_POPULATION, POPULATION_PER_VARIABLE * n)
    return size if evaluations >= 2 * size else max(5, evaluations // 2)


def differential_evolution(search: Search, branch: str, evaluations: int, seed, tol: float,
                           extra: np.ndarray | None = None):
    """Seeded differential evolution (linkcli.search.evolution) on the penalized objective
    of one branch: every generation is one call, the population (S, n) against the points.
    `extra` rows (unit box) replace the first members of the Latin hypercube start.
    Returns (converged, best member or None)."""
    n = search.model.n_variables
    size = population_size(n, evaluations)
    if evaluations < size or size < 5:
        return False, None
    rng = np.random.default_rng(seed)
    init = latin_hypercube(rng, size, n)
    check_law(search.model, init)
    if extra is not None and len(extra):
        k = min(len(extra), size // 2)
        init[:k] = extra[:k]
    out = evolve(lambda u: search.run(u, branch).penalized, [(0.0, 1.0)] * n,
                 max(evaluations // size - 1, 0), init=init, rng=rng, tol=tol)
    return (False, None) if out is None else (out.converged, out.x)


def dual_annealing(search: Search, branch: str, evaluations: int, seed: int) -> bool:
    """scipy dual annealing (with its own L-BFGS-B local searches, given central-difference
    gradients) on the penalized objective of one branch; it asks for one candidate at a
    time, the gradients for 2n at once."""
    from scipy.optimize import dual_annealing as da
    n = search.model.n_variables
    rng = np.random.default_rng(seed)
    check_law(search.model, latin_hypercube(np.random.default_rng(seed), 8, n))
    stop = search.evaluations.used + evaluations

    shifts = np.vstack([np.eye(n), -np.eye(n)]) * STEP

    def func(u):
        if search.evaluations.used >= stop:
            raise BudgetSpent
        return float(search.run(u, branch).penalized[0])

    def grad(u):  # for its local searches: 2n candidates in one call
        if search.evaluations.used + 2 * n > stop:
            raise BudgetSpent
        pen = search.run(np.clip(u, STEP, 1.0 - STEP) + shifts, branch).penalized
        return (pen[:n] - pen[n:]) / (2.0 * STEP)

    try:
        res = da(func, [(0.0, 1.0)] * n, maxfun=max(evaluations, 1), rng=rng,
                 minimizer_kwargs={"method": "L-BFGS-B", "jac": grad})
    except BudgetSpent:
        return False
    return bool(res.success)


def start_pairs(model: Model, count: int) -> np.ndarray | None:
    """Start-angle pairs (phi_s, psi_s) to fit Freudenstein's equation at: the given
    pair, or a grid of cell centres over the free start bounds (about `count` pairs);
    None for the extended start (it depends on the lengths)."""
    p = model.problem
    if p.start == "extended" or count < 1:
        return None
    free = [k for k in STARTS if k in p.start_bounds]
    given = {"input_start": p.input_start, "output_start": p.output_start}
    side = max(1, int(count ** (1.0 / len(free)))) if free else 1
    axes = []
    for k in STARTS:
        if k in p.start_bounds:
            lo, hi = p.start_bounds[k]
            axes.append(lo + (np.arange(side) + 0.5) / side * (hi - lo))
        else:
            axes.append(np.array([float(given[k] or 0.0)]))
    grid = np.meshgrid(*axes, indexing="ij")
    return np.column_stack([g.ravel() for g in grid])


def freudenstein_seeds(search: Search, branch: str, count: int):
    """Freudenstein designs at start pairs (start_pairs), evaluated on the branch
    (counted): (rows best first and distinct (unit box, (k, n)), their penalized
    objectives); empty when there are none or the budget cannot pay for them."""
    model = search.model
    none = np.zeros((0, model.n_variables)), np.zeros(0)
    pairs = start_pairs(model, count)
    if pairs is None:
        return none
    u = model.freudenstein(pairs)
    if len(u) == 0 or search.evaluations.used + len(u) > search.evaluations.total:
        return none
    return distinct(u, search.run(u, branch).penalized, len(u))


def distinct(u: np.ndarray, scores: np.ndarray, most: int):
    """(rows, scores) of u, best score first, each row more than DISTINCT (unit box, in
    some variable) from those kept before it; at most `most` rows."""
    kept = sampling.distinct(u, np.argsort(scores, kind="stable"), DISTINCT, most)
    return u[kept].reshape(len(kept), u.shape[1]), scores[kept]


def branch_best(search: Search, branch: str) -> tuple:
    """Rank of the branch's best candidate so far: feasible before infeasible, then f."""
    if branch in search.feasible:
        return (0, search.feasible[branch].f)
    if branch in search.least:
        return (1, search.least[branch].penalized)
    return (2, math.inf)


def improved(before: tuple, after: tuple) -> bool:
    """A better rank, or the same rank and an objective lower by a share IMPROVE (and by
    more than round-off of an exact fit, 1e-20 rad^2)."""
    return after[0] < before[0] or (after[0] == before[0] and after[1] < before[1] - IMPROVE * abs(before[1]) - 1e-20)


def multistart(search: Search, branch: str, evaluations: int, seed: int,
               gauss_newton_first: bool = False) -> bool:
    """SLSQP (polish) from the best distinct points of a Latin hypercube sample and of
    the Freudenstein designs; converged if the search that found the best converged."""
    n = search.model.n_variables
    rng = np.random.default_rng(seed)
    stop = search.evaluations.used + evaluations
    size = max(1, min(MULTISTART_SAMPLE * n, evaluations // 4))
    u = latin_hypercube(rng, size, n)
    check_law(search.model, u)
    try:
        seeds, seed_scores = freudenstein_seeds(search, branch, min(SEED_PAIRS, evaluations // 8))
        scores = search.run(u, branch).penalized
    except BudgetSpent:
        return False
    starts, _ = distinct(np.vstack([seeds, u]), np.concatenate([seed_scores, scores]), MULTISTART_STARTS)
    converged = False
    for k, s_ in enumerate(starts):
        left = min(stop, search.evaluations.total) - search.evaluations.used
        if left <= 2 * n + 1:
            break
        before = branch_best(search, branch)
        done = polish(search, s_, branch, left // (len(starts) - k), gauss_newton_first=gauss_newton_first)
        if improved(before, branch_best(search, branch)):
            converged = done
    return converged and search.confirmed(branch)


def auto(search: Search, branch: str, evaluations: int, seed: int) -> bool:
    """`multistart` (SLSQP from the best distinct Latin hypercube points and Freudenstein
    designs) on MULTISTART_SHARE of the branch's evaluations, then `evolution_rounds` on
    the rest: the local searches from spread starts find narrow basins a population
    misses (log_generator_grashof's crossed branch), the rounds the basins between them.
    True if the search that found the branch's best converged and the best was found
    twice."""
    start = search.evaluations.used
    # Gauss-Newton first (BLAS-free): SLSQP alone from far starts takes paths, and basins,
    # that follow the BLAS kernel's round-off
    multistart(search, branch, int(MULTISTART_SHARE * evaluations), seed, gauss_newton_first=True)
    return evolution_rounds(search, branch, evaluations - (search.evaluations.used - start), seed)


def evolution_rounds(search: Search, branch: str, evaluations: int, seed: int) -> bool:
    """Rounds of differential evolution, each followed by the polish from its best,
    until a round no longer improves on the best and two local searches from different
    starts have ended at it (Search.confirmed), or the budget is spent. The first
    round's population holds the best Freudenstein designs (start_pairs), and after its
    polish the best SEED_POLISHES distinct designs are polished too (the basins of a
    function generator are narrow in the start angles: a population can miss one that
    a design fitted there lands in). True if the polish that found the branch's best
    converged and the best was found twice (else the status is not-converged)."""
    n = search.model.n_variables
    stop = search.evaluations.used + evaluations
    seeds, _ = freudenstein_seeds(search, branch, min(SEED_PAIRS, evaluations // 8))
    converged = False
    for round_ in range(MAX_ROUNDS):
        left = min(stop, search.evaluations.total) - search.evaluations.used
        reserve = max(int(POLISH_SHARE * left), min(left, 2 * n + 1))
        if round_ and left - reserve < ROUND_GENERATIONS * population_size(n, left - reserve):
            break
        before = branch_best(search, branch)
        _, best = differential_evolution(search, branch, left - reserve, [seed, round_] if round_ else seed,
                                         tol=DE_TOL, extra=seeds if round_ == 0 else None)
        if branch not in search.least:  # too small a budget for a population: a few samples
            u = latin_hypercube(np.random.default_rng(seed), max(1, min(8, (stop - search.evaluations.used) // 4)), n)
            check_law(search.model, u)
            try:
                search.run(u, branch)
            except BudgetSpent:
                return False
        if round_ == 0:
            start = search.start_of(branch)
            converged = polish(search, start, branch, min(stop, search.evaluations.total) - search.evaluations.used)
            converged = polish_seeds(search, branch, seeds, start, stop, converged)
            continue
        if best is None:  # the budget ran out within the round
            break
        gain, done = probe(search, branch, best, stop, min(stop, search.evaluations.total) - search.evaluations.used)
        if gain or improved(before, branch_best(search, branch)):
            converged = done  # this round found the best so far
        elif search.confirmed(branch):
            break  # two local searches ended at the best: enough
    return converged and search.confirmed(branch)


def probe(search: Search, branch: str, start: np.ndarray, stop: int, evaluations: int):
    """The polish from `start` within SEED_POLISH_STEPS Gauss-Newton steps' worth of
    evaluations (a basin that needs more is rarely the best one), going on from where it
    stopped, with half of what is left, if it improved on the branch's best.
    (improved, converged)."""
    before = branch_best(search, branch)
    done = polish(search, start, branch, min(evaluations, SEED_POLISH_STEPS * (search.model.n_variables + 2)))
    if not improved(before, branch_best(search, branch)):
        return False, done
    if not done:
        done = polish(search, search.start_of(branch), branch,
                      (min(stop, search.evaluations.total) - search.evaluations.used) // 2,
                      independent=False)
    return True, done


def polish_seeds(search: Search, branch: str, seeds: np.ndarray, polished: np.ndarray, stop: int,
                 converged: bool) -> bool:
    """`probe` from each of the best SEED_POLISHES seeds not near `polished`, sharing what
    is left of the budget (however poor a design's own objective, a transmission window
    it misses for one, its polish may land in the best basin); returns the converged
    flag of the branch's best."""
    todo = [s_ for s_ in seeds if np.max(np.abs(s_ - polished)) > DISTINCT][:SEED_POLISHES]
    for k, s_ in enumerate(todo):
        left = min(stop, search.evaluations.total) - search.evaluations.used
        if left <= 4 * (search.model.n_variables + 2):
            break
        gain, done = probe(search, branch, s_, stop, left // (len(todo) - k + 1))
        if gain:
            converged = done
    return converged


def evolution_alone(search: Search, branch: str, evaluations: int, seed: int) -> bool:
    """Differential evolution with the whole budget and a tight convergence test."""
    converged, _ = differential_evolution(search, branch, evaluations, seed, tol=DE_ALONE_TOL)
    return converged


STRATEGIES = {"auto": auto, "slsqp": multistart, "differential-evolution": evolution_alone,
              "dual-annealing": dual_annealing}


def solve(problem: FunctionGenerationProblem) -> Solution:
    """Each branch asked for in turn with its share of the budget (a share left unused
    passes to the next branch); the best feasible result of any branch wins."""
    model = Model(problem)
    opts = problem.meta.solver
    n = model.n_variables
    budget = opts.budget if opts.budget is not None else DEFAULT_BUDGET_PER_VARIABLE * max(n, 1)
    branches = ("open", "crossed") if problem.branch == "either" else (problem.branch,)
    search = Search(model, budget, branches)
    polishes = opts.method in SETTLED and n > 0
    reserve = min(SETTLE_EVALUATIONS, budget // SETTLE_SHARE) if polishes else 0
    search.evaluations.total = search.evaluations.cap = budget - reserve  # the searches' part
    converged = {}
    for k, branch in enumerate(branches):
        share = search.left // (len(branches) - k)
        if n == 0:  # nothing to optimize: the fixed design is evaluated
            search.run(np.zeros((1, 0)), branch)
            converged[branch] = True
        elif share > 0:
            converged[branch] = STRATEGIES[opts.method](search, branch, share, opts.seed)
    search.evaluations.total = search.evaluations.cap = budget  # the reserve joins what is left
    if not search.least:  # no candidate fitted in the shares: one at the centre of the box
        search.run(np.full((1, n), 0.5), branches[-1])
    best_branch = search.answer().branch
    done = converged.get(best_branch, False)
    # auto and slsqp: the best must have been reached by two local searches (found twice)
    found_twice = search.confirmed(best_branch) if opts.method in SETTLED and n > 0 else True
    if polishes:
        done = settle(search, done)
    if problem.objective == "failure-probability":  # the design that fails least (analysis.robust_design)
        from linkcli.types.function_generation.robust import robust
        return robust(problem, model, search, done and found_twice, found_twice)
    return build_solution(problem, model, search, done and found_twice, found_twice)


def settle(search: Search, converged: bool) -> bool:
    """The final polish (linkcli.search.kkt): Newton on the KKT system of the constraints
    that bind at the best feasible design, in the local unit box, to machine precision;
    its end point becomes the answer when it meets every constraint and is as good within
    SETTLE_GAIN (the printed digits are then the optimum's on every machine). It spends what
    the searches left of the budget, at least their reserve (`solve`). True if the search
    converged or the polish did."""
    if not search.feasible or search.model.n_variables == 0:
        return converged
    best = search.answer()
    model = search.model
    local = Local(search, best.branch, search.left)

    def values(w):  # (N, n) -> (N, M + C + 1): residuals, constraints, objective
        batch, fv, cons = local._batch(w)
        return np.concatenate([batch.err, cons, fv[:, None]], axis=1)

    def evaluate(w):
        v, jac = kkt.slopes(values, w)
        m = len(model.t)
        err, jr, cons, jc = v[:m], jac[:m], v[m:-1], jac[m:-1]
        # grad f = 2 J^T r: its finite-difference error is that of J alone (f's own third
        # derivatives, large along the start angles, do not enter)
        return kkt.Point(float(v[-1]), 2.0 * linalg.matvec(jr.T, err), cons, jc, h=2.0 * linalg.gram(jr))

    try:
        out = kkt.settle(evaluate, model.linear_units(best.v[None, :])[0])
    except BudgetSpent:
        return converged
    if not (out.converged and out.worst <= FEASIBLE and out.f <= best.f * (1.0 + SETTLE_GAIN) + 1e-30):
        return converged
    v = model.linear_values(np.clip(out.u, 0.0, 1.0)[None, :])
    batch = search.run_values(v, best.branch)
    worst = float(batch.violation[0].max())
    if worst > FEASIBLE:
        return converged
    search.feasible[best.branch] = Best(float(batch.f[0]), worst, float(batch.penalized[0]),
                                        model.units(v)[0], best.branch, v[0].copy())
    return True


# ---------------------------------------------------------------- the report

def build_solution(problem, model: Model, search: Search, converged: bool,
                   found_twice: bool = True) -> Solution:
    best = search.answer()
    sign = BRANCH_SIGN[best.branch]
    v = best.v[None, :]
    batch, det = model.evaluate(v, sign, detail=True)
    a, b, c, d = (float(x[0, 0]) for x in model.lengths(v))
    fb = FourBar(ground=d, input=a, coupler=b, output=c, branch=best.branch)
    u = problem.meta.units
    phi0, psi0 = float(det["phi0"][0, 0]), float(det["psi0"][0, 0])
    err = det["err"][0]
    target = det["target"][0]
    positions = Positions(kind="angle", input=det["phi"][0], target=target,
                          achieved=kin.wrap(det["psi"][0]), error=kin.wrap(err))
    check_law_finite(problem, model, batch.violation[0], det, u)
    violations = describe_violations(problem, model, batch.violation[0], det, u)
    solver = SolverRecord(solver_name(problem.meta.solver.method, model.n_variables), problem.meta.solver.seed,
                          search.evaluations.used, bool(converged))
    if violations:
        status, message = Status.INFEASIBLE, "; ".join(violations)
    elif not found_twice:
        status = Status.NOT_CONVERGED
        message = ("the best linkage found meets every constraint, but within the budget "
                   f"({search.budget} evaluations) no second local search ended at it, or the "
                   "local searches found a different minimum nearly every time (too few to rule "
                   "out a lower one): another seed or a larger budget may end lower")
    elif not converged:
        status = Status.NOT_CONVERGED
        # no evaluation count here: it differs between machines (solver.evaluations has it)
        message = (f"the solver stopped before converging (budget {search.budget} "
                   "evaluations); the best linkage found meets every constraint")
    else:
        status = Status.OK
        message = (f"optimized over {len(model.t)} points on the {best.branch} branch; "
                   "within every constraint")
    notes = bound_notes(problem, model, best.u)
    if status is not Status.INFEASIBLE:  # do the printed digits hold? (printed_digits)
        note = digits_note(problem, model, v, sign, FEASIBLE,
                           lambda viol, one: describe_violations(problem, model, viol, one, u))
        if note:
            notes.append(note)
    sections = {}
    if "positions" in problem.meta.sections:
        sections["target"] = target_section(problem, phi0, psi0, u)
    if "error" in problem.meta.sections:
        sections["structural_error"] = structural_error(problem, model, (a, b, c, d), (phi0, psi0), sign, u)
    return Solution(status=status, linkage=fb, message=message, positions=positions,
                    objective=float(batch.f[0]), solver=solver, sections=sections,
                    notes=notes,
                    working_span=(phi0, problem.input_sweep))


def solver_name(method: str, n: int) -> str:
    if n == 0:
        return "evaluation (no free variable)"
    return {"auto": "differential-evolution+gauss-newton+slsqp"}.get(method, method)


def check_law_finite(problem, model: Model, viol, det, u) -> None:
    """A law that is still not finite at some point of the best design found (its start
    angles defined) is bad input, not an infeasible design: an overflow, a pole or a
    logarithm of a negative number over every design the search could reach."""
    if dict(zip(model.names, viol))["law"] <= FEASIBLE:
        return
    phi0, psi0 = float(det["phi0"][0, 0]), float(det["psi0"][0, 0])
    if not (math.isfinite(phi0) and math.isfinite(psi0)):
        return  # no start angles (no extended dead-centre): that violation is reported
    target, phi = det["target"][0], det["phi"][0]
    bad = np.flatnonzero(~np.isfinite(target))
    k = int(bad[0])
    raise SolveInputError("a law finite at every evaluation point of some design within the bounds",
                     f"{target[k]:.6g} at {len(bad)} of {len(target)} points of the best design "
                     f"found, first at phi = {float(u.from_rad(float(kin.wrap(phi[k])))):.6g} {u.angle} "
                     f"(point {k + 1})",
                     path=problem.meta.path, line=problem.lines.get("law"),
                     key=problem.lines.get("law_key"))


def describe_violations(problem, model: Model, viol, det, u) -> list[str]:
    """One phrase per violated constraint, with the amount in the file's units."""
    out = []
    names = dict(zip(model.names, viol))
    lu, au = u.length, u.angle
    scale = model.scale
    if names["extended"] > FEASIBLE:
        out.append(f"no extended dead-centre: input + coupler misses the range |output - ground| .. "
                   f"output + ground by {num(names['extended'] * scale)} {lu}")
    if names["travel"] > FEASIBLE:
        out.append(f"travel: the input meets a dead point within the sweep (coupler and output are "
                   f"{num(names['travel'] * scale)} {lu} short of assembling)")
    where = "over the full turn" if model.full_turn else "over the sweep"
    window = problem.transmission
    if names["transmission_low"] > FEASIBLE:
        mu = float(det["mu"][0][0, 0])
        out.append(f"transmission: mu falls to {num(u.from_rad(mu))} {au} {where}, "
                   f"{num(u.from_rad(names['transmission_low']))} {au} below the minimum "
                   f"{num(u.from_rad(window[0]))}")
    if names["transmission_high"] > FEASIBLE:
        mu = float(det["mu"][1][0, 0])
        out.append(f"transmission: mu reaches {num(u.from_rad(mu))} {au} {where}, "
                   f"{num(u.from_rad(names['transmission_high']))} {au} above the maximum "
                   f"{num(u.from_rad(window[1]))}")
    if names["grashof"] > FEASIBLE:
        found = kin.GRASHOF_CLASSES[int(kin.grashof_code(*(float(x[0, 0]) for x in det["lengths"])))]
        what = (f"not a {problem.grashof} but a {found}" if found != problem.grashof
                else f"a {found} within {GRASHOF_MARGIN:g} of a change-point")
        out.append(f"grashof: {what} (an inequality misses by {num(names['grashof'] * scale)} {lu})")
    if names["law"] > FEASIBLE:
        out.append(f"law: the target is not finite at {round(names['law'] * len(model.t))} of "
                   f"{len(model.t)} points")
    return out


def bound_notes(problem, model: Model, unit) -> list[str]:
    """A free length or start angle that ends on its bound: widening the bound may help."""
    notes = []
    u = problem.meta.units
    for i, name in enumerate(model.variables):
        lo, hi = model.lo[i], model.hi[i]
        at = "lower" if unit[i] <= AT_BOUND else ("upper" if unit[i] >= 1 - AT_BOUND else None)
        if at is None:
            continue
        bound = lo if at == "lower" else hi
        shown = f"{num(u.from_rad(bound))} {u.angle}" if name in STARTS else f"{num(bound)} {u.length}"
        notes.append(f"{name} ends at its {at} bound ({shown}): a wider [bounds].{name} may lower the objective")
    return notes
