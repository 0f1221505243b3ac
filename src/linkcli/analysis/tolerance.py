"""Tolerance analysis: Monte Carlo over manufactured linkages (docs/format.md, [tolerance]).

Lengths. Every link length l (ground included) is made as l + dl, dl uniform on [-t, t] or
normal with 3 sigma = t (not truncated). For a path generator the coupler point (px, py)
can carry a tolerance too (each coordinate +- t, table key `coupler_point`).

Joint clearance, effective-link model. At each revolute joint (A0, A, B, B0) the journal
centre lies anywhere in a circle of radius r (the radial clearance) around the bearing
centre: each clearance is a massless virtual link of length <= r whose direction is set by
the load (Lee & Gilmore 1991, "The determination of the probabilistic properties of
velocities and accelerations in kinematic chains with uncertainty", J. Mech. Des. 113;
Ting, Zhu & Watkins 2000, "The effects of joint clearance on position and orientation
deviation of linkages and manipulators", Mech. Mach. Theory 35). The load, and with it the
contact point, changes from one position to the next, so the offsets e1..e4 (at A0, A, B,
B0) are drawn independently per sample, joint and target, uniformly over the circle's area.
With them the loop closes as

    e1 + a e^{i phi} + e2 + b e^{i theta} + e3 = d + e4 + c e^{i psi},

a four-bar whose ground is the vector D = d + e4 - e1 - e2 - e3: `kinematics.pose` assembles
it with ground |D| at input phi - arg D, and the angles are turned back by arg D. The
coupler point is P = e1 + e2 + a e^{i phi} + (px + i py) e^{i theta}.

Error of one sample: the largest deviation over the targets, each sample assembled on the
design's branch at the target input angles: |psi - psi_target| (wrapped) for angle
targets, |P - P_target| for path targets. A problem without targets (`type = "linkage"`)
is measured against its own nominal output angle at 36 inputs spread over the input's
range of motion (every 10 deg for a full turn; the centres of 36 equal cells of a rocking
input's arc). A sample fails when a length comes out <= 0, when it cannot assemble at a
target, when its input cannot travel from the first to the last target without a dead
point (checked on the made lengths: rho^2 = a^2 + d^2 - 2 a d cos(phi) must stay within
[(b - c)^2, (b + c)^2], extreme only at the span's ends and at phi = 0, 180 deg), or when
its error exceeds `allowed_error`.

Report: error mean, 95th percentile and max over the samples that assemble; the failure
probability p = k / N with its standard error sqrt(p (1 - p) / N) and the Wilson 95 %
interval; per link, the sensitivity max_j |d(output_j) / d(length)| (central difference on
the nominal linkage): the first-order worst-case error change per unit length.

Inverse mode (`max_failure_probability`): the largest tolerance t, the same on every link,
whose failure probability stays at or below the level, by bisection on the seeded Monte
Carlo with common random numbers (the same unit draws scaled by t at every step).

Random numbers: samples are drawn in chunks of about CHUNK_ELEMENTS sample-targets; chunk k
uses numpy `default_rng([seed, k])` (the `[solver] seed`), so the same file gives the same
bytes on every run, whatever the memory. numpy only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.analysis.tolerance_input import check_lengths
from linkcli.model import LINKS, FourBar, InverseTolerance, Tolerance
from linkcli.noise import snap

COLUMNS = LINKS + ("coupler_point_x", "coupler_point_y")  # columns of the length deviations
CHUNK_ELEMENTS = 2**17  # samples x targets assembled at once
GRID = 36  # inputs over the range of motion for a problem without targets
TRAVEL_SLACK = 1e-12  # relative slack on rho^2 at the span's limits (as kinematics)
BISECTION_RTOL = 1e-4
Z95 = 1.959963984540054  # two-sided 95 % normal quantile
NO_ALLOWED_ERROR = ("no allowed_error given: a sample fails only when it cannot be made (a length "
                    "<= 0), assembled at a target or moved from the first target to the last")


@dataclass
class Targets:
    """What a manufactured linkage must reproduce, at input angles `phi` (rad)."""

    phi: np.ndarray  # (M,)
    kind: str  # "angle" (value: psi, rad) or "point" (value: (M, 2) global points)
    value: np.ndarray
    measure: str  # a sentence for the report
    span: tuple[float, float] | None  # (start, signed sweep) the input travels, rad


# ---------------------------------------------------------------- targets

def targets(problem, solution) -> Targets:
    """The solution's positions, or the nominal output over the range of motion."""
    fb = solution.linkage
    pos = solution.positions
    if pos is not None and len(pos.input):
        phi = np.asarray(pos.input, dtype=float)
        if pos.kind == "point":
            return Targets(phi, "point", np.asarray(pos.target, dtype=float).reshape(-1, 2),
                           "largest distance between coupler point and target point",
                           solution.working_span)
        return Targets(phi, "angle", np.asarray(pos.target, dtype=float),
                       "largest output-angle error at the target positions", solution.working_span)
    arcs = kin.input_arcs(*fb.abcd)
    if arcs is None:
        phi = np.arange(GRID) * (kin.TWO_PI / GRID)
        span = (0.0, kin.TWO_PI)
    elif arcs == []:
        phi = np.zeros(0)
        span = None
    else:
        near = solution.working_span[0] if solution.working_span else None
        lo, hi = kin.choose_arc(arcs, near)
        phi = lo + (np.arange(GRID) + 0.5) * ((hi - lo) / GRID)
        span = (float(phi[0]), float(phi[-1] - phi[0]))
    psi = kin.pose(*fb.abcd, phi, fb.branch).psi
    return Targets(phi, "angle", psi,
                   f"largest deviation from the nominal output angle at {len(phi)} inputs "
                   "over the input's range of motion", span)


