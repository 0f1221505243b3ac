"""Four-bar kinematics against independent references: a complex-number closure written
here, finite differences, the classical quick-return formula, dense sampling."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from linkcli.mechanisms.four_bar import kinematics as kin

FIRE_DOOR = (27.6293, 57.2363, 41.1104, 50.0)  # a, b, c, d


def ref_psi(a, b, c, d, phi, branch):
    """Output angle by intersecting circles, written independently of linkcli."""
    A = cmath.rect(a, phi)
    B0 = complex(d, 0)
    v = A - B0
    rho = abs(v)
    if rho == 0.0:  # A on B0: the output angle is indeterminate
        return None
    cos_alpha = (rho * rho + c * c - b * b) / (2 * rho * c)
    if abs(cos_alpha) > 1:
        return None if abs(cos_alpha) > 1 + 1e-9 else "toggle"
    alpha = math.acos(cos_alpha)
    return cmath.phase(v) + (-alpha if branch == "open" else alpha)


def ref_grashof(a, b, c, d):
    links = {"input": a, "coupler": b, "output": c, "ground": d}
    vals = sorted(links.values())
    s, l, p, q = vals[0], vals[3], vals[1], vals[2]
    if abs((s + l) - (p + q)) <= 1e-9 * (p + q):
        return "change-point"
    if s + l > p + q:
        return "triple-rocker"
    shortest = min(links, key=links.get)
    return {"input": "crank-rocker", "output": "rocker-crank", "ground": "double-crank",
            "coupler": "double-rocker"}[shortest]


lengths = st.tuples(*[st.floats(0.1, 10.0) for _ in range(4)])
scales = st.sampled_from([1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3])


@settings(max_examples=200, deadline=None)
@given(lengths, scales, st.floats(-math.pi, math.pi), st.sampled_from(["open", "crossed"]))
def test_closure_matches_independent_circle_intersection(abcd, k, phi, branch):
    a, b, c, d = (x * k for x in abcd)
    ref = ref_psi(a, b, c, d, phi, branch)
    p = kin.pose(a, b, c, d, phi, branch)
    if ref == "toggle":  # within round-off of a toggle: either answer is right
        return
    if ref is None:
        assert not bool(p.valid)
        return
    if bool(p.valid):
        assert abs(kin.wrap(float(p.psi) - ref)) < 1e-7
        A = cmath.rect(a, phi)
        B = complex(d, 0) + cmath.rect(c, float(p.psi))
        assert abs(abs(B - A) - b) <= 1e-9 * max(a, b, c, d)
        assert np.isfinite(p.mu) and np.isfinite(p.theta)


@settings(max_examples=300, deadline=None)
@given(lengths, scales)
def test_grashof_matches_independent_classification(abcd, k):
    a, b, c, d = (x * k for x in abcd)
    assert kin.grashof(a, b, c, d)["class"] == ref_grashof(a, b, c, d)


def test_grashof_change_point_and_vectorized():
    assert kin.grashof(1, 2, 2, 1)["class"] == "change-point"
    codes = kin.grashof_code(np.array([1.0, 3.0]), np.array([3.0, 1.0]), 2.0, 2.5)
    assert [kin.GRASHOF_CLASSES[i] for i in codes] == [ref_grashof(1, 3, 2, 2.5), ref_grashof(3, 1, 2, 2.5)]


@pytest.mark.parametrize("branch", ["open", "crossed"])
@pytest.mark.parametrize("abcd", [FIRE_DOOR, (1.0, 3.2, 2.5, 3.0), (2.0, 5.0, 4.5, 1.0)])
def test_velocity_and_acceleration_match_finite_differences(abcd, branch):
    a, b, c, d = abcd
    phi = np.linspace(-3.0, 3.0, 41)
    w2, h = 1.7, 1e-5
    p = kin.pose(a, b, c, d, phi, branch)
    assert p.valid.all()
    w3, w4 = kin.velocities(a, b, c, p, w2)
    a3, a4 = kin.accelerations(a, b, c, p, w2)
    pp, pm = kin.pose(a, b, c, d, phi + h, branch), kin.pose(a, b, c, d, phi - h, branch)
    fd_w3 = kin.wrap(pp.theta - pm.theta) / (2 * h) * w2
    fd_w4 = kin.wrap(pp.psi - pm.psi) / (2 * h) * w2
    fd_a3 = kin.wrap(pp.theta - 2 * p.theta + pm.theta) / h**2 * w2**2
    fd_a4 = kin.wrap(pp.psi - 2 * p.psi + pm.psi) / h**2 * w2**2
    assert_allclose(w3, fd_w3, rtol=1e-6, atol=1e-8)
    assert_allclose(w4, fd_w4, rtol=1e-6, atol=1e-8)
    # accelerations: central difference of the closed-form velocity (second differences
    # of angles lose too many digits for 1e-6)
    w3p, w4p = kin.velocities(a, b, c, pp, w2)
    w3m, w4m = kin.velocities(a, b, c, pm, w2)
    assert_allclose(a3, (w3p - w3m) / (2 * h) * w2, rtol=1e-6, atol=1e-8)
    assert_allclose(a4, (w4p - w4m) / (2 * h) * w2, rtol=1e-6, atol=1e-8)
    assert_allclose(a4, fd_a4, rtol=1e-3, atol=1e-3)
    assert_allclose(a3, fd_a3, rtol=1e-3, atol=1e-3)


def test_acceleration_with_input_acceleration_matches_finite_differences():
    a, b, c, d = FIRE_DOOR
    # phi(t) = phi0 + w t + alpha t^2 / 2: differentiate the output angle in time
    phi0, w, al, h = 0.7, 1.3, 0.9, 1e-5
    def psi_at(t):
        return float(kin.pose(a, b, c, d, phi0 + w * t + al * t * t / 2, "open").psi)
    fd = (psi_at(h) - 2 * psi_at(0) + psi_at(-h)) / h**2
    p = kin.pose(a, b, c, d, phi0, "open")
    _, a4 = kin.accelerations(a, b, c, p, w, al)
    assert abs(float(a4) - fd) < 1e-4 * max(1, abs(fd))


def test_quick_return_ratio_matches_classical_formula():
    a, b, c, d = FIRE_DOOR
    # Norton: beta = angle between the extended and folded crank positions
    t_ext = math.acos(((a + b) ** 2 + d * d - c * c) / (2 * (a + b) * d))
    t_fold = math.acos(((b - a) ** 2 + d * d - c * c) / (2 * (b - a) * d))
    beta = abs(t_fold - t_ext)
    q = (math.pi + beta) / (math.pi - beta)
    m = kin.motion(a, b, c, d, "open")
    assert m.input_full_turn and not m.output_full_turn
    assert m.time_ratio == pytest.approx(q, rel=1e-9)
    # output swing: psi at the two collinear positions (law of cosines)
    psi_ext = math.acos((c * c + d * d - (a + b) ** 2) / (2 * c * d))
    psi_fold = math.acos((c * c + d * d - (b - a) ** 2) / (2 * c * d))
    assert m.output_swing == pytest.approx(abs(psi_ext - psi_fold), rel=1e-9)


@settings(max_examples=150, deadline=None)
@given(lengths, scales, st.sampled_from(["open", "crossed"]))
@example(abcd=(4.0, 0.25, 0.25, 4.0), k=0.001, branch="open")  # a = d: rho^2 cancels at phi ~ 0
@example(abcd=(4.5, 3.0, 0.125, 4.278052734872926), k=0.001, branch="open")  # toggle near 180
@example(abcd=(1.9375, 4.0, 0.1015625, 2.375), k=0.001, branch="open")  # two arcs, both toggles
def test_transmission_extremes_match_dense_sampling(abcd, k, branch):
    a, b, c, d = (x * k for x in abcd)
    arcs = kin.input_arcs(a, b, c, d)
    if arcs == []:
        return
    lo, hi = (0.0, 2 * math.pi) if arcs is None else arcs[0]
    mn, _, mx, _ = kin.transmission_extremes(a, b, c, d, lo, hi)
    phi = np.linspace(lo, hi, 20001)
    rho = np.abs(a * np.exp(1j * phi) - d)
    mu = np.arccos(np.clip((b * b + c * c - rho**2) / (2 * b * c), -1, 1))
    # arccos near +-1 resolves angles only to ~sqrt(eps) = 1.5e-8
    assert mn <= mu.min() + 1e-7 and mx >= mu.max() - 1e-7
    assert mn == pytest.approx(mu.min(), abs=1e-6) and mx == pytest.approx(mu.max(), abs=1e-6)


@settings(max_examples=150, deadline=None)
@given(lengths, scales)
def test_input_limits_are_where_the_linkage_folds(abcd, k):
    a, b, c, d = (x * k for x in abcd)
    arcs = kin.input_arcs(a, b, c, d)
    if not arcs:
        return
    for lo, hi in arcs:
        for edge, step in ((lo, -1), (hi, 1)):
            rho = abs(cmath.rect(a, edge) - d)
            assert min(abs(rho - (b + c)), abs(rho - abs(b - c))) <= 1e-7 * max(a, b, c, d)
            inside = kin.pose(a, b, c, d, edge - step * 1e-4 * (hi - lo), "open")
            assert bool(inside.valid)


def test_scale_invariance_of_angles():
    phi = np.linspace(0, 2 * np.pi, 50)
    p1 = kin.pose(*FIRE_DOOR, phi, "open")
    p2 = kin.pose(*(x * 1e-3 for x in FIRE_DOOR), phi, "open")
    assert_allclose(p1.psi, p2.psi, atol=1e-12)
    assert_allclose(p1.mu, p2.mu, atol=1e-12)


def test_branch_continuity_over_a_full_turn():
    phi = np.linspace(0, 2 * np.pi, 3601)
    for branch in ("open", "crossed"):
        psi = np.unwrap(kin.pose(*FIRE_DOOR, phi, branch).psi)
        assert np.max(np.abs(np.diff(psi))) < 0.01  # no jump between steps


def test_toggle_and_change_point_give_finite_numbers():
    # change-point: 1 + 2 = 1.5 + 1.5; passes a flat position where mu = 0
    a, b, c, d = 1.0, 1.5, 1.5, 2.0
    phi = np.linspace(0, 2 * np.pi, 721)
    p = kin.pose(a, b, c, d, phi, "open")
    assert np.isfinite(p.psi).all() and np.isfinite(p.mu).all()
    w3, w4 = kin.velocities(a, b, c, p, 1.0)
    assert not np.isnan(w3).any() and not np.isnan(w4).any()
    m = kin.motion(a, b, c, d, "open")
    assert m.assembles
    # a linkage that never assembles says so
    assert kin.input_arcs(1.0, 1.0, 1.0, 10.0) == []
    assert kin.motion(1.0, 1.0, 1.0, 10.0, "open") == kin.Motion(assembles=False)


def test_change_point_row_has_no_round_off_quotients():
    # 20 + 50 = 30 + 40: at input 180 deg every link lies on the ground line and
    # sin(psi - theta) is round-off (1e-16). Velocities and accelerations there are the
    # quotient of round-off errors (an acceleration of 8e11 rad/s^2 was printed): they are
    # reported undefined (inf, shown as null), and one degree away they match finite
    # differences of the closure
    a, b, c, d = 20.0, 30.0, 40.0, 50.0
    phi = np.deg2rad([179.0, 180.0, 181.0])
    p = kin.pose(a, b, c, d, phi, "open")
    w2 = math.radians(1.0)
    w3, w4 = kin.velocities(a, b, c, p, w2)
    a3, a4 = kin.accelerations(a, b, c, p, w2)
    for v in (w3, w4, a3, a4):
        assert np.isinf(v[1]) and np.isfinite(v[[0, 2]]).all()
    h = 1e-6
    for k in (0, 2):
        pp = kin.pose(a, b, c, d, phi[k] + h, "open")
        pm = kin.pose(a, b, c, d, phi[k] - h, "open")
        assert w4[k] == pytest.approx(float(kin.wrap(pp.psi - pm.psi)) / (2 * h) * w2, rel=1e-6)
        g = 1e-3  # the velocity is smooth here; a wider step keeps round-off out
        w4p = kin.velocities(a, b, c, kin.pose(a, b, c, d, phi[k] + g, "open"), w2)[1]
        w4m = kin.velocities(a, b, c, kin.pose(a, b, c, d, phi[k] - g, "open"), w2)[1]
        assert a4[k] == pytest.approx(float(w4p - w4m) / (2 * g) * w2, rel=1e-5)


def test_kite_where_the_crank_pin_meets_the_output_pivot():
    # input = ground, coupler = output: at input 0 the pin A lies on B0 (rho = 0) and the
    # output angle is undefined. On the open branch the output then rocks through half a
    # turn (the closure gives 0 -> 180 deg), not a full turn
    a, b, c, d = 30.0, 60.0, 60.0, 30.0
    assert not bool(kin.pose(a, b, c, d, 0.0, "open").valid)
    m = kin.motion(a, b, c, d, "open")
    assert m.input_full_turn and not m.output_full_turn
    assert m.output_swing == pytest.approx(math.pi, abs=0.01)
    lo, hi = m.output_range
    assert lo == pytest.approx(0.0, abs=0.01) and hi == pytest.approx(math.pi, abs=0.01)
