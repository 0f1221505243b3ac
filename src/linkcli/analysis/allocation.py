"""Least-cost tolerance allocation ([tolerance.cost], docs/tolerance.md): the tolerances t_i of
the links (`model.inverse`) that minimize the total cost sum_i c_i(t_i) of the cost-tolerance
models (analysis.cost_models) subject to the failure probability staying at or below
`max_failure_probability`, each t_i within the bounds its process can hold.

1. Closed form on the linearized model (Chase, Greenwood, Loosli & Hauglund 1990; Chase &
   Parkinson 1991, "A survey of research in the application of tolerance analysis to the
   design of mechanical assemblies", Research in Engineering Design 3): the error is
   sum_i S_i dl_i (S_i the sensitivity), its variance v sum_i S_i^2 t_i^2 (v = 1/3 uniform,
   1/9 normal at 3 sigma), and it fails beyond allowed_error E with probability 2 (1 -
   Phi(E / sigma)). With a Lagrange multiplier mu the optimum satisfies
   -c_i'(t_i) = 2 mu v S_i^2 t_i, i.e. m_i(t_i) = mu w_i with m_i(t) = -c_i'(t) / t and
   w_i = S_i^2: for the reciprocal laws t_i = (k_i b_i / (mu w_i))^(1 / (k_i + 2)); mu is
   set (bisection) so that sigma = E / z(p / 2).
2. Correction on the Monte Carlo with common random numbers: the same unit draws (the
   study's stream) at every step, and the failure indicator smoothed, p_s(t) = mean
   sigma((e_k(t) - E) / h) (the logistic function, h = SMOOTH E; 1 for samples that cannot
   be made), so that the
   constraint is smooth in t. At the optimum -c_i'(t_i) = mu dp/dt_i, so the weights become
   w_i = (dp_s/dt_i) / t_i, from per-sample forward differences on the common draws; mu is
   set so that p_s meets the target (Illinois regula falsi) and the round repeats until the
   tolerances settle (relative SETTLE) or MAX_ROUNDS. Where a round does not at least halve
   the change of the round before (CONTRACTION: the weights overshoot, as when several links
   act on the error together, a ternary link's three distances), the next weights are
   Anderson's mixing of the last ANDERSON_DEPTH rounds, in logarithms (Anderson 1965;
   Walker & Ni 2011, "Anderson acceleration for fixed-point iterations", SIAM J. Numer.
   Anal. 49), each weight moving by at most a factor e^MAX_LOG_STEP a round (few samples
   near the limit make the gradient rough: a full step threw every link to a bound). The
   drawn Watt six-bar's ten distances oscillated, the change growing, through all twelve
   rounds (its allocation costing 18.02 against 18.25 uniform at 20,000 samples) and now
   settle (16.97 against 18.98 at 4,000 samples; 17.62 against 19.70 at 2,000). The fire
   door's rounds contract six-fold each: no mixing, the same rounds as before.
3. Along the last weights, mu is bisected on the exact count of failures of the common
   draws to the largest tolerances with at most k_target failures (relative
   BISECTION_RTOL on every t_i).
4. The allocation is checked by a fresh Monte Carlo (another seed stream, the same number
   of samples): it meets the limit when the Wilson 95 % upper bound of its failure share is
   at most the limit. k_target is the largest count whose Wilson bound meets the limit,
   lowered by Z_MARGIN sqrt(2 k) (the two samples' scatter) so that the check usually
   passes; when it does not, k_target drops by the excess and step 3 repeats (at most
   VERIFY_ROUNDS, against the same fresh draws: the report says how many).

The uniform allocation, the same tolerance on every link (within its bounds) at the same
target on the same draws, is reported beside it, with its cost: the saving is what the
cost models buy. Vectorized over samples; numpy only.

Work: a few hundred passes over the common draws (about ten per round and dimension), each
assembling every sample at every target; on a terminal the progress display counts the
sample-targets (linkcli.progress). An allocation of more than MAX_WORK samples x targets x
toleranced dimensions is refused (exit 2, naming the limit and the largest samples the file
could ask): the fire door's four links at 3 targets take 1,000,000 samples, a drawn Watt
six-bar's ten distances at 36 targets 46,000.
"""

