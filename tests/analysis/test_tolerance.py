"""Tolerance Monte Carlo against independent references.

References written here, not taken from linkcli.analysis.tolerance:
- a per-sample loop that builds each manufactured linkage from its pins (circle-circle
  intersection for the joint B, the branch picked by the sign of a cross product, the
  clearance offsets placed at the physical joints) and checks the input's travel on a
  dense grid of input angles;
- first-order statistics for small tolerances from the analytic derivatives of the loop
  equation a e^{i phi} + b e^{i theta} = d + c e^{i psi} (implicit differentiation).
"""

from __future__ import annotations

import cmath
import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from linkcli.analysis import inverse_search, tolerance_report
from linkcli.analysis import tolerance as tolmod
from linkcli.errors import InputErrors
from linkcli.mechanisms.four_bar import tolerance as fourbar_tolerance
from linkcli.mechanisms.four_bar.model import LINKS, FourBar
from linkcli.model import InverseTolerance, Meta, SolverOptions, Tolerance
from linkcli.pipeline import solve
from linkcli.reading.load import load
from linkcli.solution import Positions, Solution, Status
from linkcli.units import Units

ROOT = Path(__file__).resolve().parents[2]
DEG = math.pi / 180
# The fire-door linkage (docs/format.md, precision-position example)
FIREDOOR = FourBar(ground=50.0, input=27.6293, coupler=57.2363, output=41.1104, branch="open")
# A path linkage: the fire-door lengths with a coupler point, placed and turned
PATHBAR = FourBar(ground=50.0, input=27.6293, coupler=57.2363, output=41.1104, branch="open",
                  coupler_point=(20.0, 10.0), ground_pivot=(5.0, -3.0), ground_angle=30 * DEG)


# ---------------------------------------------------------------- the reference

def ref_assemble(a, b, c, d, phi, branch, e=(0j, 0j, 0j, 0j), cp=(0.0, 0.0)):
    """One manufactured linkage at one input, from its pins; None if it cannot assemble.

    Offsets e = (A0, A, B, B0): the crank's journal at A0 + e1, the coupler's bore at
    A + e2, the rocker's pin at B = coupler bore + e3, the rocker's ground journal at
    B0 + e4. Returns (psi, theta, coupler point in the local frame)."""
    e1, e2, e3, e4 = e
    crank_tip = e1 + a * cmath.exp(1j * phi)
    bore_a = crank_tip + e2
    c1 = bore_a + e3  # the rocker pin lies at distance b from here
    c2 = d + e4  # and at distance c from here
    dist = abs(c2 - c1)
    if dist == 0 or dist > b + c or dist < abs(b - c):
        return None
    u = (c2 - c1) / dist
    along = (b * b - c * c + dist * dist) / (2 * dist)
    h = math.sqrt(max(b * b - along * along, 0.0))
    found = None
    for pin in (c1 + along * u + 1j * h * u, c1 + along * u - 1j * h * u):
        v1, v2 = c1 - c2, pin - c2
        cross = v1.real * v2.imag - v1.imag * v2.real
        if (cross <= 0) == (branch == "open"):
            found = pin
            break
    psi = cmath.phase(found - c2)
    theta = cmath.phase(found - e3 - bore_a)
    point = bore_a + complex(*cp) * cmath.exp(1j * theta)
    return psi, theta, point


def ref_travels(a, b, c, d, start, sweep, n=2001):
    """The input runs from start over sweep: assembles at every one of n grid angles."""
    rho = np.abs(a * np.exp(1j * np.linspace(start, start + sweep, n)) - d)
    return bool(np.all((rho <= b + c) & (rho >= abs(b - c))))


def ref_errors(fb, phi, kind, target, dl, off, span):
    """Per-sample loop: the largest error over the targets, inf for a failed sample."""
    out = np.empty(len(dl))
    for i in range(len(dl)):
        d, a, b, c = (fb.ground + dl[i, 0], fb.input + dl[i, 1], fb.coupler + dl[i, 2],
                      fb.output + dl[i, 3])
        cp = ((fb.coupler_point[0] + dl[i, 4], fb.coupler_point[1] + dl[i, 5])
              if fb.coupler_point else (0.0, 0.0))
        worst, failed = 0.0, min(a, b, c, d) <= 0
        if not failed and span is not None:
            failed = not ref_travels(a, b, c, d, *span)
        for j in range(len(phi)):
            if failed:
                break
            e = ((0j,) * 4 if off is None
                 else tuple(complex(off[i, j, k, 0], off[i, j, k, 1]) for k in range(4)))
            r = ref_assemble(a, b, c, d, phi[j], fb.branch, e, cp)
            if r is None:
                failed = True
                break
            if kind == "angle":
                dev = abs((r[0] - target[j] + math.pi) % (2 * math.pi) - math.pi)
            else:
                p = complex(*fb.ground_pivot) + cmath.exp(1j * fb.ground_angle) * r[2]
                dev = abs(p - complex(*target[j]))
            worst = max(worst, dev)
        out[i] = math.inf if failed else worst
    return out


