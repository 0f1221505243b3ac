"""The slider-crank (issue 15): kinematics, precision positions, tolerances.

References written here, not taken from linkcli.mechanisms:
- the slider position as the root of the quadratic |B - A|^2 = b^2 in s,
  s^2 - 2 s a cos(phi) + a^2 + e^2 - 2 a e sin(phi) - b^2 = 0, and its velocity and
  acceleration by implicit differentiation of that quadratic F(s, phi) = 0;
- the rod angle from the complex loop a e^{i phi} + b e^{i theta} = s + i e;
- central finite differences; dense crank sweeps for stroke, time ratio and arcs;
- scipy.optimize.least_squares from many starts for the least-squares fit;
- a Monte Carlo that places the clearance offsets at the physical joints.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from linkcli.analysis import tolerance, tolerance_report
from linkcli.errors import SchemaError
from linkcli.mechanisms.slider_crank import kinematics as sc
from linkcli.mechanisms.slider_crank import tolerance as stol
from linkcli.model import InverseTolerance, LinkageProblem, Meta, SolverOptions, Tolerance
from linkcli.solution import Positions, Solution, Status
from linkcli.types.precision_position import slider_synthesis as spp

pytestmark = pytest.mark.filterwarnings("error")

TEXTBOOK = (47.2812, 104.9139, 30.0)


# ---------------------------------------------------------------- the code under test

def tolerance_section(lin, lengths, *, clearance=0.0, clearance_slider=0.0, samples=20000, seed=0,
                      distribution="uniform", allowed_error=None, max_failure_probability=None,
                      targets=None):
    """The `tolerance` section of a slider-crank linkage problem (analysis.tolerance_report.analyse),
    with targets (crank angle, slider position) as precision positions when given."""
    given = {k: float(lengths.get(k, 0.0)) for k in stol.LENGTH_KEYS}
    common = dict(lengths=given, distribution=distribution, clearance=clearance,
                  clearance_slider=clearance_slider, samples=samples, allowed_error=allowed_error)
    tol = (Tolerance(**common) if max_failure_probability is None else
           InverseTolerance(max_failure_probability=max_failure_probability,
                            lengths_given=any(v > 0 for v in given.values()), **common))
    meta = Meta(path="t.toml", type="linkage", solver=SolverOptions(seed=seed), tolerance=tol)
    positions = None if targets is None else Positions("slider", targets.phi, targets.slider,
                                                       targets.slider, np.zeros(len(targets.phi)))
    solution = Solution(Status.OK, linkage=lin, positions=positions,
                        working_span=None if targets is None else targets.span)
    return tolerance_report.analyse(LinkageProblem(meta=meta, linkage=lin), solution)


def mc(lin, tg, scale, clearance, clearance_slider, n, seed):
    return tolerance.monte_carlo(stol.Model(lin, tg), np.asarray(scale, dtype=float), clearance,
                                 clearance_slider, n, seed, "uniform")


# ---------------------------------------------------------------- the references

def ref_slider(a, b, e, phi, sign):
    """Root of s^2 - 2 s a cos(phi) + (a^2 + e^2 - 2 a e sin(phi) - b^2) = 0 (sign +1 open)."""
    p = a * np.cos(phi)
    q = a * a + e * e - 2 * a * e * np.sin(phi) - b * b
    return p + sign * np.sqrt(p * p - q)


def ref_derivatives(a, b, e, phi, sign, w2, alpha2=0.0):
    """s', s'' from F(s, phi) = s^2 - 2 s a cos(phi) + a^2 + e^2 - 2 a e sin(phi) - b^2 = 0."""
    s = ref_slider(a, b, e, phi, sign)
    fs = 2 * s - 2 * a * np.cos(phi)
    fp = 2 * s * a * np.sin(phi) - 2 * a * e * np.cos(phi)
    v = -fp * w2 / fs
    fss, fsp = 2.0, 2 * a * np.sin(phi)
    fpp = 2 * s * a * np.cos(phi) + 2 * a * e * np.sin(phi)
    acc = -(fss * v * v + 2 * fsp * v * w2 + fpp * w2 * w2 + fp * alpha2) / fs
    return s, v, acc


