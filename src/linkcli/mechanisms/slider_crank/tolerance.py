"""The slider-crank's made parts for the tolerance Monte Carlo of its slider position
(analysis.tolerance drives it; docs/tolerance.md): the four-bar's model with the slider's
own parts.

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
Random numbers (analysis.tolerance.unit_draws): in each chunk the lengths, then the pin
offsets (if clearance > 0), then the guide play (if clearance_slider > 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.slider_crank.kinematics import (
    TWO_PI,
    arc_contains,
    arc_sweep,
    choose_arc,
    input_arcs,
    slider_from_trig,
    slider_partials,
)
from linkcli.mechanisms.slider_crank.model import SliderCrank

LENGTH_KEYS = ("input", "coupler", "offset")
PINS = 3  # A0, A, B
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




def pin_sum(pins):
    """C = c1 + c2 + c3 (n, M, 2) of the pin offsets (n, M, 3, 2), or None."""
    if pins is None:
        return None
    total = pins[:, :, 0]
    for j in range(1, pins.shape[2]):
        total = total + pins[:, :, j]  # in order: as numpy's sum over that axis, faster
    return total


def sample_sliders(linkage: SliderCrank, tg: SliderTargets, dl, pins=None, guide=None, total=None):
    """Slider positions of made slider-cranks at the targets: (s (n, M), ok (n, M)).
    dl (n, 3) deviations of crank, rod, offset; pins (n, M, 3, 2) clearance offsets at A0, A,
    B (length) or None (or their sum `total` (n, M, 2), pin_sum); guide (n, M) normal play
    of the slider (length) or None."""
    a0, b0, e0 = linkage.abe
    a = a0 + dl[:, 0:1]
    b = b0 + dl[:, 1:2]
    e = e0 + dl[:, 2:3]
    made = (a > 0) & (b > 0)
    shift = 0.0
    if guide is not None:
        e = e + guide
    if total is None:
        total = pin_sum(pins)
    if total is not None:
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


def sample_errors(linkage: SliderCrank, tg: SliderTargets, dl, pins=None, guide=None, total=None):
    """(err, ok), each (n,): max |s - s_target| over the targets (inf for a failed sample)."""
    s, ok = sample_sliders(linkage, tg, dl, pins, guide, total)
    with np.errstate(invalid="ignore"):
        dev = np.abs(s - tg.slider[None, :])
    ok_all = np.all(ok, axis=1) & travel_ok(linkage, dl, tg.span)
    err = np.where(ok_all, dev.max(axis=1) if dev.shape[1] else 0.0, np.inf)
    return err, ok_all


def sensitivity(linkage: SliderCrank, tg: SliderTargets) -> dict:
    """Per length, max over the targets of |ds/dx| (closed form; None if infinite)."""
    parts = slider_partials(*linkage.abe, tg.phi, linkage.branch)
    out = {}
    for key, d in zip(LENGTH_KEYS, parts):
        mag = float(np.max(np.abs(d))) if len(tg.phi) else math.nan
        out[key] = mag if math.isfinite(mag) else None
    return out


class Model:
    """The slider-crank's made parts (analysis.tolerance.Model) at targets `tg`."""

    columns = inverse = LENGTH_KEYS
    pins = PINS
    plays = 1  # the slider's play normal to its guide
    per_row = False  # the report gives the largest error over the targets only
    pin_names = ("A0", "A", "B")  # as [joints] names them, in the order of the offsets
    play_names = ("guide",)  # a fit of the guide gives the slider's play
    keys: dict = {}
    kind = "length"
    no_assembly = "the nominal slider-crank cannot assemble at any crank angle"
    no_allowed_error = NO_ALLOWED_ERROR

    def __init__(self, linkage: SliderCrank, tg: SliderTargets) -> None:
        self.linkage, self.tg = linkage, tg
        self.measure = tg.measure
        self.inputs = tg.phi
        self.scale = max(linkage.input, linkage.coupler, abs(linkage.offset))
        self.cap = min(linkage.input, linkage.coupler)
        self.known = {"input": linkage.input, "coupler": linkage.coupler}  # the offset may be 0
        self.nominal = {**self.known, "offset": linkage.offset}  # sizes (ISO 2768)

    def given(self, tol) -> dict:
        return {"clearance_slider": float(tol.clearance_slider)}

    def play_size(self, tol) -> float:
        return float(tol.clearance_slider)

    def errors(self, dl, pins, plays):
        return sample_errors(self.linkage, self.tg, dl, pins, None if plays is None else plays[..., 0])

    def clearance_terms(self, pins, plays):
        """What the pins and the guide add, whatever the lengths: (pin sum, guide play)."""
        return pin_sum(pins), None if plays is None else plays[..., 0]

    def errors_from_terms(self, dl, terms):
        total, guide = terms
        return sample_errors(self.linkage, self.tg, dl, None, guide, total)

    def sensitivity(self) -> dict:
        return sensitivity(self.linkage, self.tg)


def model(problem, solution) -> Model:
    """Targets are the solution's positions (precision positions: crank angle, slider
    position) or the nominal slider over the range of motion."""
    sl = solution.linkage
    pos = solution.positions
    if pos is not None and len(pos.input):
        tg = targets_at(sl, np.asarray(pos.input, dtype=float), np.asarray(pos.target, dtype=float),
                        solution.working_span)
    else:
        tg = targets_over_range(sl, solution.working_span[0] if solution.working_span else None)
    return Model(sl, tg)