def dpsi_dlengths(fb, phi):
    """Analytic d psi / d (ground, input, coupler, output) and d theta / d (...) at phi.

    Differentiating the loop: F = da e^{i phi} + db e^{i theta} - dc e^{i psi} - dd,
    c sin(psi - theta) dpsi = -Re(F e^{-i theta}), b sin(theta - psi) dtheta = Re(F e^{-i psi})."""
    r = ref_assemble(fb.input, fb.coupler, fb.output, fb.ground, phi, fb.branch)
    psi, theta = r[0], r[1]
    unit = {"ground": -1.0 + 0j, "input": cmath.exp(1j * phi), "coupler": cmath.exp(1j * theta),
            "output": -cmath.exp(1j * psi)}
    dpsi = {k: -(f * cmath.exp(-1j * theta)).real / (fb.output * math.sin(psi - theta))
            for k, f in unit.items()}
    dtheta = {k: (f * cmath.exp(-1j * psi)).real / (fb.coupler * math.sin(theta - psi))
              for k, f in unit.items()}
    return dpsi, dtheta, psi, theta


def dpoint_dlengths(fb, phi):
    """Analytic d P_global / d length (complex), P = A0 + e^{i g}(a e^{i phi} + z e^{i theta})."""
    _, dtheta, _, theta = dpsi_dlengths(fb, phi)
    z = complex(*fb.coupler_point)
    rot = cmath.exp(1j * fb.ground_angle)
    out = {k: rot * 1j * z * cmath.exp(1j * theta) * dtheta[k] for k in LINKS}
    out["input"] += rot * cmath.exp(1j * phi)
    return out


def ref_point(fb, phi):
    r = ref_assemble(fb.input, fb.coupler, fb.output, fb.ground, phi, fb.branch,
                     cp=fb.coupler_point)
    p = complex(*fb.ground_pivot) + cmath.exp(1j * fb.ground_angle) * r[2]
    return [p.real, p.imag]


# ---------------------------------------------------------------- problem builders

class _Problem:
    def __init__(self, meta):
        self.meta = meta


def make(fb, tol, *, kind="angle", phi_deg=(45, 90, 135), target=None, seed=0,
         ptype="precision-position", angle="deg", positions=True):
    """A (problem, solution) pair built by hand around a known linkage."""
    meta = Meta(path="test.toml", type=ptype, units=Units(angle=angle), tolerance=tol,
                sections=("tolerance",), solver=SolverOptions(seed=seed))
    phi = np.array(phi_deg, dtype=float) * DEG
    pos = None
    if positions:
        if kind == "angle":
            tgt = (np.array([ref_assemble(fb.input, fb.coupler, fb.output, fb.ground, p,
                                          fb.branch)[0] for p in phi])
                   if target is None else np.asarray(target, dtype=float))
            pos = Positions("angle", phi, tgt, tgt, np.zeros(len(phi)))
        else:
            tgt = (np.array([ref_point(fb, p) for p in phi]) if target is None
                   else np.asarray(target, dtype=float))
            pos = Positions("point", phi, tgt, tgt, np.zeros(len(phi)))
    sol = Solution(status=Status.OK, linkage=fb, positions=pos,
                   working_span=(float(phi[0]), float(phi[-1] - phi[0])) if positions else None)
    return _Problem(meta), sol


def tol(lengths=0.05, **kw):
    table = lengths if isinstance(lengths, dict) else {k: lengths for k in LINKS}
    return Tolerance(lengths=table, **kw)