def ref_theta(a, b, e, phi, sign):
    """Rod angle from the complex loop: b e^{i theta} = s + i e - a e^{i phi}."""
    s = ref_slider(a, b, e, phi, sign)
    return np.angle(s + 1j * e - a * np.exp(1j * phi))


@st.composite
def slider_cranks(draw, turning=False):
    scale = 10.0 ** draw(st.floats(-3, 3))
    a = draw(st.floats(0.1, 1.0)) * scale
    e = draw(st.floats(-1.0, 1.0)) * scale
    if turning:
        b = (a + abs(e)) * draw(st.floats(1.1, 3.0))
    else:
        b = draw(st.floats(0.3, 3.0)) * scale
    sign = draw(st.sampled_from([1.0, -1.0]))
    return a, b, e, sign


SETTINGS = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])


# ---------------------------------------------------------------- kinematics

@SETTINGS
@given(slider_cranks(), st.floats(-math.pi, math.pi), st.floats(-50, 50, allow_subnormal=False),
       st.floats(-100, 100, allow_subnormal=False))  # a subnormal speed has no relative accuracy
@pytest.mark.slow
def test_position_velocity_acceleration_closed_form(link, phi, w2, alpha2):
    a, b, e, sign = link
    h = e - a * math.sin(phi)
    assume(abs(h) < 0.95 * b)  # away from a limit position, where s' is infinite
    branch = "open" if sign > 0 else "crossed"
    p = sc.pose(a, b, e, phi, branch)
    s, v, acc = ref_derivatives(a, b, e, phi, sign, w2, alpha2)
    scale = a + b + abs(e)
    assert bool(p.valid)
    assert_allclose(p.slider, s, rtol=0, atol=1e-12 * scale)
    assert_allclose(math.cos(p.theta - ref_theta(a, b, e, phi, sign)), 1.0, atol=1e-12)
    assert_allclose(p.mu, math.acos(abs(h) / b), atol=1e-7)
    vs, w3 = sc.velocities(a, b, p, w2)
    acs, a3 = sc.accelerations(a, b, p, w2, alpha2)
    vscale = scale * (abs(w2) + 1e-300) / (0.05 * b / scale + 1e-300)
    assert_allclose(vs, v, rtol=1e-9, atol=1e-12 * vscale)
    ascale = scale * (w2 * w2 + abs(alpha2)) / (0.05 * b / scale) ** 3
    assert_allclose(acs, acc, rtol=1e-8, atol=1e-12 * ascale)


@pytest.mark.slow
@SETTINGS
@given(slider_cranks(), st.floats(-math.pi, math.pi))
def test_derivatives_against_finite_differences(link, phi):
    a, b, e, sign = link
    assume(abs(e - a * math.sin(phi)) < 0.8 * b)
    branch = "open" if sign > 0 else "crossed"
    w2, alpha2, dt = 3.0, 0.0, 1e-4
    # crank at constant speed: phi(t) = phi + w2 t
    ph = phi + w2 * dt * np.array([-2, -1, 0, 1, 2])
    p = sc.pose(a, b, e, ph, branch)
    s, th = p.slider, np.unwrap(p.theta)
    v_fd = (8 * (s[3] - s[1]) - (s[4] - s[0])) / (12 * dt)
    acc_fd = (s[3] - 2 * s[2] + s[1]) / dt**2
    w3_fd = (8 * (th[3] - th[1]) - (th[4] - th[0])) / (12 * dt)
    a3_fd = (th[3] - 2 * th[2] + th[1]) / dt**2
    p0 = sc.pose(a, b, e, phi, branch)
    vs, w3 = sc.velocities(a, b, p0, w2)
    acs, a3 = sc.accelerations(a, b, p0, w2, alpha2)
    scale = a + b + abs(e)
    assert_allclose(vs, v_fd, rtol=1e-5, atol=1e-6 * scale * w2)
    assert_allclose(acs, acc_fd, rtol=1e-3, atol=2e-4 * scale * w2 * w2 * (scale / b) ** 3)
    assert_allclose(w3, w3_fd, rtol=1e-5, atol=1e-6 * w2 * scale / b)
    assert_allclose(a3, a3_fd, rtol=1e-3, atol=2e-4 * w2 * w2 * (scale / b) ** 3)
    # partials of s in the lengths, central differences
    parts = sc.slider_partials(a, b, e, phi, branch)
    for k, d in enumerate(parts):
        step = np.zeros(3)
        step[k] = 1e-6 * scale
        hi = ref_slider(*(np.array([a, b, e]) + step), phi, sign)
        lo = ref_slider(*(np.array([a, b, e]) - step), phi, sign)
        assert_allclose(d, (hi - lo) / (2 * step[k]), rtol=1e-5, atol=1e-5)


