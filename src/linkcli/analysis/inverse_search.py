"""The inverse mode of the tolerance study (`max_failure_probability`, docs/tolerance.md): the
largest tolerance t, the same on every dimension of `model.inverse`, whose failure
probability on the seeded Monte Carlo stays at or below a level.

The search. With common random numbers (the same unit draws scaled by t) the failure
probability p(t) is a step function of t. From p(0) (exact parts: the plays alone) the
bracket [lo, hi] with p(lo) <= level < p(hi) is found by doubling from `start`, then
bisected to a relative BISECTION_RTOL; the answer is lo and p(lo). 0 when even exact
parts fail more often than the level.

Cost: a few full passes. Each sample's error e_k(t) over the targets is a maximum of
nearly affine functions of t: nearly convex in t. So, inside the bracket, a sample that
passes at both ends passes throughout; one that fails at both ends fails throughout when
(e_k(lo) + e_k(hi) - L_k (hi - lo)) / 2 > allowed, L_k = SLOPE_SAFETY sum_i |u_ki| S_i
a bound on its slope (S_i the model's sensitivity per unit length of dimension i, u_ki the
sample's unit draws). The bisection then assembles only the undecided samples (kept in
memory from the pass that closed the bracket; as the bracket narrows they dwindle). The
answer is then verified by full passes at the final lo and hi (p(lo) <= level < p(hi) on
every sample); should the rule have misjudged a sample, the bisection goes on from the
verified ends with full passes, as it would without the rule. Draws of a full pass are
regenerated (seeded, chunked: bounded memory); the errors of each full pass are kept (n
numbers) for the report to reuse (the study at the given or found tolerance).
"""

from __future__ import annotations

import numpy as np

from linkcli.analysis.bisection import boundary
from linkcli.analysis.made_parts import Parts
from linkcli.analysis.tolerance import Chunk, chunk_errors, chunks

BISECTION_RTOL = 1e-4
SLOPE_SAFETY = 2.0  # the slope bound's margin over the nominal sensitivities


class Search:
    """One inverse search: the study's model, parts (clearance and plays as given), draws
    plan, seed and allowed error; `passes`: t -> (err, ok) of every full pass run."""

    def __init__(self, model, parts: Parts, plan, seed: int, allowed: float | None):
        self.model, self.parts, self.plan, self.seed = model, parts, plan, seed
        self.allowed = np.inf if allowed is None else allowed
        self.unit = np.array([1.0 if k in model.inverse else 0.0 for k in model.columns])
        sens = model.sensitivity()
        self.slopes = np.array([np.inf if sens.get(k, 0.0) is None else float(sens.get(k, 0.0)) * w
                                if w else 0.0 for k, w in zip(model.columns, self.unit)])
        self.passes: dict[float, tuple[np.ndarray, np.ndarray]] = {}
        self.full_passes = 0
        self.partial_samples = 0

    def errors_at(self, t: float, ch: Chunk) -> np.ndarray:
        """A chunk's errors at tolerance t (inf where a sample fails to be made or run)."""
        err, ok = chunk_errors(self.model, ch, self.parts.with_scale(self.unit * t))
        return np.where(ok, err, np.inf)

    def full(self, ts, keep=None):
        """Errors of every sample at each tolerance of `ts` (one pass over the draws: they
        are drawn once for all of them); `keep(start, fs, chunk)` -> mask of the chunk's rows
        whose draws to keep (with their indices) for partial passes. Returns ([f per t],
        kept)."""
        per_t = [self.parts.with_scale(self.unit * t) for t in ts]
        errs = [[] for _ in ts]
        oks = [[] for _ in ts]
        kept = []
        for start, ch in chunks(self.seed, self.plan):
            fs = []
            for j, parts in enumerate(per_t):
                err, ok = chunk_errors(self.model, ch, parts)
                errs[j].append(err)
                oks[j].append(ok)
                fs.append(np.where(ok, err, np.inf))
            if keep is not None:
                mask = keep(start, fs, ch)
                if mask.any():
                    kept.append((start + np.flatnonzero(mask), ch.rows(mask)))
        out = []
        for j, t in enumerate(ts):
            err, ok = np.concatenate(errs[j]), np.concatenate(oks[j])
            self.passes[t] = (err, ok)
            out.append(np.where(ok, err, np.inf))
        self.full_passes += 1
        return out, kept

    def fails(self, f: np.ndarray) -> np.ndarray:
        return f > self.allowed

    def undecided(self, f_lo, f_hi, u, width: float) -> np.ndarray:
        """Samples whose verdict may change inside a bracket of `width` (module docstring)."""
        fail_lo, fail_hi = self.fails(f_lo), self.fails(f_hi)
        both_pass = ~fail_lo & ~fail_hi
        with np.errstate(invalid="ignore"):
            slope = SLOPE_SAFETY * (np.abs(u) @ self.slopes)
            low = 0.5 * (f_lo + f_hi - slope * width)
        both_fail = fail_lo & fail_hi & (low > self.allowed)
        return ~(both_pass | both_fail)


