"""Path generation: a coupler point through target points (docs/format.md).

Objective: sum over the targets of |P_k - T_k|^2, P_k the coupler point in the global frame
(`model`). Constraints: bounds, the Grashof class, the transmission window (over the
full turn for a crank-rocker or double-crank, else over the targets' span), assembly at
every target on one branch with no dead point between the first and the last target, and
for free timing the targets reached in order within one turn.

Methods (`[solver] method`):

* `multistart` (what `auto` runs): rounds of seeded draws completed in closed form
  (`starts`: timing hypotheses on the coupler curve, a similarity fit for scale,
  angle and pivot, a linear fit for coupler point and pivot), then Levenberg-Marquardt on
  the most promising distinct candidates at once with the linear part projected out, the
  field halving after each of its rounds, then the best distinct few refined (still
  projected, bounds and penalties held) and polished on every variable; until two
  rounds end at the same optimum. The first rounds run side by side, in the same batched
  steps (each of the size and from the draws it would have in turn): four with prescribed
  timing, two with free timing (SIDE_BY_SIDE).
* `least-squares`: plain multistart, Levenberg-Marquardt (`search.polish`) from uniform random draws.
* `differential-evolution`: scipy's differential evolution alone, on the penalized sum.
* `de-polish`: differential evolution on half the budget, then the Levenberg-Marquardt polish.

Whatever the method, the reported linkage is checked against every constraint with the
exact kinematics (`violations`); a violation makes the status infeasible, named with its amount.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from linkcli.search.budget import Budget, BudgetSpent
from linkcli.solution import Solution
from linkcli.types.path_generation import starts
from linkcli.types.path_generation.model import Design, build
from linkcli.types.path_generation.result import ANGLE_VIOLATIONS, Candidate, exact_objective, solution, violations
from linkcli.types.path_generation.search import (
    POLISH_ITERATIONS,
    Space,
    batch_lm,
    differential_evolution,
    distinct,
    polish,
    settle,
)

DEFAULT_BUDGET = {"multistart": 2_000_000, "least-squares": 200_000, "differential-evolution": 200_000,
                  "de-polish": 200_000}
POINT_EVALUATIONS = 40_000_000  # default cap on evaluations x targets (the cost of a search)
LM_WEIGHT = 1e2  # penalty weight (dimensionless residuals) in the batched stage
POLISH_WEIGHTS = (1e3, 1e5, 1e7, 1e9)  # final polish; each stiffer one only while a violation is left
LM_FIELD = 96  # candidates entering the batched Levenberg-Marquardt stage
FIELD_ROUNDS = 3  # rounds of the batched stage; the field halves after each
FIELD_ITERATIONS = 20  # iterations per field round (measured: longer ones, as the earlier
# (25, 25, 40, 60, 100), cost time without a better pick)
POLISHED = 4  # distinct candidates of a round refined (projected), then
POLISH_PICKS = 2  # of those, the best this many polished on every variable (`polish_all`)
REFINE_ITERATIONS = 100  # batched Levenberg-Marquardt of the refinement, at most,
REFINE_MORE = 400  # and this many more for a polished pick left unconverged near the best
NEAR_BEST = 1e-3  # (relative: a pick this close to the best objective may confirm it)
REFINE_ALL = 1500  # ... for every pick left unconverged, however far from the best, in a round
# that must find the optimum again (`thorough`): free timing's every round, prescribed timing's rounds
# after the first ones side by side (the best still unconfirmed). The projected refinement converges
# where the polish on every variable crawls along a flat valley and stops short, "converged": tuning
# case 97 (free timing) has round picks at 1.07, 1.7 and 2.4 times the best known that all reach it
# within 1,500 projected steps (polished on every variable they stopped at 1.01 to 1.1 times it), and
# its five seeds ended `not-converged` 0.08 to 7 % above it. Tuning half, free timing: 35 -> 56 of
# 60 runs `ok`; prescribed timing (only its later rounds change): cases 8, 64, 88 8 -> 11 of 15. In
# every round of prescribed timing it cost 1.25 times the time of ten typical cases (interleaved
# whole runs, benchmarks/compare_commands.py).
MAX_DRAWS = {"free": 600, "prescribed": 2000}
ATLAS_STARTS = 96  # placed starts asked of the coupler-curve atlas (free timing, `atlas_starts`),
ATLAS_ROUNDS = 6  # dealt to this many first rounds (CLAIM_ROUNDS["free"]: a best is claimed no sooner),
ATLAS_DRAWS = 0.25  # which draw this share of their usual draws beside them
ATLAS_BUDGET = 20_000  # a smaller budget leaves the atlas out (its placing costs about 1,500)
ATLAS_POINTS = 9  # fewer targets leave the atlas out: 2n residuals against 9 + n unknowns leave a
# continuum of exact fits below nine points (nine: the nine-point problem's finitely many, Wampler,
# Morgan & Sommese 1992), which the draws reach in their first field round; the atlas's starts,
# ranked first on their cost, led it into slow valleys instead (problems/straight_line.toml, five
# points, seeds 0-2: 3.0-9.3 s with the atlas, 0.32-0.41 s without; cabrera6_line 0.44-0.70 against
# 0.32-0.58 s; both exact either way; tests/data/path_free_grashof_variant.toml, eight points and
# no exact fit: the same objective, 3.5-4.7 s against 4.1-4.7 s)
SCAN_SHARE = 0.6  # share of a round's budget for the draws
ROUND_BUDGET = 500_000  # evaluations of a round of the multistart, at most
FIRST_ROUND = 100_000  # the first round's; each next one twice the last, up to ROUND_BUDGET
MIN_ROUND = 60_000  # a budget below two of these is one round
CONFIRM = 1e-7  # a round whose own best is within this (relative) of the best so far confirms it
IMPROVE = 1e-6  # a round improves the best when it lowers it by more than this (relative)
CLAIM_ROUNDS = {"prescribed": 4, "free": 6}  # rounds run at least before a best found twice ends
# the search (an exact fit ends it at once): the first rounds can all fall into one wide basin of a
# local optimum (constrained-variant cases 13, 69 and 93: two or three rounds at 1.2 to 15 times the
# best known, said `ok`; with four, each found the best or said `not-converged`; two checking rounds
# side by side at the first rounds' size did not). With free timing six: its rounds refine every
# unconverged pick (REFINE_ALL), so that more of them arrive at a wide basin's bottom, and reporting
# case 13's four rounds of seed 3 all ended at its local optimum at 16.6 times the best known and
# claimed it (in turn, the optimum's basin is reached about one round in three or four there)
SIDE_BY_SIDE = {"free": 2, "prescribed": CLAIM_ROUNDS["prescribed"]}  # rounds run side by side at the start. A
# prescribed-timing round spends a small share of its size (its draws are capped), so its batched steps
# are call overhead and four rounds together take about the time of two (tuning cases 96, 40: 2.3 -> 1.4
# and 1.6 s, the same designs). A free-timing round fills its size, and four together saved less (tuning
# cases 9 and 33: 3 to 20 %, under load) while each round compared its picks with its own best instead
# of the best so far: refined further, rounds 2 and 3 of reporting case 13 both reached its local optimum
# at 16.6 times the best known and it was claimed (seeds 2 and 3), where in turn round 3 stopped short of it
EDGE_EVERY = 2  # free timing, a crank-rocker (starts.at_edge) whose best so far is a small crank at the
# crank-rocker's edge (starts.edge_like), a shape uniform lengths almost never give: from the round a
# best may first be claimed on (CLAIM_ROUNDS: the later rounds run only while it is unconfirmed), every
# second round draws such shapes (starts.edge_shapes), the others uniform lengths as before, so that
# other starts can reach that optimum again or a better one beside it. closed18_free's best is one;
# the atlas's first round reached it and no uniform draw did (`not-converged` on every seed): now 8 of 8
# seeds `ok` at it (benchmarks/RESULTS.md). Without the condition on the best, half the later rounds of
# searches whose best lies elsewhere were lost: a D-shaped target ended 0.77 to 0.82 against 0.55 to 0.70
MAX_STALE = 12  # rounds in a row without improvement that end the search (3 stopped an unconfirmed
# best with most of the budget left: constrained-variant case 24, seeds 1 and 3, found the
# optimum in their first round and confirmed it in their fifth and sixth; 6 stopped the tuning half's
# prescribed-timing cases 8 (seeds 1, 3), 64 (seed 3) and 88 (seed 2) `not-converged` at the best with
# 0.9 to 1.8 million of their 2 million evaluations unspent: one round in nine to fifteen arrives there, and
# with 12 each is found again, `ok`. Only runs that would end unconfirmed run longer: a run that
# confirms its best within 6 stale rounds is the same run)
MEMORY = 4_000_000  # Jacobian elements held at once by the batched stage
SETTLE_EVALUATIONS = 5000  # the final KKT polish's reserve in the budget, at most,
SETTLE_SHARE = 20  # and at most this fraction (1/20) of it
SETTLE_NEAR = 1e-2  # relative: a converged pick this close to the best is settled too (a polish
# converges by its own tolerances short of a binding window: tuning case 72's rounds ended at
# 0.30104, 0.30110, 0.3010048, 0.3010094 against 0.3010027, and never confirmed)
PICK_SETTLE = 30_000  # evaluations of the settle of a round's pick, at most (measured: those
# that converge take 4,000 to 22,000; those that fail, from far, 110,000 and more)
TIE = 1e-9  # relative: feasible objectives this close are one optimum, the first found ranked first
SETTLE_GAIN = 1e-9  # relative: the polished candidate may be this much worse (round-off)


def solve(problem) -> Solution:
    """The design of the problem's mechanism, by its home's synthesis face
    (mechanisms.synthesis): the four-bar's below (`solve_four_bar`)."""
    from linkcli.mechanisms import synthesis
    return synthesis.solve("path-generation", problem)