def test_coupler_point_motion_against_finite_differences():
    a, b, e = TEXTBOOK
    px, py = 30.0, 12.0
    w2, alpha2, dt = 2.0, 1.5, 1e-5
    t = np.array([-1.0, 0.0, 1.0]) * dt
    for branch in sc.BRANCHES:
        for phi0 in np.radians([10, 100, 200, 300]):
            ph = phi0 + w2 * t + 0.5 * alpha2 * t * t  # crank speed w2 at t = 0, accelerating
            p = sc.pose(a, b, e, ph, branch)
            x, y = sc.coupler_point(a, p, px, py)
            # independent: P = A + (px + i py) (B - A) / b
            ax, ay = a * np.cos(ph), a * np.sin(ph)
            ref = (ax + 1j * ay) + (px + 1j * py) * ((p.slider + 1j * e) - (ax + 1j * ay)) / b
            assert_allclose(x + 1j * y, ref, atol=1e-12 * (a + b))
            p0 = sc.pose(a, b, e, phi0, branch)
            (vx, vy), (acx, acy) = sc.coupler_point_motion(a, b, p0, px, py, w2, alpha2)
            assert_allclose([vx, vy], [(x[2] - x[0]) / (2 * dt), (y[2] - y[0]) / (2 * dt)], rtol=1e-6, atol=1e-6)
            assert_allclose([acx, acy], [(x[2] - 2 * x[1] + x[0]) / dt**2, (y[2] - 2 * y[1] + y[0]) / dt**2],
                            rtol=1e-3, atol=1e-2)


def test_populations_broadcast_like_single_linkages():
    rng = np.random.default_rng(3)
    a = rng.uniform(1, 2, (5, 1))
    b = rng.uniform(3, 5, (5, 1))
    e = rng.uniform(-1, 1, (5, 1))
    phi = np.linspace(-3, 3, 7)
    p = sc.pose(a, b, e, phi, "crossed")
    vs, _ = sc.velocities(a, b, p, 2.0)
    assert p.slider.shape == (5, 7) and vs.shape == (5, 7)
    for i in range(5):
        assert_allclose(p.slider[i], ref_slider(a[i, 0], b[i, 0], e[i, 0], phi, -1.0), rtol=1e-13)
    assert_allclose(sc.stroke(a[:, 0], b[:, 0], e[:, 0]),
                    np.sqrt((a + b) ** 2 - e**2)[:, 0] - np.sqrt((b - a) ** 2 - e**2)[:, 0], rtol=1e-12)


def test_no_assembly_is_nan_and_limit_velocity_infinite():
    p = sc.pose(1.0, 1.0, 5.0, np.array([0.0, 1.0]))
    assert np.all(np.isnan(p.slider)) and not np.any(p.valid)
    # a rocking slider at its limit angle: the rod is normal to the guide
    arcs = sc.input_arcs(2.0, 1.0, 0.5)
    lo = arcs[0][0]
    p = sc.pose(2.0, 1.0, 0.5, lo)
    assert bool(p.valid)
    assert math.isinf(sc.velocities(2.0, 1.0, p, 1.0)[0])


# ---------------------------------------------------------------- stroke, time ratio, arcs, class

def sweep(a, b, e, sign, n=2_000_001):
    phi = np.linspace(-math.pi, math.pi, n)
    return phi, ref_slider(a, b, e, phi, sign)