def all_draws(problem, solution):
    """The module's draws for the problem, scaled to lengths (checked separately below)."""
    t = problem.meta.tolerance
    tg = fourbar_tolerance.targets(problem, solution)
    dls, offs = [], []
    key = {"coupler_point_x": "coupler_point", "coupler_point_y": "coupler_point"}  # +- on each coordinate
    scale = np.array([float(t.lengths.get(key.get(k, k), 0.0)) for k in fourbar_tolerance.COLUMNS])
    for u, e, _ in tolmod.unit_draws(problem.meta.solver.seed, t.samples, len(tg.phi),
                                     len(fourbar_tolerance.COLUMNS), t.distribution,
                                     4 if t.clearance > 0 else 0):
        dls.append(u * scale)
        offs.append(None if e is None else e * t.clearance)
    off = None if offs[0] is None else np.concatenate(offs)
    return tg, np.concatenate(dls), off


def check_against_loop(problem, solution, min_failures=0):
    """analyse() against the per-sample loop on the same draws: every statistic."""
    tg, dl, off = all_draws(problem, solution)
    t = problem.meta.tolerance
    fb = solution.linkage
    ref = ref_errors(fb, tg.phi, tg.kind, tg.value, dl, off, tg.span)
    err, ok = fourbar_tolerance.sample_errors(fb, tg, dl, off)
    assert_allclose(np.isfinite(ref), ok)
    assert_allclose(err[ok], ref[ok], rtol=1e-9, atol=1e-12)
    rep = tolerance_report.analyse(problem, solution)
    conv = (lambda x: x / DEG) if tg.kind == "angle" else (lambda x: x)
    good = ref[np.isfinite(ref)]
    allowed = t.allowed_error if t.allowed_error is not None else math.inf
    fails = int(np.sum(~np.isfinite(ref) | (ref > allowed)))
    assert fails >= min_failures
    assert rep["samples"] == t.samples
    assert rep["assembly_failures"] == int(np.sum(~np.isfinite(ref)))
    assert_allclose(rep["error_mean"], conv(good.mean()), rtol=1e-9)
    assert_allclose(rep["error_p95"], conv(np.percentile(good, 95)), rtol=1e-9)
    assert_allclose(rep["error_max"], conv(good.max()), rtol=1e-9)
    p = fails / t.samples
    assert_allclose(rep["failure_probability"], p, rtol=1e-12)
    assert_allclose(rep["failure_probability_se"], math.sqrt(p * (1 - p) / t.samples), rtol=1e-12)
    return rep


# ---------------------------------------------------------------- against the loop

def test_precision_position_matches_per_sample_loop():
    problem, solution = make(FIREDOOR, tol(0.05, clearance=0.02, samples=1500,
                                           allowed_error=0.2 * DEG), seed=3)
    rep = check_against_loop(problem, solution, min_failures=20)
    assert rep["assembly_failures"] == 0


def test_normal_distribution_matches_per_sample_loop():
    problem, solution = make(FIREDOOR, tol({"ground": 0.02, "input": 0.1, "coupler": 0.0,
                                            "output": 0.05}, distribution="normal",
                                           samples=1500, allowed_error=0.15 * DEG), seed=11)
    check_against_loop(problem, solution, min_failures=20)


def test_path_matches_per_sample_loop():
    phi = (60, 100, 140, 180, 220)  # the span crosses 180 deg: travel checked at phi = pi
    pts = np.array([ref_point(PATHBAR, p * DEG) for p in phi]) + [[0.05, -0.02]] * 5
    t = tol({"ground": 0.1, "input": 0.05, "coupler": 0.1, "output": 0.1, "coupler_point": 0.05},
            clearance=0.03, samples=1200, allowed_error=0.12)
    problem, solution = make(PATHBAR, t, kind="point", phi_deg=phi, target=pts,
                             ptype="path-generation", seed=5)
    rep = check_against_loop(problem, solution, min_failures=20)
    assert_allclose(rep["nominal_error"], math.hypot(0.05, 0.02), rtol=1e-9)


def test_failures_to_assemble_and_travel_match_loop():
    # A crank-rocker close to the Grashof limit (s + l = 74 < p + q = 75): with +-1 many
    # samples lose the full turn of the crank. Type linkage: 36 inputs over the full turn.
    fb = FourBar(ground=54.0, input=20.0, coupler=40.0, output=35.0, branch="open")
    problem, solution = make(fb, tol(1.0, samples=800, allowed_error=2 * DEG), ptype="linkage",
                             positions=False, phi_deg=(0,), seed=2)
    tg = fourbar_tolerance.targets(problem, solution)
    assert len(tg.phi) == 36 and tg.span == (0.0, 2 * math.pi)
    assert_allclose(tg.phi, np.arange(36) * 10 * DEG)
    rep = check_against_loop(problem, solution, min_failures=100)
    assert 100 < rep["assembly_failures"] < 700
    assert rep["nominal_error"] == 0.0


