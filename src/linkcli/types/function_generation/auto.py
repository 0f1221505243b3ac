"""`method = "auto"` of function generation: a batched multistart.

Each round:
1. starts: the Freudenstein designs (first round; linkcli.types.function_generation.starts)
   and a seeded Latin hypercube sample of SAMPLE_PER_VARIABLE points per variable, each on
   every branch asked for, scored in one batch (counted) by the exact L1 penalty
   f + W * sum(violations). The first round holds two independent batches of starts (the
   designs of alternate cells of their grid, and a sample, each), a later round one batch;
2. the field: of each batch, the best starts not yet taken, FIELD_DISTINCT apart in some
   variable of the unit box from each other and from every start taken before (or on the
   other branch), FIELD in all: a later round explores elsewhere, from the designs a
   first field left out and its fresh sample;
3. Levenberg-Marquardt on the whole field at once (linkcli.search.levenberg_marquardt,
   with geodesic acceleration: the valleys trade a start angle against the lengths and
   curve), on the angle errors and quadratic penalties of the constraints (`field`), for
   FIELD_ITERATIONS steps, the penalty weight raised in turn through FIELD_WEIGHTS: the
   soft weight lets a row cross a constraint into its basin, the stiff ones bring it
   back to the edge, so that the ends rank nearly as their feasible objectives will
   (with 1e2 alone, rows that break a constraint ranked first and their polishes found
   nothing feasible; with 1e4 from the start, fewer rows reached narrow basins);
4. of each batch, its best distinct ends (POLISHED in all), one by one, polished with the
   constraints exact (search.polish: Gauss-Newton SQP, then SLSQP);
until the best is found twice (`Search.confirmed`): by polishes from two independent
batches, among polishes that repeat themselves, and CLAIM_ROUNDS rounds have run (an exact
fit ends the rounds at once); or the budget ends. Two polishes of one
batch do not count as two arrivals: the best ends of one batched search can all lie in
one basin (log_generator_grashof's 0.2023 on 1000 evaluations said `ok` so).

A round costs a few dozen batched steps where the earlier strategy (SLSQP multistart,
then rounds of differential evolution and polishes, each local search one candidate at a
time) spent most of its time in Python (docs/function_generation.md has the times). Every
step but the polishes' is plain numpy without BLAS (linkcli.search.linalg); the verdict
rests on several arrivals, not on one search's path.
"""

from __future__ import annotations

import numpy as np

from linkcli.search import sampling
from linkcli.search.budget import BudgetSpent
from linkcli.search.levenberg_marquardt import batch_lm
from linkcli.search.sampling import latin_hypercube
from linkcli.types.function_generation.field import Field, signs_of
from linkcli.types.function_generation.search import Search, polish
from linkcli.types.function_generation.starts import SEED_PAIRS, check_law, freudenstein_designs

SAMPLE_PER_VARIABLE = 20  # Latin hypercube starts per variable, each round
SCAN_SHARE = 8  # the starts take at most 1/8 of the budget (half designs, half sample)
FIELD = 64  # starts in the batched Levenberg-Marquardt, at most
FIELD_DISTINCT = 0.05  # field rows differ by this much in some variable (unit box)
FIELD_ITERATIONS = 40  # its steps (measured on the bench: 25 left fewer rows in the best basin)
FIELD_WEIGHTS = (1e2, 1e4, 1e6)  # its penalty weights in turn (rad^2 per squared unit of violation)
FIELD_SHARES = (0.4, 0.3, 0.3)  # of its steps, for each weight
POLISHED = 6  # field ends polished with exact constraints, each round (shared by its batches)
SAME_END = 1e-4  # field ends this close (unit box, every variable) are one end
POLISH_STEPS = 100  # a polish's evaluations, at most this many Gauss-Newton steps' worth
POLISH_RESERVE = 3  # the field leaves the polishes at least 1/3 of their most (they take
# 30 to 100 evaluations from a field's end on the bench)
MAX_ROUNDS = 8
CLAIM_ROUNDS = 2  # rounds run at least before a best found twice ends the search: the first
# round's two batches can both end in one basin (constrained-variant tuning case 90, seed 4, said
# `ok` 31 % above the best known; with a second round it reaches the best known). The cost: about
# twice the time (the study's function median 0.29 -> 0.54 s, every verdict else the same)
MIN_ROUND = 10  # a round needs the evaluations of this many Gauss-Newton steps
BRANCH_OF_SIGN = {-1.0: "open", 1.0: "crossed"}