def test_textbook_stroke_and_time_ratio_by_simulation():
    a, b, e = TEXTBOOK
    for sign, branch in ((1.0, "open"), (-1.0, "crossed")):
        phi, s = sweep(a, b, e, sign)
        i, j = int(np.argmax(np.abs(s))), int(np.argmin(np.abs(s)))  # extended, folded
        stroke_sim = abs(s[i]) - abs(s[j])
        out_arc = (phi[i] - phi[j]) % (2 * math.pi)  # crank ccw from folded to extended
        ret_arc = 2 * math.pi - out_arc
        k_sim = max(out_arc, ret_arc) / min(out_arc, ret_arc)
        assert abs(stroke_sim - 100.0) < 1e-4
        assert abs(k_sim - 1.25) < 1e-4
        m = sc.motion(a, b, e, branch)
        assert m["input_full_turn"]
        assert_allclose(m["stroke"], stroke_sim, atol=1e-6)
        assert_allclose(m["time_ratio"], k_sim, atol=1e-5)
        assert m["slow_stroke"] == ("return" if ret_arc > out_arc else "outward")
        assert_allclose(m["slider_range"], (s.min(), s.max()), atol=1e-6)
        dc = m["dead_centres"]
        assert_allclose(dc["extended"]["input"], phi[i], atol=1e-5)
        assert_allclose(dc["folded"]["input"], phi[j], atol=1e-5)
        assert_allclose(dc["extended"]["slider"], s[i], atol=1e-6)


@settings(max_examples=100, deadline=None)
@given(st.floats(0.01, 1000), st.floats(1.0001, 50), st.sampled_from(["open", "crossed"]))
def test_centred_slider_crank_has_time_ratio_one_exactly(a, ratio, branch):
    k, slow = sc.time_ratio(a, a * ratio, 0.0, branch)
    assert float(k) == 1.0 and float(slow) == 0.0
    assert sc.motion(a, a * ratio, 0.0, branch)["time_ratio"] == 1.0


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(slider_cranks())
def test_arcs_and_slider_range_against_a_dense_sweep(link):
    a, b, e, sign = link
    phi = np.linspace(-math.pi, math.pi, 200_001)
    ok = np.abs(e - a * np.sin(phi)) <= b
    arcs = sc.input_arcs(a, b, e)
    margin = np.abs(np.abs(e - a * np.sin(phi)) - b) > 1e-6 * b  # not at a limit
    assume(abs(a + abs(e) - b) > 1e-3 * b and abs(abs(e) - a - b) > 1e-3 * b)
    if arcs is None:
        assert np.all(ok)
        return
    if arcs == []:
        assert not np.any(ok)
        return
    inside = np.zeros_like(ok)
    for lo, hi in arcs:
        assert -math.pi < lo <= math.pi and -math.pi < hi <= math.pi
        inside |= sc.arc_contains((lo, hi), phi)
    assert np.all((inside == ok)[margin])
    branch = "open" if sign > 0 else "crossed"
    # the sweep plus the limit angles, sin(phi) = (e -+ b) / a (s has infinite slope there)
    q = np.array([(e - b) / a, (e + b) / a])
    q = q[np.abs(q) <= 1]
    ends = np.angle(np.exp(1j * np.concatenate([np.arcsin(q), math.pi - np.arcsin(q)])))
    grid = np.concatenate([phi, ends])
    p_ = a * np.cos(grid)
    disc = p_ * p_ - (a * a + e * e - 2 * a * e * np.sin(grid) - b * b)
    reach = disc >= -1e-9 * b * b
    s_all = p_ + sign * np.sqrt(np.maximum(disc, 0.0))
    for arc in arcs:
        m = sc.motion(a, b, e, branch, near=arc[0])
        s = s_all[sc.arc_contains(arc, grid, 1e-9) & reach]
        assert_allclose(m["slider_range"], (s.min(), s.max()), atol=1e-6 * (a + b + abs(e)))


def test_class_boundary():
    for a, e in ((10.0, 5.0), (10.0, -5.0), (3e-3, 1e-3), (300.0, 0.0)):
        b = a + abs(e)
        assert sc.classify(a, b, e)["class"] == "change-point"
        assert sc.classify(a, b * (1 + 1e-10), e)["class"] == "change-point"
        assert sc.classify(a, b * (1 + 1e-7), e)["class"] == "slider-crank"
        assert sc.classify(a, b * (1 - 1e-7), e)["class"] == "rocking-slider"
        assert sc.input_arcs(a, b * (1 + 1e-7), e) is None
        assert sc.input_arcs(a, b * (1 - 1e-7), e)  # arcs: the crank rocks
        assert math.isfinite(sc.motion(a, b, e)["time_ratio"])  # the boundary still turns
    assert sc.classify(1.0, 1.0, 2.5)["class"] == "no-assembly"
    # brute force: the crank turns fully iff |e - a sin(phi)| <= b for every phi
    rng = np.random.default_rng(5)
    phi = np.linspace(-math.pi, math.pi, 100_001)
    for _ in range(200):
        a, b, e = rng.uniform(0.1, 2), rng.uniform(0.1, 3), rng.uniform(-1.5, 1.5)
        if abs(a + abs(e) - b) < 1e-3:
            continue
        turns = bool(np.all(np.abs(e - a * np.sin(phi)) <= b))
        assert (sc.classify(a, b, e)["class"] == "slider-crank") == turns


