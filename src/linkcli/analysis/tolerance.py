"""Tolerance analysis: Monte Carlo over manufactured linkages (docs/tolerance.md, [tolerance]).

Generic over mechanisms: the mechanism's home gives the made-part `Model` (its toleranced
dimensions, its pins with clearance, its other plays, and the error of a made part at the
targets, vectorized over samples); this module draws the samples, counts failures and writes
the report section.

Draws. Samples come in chunks of about CHUNK_ELEMENTS sample-targets; chunk k uses numpy
`default_rng([seed, k])` (the `[solver] seed`), so the same file gives the same bytes on
every run, whatever the memory. In each chunk, in this order: the unit deviations of every
toleranced dimension (uniform on [-1, 1], or normal with sigma 1/3: the tolerance is then
3 sigma, not truncated); with clearance, the unit-disc offsets of every pin at every target
(radius sqrt(U), angle 2 pi U': uniform over the disc's area; the effective-link model of
Lee & Gilmore 1991 and Ting, Zhu & Watkins 2000: the load, and with it the contact point,
changes between positions); with a play (a slider's guide), a uniform [-1, 1] draw per play
and target.

Report: error mean, 95th percentile and max over the samples that assemble (round-off of an
exact design is 0 under the noise floor of the model's scale); the failure probability
p = k / N with its standard error sqrt(p (1 - p) / N) and the Wilson 95 % interval; the
model's sensitivity per dimension.

Inverse mode (`max_failure_probability`): the largest tolerance t, the same on every link,
whose failure probability stays at or below the level, by bisection on the seeded Monte
Carlo with common random numbers (the same unit draws scaled by t at every step).
numpy only.
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np

from linkcli.model import InverseTolerance, Tolerance
from linkcli.noise import first_max, snap

CHUNK_ELEMENTS = 2**17  # samples x targets assembled at once
BISECTION_RTOL = 1e-4
Z95 = 1.959963984540054  # two-sided 95 % normal quantile
TWO_PI = 2.0 * math.pi


class Model(Protocol):
    """A mechanism's made parts (its home's tolerance module).

    columns: the toleranced dimensions, in draw order; inverse: those the inverse mode's
    common tolerance applies to; pins: joints with radial clearance; plays: per-target
    plays drawn after the pins (a slider in its guide); kind: "angle" (errors in rad) or
    "length"; measure: what the error is, for the report; inputs: (M,) the targets' drive
    angles (none: the nominal linkage never assembles, `no_assembly` says so); scale: the
    errors' noise-floor scale; cap: the largest common tolerance (a larger one can make a
    length <= 0); known: link -> length for the tolerance checks (tolerance_input)."""

    columns: tuple[str, ...]
    inverse: tuple[str, ...]
    pins: int
    plays: int
    kind: str
    measure: str
    inputs: np.ndarray
    scale: float
    cap: float
    known: dict
    no_assembly: str
    no_allowed_error: str

    def given(self, tol: Tolerance) -> dict:
        """Keys of the [tolerance] table echoed after `clearance` (a guide's play ...)."""

    def play_size(self, tol: Tolerance) -> float:
        """The size of the plays (0: none drawn)."""

    def errors(self, dl: np.ndarray, pins: np.ndarray | None, plays: np.ndarray | None):
        """(err (n,), ok (n,)): a made part's largest deviation over the targets (inf where it
        fails to be made, assemble or travel), and whether it assembles and travels. dl (n,
        columns) deviations; pins (n, M, pins, 2) clearance offsets or None; plays (n, M,
        plays) or None."""

    def sensitivity(self) -> dict:
        """Per toleranced dimension, the first-order error change per unit (None: infinite)."""

    def column_scale(self, lengths: dict) -> np.ndarray:
        """(columns,) the tolerance of each column from [tolerance] lengths (link -> +- t, or
        column -> +- t: a home whose links hold several dimensions maps them)."""

    # A model with `per_row` True (the five-bar: its error at every row of a motion) also has
    # `rows` (M,) the row numbers of its targets, `row_errors(dl, pins, plays)` -> (dev (n, M),
    # ok (n, M), events {i: (n,) error added at event i}) with `errors` its reduction (the
    # largest dev, inf where a row fails), and `event_labels()` (one dict per event).
    per_row: bool


# ---------------------------------------------------------------- random draws

def unit_draws(seed: int, n: int, m: int, columns: int, distribution: str, pins: int = 0,
               plays: int = 0):
    """Yield per chunk (u, e, g): u (rows, columns) unit deviations (uniform on [-1, 1], or
    normal with sigma 1/3), e (rows, m, pins, 2) offsets uniform over the unit disc or None,
    g (rows, m, plays) uniform on [-1, 1] or None (module docstring: the order of draws)."""
    rows = max(1, CHUNK_ELEMENTS // max(m, 1))
    for k, start in enumerate(range(0, n, rows)):
        size = min(rows, n - start)
        rng = np.random.default_rng([seed, k])
        if distribution == "normal":
            u = rng.standard_normal((size, columns)) / 3.0
        else:
            u = rng.uniform(-1.0, 1.0, (size, columns))
        e = g = None
        if pins:
            r = np.sqrt(rng.random((size, m, pins)))
            t = rng.random((size, m, pins)) * TWO_PI
            e = np.stack([r * np.cos(t), r * np.sin(t)], axis=-1)
        if plays:
            g = rng.uniform(-1.0, 1.0, (size, m, plays))
        yield u, e, g


def monte_carlo(model: Model, scale: np.ndarray, clearance: float, play: float, n: int,
                seed: int, distribution: str):
    """(err (n,), ok (n,)) over n seeded samples, in chunks: scale (columns,) the tolerances,
    `clearance` the pins' radial clearance, `play` the plays' size."""
    errs, oks = [], []
    pins = model.pins if clearance > 0 else 0
    plays = model.plays if play > 0 else 0
    for u, e, g in unit_draws(seed, n, len(model.inputs), len(model.columns), distribution, pins, plays):
        err, ok = model.errors(u * scale[None, :], None if e is None else e * clearance,
                               None if g is None else g * play)
        errs.append(err)
        oks.append(ok)
    return np.concatenate(errs), np.concatenate(oks)


class RowDraws:
    """What monte_carlo_rows keeps: the samples' largest error and whether they hold (n,),
    each row's error and assembly (n, M), and each event's added error (n,) per event."""

    def __init__(self, err, ok, dev, row_ok, events) -> None:
        self.err, self.ok, self.dev, self.row_ok, self.events = err, ok, dev, row_ok, events


def monte_carlo_rows(model: Model, scale: np.ndarray, clearance: float, play: float, n: int,
                     seed: int, distribution: str) -> RowDraws:
    """monte_carlo (the same draws, chunk by chunk) keeping every row's error and every
    event's (a per-row model's `row_errors`): samples x rows floats, which the model's
    schema bounds."""
    parts: list = []
    pins = model.pins if clearance > 0 else 0
    plays = model.plays if play > 0 else 0
    for u, e, g in unit_draws(seed, n, len(model.inputs), len(model.columns), distribution, pins, plays):
        dev, ok, events = model.row_errors(u * scale[None, :], None if e is None else e * clearance,
                                           None if g is None else g * play)
        parts.append((dev, ok, events))
    dev = np.concatenate([p[0] for p in parts])
    row_ok = np.concatenate([p[1] for p in parts])
    events = {i: np.concatenate([p[2][i] for p in parts]) for i in parts[0][2]}
    ok = np.all(row_ok, axis=1)
    err = np.where(ok, np.max(dev, axis=1, initial=0.0), np.inf)
    return RowDraws(err, ok, dev, row_ok, events)


def column_percentile(values: np.ndarray, keep: np.ndarray, q: float) -> np.ndarray:
    """The q-th percentile of each column over its kept entries (numpy's default "linear"
    method, as np.percentile of each column's kept values), NaN for a column with none;
    vectorized: one sort of the columns."""
    v = np.sort(np.where(keep, values, np.inf), axis=0)
    count = np.sum(keep, axis=0)
    pos = q / 100.0 * np.maximum(count - 1, 0)
    lo = np.floor(pos).astype(int)
    hi = np.minimum(lo + 1, np.maximum(count - 1, 0))
    below = np.take_along_axis(v, lo[None, :], axis=0)[0]
    above = np.take_along_axis(v, hi[None, :], axis=0)[0]
    with np.errstate(invalid="ignore"):
        out = below + (above - below) * (pos - lo)
    return np.where(count > 0, np.where(hi == lo, below, out), np.nan)


def row_section(model: Model, draws: RowDraws, allowed: float | None, n: int, conv) -> dict:
    """Per row: error mean, p95, max over the samples that assemble there, the failure
    probability (error above `allowed`, or no assembly) with its Wilson 95 % interval; the
    worst row (the highest failure probability, then the highest p95, then the first);
    each event's added error (mean, p95, max over the samples that assemble there)."""
    keep = draws.row_ok
    dev = snap(np.where(keep, draws.dev, 0.0), model.scale)
    count = np.sum(keep, axis=0)
    with np.errstate(invalid="ignore"):
        mean = np.where(count > 0, np.sum(dev, axis=0) / np.maximum(count, 1), np.nan)
    p95 = column_percentile(dev, keep, 95.0)
    top = np.where(count > 0, np.max(np.where(keep, dev, -np.inf), axis=0), np.nan)
    bad = ~keep if allowed is None else (~keep | (draws.dev > allowed))
    fails = np.sum(bad, axis=0)
    opt = (lambda x: None if not math.isfinite(x) else conv(x))
    rows = []
    for i, r in enumerate(np.asarray(model.rows).tolist()):
        k = int(fails[i])
        rows.append({"row": int(r), "error_mean": opt(float(mean[i])), "error_p95": opt(float(p95[i])),
                     "error_max": opt(float(top[i])), "failure_probability": k / n,
                     "failure_probability_ci95": list(wilson(k, n))})
    out: dict = {"rows": rows}
    if rows:
        most = fails == fails.max()
        j = int(first_max(np.where(most, np.nan_to_num(p95, nan=-1.0), -np.inf)))
        out["worst_row"] = dict(rows[j])
    events = []
    for i, label in enumerate(model.event_labels()):
        added = draws.events.get(i)
        if added is None:  # no play drawn: the change adds nothing
            events.append({**label, "added_mean": 0.0, "added_p95": 0.0, "added_max": 0.0})
            continue
        good = snap(added[np.isfinite(added)], model.scale)
        events.append({**label, "added_mean": opt(float(good.mean())) if good.size else None,
                       "added_p95": opt(float(np.percentile(good, 95))) if good.size else None,
                       "added_max": opt(float(good.max())) if good.size else None})
    if events:
        out["phase_changes"] = events
    return out


def failures(err: np.ndarray, ok: np.ndarray, allowed: float | None) -> int:
    bad = ~ok if allowed is None else (~ok | (err > allowed))
    return int(np.count_nonzero(bad))


# ---------------------------------------------------------------- inverse mode

def largest_passing(prob, cap: float, level: float, start: float) -> tuple[float, float]:
    """Largest t in [0, cap] with prob(t) <= level: (t, prob(t)); prob is a deterministic,
    non-decreasing step function of t (common random numbers). Bracketed by doubling from
    `start` (at least 1e-3 cap), then bisected to a relative BISECTION_RTOL; 0 when even
    exact parts fail more often than `level`."""
    p0 = prob(0.0)
    if p0 > level:
        return 0.0, p0
    lo, p_lo = 0.0, p0
    hi = min(max(start, 1e-3 * cap), cap)
    p_hi = prob(hi)
    while p_hi <= level and hi < cap:
        lo, p_lo = hi, p_hi
        hi = min(2.0 * hi, cap)
        p_hi = prob(hi)
    if p_hi <= level:
        return hi, p_hi
    while hi - lo > BISECTION_RTOL * hi:
        mid = 0.5 * (lo + hi)
        p_mid = prob(mid)
        if p_mid <= level:
            lo, p_lo = mid, p_mid
        else:
            hi = mid
    return lo, p_lo


def largest_tolerance(model: Model, tol: Tolerance, seed: int, level: float,
                      start: float) -> tuple[float, float]:
    """Largest t (every dimension of `model.inverse` +- t) with failure probability <= level:
    (t, p(t)), common random numbers (largest_passing); the cap is `model.cap`."""
    n = tol.samples
    unit = np.array([1.0 if k in model.inverse else 0.0 for k in model.columns])
    play = model.play_size(tol)

    def prob(t: float) -> float:
        err, ok = monte_carlo(model, unit * t, tol.clearance, play, n, seed, tol.distribution)
        return failures(err, ok, tol.allowed_error) / n

    return largest_passing(prob, model.cap, level, start)


# ---------------------------------------------------------------- the report section

def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion k / n (Wilson 1927)."""
    p = k / n
    den = 1.0 + z * z / n
    mid = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    lo = 0.0 if k == 0 else max(0.0, mid - half)
    hi = 1.0 if k == n else min(1.0, mid + half)
    return lo, hi


def analyse(problem, solution) -> dict:
    """The `tolerance` report section of a solved linkage: output-ready (plain floats, angles
    in the file's unit, lengths in its length unit)."""
    from linkcli.analysis.tolerance_input import check_lengths
    from linkcli.mechanisms import of
    model = of(solution.linkage).tolerance_model(problem, solution)
    check_lengths(problem.meta, model.known, complete=True)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _analyse(problem, model)


def _analyse(problem, model: Model) -> dict:
    tol: Tolerance = problem.meta.tolerance
    units = problem.meta.units
    seed = int(problem.meta.solver.seed)
    conv = (lambda x: float(units.from_rad(x))) if model.kind == "angle" else float
    opt = (lambda x: None if x is None or not math.isfinite(x) else conv(x))
    level = tol.max_failure_probability if isinstance(tol, InverseTolerance) else None
    lengths = {k: float(v) for k, v in tol.lengths.items()}
    out: dict = {"measure": model.measure, "samples": tol.samples, "distribution": tol.distribution,
                 "lengths": dict(lengths), "clearance": float(tol.clearance), **model.given(tol)}
    if len(model.inputs) == 0:
        out["message"] = model.no_assembly
        return out
    play = model.play_size(tol)
    if level is not None:
        given = float(np.max(model.column_scale(lengths), initial=0.0))
        t, p_t = largest_tolerance(model, tol, seed, level, given)
        if not tol.lengths_given:  # no tolerance written: report the study at the one found
            # (a written 0, exact parts, is a study of its own and is reported as 0)
            lengths = {k: t for k in model.inverse}
            out["lengths"] = dict(lengths)
    scale = model.column_scale(lengths)
    draws = None
    if model.per_row:
        draws = monte_carlo_rows(model, scale, tol.clearance, play, tol.samples, seed, tol.distribution)
        err, ok = draws.err, draws.ok
    else:
        err, ok = monte_carlo(model, scale, tol.clearance, play, tol.samples, seed, tol.distribution)
    nominal, _ = model.errors(np.zeros((1, len(model.columns))), None, None)
    good = snap(err[ok], model.scale)  # round-off of an exact design (exact parts) is 0
    n = tol.samples
    k = failures(err, ok, tol.allowed_error)
    p = k / n
    lo, hi = wilson(k, n)
    out.update({
        "nominal_error": opt(snap(float(nominal[0]), model.scale)),
        "error_mean": opt(float(good.mean())) if good.size else None,
        "error_p95": opt(float(np.percentile(good, 95))) if good.size else None,
        "error_max": opt(float(good.max())) if good.size else None,
        "allowed_error": opt(tol.allowed_error),
    })
    if tol.allowed_error is None:
        out["failure"] = model.no_allowed_error
    out.update({
        "assembly_failures": int(n - good.size),
        "failure_probability": p,
        "failure_probability_se": math.sqrt(p * (1.0 - p) / n),
        "failure_probability_ci95": [lo, hi],
        "sensitivity": {key: opt(s) for key, s in model.sensitivity().items()},
    })
    if level is not None:
        out["max_failure_probability"] = float(level)
        out["largest_tolerance"] = float(t)
        out["failure_probability_at_largest"] = float(p_t)
    if draws is not None:
        out.update(row_section(model, draws, tol.allowed_error, n, conv))
    return out