from __future__ import annotations

import math
from statistics import NormalDist

import numpy as np

from linkcli.analysis.bisection import boundary
from linkcli.analysis.cost_models import Costs
from linkcli.analysis.made_parts import Parts, column_key
from linkcli.analysis.tolerance import VERIFY_STREAM, Draws, chunks, plan_of, run, wilson

SMOOTH = 0.05  # bandwidth of the smoothed failure indicator, a share of allowed_error
FD_STEP = 1e-4  # relative step of the per-sample forward differences
MAX_ROUNDS = 16
SETTLE = 1e-6
BISECTION_RTOL = 1e-6
SMOOTH_RTOL = 1e-9  # the smoothed level, relative to the target
Z_MARGIN = 1.645
VERIFY_ROUNDS = 3
ANDERSON_DEPTH = 4  # rounds mixed once a round does not contract
CONTRACTION = 0.5  # a round whose change is not at most this share of the one before: mixing starts
MAX_LOG_STEP = 2.0  # a mixed round changes each weight by at most this factor's logarithm (e^2)
WEIGHT_FLOOR = 1e-6  # mixing: a weight of 0 (no sample sensitive) becomes this share of the largest
MAX_WORK = 2**24  # samples x targets x toleranced dimensions an allocation may take
NORMAL = NormalDist()


class Allocation:
    """One allocation: the allocated columns of the model, their cost models, the common
    draws, the allowed error."""

    def __init__(self, model, parts: Parts, cost, seed: int, n: int, distribution: str, allowed: float):
        self.model, self.parts, self.allowed = model, parts, allowed
        self.columns = [i for i, c in enumerate(model.columns) if c in model.inverse]
        self.names = [model.columns[i] for i in self.columns]
        self.costs = Costs([cost.of(column_key(model, c)) for c in self.names])
        self.plan = plan_of(model, parts, n, distribution)
        self.seed, self.n, self.distribution = seed, n, distribution
        self.draws = Draws(seed, self.plan, keep=True)
        sens = model.sensitivity()
        self.sensitivity = np.array([np.inf if sens.get(c) is None else float(sens[c]) for c in self.names])
        self.passes = 0

    def scale(self, t: np.ndarray) -> np.ndarray:
        full = np.array(self.parts.scale, dtype=float)
        full[self.columns] = t
        return full

    def errors(self, t: np.ndarray) -> np.ndarray:
        """Each common sample's error at tolerances t (inf: cannot be made or assembled)."""
        self.passes += 1
        err, ok = run(self.model, self.draws, self.parts.with_scale(self.scale(t)))
        return np.where(ok, err, np.inf)

    def count(self, t: np.ndarray) -> int:
        return int(np.count_nonzero(self.errors(t) > self.allowed))

    def smoothed(self, f: np.ndarray) -> np.ndarray:
        """The smoothed failure indicator of each sample (module docstring, step 2)."""
        z = np.clip((f - self.allowed) / (SMOOTH * self.allowed), -40.0, 40.0)
        return np.where(np.isfinite(f), 1.0 / (1.0 + np.exp(-z)), 1.0)

    def gradient(self, t: np.ndarray) -> tuple[float, np.ndarray]:
        """(p_s(t), dp_s/dt_i): per-sample forward differences on the common draws."""
        f = self.errors(t)
        s = self.smoothed(f)
        weight = np.where(np.isfinite(f), s * (1.0 - s) / (SMOOTH * self.allowed), 0.0)
        grad = np.zeros(len(t))
        for j in range(len(t)):  # one pass per allocated link (a handful), vectorized over samples
            step = FD_STEP * t[j]
            moved = t.copy()
            moved[j] += step
            g = self.errors(moved)
            with np.errstate(invalid="ignore"):
                diff = np.where(np.isfinite(f) & np.isfinite(g), g - f, 0.0)
            grad[j] = float(np.mean(weight * diff)) / step
        return float(np.mean(s)), grad

    def path(self, log_mu: float, w: np.ndarray) -> np.ndarray:
        """The tolerances with m_i(t_i) = mu w_i (clipped to the bounds)."""
        with np.errstate(divide="ignore"):
            return self.costs.at_marginal(log_mu + np.log(w))

    def mu_range(self, w: np.ndarray) -> tuple[float, float]:
        """(log mu with every t_i at its upper bound, log mu with every t_i at its lower)."""
        with np.errstate(divide="ignore"):
            log_w = np.log(w)
            loose = self.costs.log_marginal(self.costs.hi) - log_w
            tight = self.costs.log_marginal(self.costs.lo) - log_w
        finite = np.isfinite(log_w)
        return float(np.min(loose[finite])) - 1.0, float(np.max(tight[finite])) + 1.0