def test_dead_point_between_targets_is_a_failure():
    # Targets at 140 and 220 deg; the crank passes 180 deg in between, where rho = a + d is
    # largest. Samples with b + c below a + d assemble at both targets but cannot get there.
    fb = FourBar(ground=54.0, input=20.0, coupler=40.0, output=35.0, branch="open")
    problem, solution = make(fb, tol(1.0, samples=600, allowed_error=5 * DEG),
                             phi_deg=(140, 220), seed=6)
    tg, dl, off = all_draws(problem, solution)
    at_targets = ref_errors(fb, tg.phi, "angle", tg.value, dl, off, None)
    with_travel = ref_errors(fb, tg.phi, "angle", tg.value, dl, off, tg.span)
    travel_only = np.isfinite(at_targets) & ~np.isfinite(with_travel)
    assert travel_only.sum() >= 30
    rep = check_against_loop(problem, solution)
    assert rep["assembly_failures"] == int(np.sum(~np.isfinite(with_travel)))


def test_rocking_input_grid_lies_inside_the_arc():
    # A triple rocker (s + l = 75 > p + q = 65): the input rocks over |phi| <= g, where
    # rho = |A B0| reaches b + c. The 36 inputs are the centres of 36 equal cells.
    fb = FourBar(ground=50.0, input=30.0, coupler=25.0, output=35.0, branch="crossed")
    problem, solution = make(fb, tol(0.3, samples=400, allowed_error=1.0 * DEG),
                             ptype="linkage", positions=False, phi_deg=(0,), seed=4)
    tg = fourbar_tolerance.targets(problem, solution)
    g = math.acos((30**2 + 50**2 - (25 + 35) ** 2) / (2 * 30 * 50))
    assert_allclose(tg.phi, -g + (np.arange(36) + 0.5) * (2 * g / 36), rtol=1e-12)
    check_against_loop(problem, solution, min_failures=10)


# ---------------------------------------------------------------- first-order theory

def _first_order_setup(fb, phi):
    dpsi, *_ = dpsi_dlengths(fb, phi)
    return np.array([dpsi[k] for k in LINKS])


def test_analytic_derivatives_match_reference_finite_difference():
    phi = 70 * DEG
    g = _first_order_setup(FIREDOOR, phi)
    h = 1e-6
    for k, link in enumerate(LINKS):
        lengths = dict(ground=FIREDOOR.ground, input=FIREDOOR.input, coupler=FIREDOOR.coupler,
                       output=FIREDOOR.output)
        vals = []
        for s in (h, -h):
            x = dict(lengths)
            x[link] += s
            vals.append(ref_assemble(x["input"], x["coupler"], x["output"], x["ground"], phi,
                                     "open")[0])
        assert_allclose((vals[0] - vals[1]) / (2 * h), g[k], rtol=1e-6)


def test_sensitivity_is_the_analytic_derivative():
    problem, solution = make(FIREDOOR, tol(0.05, samples=10))
    rep = tolerance_report.analyse(problem, solution)
    g = np.array([_first_order_setup(FIREDOOR, p * DEG) for p in (45, 90, 135)])
    expect = np.abs(g).max(axis=0) / DEG  # deg per mm
    assert_allclose([rep["sensitivity"][k] for k in LINKS], expect, rtol=1e-6)


def test_path_sensitivity_is_the_analytic_derivative():
    phi = (60, 100, 140)
    problem, solution = make(PATHBAR, tol(0.05, samples=10), kind="point", phi_deg=phi,
                             ptype="path-generation")
    rep = tolerance_report.analyse(problem, solution)
    mags = np.array([[abs(dpoint_dlengths(PATHBAR, p * DEG)[k]) for k in LINKS] for p in phi])
    assert_allclose([rep["sensitivity"][k] for k in LINKS], mags.max(axis=0), rtol=1e-6)


