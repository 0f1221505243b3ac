"""Function generation by optimization (docs/format.md; seed: the crank-rocker case).

The objective and the constraints are in model.py (numpy, vectorized over
candidates and points). Design variables: every length not fixed in [linkage] (within
[bounds]) and the free start angles, mapped to the unit box: lengths on a log scale
(lengths are ratios: bounds [0.02, 20] put 0.5 mid-box, where a linear map squeezes it
into the first 2.5 %), angles linearly; the local searches work in a linear unit box
(the valleys are straighter in the lengths than in their logarithms).

Strategies, by `[solver] method`:
- `auto` (auto.py): rounds of a batched multistart: Freudenstein designs and a Latin
  hypercube sample on every branch asked for, the best distinct ones carried into their
  basins by Levenberg-Marquardt all at once, the best ends polished with the constraints
  exact, until the best is found twice;
- `slsqp`: SLSQP alone (search.polish stage 2) from the best distinct points of a seeded
  Latin hypercube sample and of the Freudenstein designs, each branch in turn;
- `differential-evolution`, `dual-annealing`: the scipy global method alone, on the
  exact L1 penalty f + W * sum(violations), each branch in turn.
Every candidate evaluated counts against `[solver] budget` (default 4000 per variable);
the answer is the best candidate seen that meets every constraint (else the least
violating one, status infeasible, the message naming each violated constraint and by
how much). `auto` and `slsqp` end with a Newton-KKT settle of the best (`settle`); their
result is `ok` only when two local searches ended at it (search.Search.confirmed) and one
of them converged, else not-converged; the global methods' by their own test.
"""

from __future__ import annotations

import numpy as np

from linkcli.model import FunctionGenerationProblem
from linkcli.search import kkt, linalg
from linkcli.search.budget import BudgetSpent
from linkcli.search.evolution import evolve
from linkcli.search.sampling import latin_hypercube
from linkcli.solution import Solution
from linkcli.types.function_generation.auto import auto
from linkcli.types.function_generation.model import Model
from linkcli.types.function_generation.result import build_solution
from linkcli.types.function_generation.search import FEASIBLE, STEP, Best, Local, Search, polish
from linkcli.types.function_generation.starts import SEED_PAIRS, check_law, distinct, freudenstein_seeds

DEFAULT_BUDGET_PER_VARIABLE = 4000  # default budget: this many candidates per design variable
POPULATION_PER_VARIABLE = 10  # differential evolution population size per variable
MIN_POPULATION = 8
DE_ALONE_TOL = 1e-6  # scipy's relative spread of the population's energies at convergence
MULTISTART_SAMPLE = 20  # slsqp: Latin hypercube points per variable
MULTISTART_STARTS = 4  # slsqp: local searches per branch
SETTLE_EVALUATIONS = 1000  # the final KKT polish's reserve in the budget, at most,
SETTLE_SHARE = 20  # and at most this fraction (1/20) of it
SETTLED = ("auto", "slsqp")  # methods whose result is polished (a global method alone is not)
SETTLE_GAIN = 1e-6  # relative: the polished design (on its constraints) may be this much
# above a best one that used the FEASIBLE allowance


# ---------------------------------------------------------------- global stage
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

def multistart(search: Search, branch: str, evaluations: int, seed: int) -> bool:
    """SLSQP (polish) from the best distinct points of a Latin hypercube sample and of
    the Freudenstein designs; True if a search that ended at the branch's best converged."""
    model = search.model
    n = model.n_variables
    rng = np.random.default_rng(seed)
    stop = search.evaluations.used + evaluations
    size = max(1, min(MULTISTART_SAMPLE * n, evaluations // 4))
    u = latin_hypercube(rng, size, n)
    check_law(model, u)
    try:
        seeds, seed_scores = freudenstein_seeds(search, branch, min(SEED_PAIRS, evaluations // 8))
        scores = search.run(u, branch).penalized
    except BudgetSpent:
        return False
    starts, _ = distinct(np.vstack([seeds, u]), np.concatenate([seed_scores, scores]), MULTISTART_STARTS)
    for k, s_ in enumerate(starts):
        left = min(stop, search.evaluations.total) - search.evaluations.used
        if left <= 2 * n + 1:
            break
        search.new_batch()  # each start drawn on its own: its search is independent
        polish(search, model.linear_units(model.values(s_))[0], branch, left // (len(starts) - k),
               gauss_newton_first=False)
    return search.settled(branch)


def evolution_alone(search: Search, branch: str, evaluations: int, seed: int) -> bool:
    """Differential evolution with the whole budget and a tight convergence test."""
    converged, _ = differential_evolution(search, branch, evaluations, seed, tol=DE_ALONE_TOL)
    return converged


STRATEGIES = {"slsqp": multistart, "differential-evolution": evolution_alone, "dual-annealing": dual_annealing}


def solve(problem) -> Solution:
    """The design of the problem's mechanism, by its home's synthesis face
    (mechanisms.synthesis): the four-bar's below (`solve_four_bar`)."""
    from linkcli.mechanisms import synthesis
    return synthesis.solve("function-generation", problem)


def solve_four_bar(problem: FunctionGenerationProblem) -> Solution:
    """`auto` on every branch asked for at once; another method on each branch in turn
    with its share of the budget (a share left unused passes to the next branch); the
    best feasible result of any branch wins."""
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
    if n == 0:  # nothing to optimize: the fixed design is evaluated
        for branch in branches:
            search.run(np.zeros((1, 0)), branch)
            converged[branch] = True
    elif opts.method == "auto":
        auto(search, branches, opts.seed)
    else:
        for k, branch in enumerate(branches):
            share = search.left // (len(branches) - k)
            if share > 0:
                converged[branch] = STRATEGIES[opts.method](search, branch, share, opts.seed)
    search.evaluations.total = search.evaluations.cap = budget  # the reserve joins what is left
    if not search.least:  # no candidate fitted in the shares: one at the centre of the box
        search.run(np.full((1, n), 0.5), branches[-1])
    best_branch = search.answer().branch
    done = converged.get(best_branch, False)
    found_twice = True
    if polishes:  # auto and slsqp: the best must have been reached by two local searches
        found_twice = search.confirmed(best_branch)
        done = settle(search, search.settled(best_branch))
    if problem.objective == "failure-probability":  # the design that fails least (analysis.robust_design)
        from linkcli.types.function_generation.robust import robust
        return robust(problem, model, search, done and found_twice, found_twice)
    found = build_solution(problem, model, search, done and found_twice, found_twice)
    if problem.meta.front is not None:  # a Pareto front from this design (linkcli.pareto)
        from linkcli.types.function_generation.pareto import front
        return front(problem, model, search, found)
    return found


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
