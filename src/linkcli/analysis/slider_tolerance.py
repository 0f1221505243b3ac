"""Tolerance Monte Carlo of an offset slider-crank's slider position (numpy only).

Mirrors the four-bar's model (linkcli.tolerance, docs/tolerance.md) with the slider's own
parts:

Lengths. crank a, rod b and offset e are made as x + dx, dx uniform on [-t, t] or normal
with 3 sigma = t (not truncated); keys `input`, `coupler`, `offset`.

Pin clearance, effective-link model (Lee & Gilmore 1991; Ting, Zhu & Watkins 2000). At
each revolute joint (A0, A, B) the journal lies anywhere in a circle of radius r
(`clearance`) around the bearing centre: offsets c1, c2, c3 drawn per sample, joint and
target uniformly over the disc (the load, and with it the contact, changes between
positions). Guide play (`clearance_slider`): the slider shifts normal to its axis by g,
uniform on [-r_s, r_s] per sample and target. The loop then closes as

    c1 + a e^{i phi} + c2 + b e^{i theta} + c3 = s + i (e + g),

a slider-crank with the effective offset e' = e + g - Im C (C = c1 + c2 + c3) whose slider
sits at s = s'(a, b, e', phi) + Re C, on the design's branch.

Error of a sample: max over the targets of |s - s_target|. A sample fails when a or b
comes out <= 0, when it cannot assemble at a target, when its crank cannot travel from the
first to the last target without a limit position (|e - a sin(phi)| <= b over the span,
extreme only at the span's ends and phi = +-90 deg), or when its error exceeds
allowed_error. Without targets (`type = "linkage"`) the nominal slider position at GRID
crank angles over the range of motion is the target.

Sensitivity: per length, max over the targets of |ds/dx| from the closed-form partials
(slider_crank.slider_partials). Inverse mode: the largest t, the same on crank, rod and
offset, with failure probability <= a level, by bisection with common random numbers.
Random numbers: chunks of about CHUNK_ELEMENTS sample-targets, chunk k from numpy
default_rng([seed, k]); draws in each chunk: lengths, then pin offsets (if clearance > 0),
then guide play (if clearance_slider > 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.analysis.tolerance import largest_passing, wilson  # the house's own
from linkcli.mechanisms.slider_crank.kinematics import (TWO_PI, SliderCrank, arc_contains, arc_sweep, choose_arc,
                                             input_arcs, slider_from_trig, slider_partials)

LENGTH_KEYS = ("input", "coupler", "offset")
PINS = 3  # A0, A, B
CHUNK_ELEMENTS = 2**17
GRID = 36
TRAVEL_SLACK = 1e-12
NO_ALLOWED_ERROR = ("no allowed_error given: a sample fails only when it cannot be made (crank or rod "
                    "<= 0), assembled at a target or moved from the first target to the last")


@dataclass(frozen=True)
class SliderTargets:
    """Crank angles phi (rad, (M,)) and the slider positions a made part must reproduce."""

    phi: np.ndarray
    slider: np.ndarray
    measure: str
    span: tuple[float, float] | None  # (start, signed sweep) of the crank, rad

    @property
    def trig(self):
        return np.cos(self.phi), np.sin(self.phi)


def targets_at(linkage: SliderCrank, phi, slider=None, span=None) -> SliderTargets:
    """Targets at given crank angles: the given slider positions (precision positions) or
    the nominal ones. span defaults to (phi_1, phi_M - phi_1)."""
    phi = np.asarray(phi, dtype=float)
    if slider is None:
        c, s = np.cos(phi), np.sin(phi)
        slider = slider_from_trig(*linkage.abe, c, s, linkage.branch)[0]
    if span is None and len(phi):
        span = (float(phi[0]), float(phi[-1] - phi[0]))
    return SliderTargets(phi, np.asarray(slider, dtype=float),
                         "largest slider-position error at the target positions", span)


def targets_over_range(linkage: SliderCrank, near=None) -> SliderTargets:
    """The nominal slider at GRID crank angles: every 10 deg for a turning crank, else the
    centres of GRID equal cells of the arc holding `near`."""
    arcs = input_arcs(*linkage.abe)
    if arcs is None:
        phi, span = np.arange(GRID) * (TWO_PI / GRID), (0.0, TWO_PI)
    elif arcs == []:
        return SliderTargets(np.zeros(0), np.zeros(0), "the nominal slider-crank never assembles", None)
    else:
        lo, hi = choose_arc(arcs, near)
        phi = lo + (np.arange(GRID) + 0.5) * (arc_sweep(lo, hi) / GRID)
        span = (float(phi[0]), float(phi[-1] - phi[0]))
    tg = targets_at(linkage, phi, span=span)
    return SliderTargets(tg.phi, tg.slider, f"largest deviation from the nominal slider position at "
                         f"{GRID} crank angles over the range of motion", span)


# ---------------------------------------------------------------- draws and samples

def unit_draws(seed: int, n: int, m: int, distribution: str, pins: bool, guide: bool):
    """Per chunk (u, c, g): u (rows, 3) unit length deviations (uniform on [-1, 1] or normal
    with sigma 1/3), c (rows, m, 3, 2) unit-disc pin offsets or None, g (rows, m) uniform on
    [-1, 1] guide play or None."""
    rows = max(1, CHUNK_ELEMENTS // max(m, 1))
    for k, start in enumerate(range(0, n, rows)):
        size = min(rows, n - start)
        rng = np.random.default_rng([seed, k])
        if distribution == "normal":
            u = rng.standard_normal((size, len(LENGTH_KEYS))) / 3.0
        else:
            u = rng.uniform(-1.0, 1.0, (size, len(LENGTH_KEYS)))
        c = g = None
        if pins:
            r = np.sqrt(rng.random((size, m, PINS)))
            t = rng.random((size, m, PINS)) * TWO_PI
            c = np.stack([r * np.cos(t), r * np.sin(t)], axis=-1)
        if guide:
            g = rng.uniform(-1.0, 1.0, (size, m))
        yield u, c, g


def sample_sliders(linkage: SliderCrank, tg: SliderTargets, dl, pins=None, guide=None):
    """Slider positions of made slider-cranks at the targets: (s (n, M), ok (n, M)).
    dl (n, 3) deviations of crank, rod, offset; pins (n, M, 3, 2) clearance offsets at A0, A,
    B (length) or None; guide (n, M) normal play of the slider (length) or None."""
    a0, b0, e0 = linkage.abe
    a = a0 + dl[:, 0:1]
    b = b0 + dl[:, 1:2]
    e = e0 + dl[:, 2:3]
    made = (a > 0) & (b > 0)
    shift = 0.0
    if guide is not None:
        e = e + guide
    if pins is not None:
        total = pins.sum(axis=2)  # C = c1 + c2 + c3, (n, M, 2)
        e = e - total[..., 1]
        shift = total[..., 0]
    cos_phi, sin_phi = tg.trig
    s, _, _, valid = slider_from_trig(a, b, e, cos_phi, sin_phi, linkage.branch)
    return s + shift, valid & made


def travel_ok(linkage: SliderCrank, dl, span) -> np.ndarray:
    """(n,) whether each made crank runs over `span` with |e - a sin(phi)| <= b throughout."""
    if span is None:
        return np.ones(len(dl), dtype=bool)
    start, sweep = span
    lo, width = (start, sweep) if sweep >= 0 else (start + sweep, -sweep)
    if width >= TWO_PI - 1e-12:
        cands = [0.0, math.pi / 2, -math.pi / 2]
    else:
        cands = [lo, lo + width] + [x for x in (math.pi / 2, -math.pi / 2)
                                    if bool(arc_contains((lo, lo + width), x))]
    x = np.array(cands)[None, :]
    a0, b0, e0 = linkage.abe
    a, b, e = a0 + dl[:, 0:1], b0 + dl[:, 1:2], e0 + dl[:, 2:3]
    h = e - a * np.sin(x)
    return np.all(np.abs(h) <= b * (1 + TRAVEL_SLACK), axis=1)


def sample_errors(linkage: SliderCrank, tg: SliderTargets, dl, pins=None, guide=None):
    """(err, ok), each (n,): max |s - s_target| over the targets (inf for a failed sample)."""
    s, ok = sample_sliders(linkage, tg, dl, pins, guide)
    with np.errstate(invalid="ignore"):
        dev = np.abs(s - tg.slider[None, :])
    ok_all = np.all(ok, axis=1) & travel_ok(linkage, dl, tg.span)
    err = np.where(ok_all, dev.max(axis=1) if dev.shape[1] else 0.0, np.inf)
    return err, ok_all


def monte_carlo(linkage: SliderCrank, tg: SliderTargets, scale, clearance: float,
                clearance_slider: float, n: int, seed: int, distribution: str = "uniform"):
    """(err (n,), ok (n,)) over n seeded samples; scale (3,) the tolerances of crank, rod,
    offset."""
    scale = np.asarray(scale, dtype=float)
    errs, oks = [], []
    m = len(tg.phi)
    with np.errstate(invalid="ignore", over="ignore"):
        for u, c, g in unit_draws(seed, n, m, distribution, clearance > 0, clearance_slider > 0):
            err, ok = sample_errors(linkage, tg, u * scale[None, :],
                                    None if c is None else c * clearance,
                                    None if g is None else g * clearance_slider)
            errs.append(err)
            oks.append(ok)
    return np.concatenate(errs), np.concatenate(oks)


def failures(err, ok, allowed) -> int:
    bad = ~ok if allowed is None else (~ok | (err > allowed))
    return int(np.count_nonzero(bad))


def sensitivity(linkage: SliderCrank, tg: SliderTargets) -> dict:
    """Per length, max over the targets of |ds/dx| (closed form; None if infinite)."""
    parts = slider_partials(*linkage.abe, tg.phi, linkage.branch)
    out = {}
    for key, d in zip(LENGTH_KEYS, parts):
        mag = float(np.max(np.abs(d))) if len(tg.phi) else math.nan
        out[key] = mag if math.isfinite(mag) else None
    return out


def largest_tolerance(linkage: SliderCrank, tg: SliderTargets, samples: int, clearance: float,
                      clearance_slider: float, seed: int, distribution: str, allowed, level: float,
                      start: float) -> tuple[float, float]:
    """Largest t (crank, rod and offset each +- t) with failure probability <= level: (t, p).
    p(t) is a step function of t under common random numbers: bracket by doubling from
    `start`, bisected (analysis.tolerance.largest_passing); the cap is the shorter of crank and rod."""
    unit = np.ones(len(LENGTH_KEYS))

    def prob(t):
        err, ok = monte_carlo(linkage, tg, unit * t, clearance, clearance_slider, samples, seed,
                              distribution)
        return failures(err, ok, allowed) / samples

    return largest_passing(prob, min(linkage.input, linkage.coupler), level, start)


def analyse(linkage: SliderCrank, lengths: dict, *, clearance: float = 0.0,
            clearance_slider: float = 0.0, samples: int = 20000, seed: int = 0,
            distribution: str = "uniform", allowed_error: float | None = None,
            max_failure_probability: float | None = None,
            targets: SliderTargets | None = None, lengths_given: bool | None = None) -> dict:
    """The `tolerance` section for a slider-crank (plain floats, length unit): lengths is
    {input, coupler, offset} -> +- t (missing keys 0); targets default to the nominal slider
    over the range of motion. With `max_failure_probability`, the study runs at the largest
    tolerance found unless `lengths_given` (None: some length is nonzero); a written 0 is
    exact parts, a study of its own, as for the four-bar (analysis.tolerance)."""
    tg = targets if targets is not None else targets_over_range(linkage)
    lengths = {k: float(lengths.get(k, 0.0)) for k in LENGTH_KEYS}
    out: dict = {"measure": tg.measure, "samples": int(samples), "distribution": distribution,
                 "lengths": dict(lengths), "clearance": float(clearance),
                 "clearance_slider": float(clearance_slider)}
    if len(tg.phi) == 0:
        out["message"] = "the nominal slider-crank cannot assemble at any crank angle"
        return out
    opt = lambda x: None if x is None or not math.isfinite(x) else float(x)  # noqa: E731
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        level = max_failure_probability
        if level is not None:
            given = max(lengths.values())
            t, p_t = largest_tolerance(linkage, tg, samples, clearance, clearance_slider, seed,
                                       distribution, allowed_error, level, given)
            if not (given > 0.0 if lengths_given is None else lengths_given):
                lengths = {k: t for k in LENGTH_KEYS}
                out["lengths"] = dict(lengths)
        scale = np.array([lengths[k] for k in LENGTH_KEYS])
        err, ok = monte_carlo(linkage, tg, scale, clearance, clearance_slider, samples, seed, distribution)
        nominal, _ = sample_errors(linkage, tg, np.zeros((1, len(LENGTH_KEYS))))
        good = err[ok]
        k = failures(err, ok, allowed_error)
        p = k / samples
        lo, hi = wilson(k, samples)
        out.update({
            "nominal_error": opt(float(nominal[0])),
            "error_mean": opt(float(good.mean())) if good.size else None,
            "error_p95": opt(float(np.percentile(good, 95))) if good.size else None,
            "error_max": opt(float(good.max())) if good.size else None,
            "allowed_error": opt(allowed_error),
        })
        if allowed_error is None:
            out["failure"] = NO_ALLOWED_ERROR
        out.update({
            "assembly_failures": int(samples - good.size),
            "failure_probability": p,
            "failure_probability_se": math.sqrt(p * (1.0 - p) / samples),
            "failure_probability_ci95": [lo, hi],
            "sensitivity": sensitivity(linkage, tg),
        })
        if level is not None:
            out["max_failure_probability"] = float(level)
            out["largest_tolerance"] = float(t)
            out["failure_probability_at_largest"] = float(p_t)
    return out


def report_section(problem, solution) -> dict:
    """The `tolerance` report section of a solved slider-crank problem (analysis.tolerance
    dispatches here): targets are the solution's positions (precision positions) or the
    nominal slider over the range of motion; the [tolerance] table as read by io.meta
    (lengths keyed input, coupler, offset; clearance; clearance_slider; allowed_error in the
    length unit). Errors below the noise floor of the slider-crank's size are 0."""
    from linkcli.analysis.tolerance_input import check_lengths
    from linkcli.noise import snap

    sl = solution.linkage
    check_lengths(problem.meta, {"input": sl.input, "coupler": sl.coupler}, complete=True)
    tol = problem.meta.tolerance
    level = getattr(tol, "max_failure_probability", None)
    pos = solution.positions
    if pos is not None and len(pos.input):
        tg = targets_at(sl, np.asarray(pos.input, dtype=float), np.asarray(pos.target, dtype=float),
                        solution.working_span)
    else:
        tg = targets_over_range(sl, solution.working_span[0] if solution.working_span else None)
    lengths = dict(tol.lengths) if (level is None or getattr(tol, "lengths_given", True)) else {}
    out = analyse(sl, lengths, clearance=tol.clearance, clearance_slider=tol.clearance_slider,
                  samples=tol.samples, seed=int(problem.meta.solver.seed), distribution=tol.distribution,
                  allowed_error=tol.allowed_error, max_failure_probability=level, targets=tg,
                  lengths_given=getattr(tol, "lengths_given", True))
    scale = max(sl.input, sl.coupler, abs(sl.offset))
    for key in ("nominal_error", "error_mean", "error_p95", "error_max"):
        if out.get(key) is not None:
            out[key] = snap(out[key], scale)
    return out