def test_small_normal_tolerance_follows_first_order_gaussian():
    # One target: error = |sum_l g_l dl_l|, dl_l ~ N(0, (t/3)^2) -> |N(0, s^2)|:
    # mean s sqrt(2/pi), 95th percentile 1.959964 s, P(error > s) = 0.317311.
    t, n = 0.01, 40000
    g = _first_order_setup(FIREDOOR, 90 * DEG)
    s = (t / 3) * math.sqrt(float(g @ g))
    problem, solution = make(FIREDOOR, tol(t, distribution="normal", samples=n, allowed_error=s),
                             phi_deg=(90,), seed=7)
    rep = tolerance_report.analyse(problem, solution)
    assert_allclose(rep["error_mean"] * DEG, s * math.sqrt(2 / math.pi), rtol=0.02)
    assert_allclose(rep["error_p95"] * DEG, 1.959964 * s, rtol=0.03)
    p = 2 * (1 - 0.5 * (1 + math.erf(1 / math.sqrt(2))))
    assert abs(rep["failure_probability"] - p) < 4 * math.sqrt(p * (1 - p) / n)
    assert_allclose(rep["failure_probability_se"], math.sqrt(p * (1 - p) / n), rtol=0.05)


def test_small_uniform_tolerance_path_follows_first_order_model():
    # One target: error = |J dl| with J the analytic 2x4 Jacobian; its mean is taken from
    # a million draws of the linear model (independent generator).
    t, n, phi = 0.01, 40000, 120 * DEG
    jac = np.array([dpoint_dlengths(PATHBAR, phi)[k] for k in LINKS])
    rng = np.random.default_rng(12345)
    lin = np.abs(rng.uniform(-t, t, (1_000_000, 4)) @ jac)
    problem, solution = make(PATHBAR, tol(t, samples=n), kind="point", phi_deg=(120,),
                             ptype="path-generation", seed=8)
    rep = tolerance_report.analyse(problem, solution)
    assert_allclose(rep["error_mean"], lin.mean(), rtol=0.02)
    assert_allclose(rep["error_p95"], np.percentile(lin, 95), rtol=0.03)


def test_clearance_alone_follows_first_order_model():
    # The four offsets add up to an effective ground vector d + E, E_x, E_y of variance r^2;
    # psi moves by dpsi/dd E_x + (1 - dpsi/dphi) E_y / d (the ground turning by E_y / d).
    r, n, phi = 0.01, 40000, 90 * DEG
    g_d = _first_order_setup(FIREDOOR, phi)[0]
    h = 1e-6
    k = (ref_assemble(*FIREDOOR.abcd, phi + h, "open")[0]
         - ref_assemble(*FIREDOOR.abcd, phi - h, "open")[0]) / (2 * h)
    rng = np.random.default_rng(99)
    rad = r * np.sqrt(rng.random((1_000_000, 4)))
    ang = rng.random((1_000_000, 4)) * 2 * math.pi
    ex = (rad * np.cos(ang)).sum(axis=1)  # signs do not matter: isotropic
    ey = (rad * np.sin(ang)).sum(axis=1)
    lin = np.abs(g_d * ex + (1 - k) * ey / FIREDOOR.ground)
    assert_allclose(np.mean(lin**2), r**2 * (g_d**2 + ((1 - k) / FIREDOOR.ground) ** 2), rtol=0.01)
    problem, solution = make(FIREDOOR, tol(0.0, clearance=r, samples=n), phi_deg=(90,), seed=9)
    rep = tolerance_report.analyse(problem, solution)
    assert_allclose(rep["error_mean"] * DEG, lin.mean(), rtol=0.02)
    assert_allclose(rep["error_p95"] * DEG, np.percentile(lin, 95), rtol=0.03)


# ---------------------------------------------------------------- draws, determinism, units

def test_unit_draws_have_the_stated_distributions():
    u, e, _ = next(tolmod.unit_draws(0, 50000, 2, 6, "uniform", 4))
    assert u.shape == (50000, 6) and e.shape == (50000, 2, 4, 2)
    assert u.min() >= -1 and u.max() <= 1
    assert_allclose(u.var(axis=0), 1 / 3, rtol=0.02)  # uniform on [-1, 1]
    r2 = (e**2).sum(axis=-1)
    assert r2.max() <= 1
    assert_allclose(r2.mean(), 0.5, rtol=0.01)  # uniform over the disc: E r^2 = 1/2
    assert_allclose(np.mean(e, axis=(0, 1, 2)), 0, atol=0.01)
    un, none, _ = next(tolmod.unit_draws(0, 50000, 2, 6, "normal"))
    assert none is None
    assert_allclose(un.std(axis=0), 1 / 3, rtol=0.02)  # the tolerance is 3 sigma


