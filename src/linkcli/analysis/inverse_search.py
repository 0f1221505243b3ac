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
regenerated (seeded, chunked: bounded memory).

Memory is bounded whatever the samples and targets: the undecided samples' draws are kept
only while they hold at most KEEP_UNDECIDED numbers (256 MB: the 6 % of 1,000,000 samples
that a tolerance 1.4 times the answer leaves undecided, at 36 targets and four pins), in the
pieces of the chunks they were drawn in; when more samples than that are undecided (a
bracket still wide: a given tolerance far from the answer), the bracket is halved by full
passes (chunked) until they fit. Of the full passes, the failure counts are kept, and the
errors (n numbers) of the pass at the given tolerance and of the latest pass only, for the
report to reuse (the study at the given or found tolerance). So the search holds a few
arrays of n numbers, at most KEEP_UNDECIDED kept draws and one chunk being assembled: at the
1,000,000 samples a file may ask, under 450 MB whatever the targets, where keeping every
undecided sample's draws took 0.8 to 12 GB (samples x targets x pins).
"""

from __future__ import annotations

import numpy as np

from linkcli.analysis.bisection import boundary
from linkcli.analysis.made_parts import Parts
from linkcli.analysis.tolerance import Chunk, chunk_errors, chunks

BISECTION_RTOL = 1e-4
SLOPE_SAFETY = 2.0  # the slope bound's margin over the nominal sensitivities
KEEP_UNDECIDED = 2**25  # unit draws of undecided samples kept for partial passes (256 MB)


class Search:
    """One inverse search: the study's model, parts (clearance and plays as given), draws
    plan, seed and allowed error; `passes`: t -> (err, ok) of the full passes whose errors
    are kept (module docstring), `counts`: t -> failures of every full pass."""

    def __init__(self, model, parts: Parts, plan, seed: int, allowed: float | None,
                 keep_elements: int = KEEP_UNDECIDED):
        self.model, self.parts, self.plan, self.seed = model, parts, plan, seed
        self.allowed = np.inf if allowed is None else allowed
        self.unit = np.array([1.0 if k in model.inverse else 0.0 for k in model.columns])
        sens = model.sensitivity()
        self.slopes = np.array([np.inf if sens.get(k, 0.0) is None else float(sens.get(k, 0.0)) * w
                                if w else 0.0 for k, w in zip(model.columns, self.unit)])
        self.passes: dict[float, tuple[np.ndarray, np.ndarray]] = {}
        self.counts: dict[float, int] = {}
        self.kept_t: float | None = None  # the given tolerance: its errors stay for the report
        self.full_passes = 0
        self.partial_samples = 0
        self.keep_elements = keep_elements
        self.per_sample = (plan.columns + plan.m * (2 * plan.pins + plan.plays)
                           + 2 * (plan.fit_pins + plan.fit_plays))  # unit draws of one sample

    def errors_at(self, t: float, ch: Chunk) -> np.ndarray:
        """A chunk's errors at tolerance t (inf where a sample fails to be made or run)."""
        err, ok = chunk_errors(self.model, ch, self.parts.with_scale(self.unit * t))
        return np.where(ok, err, np.inf)

    def full(self, ts, keep=None):
        """Errors of every sample at each tolerance of `ts` (one pass over the draws: they
        are drawn once for all of them); `keep(start, fs, chunk)` -> mask of the chunk's rows
        whose draws to keep (with their indices) for partial passes. Returns ([f per t],
        kept): kept a list of pieces (indices, Chunk rows), or None when more than
        `keep_elements` unit draws would be kept (module docstring)."""
        per_t = [self.parts.with_scale(self.unit * t) for t in ts]
        errs = [[] for _ in ts]
        oks = [[] for _ in ts]
        kept: list | None = []
        held = 0
        for start, ch in chunks(self.seed, self.plan):
            fs = []
            for j, parts in enumerate(per_t):
                err, ok = chunk_errors(self.model, ch, parts)
                errs[j].append(err)
                oks[j].append(ok)
                fs.append(np.where(ok, err, np.inf))
            if keep is not None and kept is not None:
                mask = keep(start, fs, ch)
                count = int(np.count_nonzero(mask))
                held += count * self.per_sample
                if held > self.keep_elements:
                    kept = None  # too many undecided samples to hold: the caller halves the bracket
                elif count:
                    kept.append((start + np.flatnonzero(mask), ch.rows(mask)))
        out = []
        latest = {}
        for j, t in enumerate(ts):
            err, ok = np.concatenate(errs[j]), np.concatenate(oks[j])
            errs[j] = oks[j] = None
            self.counts[t] = int(np.count_nonzero(~ok | (err > self.allowed)))
            latest[t] = (err, ok)
            out.append(np.where(ok, err, np.inf))
        # errors kept: the given tolerance's and the latest pass's (module docstring)
        self.passes = {t: v for t, v in self.passes.items() if t == self.kept_t}
        self.passes.update(latest)
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
    search.kept_t = hi
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
    lo, hi, f_lo, f_hi, kept = _narrow(search, lo, hi, f_lo, f_hi, kept, level)
    lo, hi = _bisect_partial(search, lo, hi, f_lo, f_hi, kept, level)
    return _verified(search, lo, hi, level)