def linearized(prob: Allocation, level: float) -> np.ndarray:
    """Step 1: the closed form on the linearized model (module docstring)."""
    s = np.where(np.isfinite(prob.sensitivity), prob.sensitivity, 1e300)
    w = s * s
    v = 1.0 / 9.0 if prob.distribution == "normal" else 1.0 / 3.0
    sigma = prob.allowed / NORMAL.inv_cdf(1.0 - level / 2.0)
    if not np.any(w > 0):
        return prob.costs.hi.copy()
    lo, hi = prob.mu_range(w)
    for _ in range(200):  # variance decreases as mu grows
        mid = 0.5 * (lo + hi)
        if v * float(np.sum(w * prob.path(mid, w) ** 2)) > sigma * sigma:
            lo = mid
        else:
            hi = mid
    return prob.path(hi, w)


def corrected(prob: Allocation, t: np.ndarray, target: float) -> tuple[np.ndarray, np.ndarray, float, int]:
    """Step 2: (t, w, log mu, rounds) after the Monte Carlo corrections (module docstring)."""
    w, log_mu, rounds = np.ones(len(t)), None, 0
    given: list[np.ndarray] = []  # log w each round used, and the log w its tolerances gave
    found: list[np.ndarray] = []
    previous, mixing = math.inf, False
    for rounds in range(1, MAX_ROUNDS + 1):
        _, grad = prob.gradient(t)
        new_w = np.maximum(grad, 0.0) / t
        if not np.any(new_w > 0):  # no link's tolerance matters: every one at its upper bound
            w = np.ones(len(t))
            return prob.costs.hi.copy(), w, prob.mu_range(w)[0], rounds
        if mixing:  # a link no sample is sensitive to (a round at the bounds): a small weight, not 0
            new_w = np.maximum(new_w, WEIGHT_FLOOR * float(np.max(new_w)))
        if rounds > 1:
            given.append(np.log(w))
            with np.errstate(divide="ignore"):
                found.append(np.log(new_w))
        if mixing:
            mixed = anderson(given[-(ANDERSON_DEPTH + 1):], found[-(ANDERSON_DEPTH + 1):], new_w)
            new_w = w * np.exp(np.clip(np.log(mixed / w), -MAX_LOG_STEP, MAX_LOG_STEP))
        w = new_w
        guess = log_mu if log_mu is not None else _log_mu_of(prob, t, w)
        log_mu = smooth_level(prob, w, target, guess)
        new = prob.path(log_mu, w)
        change = float(np.max(np.abs(np.log(new / t))))
        t = new
        if change <= SETTLE:
            break
        mixing = mixing or change > CONTRACTION * previous
        previous = change
    return t, w, log_mu, rounds


