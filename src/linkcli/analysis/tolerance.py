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
and target; with fits (analysis.made_parts), per sample and fitted joint a unit draw of its
hole and of its shaft (the pins', then the plays'). A fresh check of a chosen design
(allocation, schemes, robust designs) uses another stream, `default_rng([seed, k, 1])`.

Counted: the error of each sample that assembles and the failure probability p = k / N with
its Wilson 95 % interval; the report section built from them, the inverse mode, the
allocation and the schemes are analysis.tolerance_report's. numpy only.
"""

from __future__ import annotations

import math
from typing import NamedTuple, Protocol

import numpy as np

from linkcli import progress
from linkcli.analysis.made_parts import FitZones, Parts
from linkcli.model import Tolerance
from linkcli.noise import first_max, snap

CHUNK_ELEMENTS = 2**17  # samples x targets assembled at once
KEEP_ELEMENTS = 2**24  # unit draws kept in memory for common random numbers (128 MB)
WORK = "tolerance sample-targets"  # what the progress display counts (linkcli.progress)
VERIFY_STREAM = (1,)  # the fresh Monte Carlo that checks a chosen design: default_rng([seed, k, 1])
Z95 = 1.959963984540054  # two-sided 95 % normal quantile
TWO_PI = 2.0 * math.pi


class Model(Protocol):
    """A mechanism's made parts (its home's tolerance module).

    columns: the toleranced dimensions, in draw order; inverse: those the inverse mode's
    common tolerance (and the least-cost allocation) applies to; pins: joints with radial
    clearance; plays: per-target plays drawn after the pins (a slider in its guide); kind:
    "angle" (errors in rad) or "length"; measure: what the error is, for the report;
    inputs: (M,) the targets' drive angles (none: the nominal linkage never assembles,
    `no_assembly` says so); scale: the errors' noise-floor scale; cap: the largest common
    tolerance (a larger one can make a length <= 0); known: link -> length for the
    tolerance checks (reading.tolerance_lengths).

    Optional (read with defaults, so that a Model written before them keeps working):
    pin_names and play_names, the [joints] names of the pins and plays in the order of
    their draws (fits need them); keys, column -> its [tolerance] lengths key where they
    differ (default: the column's name); nominal, column -> nominal size for general
    tolerances (default: `known`); clearance_terms(pins, plays) -> terms and
    errors_from_terms(dl, terms), what the plays add whatever the lengths, computed once
    for many passes over the same draws (default: the offsets, and `errors`);
    deviations(dl, terms) -> (n, M), each target's deviation (inf where it fails there),
    for designs that minimize failure (analysis.robust_design)."""

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

    # Also optional: column_scale(lengths) -> (columns,) each column's tolerance from the
    # [tolerance] lengths where a home's links hold several dimensions (a drawn link: each
    # distance between two of its joints; default: by `keys`, made_parts.scales); and
    # `per_row` True (the five-bar: its error at every row of a motion) with `rows` (M,) the
    # row numbers of its targets, `row_errors(dl, pins, plays)` -> (dev (n, M), ok (n, M),
    # events {i: (n,) error added at event i}) whose reduction is `errors` (the largest dev,
    # inf where a row fails), and `event_labels()` (one dict per event).


# ---------------------------------------------------------------- random draws

class Plan(NamedTuple):
    """What each sample draws: n samples at m targets; `columns` unit deviations; `pins`
    and `plays` the offsets drawn (0: none); `fit_pins`, `fit_plays` the joints whose hole
    and shaft are drawn (0: none)."""

    n: int
    m: int
    columns: int
    distribution: str
    pins: int = 0
    plays: int = 0
    fit_pins: int = 0
    fit_plays: int = 0


class Chunk(NamedTuple):
    """One chunk's unit draws: u (rows, columns), e (rows, m, pins, 2) or None, g (rows, m,
    plays) or None, vp (rows, fit_pins, 2) or None, vg (rows, fit_plays, 2) or None."""

    u: np.ndarray
    e: np.ndarray | None
    g: np.ndarray | None
    vp: np.ndarray | None = None
    vg: np.ndarray | None = None

    def rows(self, index) -> Chunk:
        """The chunk restricted to some rows (a boolean mask or indices)."""
        return Chunk(*(None if a is None else a[index] for a in self))


def _unit(rng, shape, distribution: str) -> np.ndarray:
    if distribution == "normal":
        return rng.standard_normal(shape) / 3.0
    return rng.uniform(-1.0, 1.0, shape)


def chunks(seed: int, plan: Plan, stream: tuple[int, ...] = ()):
    """Yield (start, Chunk) per chunk of the seeded draws (module docstring: the order);
    `stream` names another seed stream (a fresh check: VERIFY_STREAM)."""
    m = plan.m
    rows = max(1, CHUNK_ELEMENTS // max(m, 1))
    for k, start in enumerate(range(0, plan.n, rows)):
        size = min(rows, plan.n - start)
        rng = np.random.default_rng([seed, k, *stream])
        u = _unit(rng, (size, plan.columns), plan.distribution)
        e = g = vp = vg = None
        if plan.pins:
            r = np.sqrt(rng.random((size, m, plan.pins)))
            t = rng.random((size, m, plan.pins)) * TWO_PI
            e = np.stack([r * np.cos(t), r * np.sin(t)], axis=-1)
        if plan.plays:
            g = rng.uniform(-1.0, 1.0, (size, m, plan.plays))
        if plan.fit_pins:
            vp = _unit(rng, (size, plan.fit_pins, 2), plan.distribution)
        if plan.fit_plays:
            vg = _unit(rng, (size, plan.fit_plays, 2), plan.distribution)
        yield start, Chunk(u, e, g, vp, vg)


def unit_draws(seed: int, n: int, m: int, columns: int, distribution: str, pins: int = 0,
               plays: int = 0):
    """Yield per chunk (u, e, g): u (rows, columns) unit deviations (uniform on [-1, 1], or
    normal with sigma 1/3), e (rows, m, pins, 2) offsets uniform over the unit disc or None,
    g (rows, m, plays) uniform on [-1, 1] or None (module docstring: the order of draws)."""
    for _, ch in chunks(seed, Plan(n, m, columns, distribution, pins, plays)):
        yield ch.u, ch.e, ch.g


def plan_of(model: Model, parts: Parts, n: int, distribution: str) -> Plan:
    """The draws a study of `parts` needs."""
    fit_pins = len(parts.clearance.names) if isinstance(parts.clearance, FitZones) else 0
    fit_plays = len(parts.play.names) if isinstance(parts.play, FitZones) else 0
    return Plan(n, len(model.inputs), len(model.columns), distribution,
                model.pins if parts.pins_drawn else 0, model.plays if parts.plays_drawn else 0,
                fit_pins, fit_plays)


class Draws:
    """The seeded unit draws of one study plan, regenerated on every pass, or kept in memory
    (common random numbers for many passes) when `keep` and they hold at most
    KEEP_ELEMENTS numbers."""

    def __init__(self, seed: int, plan: Plan, stream: tuple[int, ...] = (), keep: bool = False):
        self.seed, self.plan, self.stream = seed, plan, stream
        per_sample = (plan.columns + plan.m * (2 * plan.pins + plan.plays)
                      + 2 * (plan.fit_pins + plan.fit_plays))
        self._kept = [] if keep and plan.n * per_sample <= KEEP_ELEMENTS else None
        self._complete = False
        self.terms: dict = {}  # (chunk start, clearance, play) -> (clearance terms, the plays) (run)

    @property
    def kept(self) -> bool:
        """Every chunk is in memory (after one full pass)."""
        return self._complete

    def __iter__(self):
        if self.kept:
            yield from self._kept
            return
        fresh = [] if self._kept is not None else None
        for item in chunks(self.seed, self.plan, self.stream):
            if fresh is not None:
                fresh.append(item)
            yield item
        if fresh is not None:
            self._kept, self._complete = fresh, True


# ---------------------------------------------------------------- passes

def clearance_terms(model: Model, ch: Chunk, parts: Parts):
    """(terms, jammed) of one chunk: what its pins and plays add whatever the lengths (the
    Model's `clearance_terms` of the offsets e times the radial clearance, one or each
    joint's from its fit, and the plays g times their size; Models without it: the offsets
    themselves), and the samples whose fitted shaft comes out larger than its hole (None:
    no fits): those cannot run, a failure."""
    jammed = None
    pins = plays = None
    if ch.e is not None:
        if isinstance(parts.clearance, FitZones):
            r = parts.clearance.radii(ch.vp)
            jammed = np.any(r < 0, axis=1)
            pins = ch.e * np.maximum(r, 0.0)[:, None, :, None]
        else:
            pins = ch.e * parts.clearance
    if ch.g is not None:
        if isinstance(parts.play, FitZones):
            r = parts.play.radii(ch.vg)
            stuck = np.any(r < 0, axis=1)
            jammed = stuck if jammed is None else jammed | stuck
            plays = ch.g * np.maximum(r, 0.0)[:, None, :]
        else:
            plays = ch.g * parts.play
    make = getattr(model, "clearance_terms", None)  # optional: older Models take the offsets
    return (make(pins, plays) if make is not None else (pins, plays)), jammed


def chunk_errors(model: Model, ch: Chunk, parts: Parts, terms=None):
    """(err, ok) of one chunk's made parts: deviations u * scale, and the clearance terms
    (given, or computed here)."""
    progress.count(WORK, ch.u.shape[0] * max(len(model.inputs), 1))
    dl = ch.u * parts.scale[None, :]
    terms, jammed = terms if terms is not None else clearance_terms(model, ch, parts)
    use = getattr(model, "errors_from_terms", None)
    err, ok = use(dl, terms) if use is not None else model.errors(dl, *terms)
    if jammed is not None and jammed.any():
        ok = ok & ~jammed
        err = np.where(ok, err, np.inf)
    return err, ok


def run(model: Model, draws, parts: Parts):
    """(err (n,), ok (n,)) over every chunk of `draws` (an iterable of (start, Chunk); kept
    Draws also keep each chunk's clearance terms for the next pass with the same plays)."""
    errs, oks = [], []
    cache = draws.terms if isinstance(draws, Draws) and draws.kept else None
    for start, ch in draws:
        terms = None
        if cache is not None:
            key = (start, _play_key(parts.clearance), _play_key(parts.play))
            if key not in cache:  # the plays kept with their terms: their ids stay theirs
                cache[key] = (clearance_terms(model, ch, parts), parts.clearance, parts.play)
            terms = cache[key][0]
        err, ok = chunk_errors(model, ch, parts, terms)
        errs.append(err)
        oks.append(ok)
    return np.concatenate(errs), np.concatenate(oks)


def _play_key(play):
    return id(play) if isinstance(play, FitZones) else float(play)


def monte_carlo(model: Model, scale: np.ndarray, clearance: float, play: float, n: int,
                seed: int, distribution: str):
    """(err (n,), ok (n,)) over n seeded samples, in chunks: scale (columns,) the tolerances,
    `clearance` the pins' radial clearance, `play` the plays' size."""
    parts = Parts(np.asarray(scale, dtype=float), float(clearance), float(play))
    return run(model, chunks(seed, plan_of(model, parts, n, distribution)), parts)


class RowDraws:
    """What run_rows keeps: the samples' largest error and whether they hold (n,),
    each row's error and assembly (n, M), and each event's added error (n,) per event."""

    def __init__(self, err, ok, dev, row_ok, events) -> None:
        self.err, self.ok, self.dev, self.row_ok, self.events = err, ok, dev, row_ok, events


def run_rows(model: Model, draws, parts: Parts) -> RowDraws:
    """`run` (the same draws, chunk by chunk) keeping every row's error and every event's (a
    per-row model's `row_errors`): samples x rows floats, which the model's schema bounds."""
    pieces: list = []
    for _, ch in draws:
        progress.count(WORK, ch.u.shape[0] * max(len(model.inputs), 1))
        (pins, plays), jammed = clearance_terms(model, ch, parts)
        dev, ok, events = model.row_errors(ch.u * parts.scale[None, :], pins, plays)
        if jammed is not None:
            ok = ok & ~jammed[:, None]
        pieces.append((dev, ok, events))
    dev = np.concatenate([p[0] for p in pieces])
    row_ok = np.concatenate([p[1] for p in pieces])
    events = {i: np.concatenate([p[2][i] for p in pieces]) for i in pieces[0][2]}
    ok = np.all(row_ok, axis=1)
    err = np.where(ok, np.max(dev, axis=1, initial=0.0), np.inf)
    return RowDraws(err, ok, dev, row_ok, events)


def monte_carlo_rows(model: Model, scale: np.ndarray, clearance: float, play: float, n: int,
                     seed: int, distribution: str) -> RowDraws:
    """`monte_carlo` keeping every row (run_rows): scale (columns,) the tolerances,
    `clearance` the pins' radial clearance, `play` the plays' size."""
    parts = Parts(np.asarray(scale, dtype=float), float(clearance), float(play))
    return run_rows(model, chunks(seed, plan_of(model, parts, n, distribution)), parts)


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


def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion k / n (Wilson 1927)."""
    p = k / n
    den = 1.0 + z * z / n
    mid = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    lo = 0.0 if k == 0 else max(0.0, mid - half)
    hi = 1.0 if k == n else min(1.0, mid + half)
    return lo, hi