def solve_four_bar(problem) -> Solution:
    """The four-bar's path design (the module docstring's methods)."""
    design = build(problem)
    opts = problem.meta.solver
    method = "multistart" if opts.method == "auto" else opts.method
    budget = Budget(opts.budget or default_budget(method, design.n_targets))
    polishes = method != "differential-evolution" and bool(design.free.any())  # a global method alone is not
    reserve = min(SETTLE_EVALUATIONS, budget.total // SETTLE_SHARE) if polishes else 0
    budget.cap -= reserve  # the searches' part; the reserve is the final polish's
    rng = np.random.default_rng(opts.seed)
    confirmed = True  # the global methods' own criteria; the multistart's: two rounds agree
    with np.errstate(all="ignore"):
        if not design.free.any():  # nothing to choose: the given linkage on the allowed branches
            signs = {"open": (-1.0,), "crossed": (1.0,)}.get(design.branch, (-1.0, 1.0))
            cands = [Candidate(design.lo.copy(), sg, 1.0, True) for sg in signs]
            budget.add(len(cands))
        elif method == "multistart":
            cands, confirmed = multistart(design, budget, rng, atlas=design.timing == "free"
                                          and opts.atlas is not False and design.n_targets >= ATLAS_POINTS)
        elif method == "least-squares":
            cands = plain_multistart(design, budget, rng)
        else:
            cands = evolve(design, budget, opts.seed, polish_after=method == "de-polish")
        best, violations = choose(design, cands)
        budget.cap = budget.total
        if not violations and polishes:
            best = settled(design, budget, best)
        if problem.objective == "failure-probability":  # the design that fails least (analysis.robust_design)
            from linkcli.types.path_generation.robust import robust
            return robust(problem, design, best, method, budget, confirmed)
        found = solution(problem, design, best, violations, method, budget, confirmed)
        if problem.meta.front is not None:  # a Pareto front from this design (linkcli.pareto)
            from linkcli.types.path_generation.pareto import front
            return front(problem, design, best, method, budget, found)
        return found


def default_budget(method: str, points: int) -> int:
    """The method's default evaluations, fewer for many targets (each evaluation costs one
    assembly per target): 2,000,000 up to 20 targets, 200,000 at 200."""
    return max(1, min(DEFAULT_BUDGET[method], POINT_EVALUATIONS // max(points, 1)))


def uses_atlas(problem) -> bool:
    """Whether this problem's search uses the coupler-curve atlas (a bench runs it with and
    without): a four-bar design with free timing through ATLAS_POINTS targets or more whose
    `[solver] atlas` is not false, solved by the multistart."""
    solver = problem.meta.solver
    return (getattr(problem, "timing", None) == "free" and problem.mechanism == "four-bar"
            and len(problem.points) >= ATLAS_POINTS
            and solver.method in ("auto", "multistart") and solver.atlas is not False)


# ---------------------------------------------------------------- methods

def multistart(design: Design, budget: Budget, rng, atlas: bool = False) -> tuple[list[Candidate], bool]:
    """Rounds of `one_round` (the first SIDE_BY_SIDE side by side) until an exact fit, a round
    whose own best lands within CONFIRM of the best so far (the same optimum found again
    from other starts), MAX_STALE rounds in a row that do not improve the best by more
    than IMPROVE, or the budget's end.
    Objectives are compared while a candidate is feasible, total violations while none is.
    Returns the best few candidates and whether the best was confirmed: exact, found again
    by a later round (its own best, or the next best kept, `_found_twice`). A
    search that ended otherwise found a different optimum from every start, and does not
    claim its best is the optimum (status not-converged).
    With `atlas` (free timing), the first ATLAS_ROUNDS rounds also start from their share of
    the coupler-curve atlas's placed starts (`atlas_starts`): starts like the draws, ranked
    with them, refined, polished and confirmed as they are; they draw ATLAS_DRAWS of their
    usual draws beside them. The rounds keep their sizes, order and pairing, and each later
    round is drawn as without the atlas. (Measured, seed 0: all six side by side took
    1.6 to 1.8 times the CPU time on free_closed150 and closed18_free, the latter then
    `not-converged`; in turn, closed18_free is `ok` at its best known.)
    With free timing for a crank-rocker whose best so far is a small crank at its edge,
    every EDGE_EVERY-th round from CLAIM_ROUNDS on (the best still unconfirmed) draws its
    shapes at that edge."""
    shares = atlas_starts(design, budget) if atlas else None
    found: list[Candidate] = []
    best = None
    stale = 0
    confirmed = False
    exact = exact_objective(design)
    size = FIRST_ROUND
    index = 0
    while True:
        sizes = [round_limit(budget.left, size)]
        for later in range(1, SIDE_BY_SIDE[design.timing] if index == 0 else 1):  # the first rounds side
            # by side, each of the size it would have in turn (the second as the first, then doubling)
            if budget.left - sum(sizes) < MIN_ROUND // 2:
                break
            size = size if later == 1 else min(2 * size, ROUND_BUDGET)
            sizes.append(round_limit(budget.left - sum(sizes), size))
        size = min(2 * size, ROUND_BUDGET)  # a round that did not settle it: the next is larger
        atlas_kw = {} if shares is None else {"extras": [shares(index + k) for k in range(len(sizes))]}
        claim = CLAIM_ROUNDS[design.timing]
        edge = (index >= claim and (index - claim) % EDGE_EVERY == 0 and best is not None and not best[0]
                and starts.at_edge(design) and starts.edge_like(found[0].x))
        with budget.limit(sum(sizes)):
            rounds = one_round(design, budget, rng, sizes, None if best is None or best[0] else best[2],
                               later=index > 0, edge=edge, **atlas_kw)
        for new in rounds:
            new = [replace(c, round=index) for c in new]
            index += 1
            mine = min((_rank(design, c) for c in new), default=None)
            found = _ranked(design, found + new)[:POLISHED]
            top = _rank(design, found[0])
            done = not top[0] and top[2] <= exact
            if best is not None and mine is not None:
                k = 1 if best[0] else 2  # compare violations while infeasible, else objectives
                tiny = exact if k == 2 else 0.0
                again = mine[0] == best[0] and abs(mine[k] - best[k]) <= CONFIRM * best[k] + tiny
                better = top[0] < best[0] or (top[0] == best[0] and top[k] < best[k] * (1 - IMPROVE) - tiny)
                stale = 0 if better else stale + 1
                confirmed = again and not better  # a better round is a new optimum, to confirm
                done |= stale >= MAX_STALE
            best = top if best is None or top < best else best
            confirmed |= _found_twice(design, found, exact)
            if done or (confirmed and index >= CLAIM_ROUNDS[design.timing]):
                return found, confirmed
        if budget.left < MIN_ROUND // 2:  # too little left for a round that could settle it
            return found, confirmed


def round_limit(left: int, size: int) -> int:
    """A round's evaluations: `size`; what is left when that is less than two rounds,
    split in two while each half still holds MIN_ROUND (a second round can confirm)."""
    if left >= 2 * size:
        return size
    return left // 2 if left >= 2 * MIN_ROUND else left


def _found_twice(design: Design, found: list[Candidate], exact: float) -> bool:
    """The best candidate is an exact fit, or another one found by another round (other
    draws: two starts of one round can be led into one basin by its shared stages) ends
    within CONFIRM of it: the optimum found again. Any of the kept candidates may be that
    arrival: a round whose two picks both reach the best ranks them first and second, the
    other round's arrival third."""
    if not found:
        return False
    top = _rank(design, found[0])
    if top[0]:
        return False
    if top[2] <= exact:
        return True
    for c in found[1:]:
        r = _rank(design, c)
        if c.round != found[0].round and not r[0] and r[2] - top[2] <= CONFIRM * top[2]:
            return True
    return False


@dataclass
class Field:
    """One round's rows in the batched stage: free variables (N, k) of the projected space,
    branch signs, directions, penalized costs, and the field rounds done."""

    z: np.ndarray
    sign: np.ndarray
    s: np.ndarray
    f: np.ndarray
    done: int = 0

    def take(self, keep: np.ndarray) -> None:
        self.z, self.sign, self.s, self.f = self.z[keep], self.sign[keep], self.s[keep], self.f[keep]


def one_round(design: Design, budget: Budget, rng, sizes: list[int], best_so_far: float | None = None,
              later: bool = False, extras: list | None = None, edge: bool = False) -> list[list[Candidate]]:
    """Rounds of the multistart (one per entry of `sizes`, its evaluations) run side by
    side, each from its own draws: draws completed in closed form, batched
    Levenberg-Marquardt with the linear part projected out (the field halving after each
    of the FIELD_ROUNDS), then the best distinct few refined (projected, bounds and
    penalties held), then polished on every variable; a pick the polish leaves unconverged
    within NEAR_BEST of the best (`_short_of_best`: the search's best so far or its round's)
    is refined REFINE_MORE steps further and polished again (one stopped short of the
    optimum is a second arrival lost: arc6 with windows other than the bench's ended
    `not-converged` at the optimum that way); in a `thorough` round (free timing's every
    round; with prescribed timing the `later` ones, after the first batch) every unconverged
    pick, REFINE_ALL steps. The other rounds start one field
    round after the first (their draws only once the first round's field holds no exact
    fit, which settles the search alone), so that all share every batched step: at
    these sizes a step is mostly numpy's call overhead (prescribed timing's four rounds
    together take about the time of two, SIDE_BY_SIDE). The
    rounds never exchange rows: each is as independent of the others as in turn. `extras`:
    each round's starts from the atlas (x, sign, s), or None, ranked with its draws; `edge`:
    the rounds draw their shapes at the crank-rocker's edge (EDGE_EVERY)."""
    extras = extras or [None] * len(sizes)
    proj = Space(design, budget, project=True)
    width = proj.hi - proj.lo
    exact = exact_objective(design) / design.scale ** 2  # dimensionless, as the costs
    fields = [_drawn(design, proj, budget, rng, sizes[0], len(sizes), extras[0], edge)]
    reserve = int(0.15 * budget.left)
    while True:
        if any(g.f.min() <= exact for g in fields):  # an exact fit settles the search alone
            fields = [g for g in fields if g.f.min() <= exact]
        active = [g for g in fields if g.done < FIELD_ROUNDS]
        if proj.k == 0 or budget.left <= reserve or not active:
            break
        _field_round(proj, active, reserve, width, exact)
        if len(fields) < len(sizes) and fields[0].f.min() > exact:  # the other rounds' draws
            fields += [_drawn(design, proj, budget, rng, size, len(sizes), extra, edge)
                       for size, extra in zip(sizes[1:], extras[1:])]
            reserve = int(0.15 * budget.left)
    for g in fields:  # the best distinct few; only exact fits where the round has one
        f = np.where(g.f > exact, np.inf, g.f) if g.f.min() <= exact else g.f
        keep = distinct(g.z, f, width, POLISHED)
        g.take(keep if len(keep) else np.arange(min(POLISHED, len(g.z))))
    space = Space(design, budget, project=True, closed_penalties=False)
    z, f, conv = batch_lm(space, *_stacked(fields), LM_WEIGHT, REFINE_ITERATIONS, reserve=reserve // 2,
                          enough=exact)
    picks, at = [], 0
    for g in fields:  # each round's best POLISH_PICKS (its exact fits alone), polished together
        f_g = f[at:at + len(g.z)]
        best = np.argsort(f_g, kind="stable")[:POLISH_PICKS]
        picks.append(at + (best[f_g[best] <= exact] if f.min() <= exact else best))
        at += len(g.z)
    pick = np.concatenate(picks)
    sign, s = np.concatenate([g.sign for g in fields]), np.concatenate([g.s for g in fields])
    done = polish_all(design, budget, space.full(z[pick], sign[pick], s[pick]), sign[pick], s[pick],
                      conv[pick])
    bounds = np.cumsum([0] + [len(p) for p in picks])
    thorough = design.timing == "free" or later
    share, steps = (math.inf, REFINE_ALL) if thorough else (NEAR_BEST, REFINE_MORE)
    short = np.concatenate([a + _short_of_best(design, done[a:b], best_so_far, share)
                            for a, b in zip(bounds[:-1], bounds[1:])]).astype(int)
    if steps and len(short) and f.min() > exact:  # refined further from where the refinement
        # stopped (in the projected space, which converges where the full one crawls), polished again
        more = pick[short]
        z[more], f[more], conv[more] = batch_lm(space, z[more], sign[more], s[more], LM_WEIGHT, steps,
                                                reserve=reserve // 2, enough=exact)
        again = polish_all(design, budget, space.full(z[more], sign[more], s[more]), sign[more], s[more],
                           conv[more])
        for j, c in zip(short, again):
            done[j] = c
    if not _holds_exact_fit(design, done):  # an exact fit ends the search: the others' settles would be spent for nothing
        near = set(_near_best(design, done, best_so_far, SETTLE_NEAR))
        done = [_settled_pick(design, budget, c) if not c.converged or j in near else c for j, c in enumerate(done)]
    return [done[a:b] for a, b in zip(bounds[:-1], bounds[1:]) if b > a]


def _holds_exact_fit(design: Design, done: list[Candidate]) -> bool:
    """Whether a feasible pick fits exactly (`exact_objective`): the search then ends with
    this batch of rounds (`multistart`), an exact fit ranked first, and `settled` keeps an
    exact fit as found. Settling the other picks (up to PICK_SETTLE evaluations each) could
    at most swap one exact fit for another; it took a third of free_partial16's solve
    (measured: 1.9-2.1 s CPU as a process, 1.1-1.3 s without, the same reports on
    the eight exact-target bench files, seeds 0 to 2)."""
    exact = exact_objective(design)
    return any(not r[0] and r[2] <= exact for r in (_rank(design, c) for c in done))


def _near_best(design: Design, done: list[Candidate], best: float | None, share: float) -> list[int]:
    """The feasible picks within `share` (relative) of the best feasible objective (the
    search's so far, `best`, or these picks')."""
    ranks = [_rank(design, c) for c in done]
    objective = [r[2] for r in ranks if not r[0]] + ([best] if best is not None else [])
    if not objective:
        return []
    top = min(objective)
    return [j for j, r in enumerate(ranks) if not r[0] and (math.isinf(share) or r[2] <= top * (1.0 + share))]


def _short_of_best(design: Design, done: list[Candidate], best: float | None, share: float) -> np.ndarray:
    """The polished picks left unconverged within `share` (relative; NEAR_BEST, or infinite
    in a `thorough` round) of the best feasible objective (`_near_best`): those that may confirm it or
    beat it; one stopped short of it would be a lost second arrival."""
    return np.array([j for j in _near_best(design, done, best, share) if not done[j].converged], dtype=int)


def _drawn(design: Design, proj: Space, budget: Budget, rng, size: int, rounds: int, extra=None,
           edge: bool = False) -> Field:
    """A round's draws (`starts`, SCAN_SHARE of its `size` evaluations; ATLAS_DRAWS of that
    share when the atlas gave it starts, `extra` (x, sign, s), which join them), ranked by
    their penalized cost, the LM_FIELD best distinct kept (fewer when so many Jacobians of
    `rounds` rounds at once would pass MEMORY elements). `edge`: shapes at the crank-rocker's
    edge (starts.edge_shapes)."""
    per = starts.hypotheses_per_draw(design)
    share = SCAN_SHARE * (ATLAS_DRAWS if extra is not None else 1.0)
    n_draws = min(MAX_DRAWS[design.timing], int(share * size) // per)
    if n_draws >= 8:
        x, sign, s = starts.starts(design, rng, n_draws, edge)
        budget.add(n_draws * per)
    else:  # a tiny budget: plain draws only, half of it to rank them
        n_draws = max(1, min(64, size // 2))
        x, sign, s = starts.plain_starts(design, rng, n_draws)
    if extra is not None:
        x, sign, s = (np.concatenate([e, v]) for e, v in zip(extra, (x, sign, s)))
        n_draws = len(x)
    z = proj.free(x)
    f = proj.cost(z, sign, s, LM_WEIGHT) if budget.left >= n_draws else np.zeros(n_draws)
    m = 2 * design.n_targets + design.n_penalties
    field = max(1, min(LM_FIELD, MEMORY // max(1, rounds * m * max(proj.k, 1))))
    out = Field(z, sign, s, f)
    keep = distinct(z, f, proj.hi - proj.lo, field)
    out.take(keep if len(keep) else np.arange(min(field, len(z))))
    return out


def _stacked(fields: list[Field]):
    return tuple(np.concatenate([getattr(g, a) for g in fields]) for a in ("z", "sign", "s"))


def _field_round(proj: Space, fields: list[Field], reserve: int, width, exact: float) -> None:
    """FIELD_ITERATIONS of batched Levenberg-Marquardt on the rows of every field at once
    (fewer once a row fits exactly), then each field halved to its best distinct rows
    (POLISHED at least)."""
    z, f, _ = batch_lm(proj, *_stacked(fields), LM_WEIGHT, FIELD_ITERATIONS, reserve=reserve, enough=exact)
    at = 0
    for g in fields:
        rows = slice(at, at + len(g.z))
        at += len(g.z)
        g.z, g.f = z[rows], f[rows]
        keep = distinct(g.z, g.f, width, max(POLISHED, len(g.z) // 2))
        if len(keep):
            g.take(keep)
        g.done += 1


def atlas_starts(design: Design, budget: Budget):
    """The atlas's placed starts for a free-timing design (atlas_starts), dealt to the
    first ATLAS_ROUNDS rounds in turn (round r: the starts r, r + ATLAS_ROUNDS, ..., so
    that every round has near and far ones and a later round can find the first round's
    optimum from starts of its own): a function of the round's index returning its
    (x, sign, s) or None; None without an atlas or any start from it, or when the budget
    is below ATLAS_BUDGET (the lookup's placing hypotheses count as evaluations: a few
    thousand)."""
    if budget.left < ATLAS_BUDGET:
        return None
    from linkcli.types.path_generation.atlas_starts import starts_for
    found = starts_for(design, ATLAS_STARTS)
    if found is None:
        return None
    x, sign, s, _, evaluations = found
    budget.add(evaluations)
    x = design.wrapped(np.clip(x, design.lo, design.hi))

    def share(index: int):
        rows = np.arange(index, len(x), ATLAS_ROUNDS) if index < ATLAS_ROUNDS else np.zeros(0, dtype=int)
        return (x[rows], sign[rows], s[rows]) if len(rows) else None
    return share


def plain_multistart(design: Design, budget: Budget, rng) -> list[Candidate]:
    """The Levenberg-Marquardt polish from uniform random draws until the budget is spent."""
    space = Space(design, budget)
    out: list[Candidate] = []
    while budget.left > 0:
        batch = min(16, budget.left)
        x, sign, s = starts.plain_starts(design, rng, batch)
        budget.add(batch)
        for i in range(batch):
            if budget.left <= 0:
                break
            cap = min(budget.left, max(200, budget.cap // 20))
            if cap < 2 * space.k + 2:
                break
            z, _, conv = polish(space, space.free(x[i:i + 1])[0], sign[i], s[i], POLISH_WEIGHTS[0], cap)
            out.append(Candidate(space.full(z[None])[0], sign[i], s[i], conv))
        out = sorted(out, key=lambda c: _rank(design, c))[:POLISHED]
    return out or [Candidate(x[0], sign[0], s[0], False)]


def evolve(design: Design, budget: Budget, seed: int, polish_after: bool) -> list[Candidate]:
    space = Space(design, budget)
    share = budget.cap // 2 if polish_after else budget.cap
    z, sign, s, _, converged = differential_evolution(space, seed, POLISH_WEIGHTS[0], share)
    x = space.full(z[None])
    if not polish_after:
        return [Candidate(x[0], sign, s, converged)]
    return polish_all(design, budget, x, np.array([sign]), np.array([s]))


def polish_all(design: Design, budget: Budget, x, sign, s, converged=None) -> list[Candidate]:
    """The Levenberg-Marquardt polish on every free variable (`search.batch_lm`, at most
    POLISH_ITERATIONS steps) from every row of x at once, at the penalty weights
    POLISH_WEIGHTS in turn: the rows a weight leaves violating a constraint go on to the
    next, stiffer one. A row converges when a polish meets its tolerances or the batched
    stage before it had converged."""
    space = Space(design, budget)
    z = np.clip(space.free(x), space.lo, space.hi)
    conv = np.zeros(len(x), dtype=bool) if converged is None else np.array(converged, dtype=bool)
    todo = np.flatnonzero(np.all(np.isfinite(z), axis=1))
    for weight in POLISH_WEIGHTS:
        if (space.k == 0 or not len(todo) or not np.all(space.lo <= space.hi)
                or budget.left < len(todo) * (2 * space.k + 2)):
            break
        z[todo], _, ok = batch_lm(space, z[todo], sign[todo], s[todo], weight, POLISH_ITERATIONS)
        conv[todo] |= ok
        full = space.full(z[todo])
        todo = todo[[bool(violations(design, full[j], sign[i], s[i])) for j, i in enumerate(todo)]]
    full = space.full(z)
    return [Candidate(full[i], sign[i], s[i], bool(conv[i]) or space.k == 0) for i in range(len(x))]


def _settled_pick(design: Design, budget: Budget, pick: Candidate) -> Candidate:
    """A round's polished pick that did not converge, or lies within SETTLE_NEAR of the best,
    settled (`settled`) within PICK_SETTLE evaluations: the penalized polish stops short of
    a binding constraint's optimum (a flat valley along it), where rounds that reached one
    basin would not compare equal; Newton-KKT ends them at its one point. (The other
    converged picks are left: settling every pick doubled the time of a prescribed-timing
    round, measured on case 4.)"""
    with budget.limit(PICK_SETTLE):
        return settled(design, budget, pick)


def settled(design: Design, budget: Budget, best: Candidate) -> Candidate:
    """The best candidate after the final polish (`search.settle`: Newton on the KKT
    system of the constraints that bind, to machine precision), when that polish
    converges to a point that meets every constraint with an objective as low within a
    relative SETTLE_GAIN (else the candidate as found). An exact fit (a point of a
    continuum of them, when the unknowns outnumber the equations) is kept as found.
    It spends what the search left of the budget, at least the reserve `solve` kept."""
    space = Space(design, budget)
    f0 = _rank(design, best)[2]
    if space.k == 0 or f0 <= exact_objective(design):
        return best
    try:
        out = settle(space, space.free(best.x[None])[0], best.sign, best.s)
    except BudgetSpent:
        return best
    if not out.converged:
        return best
    cand = Candidate(design.wrapped(space.full(out.u[None]))[0], best.sign, best.s, True)
    rank = _rank(design, cand)
    if rank[0] or rank[2] > f0 * (1.0 + SETTLE_GAIN):
        return best
    return cand


# ---------------------------------------------------------------- checks

def _rank(design: Design, c: Candidate):
    """(infeasible, total violation, objective): lengths count relative to the linkage's size
    (d + a + b + c) and angles in radians, so that shrinking a linkage does not pass for
    coming closer to feasible."""
    v = violations(design, c.x, c.sign, c.s)
    obj = float(design.objective(c.x[None], np.array([c.sign]), np.array([c.s]))[0])
    size = float(np.sum(c.x[:4]))
    total = sum(a if name in ANGLE_VIOLATIONS else a / size for name, a, _ in v)
    return (len(v) > 0, total, obj if math.isfinite(obj) else math.inf)


def _ranked(design: Design, cands: list[Candidate]) -> list[Candidate]:
    """Candidates best first (`_rank`), those feasible within TIE (relative) of the best
    objective counted as one optimum and taken in the order they were found (round, then
    place): which of them is a hair lower follows the machine's round-off, and in a flat
    valley their designs differ in the printed digits (arc6_timed's ground angle, -3.85757
    or -3.85756 with numpy's vector paths narrowed, when later rounds reach it again)."""
    ranks = [_rank(design, c) for c in cands]
    order = sorted(range(len(cands)), key=lambda i: ranks[i])
    if not order or ranks[order[0]][0]:
        return [cands[i] for i in order]
    top = ranks[order[0]][2]
    tied = [i for i in order if not ranks[i][0] and ranks[i][2] <= top + TIE * abs(top)]
    one = set(tied)
    rest = [i for i in order if i not in one]
    tied.sort(key=lambda i: (cands[i].round, i))
    return [cands[i] for i in tied + rest]


def choose(design: Design, cands: list[Candidate]):
    best = _ranked(design, cands)[0]
    return best, violations(design, best.x, best.sign, best.s)