def anderson(given: list[np.ndarray], found: list[np.ndarray], plain: np.ndarray) -> np.ndarray:
    """The weights of Anderson's mixing (module docstring, step 2) of the rounds' log weights
    `given` and the log weights each gave (`found`), the last round last: x = g_k - dG gamma,
    gamma the least-squares solution of dR gamma = r_k (r = g - x, dR and dG the differences
    of successive rounds), solved without BLAS (search.linalg: the same bits on every
    machine). `plain` (the last round's own weights) where a weight is 0 (a log of -inf) or
    the differences are singular."""
    from linkcli.search.linalg import gram, matvec, solve
    if len(given) < 2 or not all(np.all(np.isfinite(x)) for x in given + found):
        return plain
    r = [g - x for x, g in zip(given, found)]
    d_r = np.stack([b - a for a, b in zip(r, r[1:])], axis=1)  # (links, depth)
    d_g = np.stack([b - a for a, b in zip(found, found[1:])], axis=1)
    normal = gram(d_r)
    normal = normal + 1e-12 * np.trace(normal) * np.eye(len(normal))  # a repeated round: still solvable
    gamma = solve(normal, matvec(d_r.T, r[-1]))
    mixed = found[-1] - matvec(d_g, gamma)
    return np.exp(mixed) if np.all(np.isfinite(mixed)) else plain


def _log_mu_of(prob: Allocation, t: np.ndarray, w: np.ndarray) -> float:
    """The log mu along w nearest to t: the mean of log m_i(t_i) - log w_i over the links
    inside their bounds."""
    with np.errstate(divide="ignore"):
        each = prob.costs.log_marginal(t) - np.log(w)
    inside = np.isfinite(each) & (t > prob.costs.lo) & (t < prob.costs.hi)
    return float(np.mean(each[inside])) if inside.any() else float(np.mean(each[np.isfinite(each)]))


def smooth_level(prob: Allocation, w: np.ndarray, target: float, guess: float) -> float:
    """log mu where p_s(t(mu)) = target along the weights w: bracketed outwards from `guess`,
    then Illinois regula falsi on log p_s (p_s falls as mu grows); a bound of the range
    where the target is out of reach."""
    loose, tight = prob.mu_range(w)

    def g(x: float) -> float:
        p = float(np.mean(prob.smoothed(prob.errors(prob.path(x, w)))))
        return math.log(max(p, 1e-300)) - math.log(target)

    x = min(max(guess, loose), tight)
    gx, step = g(x), 0.05
    a, ga, b, gb = (x, gx, None, None) if gx > 0 else (None, None, x, gx)
    while a is None or b is None:  # a: p_s above the target (smaller mu), b: below
        y = min(x + step, tight) if a is not None else max(x - step, loose)
        gy = g(y)
        if gy > 0:
            a, ga = y, gy
        else:
            b, gb = y, gy
        if (a is None and y == loose) or (b is None and y == tight):
            return y
        x, step = y, 2 * step
    side = 0
    for _ in range(60):
        x = (a * gb - b * ga) / (gb - ga)
        gx = g(x)
        if abs(gx) <= SMOOTH_RTOL or b - a <= 1e-12 * max(1.0, abs(x)):
            return x
        if gx > 0:
            a, ga = x, gx
            if side == 1:
                gb /= 2
            side = 1
        else:
            b, gb = x, gx
            if side == -1:
                ga /= 2
            side = -1
    return x