def largest_tolerance(search: Search, level: float, start: float, cap: float) -> tuple[float, float]:
    """Largest t in [0, cap] with p(t) <= level: (t, p(t)) (module docstring)."""
    n = search.plan.n
    hi = min(max(start, 1e-3 * cap), cap)
    (f0, f_hi), kept = search.full([0.0, hi], keep=lambda s, fs, ch: search.undecided(fs[0], fs[1], ch.u, hi))
    if int(np.count_nonzero(search.fails(f0))) / n > level:
        return 0.0, int(np.count_nonzero(search.fails(f0))) / n
    lo, f_lo = 0.0, f0
    while int(np.count_nonzero(search.fails(f_hi))) / n <= level and hi < cap:
        lo, f_lo = hi, f_hi
        hi = min(2.0 * hi, cap)
        (f_hi,), kept = search.full([hi], keep=lambda s, fs, ch, f=f_lo, w=hi - lo:
                                    search.undecided(f[s:s + len(fs[0])], fs[0], ch.u, w))
    k_hi = int(np.count_nonzero(search.fails(f_hi)))
    if k_hi / n <= level:
        return hi, k_hi / n
    lo, hi = _bisect_partial(search, lo, hi, f_lo, f_hi, kept, level)
    return _verified(search, lo, hi, level)


def _bisect_partial(search: Search, lo, hi, f_lo, f_hi, kept, level: float):
    """Bisect [lo, hi] assembling only the undecided samples (module docstring): the final
    bracket, each end judged on every sample under the rule."""
    if not kept:
        index = np.zeros(0, dtype=int)
        rows = None
    else:
        index = np.concatenate([i for i, _ in kept])
        rows = Chunk(*(None if parts[0] is None else np.concatenate(parts)
                       for parts in zip(*(ch for _, ch in kept))))
    fail_lo, fail_hi = search.fails(f_lo), search.fails(f_hi)
    active = np.zeros(len(f_lo), dtype=bool)
    active[index] = True
    decided_fail = int(np.count_nonzero(fail_lo & fail_hi & ~active))  # both ends fail: throughout
    a_lo, a_hi = f_lo[index], f_hi[index]
    while hi - lo > BISECTION_RTOL * hi:
        mid = 0.5 * (lo + hi)
        f_mid = search.errors_at(mid, rows) if len(index) else np.zeros(0)
        search.partial_samples += len(index)
        count = decided_fail + int(np.count_nonzero(search.fails(f_mid)))
        if count / len(f_lo) <= level:
            lo, a_lo = mid, f_mid
        else:
            hi, a_hi = mid, f_mid
        if len(index):
            still = search.undecided(a_lo, a_hi, rows.u, hi - lo)
            decided_fail += int(np.count_nonzero(~still & search.fails(a_lo)))
            index, a_lo, a_hi, rows = index[still], a_lo[still], a_hi[still], rows.rows(still)
    return lo, hi


def _verified(search: Search, lo: float, hi: float, level: float) -> tuple[float, float]:
    """(lo, p(lo)) once full passes confirm p(lo) <= level < p(hi); else the bisection goes
    on between the nearest verified ends with full passes."""
    n = search.plan.n

    def p(t: float) -> float:
        if t not in search.passes:
            search.full([t])
        err, ok = search.passes[t]
        return int(np.count_nonzero(~ok | (err > search.allowed))) / n

    missing = [t for t in (lo, hi) if t not in search.passes]
    if missing:
        search.full(missing)  # both ends on one set of draws
    p_lo, p_hi = p(lo), p(hi)
    if p_lo <= level < p_hi:
        return lo, p_lo
    known = sorted(search.passes)  # fall back: exact bisection between verified ends
    good = [t for t in known if p(t) <= level]
    a = max(good) if good else 0.0
    b = min([t for t in known if t > a and p(t) > level], default=hi)
    return boundary(lambda x: (p(x) <= level, p(x)), a, b, p(a), lambda a, b: b - a <= BISECTION_RTOL * b)