def auto(search: Search, branches: tuple[str, ...], seed: int) -> None:
    """Rounds (module docstring) until the best is found twice or the budget is spent;
    the polishes' ends are in `search`. The first round holds two independent batches of
    starts side by side (half the Freudenstein designs, on alternate cells of their grid,
    and a sample each), so that one round can find the best twice; a later round is one
    batch."""
    model = search.model
    n = model.n_variables
    signs = signs_of(branches)
    starts = Starts(n)
    designs = freudenstein_designs(model, min(SEED_PAIRS, search.left // (2 * SCAN_SHARE * len(signs))))
    for round_ in range(MAX_ROUNDS):
        if search.left < MIN_ROUND * (n + 2):
            break
        halves = (designs[0::2], designs[1::2]) if round_ == 0 else (designs[:0],)
        scan = max(1, search.left // (2 * SCAN_SHARE * len(signs) * len(halves)))  # points per sample
        batches = []
        try:
            for k, half in enumerate(halves):
                sample = latin_hypercube(np.random.default_rng([seed, round_, k]),
                                         min(SAMPLE_PER_VARIABLE * n, scan), n)
                if round_ == 0:  # the law judged on the first round's samples alone: how
                    check_law(model, sample)  # many rounds run follows the search's path
                search.new_batch()
                starts.add(search, np.vstack([half, sample]), signs, search.batch, len(halves))
                batches.append(search.batch)
            one_round(search, starts, batches)
        except BudgetSpent:
            break
        branch = search.answer().branch
        if search.confirmed(branch) and (round_ + 1 >= CLAIM_ROUNDS or search.fits_exactly(branch)):
            break


class Starts:
    """Every start scored so far (global unit box, each on a branch, from its batch) and
    which of them went into a field: a later field takes the best of the others that lie
    apart from every start taken before (the Freudenstein designs a first field left out,
    and the round's fresh sample)."""

    def __init__(self, n: int) -> None:
        self.rows = np.zeros((0, n))
        self.signs = np.zeros(0)
        self.scores = np.zeros(0)
        self.batch = np.zeros(0, dtype=int)
        self.taken = np.zeros(0, dtype=int)

    def add(self, search: Search, starts: np.ndarray, signs: np.ndarray, batch: int, parts: int) -> None:
        """Score `starts` on every branch of `signs`, at most 1/(SCAN_SHARE parts) of what
        is left (the first rows first), and keep them as `batch`."""
        rows = np.repeat(starts, len(signs), axis=0)  # each start on every branch, side by side
        row_signs = np.tile(signs, len(starts))
        room = min(len(rows), max(2, search.left // (SCAN_SHARE * parts)))
        rows, row_signs = rows[:room], row_signs[:room]
        scores = search.run_signed(search.model.values(rows), row_signs, rows).penalized
        self.rows = np.vstack([self.rows, rows])
        self.signs = np.concatenate([self.signs, row_signs])
        self.scores = np.concatenate([self.scores, scores])
        self.batch = np.concatenate([self.batch, np.full(len(rows), batch)])

    def take(self, most: int, batch: int) -> np.ndarray:
        """Indices of the best `most` starts of `batch` not taken, each FIELD_DISTINCT
        apart from the others and from every start taken before (the other branch: always
        apart)."""
        apart = np.column_stack([self.rows, self.signs / FIELD_DISTINCT])
        free = np.setdiff1d(np.flatnonzero(self.batch == batch), self.taken)
        order = np.concatenate([self.taken, free[np.argsort(self.scores[free], kind="stable")]])
        picked = sampling.distinct(apart, order, FIELD_DISTINCT, len(self.taken) + most)
        new = np.array(picked[len(self.taken):], dtype=int)
        self.taken = np.concatenate([self.taken, new])
        return new


def polish_evaluations(n: int) -> int:
    """The most one polish of n variables may spend: POLISH_STEPS forward-difference
    Gauss-Newton steps."""
    return POLISH_STEPS * (n + 2)


def one_round(search: Search, starts: Starts, batches: list[int]) -> None:
    """Steps 2 to 4 of the module docstring from the best starts not yet taken of each
    batch (a share of the field and of the polishes each), within what is left of the
    budget: the polishes keep up to half of it; the field has POLISHED rows at least, and a
    small budget shortens its steps, each weight keeping its share. Each polish counts
    for the batch its start came from."""
    model = search.model
    n = model.n_variables
    reserve = min(POLISHED * polish_evaluations(n) // POLISH_RESERVE, search.left // 2)
    room = search.left - reserve
    size = min(FIELD, max(POLISHED, room // (FIELD_ITERATIONS * row_cost(n)))) // len(batches)
    picked = np.concatenate([starts.take(size, batch) for batch in batches])
    if len(picked) == 0:
        return
    steps = max(len(FIELD_WEIGHTS), min(FIELD_ITERATIONS, room // (len(picked) * row_cost(n))))
    z = model.linear_units(model.values(starts.rows[picked]))
    cost = np.zeros(len(picked))
    for weight, share in zip(FIELD_WEIGHTS, FIELD_SHARES):
        field = Field(search, starts.signs[picked], weight)
        moved, costs, _ = batch_lm(field, z, max(1, round(share * steps)), reserve=reserve, acceleration=True)
        if np.all(np.isinf(costs)):  # no budget left for this weight: the last one's ends stand
            break
        z, cost = moved, costs
    origin = starts.batch[picked]
    ends = [i for batch in batches for i in distinct_ends(z, cost, np.flatnonzero(origin == batch),
                                                            POLISHED // len(batches))]
    for k, i in enumerate(ends):
        if search.left <= 2 * n + 1:
            break
        search.batch = int(origin[i])
        share = min(search.left // (len(ends) - k), polish_evaluations(n))
        polish(search, z[i], BRANCH_OF_SIGN[float(starts.signs[picked][i])], share)


def distinct_ends(z: np.ndarray, cost: np.ndarray, rows: np.ndarray, most: int) -> list[int]:
    """The `most` lowest-cost field ends among `rows`, leaving out an end that lies within
    SAME_END (unit box, every variable) of one kept before it: rows that ended at one
    point would polish to one minimum, a polish another basin may use."""
    rows = rows[np.argsort(cost[rows], kind="stable")]
    return [int(rows[k]) for k in sampling.distinct(z[rows], range(len(rows)), SAME_END, most)]


def row_cost(n: int) -> int:
    """Evaluations of one field row's step, as measured: the trial and the acceleration's
    probe, and the n-column Jacobian after about half the steps (the kept ones)."""
    return 2 + (n + 1) // 2