def exact_level(prob: Allocation, w: np.ndarray, log_mu: float, k_target: int) -> tuple[np.ndarray, int]:
    """Step 3: (t, failures) at the smallest mu along w (the largest tolerances) whose common
    draws fail at most k_target times; the lower bounds (and their count) when even they
    fail more, the upper bounds when they do not. mu grows: tolerances shrink, failures fall."""
    loose, tight = prob.mu_range(w)

    def count(x: float) -> int:
        return prob.count(prob.path(x, w))

    k_tight = count(tight)
    if k_tight > k_target:
        return prob.path(tight, w), k_tight
    k_loose = count(loose)
    if k_loose <= k_target:
        return prob.path(loose, w), k_loose
    x, step = min(max(log_mu, loose), tight), 0.02  # bracket from the smoothed solution outwards
    k = count(x)
    if k <= k_target:
        good, k_good, fail = x, k, loose
        while True:
            y = max(good - step, loose)
            k = count(y) if y > loose else k_loose
            if k > k_target:
                fail = y
                break
            good, k_good, step = y, k, 2 * step
    else:
        fail, good, k_good = x, tight, k_tight
        while True:
            y = min(fail + step, tight)
            k = count(y) if y < tight else k_tight
            if k <= k_target:
                good, k_good = y, k
                break
            fail, step = y, 2 * step
    def judge(x: float):
        k = count(x)
        return k <= k_target, k

    def settled(a: float, b: float) -> bool:
        t_a, t_b = prob.path(a, w), prob.path(b, w)
        return bool(np.all(np.abs(t_b - t_a) <= BISECTION_RTOL * t_a))

    good, k_good = boundary(judge, good, fail, k_good, settled)
    return prob.path(good, w), k_good


def uniform(prob: Allocation, k_target: int) -> tuple[np.ndarray, float, int]:
    """(t per link, the common t, failures): the same tolerance on every link, within each
    link's bounds, largest with at most k_target failures on the common draws."""
    lo, hi = float(np.min(prob.costs.lo)), float(np.max(prob.costs.hi))
    clip = lambda x: np.clip(np.full(len(prob.columns), x), prob.costs.lo, prob.costs.hi)  # noqa: E731
    k_lo = prob.count(clip(lo))
    if k_lo > k_target:
        return clip(lo), lo, k_lo
    k_hi = prob.count(clip(hi))
    if k_hi <= k_target:
        return clip(hi), hi, k_hi
    def judge(x: float):
        k = prob.count(clip(x))
        return k <= k_target, k

    a, k_a = boundary(judge, lo, hi, k_lo, lambda a, b: b - a <= BISECTION_RTOL * b,
                      middle=lambda a, b: math.sqrt(a * b))
    return clip(a), a, k_a


def largest_count(n: int, level: float) -> int:
    """The largest failure count k of n samples whose Wilson 95 % upper bound is <= level
    (-1 when even none is enough)."""
    lo, hi = -1, n
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if wilson(mid, n)[1] <= level:
            lo = mid
        else:
            hi = mid
    return lo


def fresh_count(prob: Allocation, t: np.ndarray) -> int:
    """Failures of the allocation on a fresh Monte Carlo (the VERIFY_STREAM draws)."""
    err, ok = run(prob.model, chunks(prob.seed, prob.plan, VERIFY_STREAM), prob.parts.with_scale(prob.scale(t)))
    return int(np.count_nonzero(~ok | (err > prob.allowed)))


def allocate(prob: Allocation, level: float) -> dict:
    """Steps 1-4 (module docstring): the allocation, its counts and how it was found."""
    n = prob.n
    k_max = largest_count(n, level)
    k_target = max(0, int(math.floor(k_max - Z_MARGIN * math.sqrt(2.0 * max(k_max, 0)))))
    t = linearized(prob, level)
    t, w, log_mu, rounds = corrected(prob, t, max(k_target, 0.5) / n)
    out = {"k_max": k_max, "rounds": rounds}
    for check in range(1, VERIFY_ROUNDS + 1):
        t, k = exact_level(prob, w, log_mu, k_target)
        fresh = fresh_count(prob, t)
        out.update(t=t, k=k, fresh=fresh, checks=check, k_target=k_target)
        if fresh <= k_max or k_target == 0:
            break
        k_target = max(0, k_target - (fresh - k_max))
    out["uniform"] = uniform(prob, out["k_target"])
    return out