def test_chunks_cover_every_sample_once():
    m = 7
    rows = tolmod.CHUNK_ELEMENTS // m
    n = 2 * rows + 5
    sizes = [len(u) for u, _, _ in tolmod.unit_draws(0, n, m, 6, "uniform")]
    assert sizes == [rows, rows, 5]


def test_same_seed_same_numbers_other_seed_other_numbers():
    t = tol(0.05, clearance=0.02, samples=3000, allowed_error=0.2 * DEG)
    a = tolerance_report.analyse(*make(FIREDOOR, t, seed=4))
    b = tolerance_report.analyse(*make(FIREDOOR, t, seed=4))
    c = tolerance_report.analyse(*make(FIREDOOR, t, seed=5))
    assert a == b
    assert a["error_mean"] != c["error_mean"]


def test_radian_files_report_radians():
    t = tol(0.05, clearance=0.02, samples=2000, allowed_error=0.2 * DEG)
    deg = tolerance_report.analyse(*make(FIREDOOR, t, seed=4))
    rad = tolerance_report.analyse(*make(FIREDOOR, t, seed=4, angle="rad"))
    for key in ("error_mean", "error_p95", "error_max", "allowed_error"):
        assert_allclose(rad[key], deg[key] * DEG, rtol=1e-12)
    assert_allclose(rad["sensitivity"]["input"], deg["sensitivity"]["input"] * DEG, rtol=1e-12)
    assert rad["failure_probability"] == deg["failure_probability"]


def test_without_allowed_error_only_assembly_failures_count():
    fb = FourBar(ground=54.0, input=20.0, coupler=40.0, output=35.0, branch="open")
    problem, solution = make(fb, tol(0.5, samples=500), ptype="linkage", positions=False,
                             phi_deg=(0,), seed=2)
    rep = tolerance_report.analyse(problem, solution)
    assert rep["allowed_error"] is None
    assert rep["assembly_failures"] > 0
    assert rep["failure_probability"] == rep["assembly_failures"] / 500
    # the report says what a failure is then
    assert rep["failure"].startswith("no allowed_error given: a sample fails only when it cannot")
    with_allowed = tolerance_report.analyse(*make(fb, tol(0.5, samples=500, allowed_error=1.0), ptype="linkage",
                                        positions=False, phi_deg=(0,), seed=2))
    assert "failure" not in with_allowed


# ---------------------------------------------------------------- inverse mode

def _inverse(level, allowed_deg, seed=1, samples=4000, clearance=0.0):
    t = InverseTolerance(lengths={k: 0.0 for k in LINKS}, clearance=clearance, samples=samples,
                         allowed_error=allowed_deg * DEG, max_failure_probability=level)
    return make(FIREDOOR, t, seed=seed)


def test_inverse_mode_finds_the_boundary_of_the_seeded_monte_carlo():
    problem, solution = _inverse(0.02, 0.2, clearance=0.01)
    rep = tolerance_report.analyse(problem, solution)
    t_max = rep["largest_tolerance"]
    assert rep["failure_probability_at_largest"] <= 0.02
    # the study is reported at the tolerance found (no `lengths` given)
    assert rep["lengths"]["input"] == t_max and rep["failure_probability"] <= 0.02
    # an independent check: the forward study just above the tolerance found fails more
    above = tol(t_max * (1 + 2 * inverse_search.BISECTION_RTOL), clearance=0.01, samples=4000,
                allowed_error=0.2 * DEG)
    assert tolerance_report.analyse(*make(FIREDOOR, above, seed=1))["failure_probability"] > 0.02


def test_inverse_mode_first_order_value():
    # Uniform dl on all links, one target, no clearance: error ~ |sum g_l U(-t, t)|, whose
    # 1 - level quantile is linear in t; the quantile of the linear model at t = 1 (an
    # independent million-draw Monte Carlo) gives t_max = allowed / q.
    phi = 90 * DEG
    g = _first_order_setup(FIREDOOR, phi)
    rng = np.random.default_rng(2024)
    q = np.percentile(np.abs(rng.uniform(-1, 1, (1_000_000, 4)) @ g), 95)
    allowed = 0.05 * DEG
    t = InverseTolerance(lengths={k: 0.0 for k in LINKS}, samples=20000, allowed_error=allowed,
                         max_failure_probability=0.05)
    rep = tolerance_report.analyse(*make(FIREDOOR, t, phi_deg=(90,), seed=3))
    assert_allclose(rep["largest_tolerance"], allowed / q, rtol=0.03)