# ---------------------------------------------------------------- precision positions

@pytest.mark.slow
@settings(max_examples=150, deadline=None)
@given(slider_cranks(), st.lists(st.floats(-math.pi, math.pi), min_size=3, max_size=3))
def test_three_positions_reproduce_the_generating_slider_crank(link, angles):
    a, b, e, sign = link
    phi = np.array(angles)
    d = np.abs(np.angle(np.exp(1j * (phi[:, None] - phi[None, :]))))
    assume(np.min(d[np.triu_indices(3, 1)]) > 0.3)
    assume(np.all(np.abs(e - a * np.sin(phi)) < 0.9 * b))
    s = ref_slider(a, b, e, phi, sign)
    assume(np.max(np.abs(s)) > 1e-6 * (a + b))  # every slider position at the crank pivot: degenerate
    m = np.stack([s * np.cos(phi), np.sin(phi), -np.ones(3)], axis=1) / np.array([np.max(np.abs(s)), 1, 1])
    assume(np.linalg.cond(m) < 1e5)
    fit = spp.synthesize(phi, s)
    assert fit.exact and not fit.crank_reversed and not fit.branch_defect
    assert fit.linkage.branch == ("open" if sign > 0 else "crossed")
    scale = a + b + abs(e)
    assert_allclose([fit.linkage.input, fit.linkage.coupler, fit.linkage.offset], [a, b, e],
                    rtol=1e-9, atol=1e-9 * scale)
    assert np.max(np.abs(fit.error)) <= 1e-12 * scale


def test_three_positions_with_the_crank_pointing_back():
    a, b, e = TEXTBOOK
    phi = np.radians([20.0, 80.0, 150.0])
    s = ref_slider(a, b, e, phi + math.pi, 1.0)  # the crank sits at phi + 180
    fit = spp.synthesize(phi, s)
    assert fit.crank_reversed and "opposite" in fit.notes[0]
    assert_allclose([fit.linkage.input, fit.linkage.coupler, fit.linkage.offset], [a, b, e], rtol=1e-11)
    assert_allclose(np.cos(fit.input_angles - phi), -1.0, atol=1e-15)


def scipy_best(phi, s):
    """Many-start scipy least_squares on the true slider error, both branches."""
    from scipy.optimize import least_squares
    best = math.inf
    big = float(np.max(np.abs(s)))
    for sign in (1.0, -1.0):
        for a0 in np.array([0.1, 0.3, 0.6, 1.0]) * big:
            for b0 in np.array([0.5, 1.0, 2.0]) * big:
                for e0 in np.array([-0.3, 0.0, 0.3]) * big:
                    def res(x):
                        a, b, e = x
                        p = a * np.cos(phi)
                        q = a * a + e * e - 2 * a * e * np.sin(phi) - b * b
                        disc = p * p - q
                        return np.where(disc >= 0, p + sign * np.sqrt(np.abs(disc)) - s, 1e3 * big)
                    r = least_squares(res, [a0, b0, e0], method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
                    best = min(best, 2 * r.cost if np.all(np.isfinite(r.fun)) else math.inf)
    return best


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(6))
def test_least_squares_beats_the_generator_and_matches_scipy(seed):
    rng = np.random.default_rng(seed)
    scale = 10.0 ** rng.uniform(-3, 3)
    a = rng.uniform(0.3, 1.0) * scale
    e = rng.uniform(-0.5, 0.5) * scale
    b = (a + abs(e)) * rng.uniform(1.3, 2.5)
    sign = 1.0 if seed % 2 == 0 else -1.0
    n = 5 + seed
    phi = np.sort(rng.uniform(-math.pi, math.pi, n))
    s = ref_slider(a, b, e, phi, sign) + rng.normal(0, 0.01 * scale, n)
    fit = spp.synthesize(phi, s)
    assert not fit.exact and fit.converged and fit.travels
    generator = float(np.sum((ref_slider(a, b, e, phi, sign) - s) ** 2))
    assert fit.objective <= generator * (1 + 1e-12)
    own = float(np.sum((ref_slider(fit.linkage.input, fit.linkage.coupler, fit.linkage.offset,
                                   fit.input_angles, 1.0 if fit.linkage.branch == "open" else -1.0) - s) ** 2))
    assert_allclose(own, fit.objective, rtol=1e-9)
    best = scipy_best(phi, s)
    assert fit.objective <= best * (1 + 1e-7)
    assert_allclose(fit.objective, best, rtol=1e-6)