def allocation_section(problem, model, parts: Parts, level: float) -> dict:
    """The `allocation` part of the tolerance section: per link its tolerance, cost and role;
    the links' cost against the uniform allocation's, and with the fits priced too
    (`total_cost`, as a scheme's); the fresh check (module docstring)."""
    from linkcli.analysis.schemes import scheme_cost
    tol = problem.meta.tolerance
    refuse_oversized(problem, model)
    prob = Allocation(model, parts, tol.cost, int(problem.meta.solver.seed), tol.samples, tol.distribution,
                   float(tol.allowed_error))
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        res = allocate(prob, level)
    t = res["t"]
    t_u, common, _ = res["uniform"]
    costs = prob.costs.cost(t)
    costs_u = prob.costs.cost(t_u)
    n = prob.n
    lo, hi = wilson(res["fresh"], n)
    meets = hi <= level
    rows = []
    for j, name in enumerate(prob.names):
        rows.append({"link": column_key(model, name), "tolerance": float(t[j]), "cost": float(costs[j]),
                     "uniform_tolerance": float(t_u[j]), "role": role(t[j], t_u[j], prob.costs.lo[j], prob.costs.hi[j])})
    out = {
        "links": rows,
        "cost": float(np.sum(costs)),
        "total_cost": scheme_cost(tol.cost, model, parts.with_scale(prob.scale(t))),
        "uniform_cost": float(np.sum(costs_u)),
        "saving": float(np.sum(costs_u) - np.sum(costs)),
        "failure_probability": res["fresh"] / n,
        "failure_probability_ci95": [lo, hi],
        "check_samples": n,
        "design_failure_probability": res["k"] / n,
        "max_failure_probability": float(level),
        "meets": bool(meets),
        "checks": res["checks"],
    }
    if not meets:
        out["message"] = ("no tolerances within the bounds meet the limit: even at the lower bounds the "
                          "fresh check's Wilson upper bound exceeds it" if res["k"] > res["k_target"] else
                          "the fresh check's Wilson upper bound exceeds the limit: more samples would "
                          "separate the allocation from the limit")
    return out


def shortfall(tolerance: dict) -> str | None:
    """The report's message when the least-cost allocation does not meet its limit (the
    report's status is then `infeasible`, exit 1, as for a broken constraint): the limit and
    what the fresh check reached; None when it meets it or there is no allocation."""
    alloc = tolerance.get("allocation")
    if not alloc or alloc.get("meets", True):
        return None
    level = alloc["max_failure_probability"]
    reached = alloc["failure_probability"]
    upper = alloc["failure_probability_ci95"][1]
    why = alloc.get("message", "")
    return (f"tolerance allocation: max_failure_probability {level:g} not met: the fresh check's "
            f"failure probability is {reached:.6g} (Wilson 95 % upper bound {upper:.6g})"
            + (f"; {why}" if why else ""))


def refuse_oversized(problem, model) -> None:
    """SolveInputError (exit 2) for an allocation of more than MAX_WORK samples x targets x
    toleranced dimensions (module docstring, Work), naming the samples the file could ask."""
    from linkcli.errors import SolveInputError
    tol = problem.meta.tolerance
    targets, dimensions = max(len(model.inputs), 1), max(len(model.inverse), 1)
    work = tol.samples * targets * dimensions
    if work <= MAX_WORK:
        return
    raise SolveInputError(
        f"samples x targets x toleranced dimensions of at most {MAX_WORK:,} for a least-cost allocation "
        f"([tolerance.cost] assembles every sample at every target a few hundred times): at most "
        f"{MAX_WORK // (targets * dimensions):,} samples here",
        f"{tol.samples:,} samples x {targets} targets x {dimensions} dimensions = {work:,}",
        path=problem.meta.path, line=tol.lines.get("samples"), key="tolerance.samples")


def role(t: float, t_uniform: float, lo: float, hi: float) -> str:
    """What the cost made of a link: held at a bound of its process, or tighter / looser
    than the same tolerance on every link."""
    if t <= lo * (1 + 1e-9):
        return "tight: at the lower bound"
    if t >= hi * (1 - 1e-9):
        return "loose: at the upper bound"
    return "tight" if t < t_uniform else "loose"