# ---------------------------------------------------------------- random draws

def unit_draws(seed: int, n: int, m: int, distribution: str, clearance: bool):
    """Yield per chunk (u, e): u (rows, 6) unit length deviations (uniform on [-1, 1], or
    normal with sigma 1/3), e (rows, m, 4, 2) offsets uniform over the unit disc, or None."""
    rows = max(1, CHUNK_ELEMENTS // max(m, 1))
    for k, start in enumerate(range(0, n, rows)):
        size = min(rows, n - start)
        rng = np.random.default_rng([seed, k])
        if distribution == "normal":
            u = rng.standard_normal((size, len(COLUMNS))) / 3.0
        else:
            u = rng.uniform(-1.0, 1.0, (size, len(COLUMNS)))
        e = None
        if clearance:
            r = np.sqrt(rng.random((size, m, 4)))
            t = rng.random((size, m, 4)) * kin.TWO_PI
            e = np.stack([r * np.cos(t), r * np.sin(t)], axis=-1)
        yield u, e


def scale_vector(lengths: dict) -> np.ndarray:
    """Tolerances in the column order of `unit_draws`: ground, input, coupler, output, px, py."""
    cp = float(lengths.get("coupler_point", 0.0))
    return np.array([float(lengths.get(k, 0.0)) for k in LINKS] + [cp, cp])


# ---------------------------------------------------------------- one batch of samples

def sample_outputs(fb: FourBar, tg: Targets, dl: np.ndarray, off: np.ndarray | None):
    """Outputs of manufactured linkages at the targets.

    dl (n, 6): deviations of ground, input, coupler, output, px, py; off (n, M, 4, 2):
    clearance offsets at A0, A, B, B0, or None. Returns (out, ok): out (n, M) output angles
    (rad) or (n, M, 2) global coupler points; ok (n, M) where the sample assembles.
    """
    d = fb.ground + dl[:, 0:1]
    a = fb.input + dl[:, 1:2]
    b = fb.coupler + dl[:, 2:3]
    c = fb.output + dl[:, 3:4]
    made = (a > 0) & (b > 0) & (c > 0) & (d > 0)
    a, b, c, d = (np.where(made, x, 1.0) for x in (a, b, c, d))
    phi = tg.phi[None, :]
    if off is None:
        gamma = 0.0
        p = kin.pose(a, b, c, d, phi, fb.branch)
        psi, theta = p.psi, p.theta
    else:
        e1, e2, e3, e4 = (off[:, :, j, 0] + 1j * off[:, :, j, 1] for j in range(4))
        big_d = d + e4 - e1 - e2 - e3
        gamma = np.angle(big_d)
        p = kin.pose(a, b, c, np.abs(big_d), phi - gamma, fb.branch)
        psi, theta = p.psi + gamma, p.theta + gamma
    ok = p.valid & made
    if tg.kind == "angle":
        return psi, ok
    px, py = fb.coupler_point or (0.0, 0.0)
    cp = (px + dl[:, 4:5]) + 1j * (py + dl[:, 5:6])
    local = a * np.exp(1j * phi) + cp * np.exp(1j * theta)
    if off is not None:
        local = local + off[:, :, 0, 0] + 1j * off[:, :, 0, 1] + off[:, :, 1, 0] + 1j * off[:, :, 1, 1]
    glob = complex(*fb.ground_pivot) + np.exp(1j * fb.ground_angle) * local
    return np.stack([glob.real, glob.imag], axis=-1), ok


def travel_ok(fb: FourBar, dl: np.ndarray, span) -> np.ndarray:
    """(n,) whether each sample's input can run over `span` without a dead point."""
    if span is None:
        return np.ones(len(dl), dtype=bool)
    start, sweep = span
    lo, width = (start, sweep) if sweep >= 0 else (start + sweep, -sweep)
    cands = [lo, lo + width] + [x for x in (0.0, math.pi)
                                if np.mod(x - lo, kin.TWO_PI) <= width + 1e-12]
    x = np.array(cands)[None, :]
    d = fb.ground + dl[:, 0:1]
    a = fb.input + dl[:, 1:2]
    b = fb.coupler + dl[:, 2:3]
    c = fb.output + dl[:, 3:4]
    rho2 = a * a + d * d - 2.0 * a * d * np.cos(x)
    lo2, hi2 = (b - c) ** 2, (b + c) ** 2
    slack = TRAVEL_SLACK * hi2
    return np.all((rho2 >= lo2 - slack) & (rho2 <= hi2 + slack), axis=1)


def sample_errors(fb: FourBar, tg: Targets, dl: np.ndarray, off: np.ndarray | None):
    """(err, ok), each (n,): largest deviation over the targets (rad or length; inf where
    the sample fails to assemble or to travel) and whether it assembles and travels."""
    out, ok = sample_outputs(fb, tg, dl, off)
    if tg.kind == "angle":
        dev = np.abs(kin.wrap(out - tg.value[None, :]))
    else:
        dev = np.hypot(out[..., 0] - tg.value[None, :, 0], out[..., 1] - tg.value[None, :, 1])
    ok_all = np.all(ok, axis=1) & travel_ok(fb, dl, tg.span)
    err = np.where(ok_all, dev.max(axis=1), np.inf)
    return err, ok_all


def monte_carlo(fb: FourBar, tg: Targets, scale: np.ndarray, clearance: float, n: int,
                seed: int, distribution: str):
    """(err (n,), ok (n,)) over n seeded samples, in chunks."""
    errs, oks = [], []
    for u, e in unit_draws(seed, n, len(tg.phi), distribution, clearance > 0):
        err, ok = sample_errors(fb, tg, u * scale[None, :], None if e is None else e * clearance)
        errs.append(err)
        oks.append(ok)
    return np.concatenate(errs), np.concatenate(oks)


def failures(err: np.ndarray, ok: np.ndarray, allowed: float | None) -> int:
    bad = ~ok if allowed is None else (~ok | (err > allowed))
    return int(np.count_nonzero(bad))


# ---------------------------------------------------------------- sensitivity

def sensitivity(fb: FourBar, tg: Targets) -> dict:
    """Per link, max over targets of |d output / d length| (rad or length per length),
    by a central difference on the nominal linkage (one vectorized assembly)."""
    h = 1e-6 * max(fb.abcd)
    dl = np.zeros((2 * len(LINKS), len(COLUMNS)))
    for k in range(len(LINKS)):
        dl[2 * k, k], dl[2 * k + 1, k] = h, -h
    out, ok = sample_outputs(fb, tg, dl, None)
    if tg.kind == "angle":
        diff = kin.wrap(out[0::2] - out[1::2]) / (2 * h)
        mag = np.abs(diff)
    else:
        diff = (out[0::2] - out[1::2]) / (2 * h)
        mag = np.hypot(diff[..., 0], diff[..., 1])
    good = ok[0::2] & ok[1::2]
    res = {}
    for k, link in enumerate(LINKS):
        res[link] = float(mag[k].max()) if good[k].all() and mag.shape[1] else None
    return res


# ---------------------------------------------------------------- inverse mode

def largest_tolerance(fb: FourBar, tg: Targets, tol: Tolerance, seed: int,
                      level: float, start: float) -> tuple[float, float]:
    """Largest t (every link +- t) with failure probability <= level: (t, p(t)).

    Common random numbers make p(t) a deterministic step function of t; it is bracketed by
    doubling from `start`, then bisected to a relative BISECTION_RTOL. The cap is the
    shortest link (a larger tolerance can make a length <= 0)."""
    n = tol.samples
    unit = np.array([1.0, 1.0, 1.0, 1.0, 0.0, 0.0])

    def prob(t: float) -> float:
        err, ok = monte_carlo(fb, tg, unit * t, tol.clearance, n, seed, tol.distribution)
        return failures(err, ok, tol.allowed_error) / n

    return largest_passing(prob, min(fb.abcd), level, start)


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


def check_input(problem, fb: FourBar) -> None:
    """A length tolerance must be smaller than its link, the clearance than every link
    (tolerance_input.check_lengths, which `check` runs on the lengths a file fixes)."""
    check_lengths(problem.meta, {k: getattr(fb, k) for k in LINKS}, complete=True)


def analyse(problem, solution) -> dict:
    """The `tolerance` report section: output-ready (plain floats, angles in the file's
    unit, lengths in its length unit)."""
    if hasattr(solution.linkage, "abe"):  # a slider-crank (analysis.slider_tolerance)
        from linkcli.analysis.slider_tolerance import report_section
        return report_section(problem, solution)
    check_input(problem, solution.linkage)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _analyse(problem, solution)


def _analyse(problem, solution) -> dict:
    tol: Tolerance = problem.meta.tolerance
    units = problem.meta.units
    seed = int(problem.meta.solver.seed)
    fb = solution.linkage
    tg = targets(problem, solution)
    conv = (lambda x: float(units.from_rad(x))) if tg.kind == "angle" else float
    opt = (lambda x: None if x is None or not math.isfinite(x) else conv(x))
    level = tol.max_failure_probability if isinstance(tol, InverseTolerance) else None
    out: dict = {"measure": tg.measure, "samples": tol.samples, "distribution": tol.distribution,
                 "lengths": {k: float(v) for k, v in tol.lengths.items()},
                 "clearance": float(tol.clearance)}
    if len(tg.phi) == 0:
        out["message"] = "the nominal linkage cannot assemble at any input angle"
        return out
    lengths = dict(tol.lengths)
    if level is not None:
        given = max((lengths.get(k, 0.0) for k in LINKS), default=0.0)
        t, p_t = largest_tolerance(fb, tg, tol, seed, level, given)
        if not tol.lengths_given:  # no tolerance written: report the study at the one found
            # (a written 0, exact parts, is a study of its own and is reported as 0)
            lengths = {k: t for k in LINKS}
            out["lengths"] = {k: float(t) for k in LINKS}
    err, ok = monte_carlo(fb, tg, scale_vector(lengths), tol.clearance, tol.samples, seed,
                          tol.distribution)
    nominal, _ = sample_errors(fb, tg, np.zeros((1, len(COLUMNS))), None)
    scale = 1.0 if tg.kind == "angle" else max(fb.abcd)
    good = snap(err[ok], scale)  # round-off of an exact design (exact parts) is 0
    n = tol.samples
    k = failures(err, ok, tol.allowed_error)
    p = k / n
    lo, hi = wilson(k, n)
    out.update({
        "nominal_error": opt(snap(float(nominal[0]), scale)),
        "error_mean": opt(float(good.mean())) if good.size else None,
        "error_p95": opt(float(np.percentile(good, 95))) if good.size else None,
        "error_max": opt(float(good.max())) if good.size else None,
        "allowed_error": opt(tol.allowed_error),
    })
    if tol.allowed_error is None:
        out["failure"] = NO_ALLOWED_ERROR
    out.update({
        "assembly_failures": int(n - good.size),
        "failure_probability": p,
        "failure_probability_se": math.sqrt(p * (1.0 - p) / n),
        "failure_probability_ci95": [lo, hi],
        "sensitivity": {link: opt(s) for link, s in sensitivity(fb, tg).items()},
    })
    if level is not None:
        out["max_failure_probability"] = float(level)
        out["largest_tolerance"] = float(t)
        out["failure_probability_at_largest"] = float(p_t)
    return out