def test_inverse_mode_clearance_alone_too_large():
    problem, solution = _inverse(0.01, 0.01, clearance=0.5)
    rep = tolerance_report.analyse(problem, solution)
    assert rep["largest_tolerance"] == 0.0
    assert rep["failure_probability_at_largest"] > 0.01


# ---------------------------------------------------------------- problem files

def test_firedoor_tolerance_example():
    problem = load("problems/firedoor_tolerance.toml")
    t = problem.meta.tolerance
    assert isinstance(t, InverseTolerance) and t.max_failure_probability == 0.01
    assert t.lengths == {k: 0.05 for k in LINKS} and t.clearance == 0.02
    assert_allclose(t.allowed_error, 0.25 * DEG)
    solution = solve(problem)
    rep = tolerance_report.analyse(problem, solution)
    assert rep["samples"] == 20000 and rep["assembly_failures"] == 0
    assert rep["nominal_error"] < 1e-9
    assert 0.0 < rep["failure_probability"] < 0.2
    assert 0.0 < rep["largest_tolerance"] < 0.05  # tighter than the drawing's 0.05 mm


def test_path_table_may_hold_the_coupler_point():
    text = """type = "path-generation"
[tolerance]
lengths = { input = 0.02, coupler_point = 0.1 }
allowed_error = 0.3
"""
    from linkcli.io.reader import Reader
    from linkcli.reading.meta import read_tolerance
    reader = Reader("p.toml", text)
    got = read_tolerance(reader.root(), Units())
    assert got.lengths == {"ground": 0.0, "input": 0.02, "coupler": 0.0, "output": 0.0,
                           "coupler_point": 0.1}
    assert got.allowed_error == 0.3  # a length: not converted to radians


BASE = """type = "precision-position"
[linkage]
ground = 50.0
[positions]
input  = [45, 90, 135]
output = [52, 82, 112]
[tolerance]
"""


@pytest.mark.parametrize("body, key, expected", [
    ("lengths = -0.05", "tolerance.lengths", "a tolerance >= 0"),
    ("samples = 0", "tolerance.samples", "an integer in [1, 1000000]"),
    ("samples = 2000000", "tolerance.samples", "an integer in [1, 1000000]"),
    ("samples = -3", "tolerance.samples", "an integer in [1, 1000000]"),
    ("lengths = { crank = 0.02 }", "tolerance.lengths.crank", "a known key"),
    ("lengths = { coupler_point = 0.02 }", "tolerance.lengths.coupler_point", "a known key"),
    ("lengths = { input = -1 }", "tolerance.lengths.input", "a tolerance >= 0"),
    ("clearance = -0.1", "tolerance.clearance", "a radial clearance >= 0"),
    ("allowed_error = -1", "tolerance.allowed_error", "a positive number"),
    ('distribution = "gauss"', "tolerance.distribution", "one of: uniform, normal"),
    ("max_failure_probability = 0", "tolerance.max_failure_probability", "strictly between"),
    # below 10 / 1,000,000 no sample count can be enough: a denormal overflowed the count
    # (an internal error), 1e-300 asked for a 300-digit one of `samples`
    ("max_failure_probability = 5e-324\nallowed_error = 0.5", "tolerance.max_failure_probability",
     "a probability of at least 1e-05"),
    ("max_failure_probability = 1e-300\nallowed_error = 0.5", "tolerance.max_failure_probability",
     "a probability of at least 1e-05"),
    ("max_failure_probability = 9.9e-6\nsamples = 1000000\nallowed_error = 0.5",
     "tolerance.max_failure_probability", "a probability of at least 1e-05"),
    ("lengths = { input = 1 }\nmax_failure_probability = 0.1\nallowed_error = 0.5", "tolerance.lengths",
     "a single"),
    ("samples = 100\nmax_failure_probability = 0.01\nallowed_error = 0.5", "tolerance.samples",
     "at least 1000 samples"),
])
def test_bad_tolerance_is_a_schema_error_with_line_and_key(body, key, expected):
    with pytest.raises(InputErrors) as info:
        load("bad.toml", BASE + body + "\n")
    errors = info.value.errors
    assert len(errors) == 1
    assert errors[0].key == key and errors[0].line == 8
    assert expected in errors[0].expected
    assert str(errors[0]).startswith(f"bad.toml:8: {key}: expected ")