def _narrow(search: Search, lo, hi, f_lo, f_hi, kept, level: float):
    """While the undecided samples of [lo, hi] are too many to keep (kept None), halve the
    bracket with full passes, keeping the samples undecided on either half: the same
    bisection steps as the partial passes take (the same answer), in bounded memory."""
    n = search.plan.n
    while kept is None and hi - lo > BISECTION_RTOL * hi:
        mid = 0.5 * (lo + hi)

        def keep(s, fs, ch, a=f_lo, b=f_hi, lo=lo, mid=mid, hi=hi):
            rows = slice(s, s + len(fs[0]))
            return (search.undecided(a[rows], fs[0], ch.u, mid - lo)
                    | search.undecided(fs[0], b[rows], ch.u, hi - mid))

        (f_mid,), kept = search.full([mid], keep=keep)
        if int(np.count_nonzero(search.fails(f_mid))) / n <= level:
            lo, f_lo = mid, f_mid
        else:
            hi, f_hi = mid, f_mid
    return lo, hi, f_lo, f_hi, kept or []


def _bisect_partial(search: Search, lo, hi, f_lo, f_hi, kept, level: float):
    """Bisect [lo, hi] assembling only the undecided samples (module docstring), piece by
    piece as they were kept: the final bracket, each end judged on every sample under the
    rule."""
    pieces = [(index, rows, f_lo[index], f_hi[index]) for index, rows in kept]
    fail_lo, fail_hi = search.fails(f_lo), search.fails(f_hi)
    active = np.zeros(len(f_lo), dtype=bool)
    for index, _, _, _ in pieces:
        active[index] = True
    decided_fail = int(np.count_nonzero(fail_lo & fail_hi & ~active))  # both ends fail: throughout
    while hi - lo > BISECTION_RTOL * hi:
        mid = 0.5 * (lo + hi)
        f_mid = [search.errors_at(mid, rows) for _, rows, _, _ in pieces]
        search.partial_samples += sum(len(index) for index, _, _, _ in pieces)
        count = decided_fail + sum(int(np.count_nonzero(search.fails(f))) for f in f_mid)
        good = count / len(f_lo) <= level
        if good:
            lo = mid
        else:
            hi = mid
        still_pieces = []
        for (index, rows, a_lo, a_hi), f in zip(pieces, f_mid):
            a_lo, a_hi = (f, a_hi) if good else (a_lo, f)
            still = search.undecided(a_lo, a_hi, rows.u, hi - lo)
            decided_fail += int(np.count_nonzero(~still & search.fails(a_lo)))
            if still.any():
                still_pieces.append((index[still], rows.rows(still), a_lo[still], a_hi[still]))
        pieces = still_pieces
    return lo, hi


def _verified(search: Search, lo: float, hi: float, level: float) -> tuple[float, float]:
    """(lo, p(lo)) once full passes confirm p(lo) <= level < p(hi); else the bisection goes
    on between the nearest verified ends with full passes."""
    n = search.plan.n

    def p(t: float) -> float:
        if t not in search.counts:
            search.full([t])
        return search.counts[t] / n

    missing = [t for t in (lo, hi) if t not in search.counts]
    if missing:
        search.full(missing)  # both ends on one set of draws
    p_lo, p_hi = p(lo), p(hi)
    if p_lo <= level < p_hi:
        return lo, p_lo
    known = sorted(search.counts)  # fall back: exact bisection between verified ends
    good = [t for t in known if p(t) <= level]
    a = max(good) if good else 0.0
    b = min([t for t in known if t > a and p(t) > level], default=hi)
    return boundary(lambda x: (p(x) <= level, p(x)), a, b, p(a), lambda a, b: b - a <= BISECTION_RTOL * b)