def test_impossible_positions_raise_schema_errors_naming_them():
    with pytest.raises(SchemaError, match="positions 1 and 3 at the same angle"):
        spp.synthesize(np.radians([10.0, 50.0, 370.0]), [1.0, 2.0, 3.0])
    phi = np.radians([30.0, 150.0, 90.0])  # rows 1 and 2 identical: s1 cos 30 = s2 cos 150
    with pytest.raises(SchemaError, match="positions 1, 2, 3 give a singular system"):
        spp.synthesize(phi, [10.0, -10.0, 5.0])
    with pytest.raises(SchemaError, match="positions 1, 2, 3, 4 give a zero crank"):
        spp.synthesize(np.radians([0.0, 40.0, 100.0, 200.0]), [7.0, 7.0, 7.0, 7.0])
    with pytest.raises(SchemaError, match="three"):
        spp.synthesize([0.0, 1.0], [1.0, 2.0])
    err = None
    try:
        spp.synthesize(np.radians([10.0, 10.0, 30.0]), [1.0, 2.0, 3.0], path="f.toml", line=7)
    except SchemaError as ex:
        err = ex
    assert err is not None and str(err).startswith("f.toml:7: positions.input: expected distinct")


# ---------------------------------------------------------------- tolerances

def independent_mc(link, phi, target, tol, clearance, guide, n, rng, normal=False):
    """Per-sample made slider-cranks with the offsets placed at the physical joints:
    journal of the crank at c1, pin A at c1 + a e^{i phi}, the rod's end at A + c2, B at
    rod length on the line y = e + g - c3_y (the slider's bearing is B + c3)."""
    a0, b0, e0, sign = link
    draw = (lambda size: rng.normal(0, 1 / 3, size)) if normal else (lambda size: rng.uniform(-1, 1, size))
    dl = draw((n, 3)) * np.asarray(tol)
    a, b, e = a0 + dl[:, 0:1], b0 + dl[:, 1:2], e0 + dl[:, 2:3]

    def disc(size):
        r = np.sqrt(rng.uniform(0, 1, size)) * clearance
        t = rng.uniform(0, 2 * math.pi, size)
        return r * np.exp(1j * t)

    m = len(phi)
    c1, c2, c3 = disc((n, m)), disc((n, m)), disc((n, m))
    g = rng.uniform(-1, 1, (n, m)) * guide
    rod_start = c1 + a * np.exp(1j * phi) + c2
    y_b = e + g - c3.imag
    rise = y_b - rod_start.imag
    ok = (np.abs(rise) <= b) & (a > 0) & (b > 0)
    run = sign * np.sqrt(np.where(ok, b * b - rise * rise, 0.0))
    s = rod_start.real + run + c3.real
    err = np.where(np.all(ok, axis=1), np.max(np.abs(s - target), axis=1), np.inf)
    return err