def test_the_least_failure_probability_is_met_by_the_most_samples():
    tolerance = load("p.toml", BASE + "max_failure_probability = 1e-5\nsamples = 1000000\n"
                     "allowed_error = 0.5\n").meta.tolerance
    assert isinstance(tolerance, InverseTolerance) and tolerance.max_failure_probability == 1e-5


@pytest.mark.parametrize("bad", sorted((ROOT / "tests" / "bad").glob("tolerance_*.toml")))
def test_bad_files_give_their_expected_text(bad):
    rel = bad.relative_to(ROOT).as_posix()
    with pytest.raises(InputErrors) as info:
        load(rel)
    expected = bad.with_suffix(".txt").read_text(encoding="utf-8")
    assert "\n".join(info.value.lines()) + "\n" == expected


@pytest.mark.parametrize("lengths, clearance, key, expected", [
    (30.0, 0.0, "tolerance.lengths", "a tolerance smaller than the input length (27.6293)"),
    ({"ground": 0.1, "input": 0.1, "coupler": 60.0, "output": 0.1}, 0.0,
     "tolerance.lengths.coupler", "a tolerance smaller than the coupler length (57.2363)"),
    (0.05, 27.7, "tolerance.clearance", "a clearance smaller than the shortest link (27.6293)"),
])
def test_tolerance_as_large_as_a_link_is_an_input_error(lengths, clearance, key, expected):
    from linkcli.errors import InputError
    problem, solution = make(FIREDOOR, tol(lengths, clearance=clearance, samples=10))
    with pytest.raises(InputError) as info:
        tolerance_report.analyse(problem, solution)
    assert info.value.key == key and info.value.expected == expected
    assert info.value.exit_code == 2


def test_inverse_mode_without_allowed_error_is_an_input_error():
    with pytest.raises(InputErrors) as info:
        load("bad.toml", BASE + "lengths = 0.05\nmax_failure_probability = 0.01\n")
    (err,) = info.value.errors
    assert (err.key, err.line) == ("tolerance.allowed_error", 7)  # the [tolerance] header
    assert err.expected.startswith("a positive number (needed by max_failure_probability")
    assert err.got == "nothing (the key is missing)"


LINKAGE_FILE = """type = "linkage"
[linkage]
ground = 50
input = 27.6293
coupler = 57.2363
output = 41.1104
"""


@pytest.mark.parametrize("body, line, key, expected", [
    ("[tolerance]\nsamples = 10\nclearance = 100\n", 9, "tolerance.clearance",
     "a clearance smaller than the shortest link (27.6293), found 100"),
    ("[tolerance]\nlengths = 30\n", 8, "tolerance.lengths",
     "a tolerance smaller than the input length (27.6293), found 30"),
    ("[tolerance]\nsamples = 10\nlengths = { input = 0.1, coupler = 60 }\n", 9,
     "tolerance.lengths.coupler", "a tolerance smaller than the coupler length (57.2363), found 60"),
    ("[tolerance]\nsamples = 10\n[tolerance.lengths]\ninput = 0.1\n\noutput = 45\n", 12,
     "tolerance.lengths.output", "a tolerance smaller than the output length (41.1104), found 45"),
])
def test_solve_time_tolerance_errors_give_the_line_of_their_key(body, line, key, expected):
    """Known from the file (a linkage file fixes every length): refused when read, so
    `check` and `synth` give the same line (issue 21); the analysis keeps the same check
    for solved linkages."""
    from linkcli.errors import InputError
    with pytest.raises(InputError) as info:
        load("tl.toml", LINKAGE_FILE + body)
    assert str(info.value) == f"tl.toml:{line}: {key}: expected {expected}"


def test_linkage_file_end_to_end():
    # type = "linkage": the nominal output over 36 inputs is the target; the reference is
    # the per-sample loop on the same draws.
    text = """type = "linkage"
[linkage]
ground = 50
input = 27.6293
coupler = 57.2363
output = 41.1104
[tolerance]
lengths = 0.1
clearance = 0.02
samples = 300
allowed_error = 0.3
[solver]
seed = 21
"""
    problem = load("linkage.toml", text)
    solution = solve(problem)
    rep = check_against_loop(problem, solution, min_failures=10)
    assert rep["measure"].startswith("largest deviation from the nominal output angle at 36")
    assert rep["nominal_error"] == 0.0
