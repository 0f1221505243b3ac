"""What every strategy of function generation shares: the counted, recorded evaluations
(`Search`) and the local stage (`polish`).

`Search` counts every candidate against `[solver] budget` and keeps, per branch, the best
candidate that meets every constraint (within FEASIBLE) and the least violating one; it
also keeps where each local search ended, for the found-twice rule (`Search.confirmed`).
`Local` presents one branch to linkcli.search.polish (Gauss-Newton SQP steps, then SLSQP
with the constraints explicit) in the local unit box, which is linear in every variable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.search import polish as local_polish
from linkcli.search.budget import Budget, BudgetSpent
from linkcli.types.function_generation.model import BRANCH_SIGN, Batch, Model

CONFIRM = 1e-6  # relative: a second polish ending this close to the best has found it again
REPEATS = 3  # local searches that ended in a minimum found before, at least (Search.confirmed)
EXACT_RMS = 1e-9  # rad: an rms error this small is an exact fit (round-off)
STEP = 1e-7  # central-difference step in the unit box
FEASIBLE = 1e-8  # largest violation (rad, or fraction of L) accepted as feasible


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
        self.ends: dict[str, list[tuple[float, bool, int]]] = {}  # per branch, each polish:
        # (its best feasible f, whether it converged, the batch of starts it came from)
        self.batch = 0  # the batch of starts the polishes come from (`new_batch`)
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
        return self.run_signed(v, np.full(len(v), BRANCH_SIGN[branch]), u)

    def run_signed(self, v: np.ndarray, signs: np.ndarray, u: np.ndarray | None = None) -> Batch:
        """Evaluate candidates (N, n), each on the branch of its sign (N,): N evaluations
        (`u`: their global unit box, when the caller has it)."""
        self.evaluations.spend(len(v))
        batch = self.model.evaluate(v, signs[:, None])
        for branch, sign in BRANCH_SIGN.items():
            rows = np.flatnonzero(signs == sign)
            if len(rows) == len(v):
                self._record(u, v, batch, branch)
            elif len(rows):
                self._record(None if u is None else u[rows], v[rows], batch.take(rows), branch)
        return batch

    def _record(self, u, v, batch: Batch, branch: str) -> None:
        """Keep the branch's best feasible and least violating candidates of the batch."""
        worst = batch.violation.max(axis=1)
        ok = worst <= FEASIBLE
        if ok.any():
            i = int(np.argmin(np.where(ok, batch.f, np.inf)))
            if not math.isnan(self._session):
                self._session = min(self._session, float(batch.f[i]))
            best = self.feasible.get(branch)
            if best is None or batch.f[i] < best.f:
                self.feasible[branch] = self._best(u, v, batch, worst, i, branch)
        i = int(np.argmin(batch.penalized))
        best = self.least.get(branch)
        if best is None or batch.penalized[i] < best.penalized:
            self.least[branch] = self._best(u, v, batch, worst, i, branch)

    def _best(self, u, v, batch: Batch, worst, i: int, branch: str) -> Best:
        unit = self.model.units(v[i:i + 1])[0] if u is None else u[i].copy()
        return Best(float(batch.f[i]), float(worst[i]), float(batch.penalized[i]), unit, branch, v[i].copy())

    def new_batch(self) -> None:
        """The polishes from here on start from a new, independent set of starts."""
        self.batch += 1

    def begin_polish(self) -> None:
        self._session = math.inf

    def end_polish(self, branch: str, converged: bool) -> None:
        """Record where the polish just run ended (its best feasible f), if anywhere feasible."""
        if math.isfinite(self._session):
            self.ends.setdefault(branch, []).append((self._session, bool(converged), self.batch))
        self._session = math.nan

    def _at_best(self, branch: str) -> list[tuple[float, bool, int]]:
        """The polishes that ended at the branch's best (within CONFIRM, relative)."""
        best = self.feasible.get(branch)
        if best is None:
            return []
        tol = CONFIRM * abs(best.f) + 1e-20
        return [end for end in self.ends.get(branch, []) if end[0] <= best.f + tol]

    def settled(self, branch: str) -> bool:
        """A polish that ended at the branch's best converged there."""
        return any(done for _, done, _ in self._at_best(branch))

    def confirmed(self, branch: str) -> bool:
        """Local searches from two independent sets of starts (`new_batch`) ended at the
        branch's best (within CONFIRM, relative, and round-off of an exact fit): the
        optimum found again; and the searches have begun to repeat themselves: n searches
        ended in w distinct minima with n - w >= REPEATS. (Boender & Rinnooy Kan, Bayesian
        stopping rules for multistart global optimization, Math. Programming 37, 1987: the
        expected number of minima w (n - 1) / (n - w - 2) exists only from n = w + 3; three
        searches that found 0.2023 twice and 6.08 once have seen too little to rule out a
        lower basin, as log_generator_grashof's 0.1072 on a small budget. Two polishes of
        one batch of starts are not independent enough: the best ends of one batched
        search can all lie in one basin, log_generator_grashof's 0.2023 on 1000
        evaluations.)"""
        best = self.feasible.get(branch)
        if best is None:
            return False
        if self.fits_exactly(branch):  # nothing lower to find
            return True
        if len({batch for _, _, batch in self._at_best(branch)}) < 2:
            return False
        ends = sorted(f for f, _, _ in self.ends.get(branch, []))
        distinct = sum(1 for i, f in enumerate(ends) if i == 0 or f - ends[i - 1] > CONFIRM * abs(f) + 1e-20)
        return len(ends) - distinct >= REPEATS

    def fits_exactly(self, branch: str) -> bool:
        """The branch's best feasible design fits exactly (rms error EXACT_RMS, round-off)."""
        best = self.feasible.get(branch)
        return best is not None and best.f <= len(self.model.t) * EXACT_RMS ** 2

    def answer(self) -> Best:
        """The best feasible candidate of any branch, else the least violating one."""
        if self.feasible:
            return min(self.feasible.values(), key=lambda b: (b.f, b.branch))
        return min(self.least.values(), key=lambda b: (b.penalized, b.branch))


# ---------------------------------------------------------------- the local stage

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


def polish(search: Search, w0: np.ndarray, branch: str, evaluations: int,
           gauss_newton_first: bool = True) -> bool:
    """The local solver of search.polish on one branch from w0 (the local, linear unit
    box), within `evaluations`; True if it converged. Where it ends counts towards
    confirming the best (Search.confirmed)."""
    local = Local(search, branch, evaluations)
    search.begin_polish()
    done = False
    try:
        done = local_polish.polish(local, w0, gauss_newton_first)
        return done
    except BudgetSpent:
        return False
    finally:
        search.end_polish(branch, done)