@pytest.mark.parametrize("case", ["lengths", "clearances", "normal-rocking"])
def test_tolerance_against_an_independent_monte_carlo(case):
    n = 20000
    if case == "normal-rocking":
        link = (2.0, 1.5, 0.3, 1.0)
        lin = sc.SliderCrank(*link[:3], branch="open")
        arcs = sc.input_arcs(*link[:3])
        lo, hi = arcs[0]
        phi = lo + np.array([0.002, 0.3, 0.6, 0.99]) * sc.arc_sweep(lo, hi)
        tol, clearance, guide, allowed, normal = (0.02, 0.02, 0.01), 0.0, 0.0, 0.03, True
    else:
        link = (*TEXTBOOK, -1.0 if case == "clearances" else 1.0)
        lin = sc.SliderCrank(*link[:3], branch="open" if link[3] > 0 else "crossed")
        phi = np.radians(np.arange(0, 360, 10.0))
        tol = (0.05, 0.05, 0.05)
        clearance, guide = (0.02, 0.03) if case == "clearances" else (0.0, 0.0)
        allowed, normal = (0.16 if case == "clearances" else 0.11), False
    target = ref_slider(*link[:3], phi, link[3])
    tg = stol.targets_at(lin, phi, target) if case == "normal-rocking" else None
    out = tolerance_section(lin, dict(zip(stol.LENGTH_KEYS, tol)), clearance=clearance, clearance_slider=guide,
                       samples=n, seed=11, distribution="normal" if normal else "uniform",
                       allowed_error=allowed, targets=tg)
    ref = independent_mc(link, phi, target, tol, clearance, guide, n, np.random.default_rng(99), normal)
    good = ref[np.isfinite(ref)]
    p_ref = float(np.mean(~np.isfinite(ref) | (ref > allowed)))
    p = out["failure_probability"]
    se = math.sqrt((p * (1 - p) + p_ref * (1 - p_ref)) / n)
    assert 0.01 < p_ref < 0.9  # the comparison means something
    assert abs(p - p_ref) <= 4 * se
    assert abs(out["error_mean"] - good.mean()) <= 4 * good.std() * math.sqrt(2 / n)
    assert_allclose(out["error_p95"], np.percentile(good, 95), rtol=0.03)
    assert out["error_max"] <= good.max() * 1.5
    if case == "normal-rocking":
        assert out["assembly_failures"] > 0 and np.any(~np.isfinite(ref))
        assert abs(out["assembly_failures"] / n - np.mean(~np.isfinite(ref))) <= 4 * se


def test_zero_tolerance_gives_zero_error_exactly():
    for branch in sc.BRANCHES:
        lin = sc.SliderCrank(*TEXTBOOK, branch=branch)
        out = tolerance_section(lin, {}, samples=500, seed=3, allowed_error=1e-300)
        assert out["error_max"] == 0.0 and out["error_mean"] == 0.0 and out["nominal_error"] == 0.0
        assert out["failure_probability"] == 0.0
    lin = sc.SliderCrank(2.0, 1.5, 0.3)  # rocking: targets over its arc
    out = tolerance_section(lin, {"input": 0.0}, samples=200, seed=3)
    assert out["error_max"] == 0.0 and out["assembly_failures"] == 0


def test_sensitivity_is_the_largest_partial_over_the_targets():
    lin = sc.SliderCrank(*TEXTBOOK)
    out = tolerance_section(lin, {"input": 0.01}, samples=100, seed=1)
    phi = np.radians(np.arange(0, 360, 10.0))
    h = 1e-5
    for k, key in enumerate(stol.LENGTH_KEYS):
        step = np.zeros(3)
        step[k] = h
        fd = (ref_slider(*(np.array(TEXTBOOK) + step), phi, 1.0)
              - ref_slider(*(np.array(TEXTBOOK) - step), phi, 1.0)) / (2 * h)
        assert_allclose(out["sensitivity"][key], np.max(np.abs(fd)), rtol=1e-6)


def test_inverse_mode_finds_the_boundary_and_is_deterministic():
    lin = sc.SliderCrank(*TEXTBOOK)
    kw = dict(clearance=0.01, clearance_slider=0.01, samples=4000, seed=2, allowed_error=0.2,
              max_failure_probability=0.02)
    out = tolerance_section(lin, {}, **kw)
    t = out["largest_tolerance"]
    assert out["failure_probability_at_largest"] <= 0.02
    assert out == tolerance_section(lin, {}, **kw)
    tg = stol.targets_over_range(lin)
    above = mc(lin, tg, np.full(3, t * (1 + 2e-4)), 0.01, 0.01, 4000, 2)
    assert tolerance.failures(*above, 0.2) / 4000 > 0.02
