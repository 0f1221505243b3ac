"""Loads (issue 18): inverse dynamics checked by virtual work, energy balance and closed forms.

The kinematics here are written in the test (closed-form positions per the conventions of docs/format.md, the
loop equations differentiated by hand for velocities and accelerations), independent of
linkcli.kinematics; every check compares with a physical law, not with the solver's output.
"""

import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from linkcli.analysis.loads import forces_rows, load_cycle
from linkcli.mechanisms.four_bar.loads import FourBarState, four_bar_loads
from linkcli.mechanisms.newton_euler import cross as cross_rows
from linkcli.mechanisms.newton_euler import mechanical_advantage
from linkcli.mechanisms.slider_crank.loads import SliderCrankState, slider_crank_loads
from linkcli.model import LinkMass, Loads, Masses

STEP = 1e-3   # time step of the finite differences (s): error ~ STEP^4


def unit(angle):
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def perp(v):
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def in_frame(origin, towards, local):
    axis = (towards - origin) / np.linalg.norm(towards - origin, axis=-1, keepdims=True)
    return origin + local[0] * axis + local[1] * perp(axis)


# ---------------------------------------------------------------- independent kinematics
def four_bar_motion(lengths, phi, w2, al2, branch=-1.0, origin=(0.0, 0.0), gamma=0.0,
                    point=None):
    """Positions (global), angular velocities and accelerations of a four-bar.

    psi = theta_rho + branch * alpha (open: branch = -1). Velocities from
    a w2 e'(t2) + b w3 e'(t3) = c w4 e'(t4), accelerations from its derivative (Cramer).
    """
    with np.errstate(invalid="ignore", divide="ignore"):   # rows that do not assemble: NaN
        return _four_bar_motion(lengths, phi, w2, al2, branch, origin, gamma, point)


def _four_bar_motion(lengths, phi, w2, al2, branch, origin, gamma, point):
    a, b, c, d = lengths
    phi = np.asarray(phi, dtype=float)
    a_local = a * unit(phi)
    to_a = a_local - np.array([d, 0.0])
    rho = np.hypot(to_a[..., 0], to_a[..., 1])
    theta_rho = np.arctan2(to_a[..., 1], to_a[..., 0])
    psi = theta_rho + branch * np.arccos((rho ** 2 + c ** 2 - b ** 2) / (2 * rho * c))
    b_local = np.array([d, 0.0]) + c * unit(psi)
    t2, t4 = phi + gamma, psi + gamma
    to_b = b_local - a_local
    t3 = np.arctan2(to_b[..., 1], to_b[..., 0]) + gamma
    # b w3 e'(t3) - c w4 e'(t4) = -a w2 e'(t2): solve the 2 x 2 by Cramer
    e3, e4, e2 = perp(unit(t3)), perp(unit(t4)), perp(unit(t2))
    det = cross(b * e3, -c * e4)
    rhs = -a * w2 * e2
    w3 = cross(rhs, -c * e4) / det
    w4 = cross(b * e3, rhs) / det
    rhs = (-a * al2 * e2 + a * w2 ** 2 * unit(t2) + b * w3[..., None] ** 2 * unit(t3)
           - c * w4[..., None] ** 2 * unit(t4))
    al3 = cross(rhs, -c * e4) / det
    al4 = cross(b * e3, rhs) / det
    rotation = np.array([[np.cos(gamma), -np.sin(gamma)], [np.sin(gamma), np.cos(gamma)]])
    shift = np.asarray(origin, dtype=float)
    pa0 = shift + 0 * a_local
    pa = shift + a_local @ rotation.T
    pb = shift + b_local @ rotation.T
    pb0 = shift + np.array([d, 0.0]) @ rotation.T + 0 * a_local
    pp = None if point is None else in_frame(pa, pb, point)
    n = np.shape(phi)
    return dict(A0=pa0, A=pa, B=pb, B0=pb0, P=pp, w2=np.broadcast_to(w2, n) * 1.0,
                w3=w3, w4=w4, al2=np.broadcast_to(al2, n) * 1.0, al3=al3, al4=al4,
                t2=t2, t3=t3, t4=t4, valid=np.abs((rho ** 2 + c ** 2 - b ** 2) / (2 * rho * c)) < 1)


def four_bar_state(m):
    return FourBarState(m["A0"], m["A"], m["B"], m["B0"], m["w2"], m["w3"], m["w4"],
                        m["al2"], m["al3"], m["al4"], m["P"])


def slider_crank_motion(a, b, e, phi, w2, al2, point=None):
    """Slider-crank (docs/format.md): A = a e(phi), B = (s, e), s with the + root; rod angle t3 from
    a sin(phi) + b sin(t3) = e, differentiated twice."""
    phi = np.asarray(phi, dtype=float)
    s = a * np.cos(phi) + np.sqrt(b ** 2 - (e - a * np.sin(phi)) ** 2)
    t3 = np.arctan2(e - a * np.sin(phi), s - a * np.cos(phi))
    w3 = -a * w2 * np.cos(phi) / (b * np.cos(t3))
    al3 = (a * w2 ** 2 * np.sin(phi) - a * al2 * np.cos(phi)
           + b * w3 ** 2 * np.sin(t3)) / (b * np.cos(t3))
    v = -a * w2 * np.sin(phi) - b * w3 * np.sin(t3)
    pa = a * unit(phi)
    pb = np.stack([s, np.full_like(s, e)], axis=-1)
    pp = None if point is None else in_frame(pa, pb, point)
    n = np.shape(phi)
    return dict(A0=np.zeros(n + (2,)), A=pa, B=pb, P=pp, w2=np.broadcast_to(w2, n) * 1.0,
                w3=w3, al2=np.broadcast_to(al2, n) * 1.0, al3=al3, v=v, t3=t3)


def slider_crank_state(m):
    return SliderCrankState(m["A0"], m["A"], m["B"], m["w2"], m["w3"], m["al2"], m["al3"],
                            m["P"])


# ---------------------------------------------------------------- energy, derivatives
def five_point(values_at, step=STEP):
    """d/dt at 0 of values_at(t) (fourth-order central difference)."""
    return (values_at(-2 * step) - 8 * values_at(-step) + 8 * values_at(step)
            - values_at(2 * step)) / (12 * step)


def four_bar_energy(m, masses, gravity):
    """Kinetic + potential energy of the three links (v_G from the test's own velocities)."""
    g = np.asarray(gravity)
    bodies = [(masses.input, m["A0"], m["A"], m["w2"], 0.0),
              (masses.coupler, m["A"], m["B"], m["w3"], m["w2"][..., None] * perp(m["A"] - m["A0"])),
              (masses.output, m["B0"], m["B"], m["w4"], 0.0)]
    energy = 0.0
    for mass, origin, towards, omega, origin_velocity in bodies:
        centre = in_frame(origin, towards, np.asarray(mass.center, dtype=float))
        velocity = origin_velocity + omega[..., None] * perp(centre - origin)
        energy = energy + 0.5 * mass.mass * np.sum(velocity ** 2, axis=-1) \
            + 0.5 * mass.inertia * omega ** 2 - mass.mass * centre @ g
    return energy


def slider_crank_energy(m, masses, gravity):
    g = np.asarray(gravity)
    energy = 0.0
    for mass, origin, towards, omega, origin_velocity in [
            (masses.input, m["A0"], m["A"], m["w2"], 0.0),
            (masses.coupler, m["A"], m["B"], m["w3"], m["w2"][..., None] * perp(m["A"]))]:
        centre = in_frame(origin, towards, np.asarray(mass.center, dtype=float))
        velocity = origin_velocity + omega[..., None] * perp(centre - origin)
        energy = energy + 0.5 * mass.mass * np.sum(velocity ** 2, axis=-1) \
            + 0.5 * mass.inertia * omega ** 2 - mass.mass * centre @ g
    slider = masses.output.mass
    return energy + 0.5 * slider * m["v"] ** 2 - slider * m["B"] @ g


# ---------------------------------------------------------------- the seed case
LENGTHS = (1.0, 3.5, 3.0, 4.0)          # input, coupler, output, ground (m)
POINT = np.array([1.5, 1.0])


def test_seed_case_input_torque_at_60_degrees():
    """Issue 18: coupler force (0, -100) N at P, no masses: +36.7824 N m at 60 deg."""
    m = four_bar_motion(LENGTHS, np.radians([60.0]), 0.0, 0.0, point=POINT)
    rows = four_bar_loads(four_bar_state(m), Loads(coupler_force=(0.0, -100.0)))
    assert rows.input_torque[0] == pytest.approx(36.7824, abs=5e-5)


def test_test_kinematics_match_finite_differences():
    """The test's own velocity and acceleration formulas agree with the positions."""
    phi0, w2, al2 = np.linspace(0, 2 * np.pi, 37), 1.7, 0.3
    m = four_bar_motion(LENGTHS, phi0, w2, al2)

    def angle_at(t, key):
        mt = four_bar_motion(LENGTHS, phi0 + w2 * t + al2 * t ** 2 / 2, w2 + al2 * t, al2)
        return np.unwrap(np.stack([m[key], mt[key]]), axis=0)[1]

    np.testing.assert_allclose(five_point(lambda t: angle_at(t, "t3")), m["w3"], atol=1e-9)
    np.testing.assert_allclose(five_point(lambda t: angle_at(t, "t4")), m["w4"], atol=1e-9)

    def w_at(t, key):
        return four_bar_motion(LENGTHS, phi0 + w2 * t + al2 * t ** 2 / 2, w2 + al2 * t, al2)[key]

    np.testing.assert_allclose(five_point(lambda t: w_at(t, "w3")), m["al3"], atol=1e-8)
    np.testing.assert_allclose(five_point(lambda t: w_at(t, "w4")), m["al4"], atol=1e-8)


# ---------------------------------------------------------------- statics: virtual work
def dpoint(m):
    """dP/dphi at unit input speed: v_A + w3 k x (P - A), v_A = w2 k x (A - A0)."""
    return m["w2"][..., None] * perp(m["A"] - m["A0"]) + m["w3"][..., None] * perp(m["P"] - m["A"])


def test_four_bar_static_torque_equals_virtual_work_every_row():
    phi = np.radians(np.arange(0.0, 360.0, 1.0))
    force, torque = np.array([30.0, -100.0]), 25.0
    m = four_bar_motion(LENGTHS, phi, 1.0, 0.0, point=POINT, origin=(0.3, -0.2), gamma=0.4)
    rows = four_bar_loads(four_bar_state(m), Loads(coupler_force=tuple(force),
                                                   output_torque=torque))
    expected = -(dpoint(m) @ force + torque * m["w4"])
    scale = np.abs(dpoint(m) @ force).max() + abs(torque) * np.abs(m["w4"]).max()
    np.testing.assert_allclose(rows.input_torque, expected, rtol=0, atol=1e-9 * scale)
    # the same by finite differences of the positions (no velocity formula)
    def p_at(h):
        return four_bar_motion(LENGTHS, phi + h, 1.0, 0.0, point=POINT, origin=(0.3, -0.2),
                               gamma=0.4)
    dp = five_point(lambda h: p_at(h)["P"])
    dpsi = five_point(lambda h: np.unwrap(np.stack([m["t4"], p_at(h)["t4"]]), axis=0)[1])
    np.testing.assert_allclose(rows.input_torque, -(dp @ force + torque * dpsi),
                               rtol=0, atol=1e-8 * scale)


def test_four_bar_static_gravity_equals_virtual_work():
    """Masses at zero speed: T_in = -(F . dP + T dpsi + sum m g . dG) / dphi."""
    masses = Masses(LinkMass(2.0, (0.4, 0.1), 0.3), LinkMass(5.0, (1.2, -0.3), 1.1),
                    LinkMass(3.0, (1.0, 0.2), 0.7))
    gravity = np.array([0.5, -9.81])
    phi = np.radians(np.arange(0.0, 360.0, 5.0))
    m = four_bar_motion(LENGTHS, phi, 1.0, 0.0, point=POINT, gamma=-0.3)
    still = dict(m, w2=0 * m["w2"], w3=0 * m["w3"], w4=0 * m["w4"], al3=0 * m["w3"],
                 al4=0 * m["w4"])
    rows = four_bar_loads(four_bar_state(still), Loads(gravity=tuple(gravity)), masses)

    def potential_at(h):
        return four_bar_energy(dict(four_bar_motion(LENGTHS, phi + h, 0.0, 0.0, gamma=-0.3)),
                               masses, gravity)
    np.testing.assert_allclose(rows.input_torque, five_point(potential_at), rtol=0,
                               atol=1e-8 * np.abs(rows.input_torque).max())


def test_four_bar_static_pin_forces_closed_form():
    """No masses, a coupler force only: the output is a two-force member, so B lies along
    B0 -> B with k from the coupler's moment about A; A = F_B - F, A0 = A, B0 = -B."""
    phi = np.radians(np.arange(0.0, 360.0, 10.0))
    force = np.array([0.0, -100.0])
    m = four_bar_motion(LENGTHS, phi, 1.0, 0.0, point=POINT)
    rows = four_bar_loads(four_bar_state(m), Loads(coupler_force=tuple(force)))
    along = (m["B"] - m["B0"]) / LENGTHS[2]
    k = cross(m["P"] - m["A"], np.broadcast_to(force, m["P"].shape)) / cross(m["B"] - m["A"], along)
    pin_b = k[:, None] * along
    np.testing.assert_allclose(rows.pins["B"], pin_b, atol=1e-9 * 100)
    np.testing.assert_allclose(rows.pins["B0"], -pin_b, atol=1e-9 * 100)
    np.testing.assert_allclose(rows.pins["A"], pin_b - force, atol=1e-9 * 100)
    np.testing.assert_allclose(rows.pins["A0"], pin_b - force, atol=1e-9 * 100)


# ---------------------------------------------------------------- dynamics: energy balance
MASSES = Masses(LinkMass(0.8, (0.5, 0.05), 0.07), LinkMass(4.0, (1.6, 0.4), 4.2),
                LinkMass(2.5, (1.4, -0.1), 1.9))


def four_bar_power_check(lengths, masses, loads, phi0, w2, al2, point, origin=(0, 0), gamma=0.0,
                         branch=-1.0, rtol=1e-6):
    """T_in w2 = d/dt(T + V) - F . v_P - T_out w4, the derivative by finite differences."""
    def motion(t):
        return four_bar_motion(lengths, phi0 + w2 * t + al2 * t ** 2 / 2, w2 + al2 * t, al2,
                               branch, origin, gamma, point)
    m = motion(0.0)
    rows = four_bar_loads(four_bar_state(m), loads, masses)
    step = 2e-5 / max(abs(w2), 1.0)     # about 2e-5 rad of input per step
    rate = five_point(lambda t: four_bar_energy(motion(t), masses, loads.gravity), step)
    v_p = dpoint(m)      # v_A + w3 k x (P - A) at the actual speed
    load_power = v_p @ np.asarray(loads.coupler_force) + loads.output_torque * m["w4"]
    terms = np.abs(rate) + np.abs(load_power) + np.abs(rows.input_torque * m["w2"])
    np.testing.assert_allclose(rows.input_torque * m["w2"], rate - load_power, rtol=0,
                               atol=rtol * terms.max())
    return rows, m


def test_four_bar_energy_balance_every_row():
    phi = np.radians(np.arange(0.0, 360.0, 2.0))
    loads = Loads(coupler_force=(40.0, -100.0), output_torque=-15.0, gravity=(0.0, -9.81))
    four_bar_power_check(LENGTHS, MASSES, loads, phi, 12.0, 0.0, POINT, (0.2, 0.1), 0.25)


def test_four_bar_energy_balance_with_input_acceleration():
    phi = np.radians(np.arange(0.0, 360.0, 7.5))
    loads = Loads(coupler_force=(0.0, -50.0), gravity=(0.0, -9.81))
    four_bar_power_check(LENGTHS, MASSES, loads, phi, -6.0, 40.0, POINT)


def test_four_bar_pin_forces_obey_newton_euler_with_finite_difference_accelerations():
    """Each link: forces on it = m a_G and moments about G = I alpha, with a_G and alpha
    by finite differences of the positions (not the solver's acceleration formula)."""
    phi0, w2 = np.radians(np.arange(0.0, 360.0, 10.0)), 9.0
    loads = Loads(coupler_force=(20.0, -80.0), output_torque=7.0, gravity=(0.0, -9.81))

    def motion(t):
        return four_bar_motion(LENGTHS, phi0 + w2 * t, w2, 0.0, point=POINT)
    m = motion(0.0)
    rows = four_bar_loads(four_bar_state(m), loads, MASSES)
    step, g = 1e-3, np.asarray(loads.gravity)
    force = np.asarray(loads.coupler_force)

    def second(values_at):
        return (-values_at(2 * step) + 16 * values_at(step) - 30 * values_at(0)
                + 16 * values_at(-step) - values_at(-2 * step)) / (12 * step ** 2)
    pins = rows.pins
    links = [(MASSES.input, "A0", "A", "t2", [("A0", 1), ("A", -1)], 0.0, 0.0),
             (MASSES.coupler, "A", "B", "t3", [("A", 1), ("B", -1)], force, None),
             (MASSES.output, "B0", "B", "t4", [("B", 1), ("B0", 1)], 0.0, loads.output_torque)]
    for mass, origin, towards, angle, forces, external, torque in links:
        def centre_at(t):
            mt = motion(t)
            return in_frame(mt[origin], mt[towards], np.asarray(mass.center))
        acc = second(centre_at)
        alpha = second(lambda t: np.unwrap(np.stack([m[angle], motion(t)[angle]]), axis=0)[1])
        centre = centre_at(0.0)
        total = sum(sign * pins[name] for name, sign in forces) + external + mass.mass * g
        np.testing.assert_allclose(total, mass.mass * acc, atol=1e-5 * 100)
        moment = sum(sign * cross(m[name] - centre, pins[name]) for name, sign in forces)
        if torque is None:
            moment = moment + cross(m["P"] - centre, np.broadcast_to(force, centre.shape))
        elif origin == "A0":
            moment = moment + rows.input_torque
        else:
            moment = moment + torque
        np.testing.assert_allclose(moment, mass.inertia * alpha, atol=1e-5 * 100)


# ---------------------------------------------------------------- slider-crank
CRANK, ROD, OFFSET = 0.05, 0.2, 0.015


def test_slider_crank_static_virtual_work_and_guide():
    phi = np.radians(np.arange(0.0, 360.0, 1.0))
    force, push = np.array([10.0, -40.0]), -250.0
    point = np.array([0.08, 0.02])
    m = slider_crank_motion(CRANK, ROD, OFFSET, phi, 1.0, 0.0, point)
    rows = slider_crank_loads(slider_crank_state(m), Loads(coupler_force=tuple(force),
                                                           output_force=push))
    expected = -(dpoint(m) @ force + push * m["v"])
    scale = np.abs(dpoint(m) @ force).max() + abs(push) * np.abs(m["v"]).max()
    np.testing.assert_allclose(rows.input_torque, expected, rtol=0, atol=1e-9 * scale)
    # finite differences of the positions
    def at(h):
        return slider_crank_motion(CRANK, ROD, OFFSET, phi + h, 1.0, 0.0, point)
    ds = five_point(lambda h: at(h)["B"][:, 0])
    dp = five_point(lambda h: at(h)["P"])
    np.testing.assert_allclose(rows.input_torque, -(dp @ force + push * ds), rtol=0,
                               atol=1e-8 * scale)
    # massless slider: the guide force balances the rod's y component, x is along the guide
    np.testing.assert_allclose(rows.pins["guide"][:, 0], 0.0)
    np.testing.assert_allclose(rows.pins["guide"][:, 1], -rows.pins["B"][:, 1], atol=1e-9)
    np.testing.assert_allclose(rows.pins["B"][:, 0], -push, atol=1e-9)


def test_slider_crank_energy_balance_every_row():
    phi0, w2, al2 = np.radians(np.arange(0.0, 360.0, 2.0)), 150.0, 300.0
    masses = Masses(LinkMass(0.3, (0.01, 0.002), 2e-4), LinkMass(0.6, (0.07, 0.0), 3e-3),
                    LinkMass(0.9))
    loads = Loads(coupler_force=(5.0, -20.0), output_force=-400.0, gravity=(2.0, -9.81))
    point = np.array([0.1, -0.01])

    def motion(t):
        return slider_crank_motion(CRANK, ROD, OFFSET, phi0 + w2 * t + al2 * t ** 2 / 2,
                                   w2 + al2 * t, al2, point)
    m = motion(0.0)
    rows = slider_crank_loads(slider_crank_state(m), loads, masses)
    rate = five_point(lambda t: slider_crank_energy(motion(t), masses, loads.gravity),
                      step=1e-5)
    load_power = dpoint(m) @ np.asarray(loads.coupler_force) + loads.output_force * m["v"]
    terms = np.abs(rate) + np.abs(load_power) + np.abs(rows.input_torque * m["w2"])
    np.testing.assert_allclose(rows.input_torque * m["w2"], rate - load_power, rtol=0,
                               atol=1e-6 * terms.max())
    # the slider: rod + guide + load + weight = m a along x, 0 across
    acc_x = five_point(lambda t: motion(t)["v"], step=1e-5)
    np.testing.assert_allclose(rows.pins["B"][:, 0] + loads.output_force + 0.9 * 2.0,
                               0.9 * acc_x, atol=1e-6 * np.abs(rows.pins["B"]).max())
    np.testing.assert_allclose(rows.pins["B"][:, 1] + rows.pins["guide"][:, 1], 0.9 * 9.81,
                               atol=1e-9 * np.abs(rows.pins["B"]).max())


def test_slider_crank_mechanical_advantage_is_force_over_torque():
    phi = np.radians(np.arange(5.0, 360.0, 10.0))
    m = slider_crank_motion(CRANK, ROD, OFFSET, phi, 1.0, 0.0)
    rows = slider_crank_loads(slider_crank_state(m), Loads(output_force=-100.0))
    np.testing.assert_allclose(rows.mechanical_advantage, 1.0 / m["v"], rtol=1e-9)
    np.testing.assert_allclose(rows.mechanical_advantage, 100.0 / rows.input_torque, rtol=1e-9)


# ---------------------------------------------------------------- properties over scales
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(st.lists(st.floats(0.2, 5.0), min_size=4, max_size=4), st.integers(-3, 3),
       st.sampled_from([-1.0, 1.0]), st.floats(-3.0, 3.0), st.floats(-2.0, 2.0),
       st.floats(-3.0, 3.0), st.floats(0.5, 50.0), st.integers(0, 2 ** 31 - 1))
def test_random_linkages_virtual_work_and_energy(lengths, exponent, branch, gamma, rx, ry, w2,
                                                 seed):
    scale = 10.0 ** exponent
    w2 = -w2 if seed % 2 else w2
    a, b, c, d = (scale * v for v in lengths)
    rng = np.random.default_rng(seed)
    phi = np.linspace(0.0, 2 * np.pi, 73)
    m = four_bar_motion((a, b, c, d), phi, 1.0, 0.0, branch)
    # keep rows that assemble, clear of dead points and toggles (finite differences need room)
    with np.errstate(all="ignore"):
        clear = (m["valid"] & (np.abs(np.sin(m["t3"] - m["t4"])) > 0.15)
                 & (np.abs(np.sin(m["t3"] - m["t2"])) > 0.05))
    assume(clear.sum() >= 3)
    phi = phi[clear]
    point = np.array([rx, ry]) * b
    force = tuple(rng.normal(size=2) * 100)
    torque = float(rng.normal() * 100 * scale)
    m = four_bar_motion((a, b, c, d), phi, 1.0, 0.0, branch, (scale, -scale), gamma, point)
    rows = four_bar_loads(four_bar_state(m), Loads(coupler_force=force, output_torque=torque))
    expected = -(dpoint(m) @ np.asarray(force) + torque * m["w4"])
    size = np.abs(dpoint(m) @ np.asarray(force)).max() + abs(torque) * np.abs(m["w4"]).max()
    np.testing.assert_allclose(rows.input_torque, expected, rtol=0, atol=1e-9 * size)
    np.testing.assert_allclose(rows.mechanical_advantage, m["w2"] / m["w4"], rtol=1e-9)

    length = max(a, b, c)
    masses = Masses(*(LinkMass(float(rng.uniform(0.1, 5)) * scale,
                               tuple(rng.normal(size=2) * length),
                               float(rng.uniform(0.01, 1)) * scale ** 3) for _ in range(3)))
    four_bar_power_check((a, b, c, d), masses,
                         Loads(coupler_force=force, output_torque=torque, gravity=(0.0, -9.81)),
                         phi, w2, float(rng.normal() * 10), point, (scale, -scale), gamma,
                         branch, rtol=1e-6)


# ---------------------------------------------------------------- toggles, dead points
def test_toggle_row_gives_no_mechanical_advantage():
    """Input and coupler extended in line (|A0 B| = a + b): MA is infinite -> None."""
    a, b, c, d = LENGTHS
    toggle = np.arccos(((a + b) ** 2 + d ** 2 - c ** 2) / (2 * (a + b) * d))
    phi = np.array([np.radians(30.0), toggle, np.radians(90.0)])
    for branch in (-1.0, 1.0):
        m = four_bar_motion(LENGTHS, phi, 1.0, 0.0, branch, point=POINT)
        if abs(np.sin(m["t3"][1] - m["t2"][1])) < 1e-12:
            break
    else:
        pytest.fail("no branch puts the input and coupler in line")
    rows = four_bar_loads(four_bar_state(m), Loads(output_torque=-40.0))
    listed = forces_rows(rows, np.degrees(phi))
    assert listed[1]["mechanical_advantage"] is None
    assert listed[1]["input_torque"] == 0.0     # the output torque is held without drive torque
    assert listed[0]["mechanical_advantage"] == pytest.approx(1.0 / m["w4"][0], rel=1e-9)
    state = four_bar_state(m)
    assert np.isnan(mechanical_advantage(state, cross_rows(state.B - state.B0, state.B - state.A))[1])


def test_dead_point_row_is_none_not_a_crash():
    """Coupler and output in line (|A B0| = b + c): the row is singular, reported as None."""
    a, b, c, d = 3.0, 1.0, 1.0, 3.0
    dead = np.arccos((a ** 2 + d ** 2 - (b + c) ** 2) / (2 * a * d))
    phi = np.array([dead, dead - 0.1])
    m = four_bar_motion((a, b, c, d), phi, 1.0, 0.0, point=np.array([0.5, 0.2]))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rows = four_bar_loads(four_bar_state(m), Loads(coupler_force=(0.0, -100.0)), MASSES)
        listed = forces_rows(rows, np.degrees(phi))
        cycle = load_cycle(rows, np.degrees(phi))
    assert rows.singular.tolist() == [True, False]
    assert np.isfinite(rows.force_scale) and rows.force_scale > 0    # the dead row spoils no scale
    assert listed[0]["input_torque"] is None
    assert listed[0]["pins"]["B"] == {"x": None, "y": None, "magnitude": None}
    assert listed[1]["input_torque"] is not None
    assert cycle["singular_rows"] == 1
    assert cycle["input_torque"]["at_input"] == pytest.approx(np.degrees(dead - 0.1))


# ---------------------------------------------------------------- the load cycle
def test_load_cycle_statistics_and_peak_tie():
    """Statistics against plain numpy on the rows; a symmetric case for the tie rule."""
    phi = np.radians(np.arange(0.0, 360.0, 1.0))
    m = four_bar_motion(LENGTHS, phi, 10.0, 0.0, point=POINT)
    rows = four_bar_loads(four_bar_state(m), Loads(coupler_force=(0.0, -100.0),
                                                   gravity=(0.0, -9.81)), MASSES)
    cycle = load_cycle(rows, np.degrees(phi))
    size = np.hypot(*rows.pins["B"].T)
    assert cycle["pins"]["B"]["max"] == pytest.approx(size.max())
    assert cycle["pins"]["B"]["amplitude"] == pytest.approx((size.max() - size.min()) / 2)
    assert cycle["pins"]["A0"]["y"]["mean"] == pytest.approx(rows.pins["A0"][:, 1].mean())
    peak = int(np.argmax(np.abs(rows.input_torque)))
    assert cycle["input_torque"]["at_input"] == pytest.approx(np.degrees(phi[peak]))
    assert cycle["input_torque"]["rms"] == pytest.approx(np.sqrt(np.mean(rows.input_torque ** 2)))

    # an output torque on a parallelogram (a = c, b = d): T_in = -T_out at every row; two
    # rows of equal |T| -> the first in sweep order
    par = (1.0, 4.0, 1.0, 4.0)
    phi = np.radians([20.0, 50.0, 80.0])
    m = four_bar_motion(par, phi, 1.0, 0.0, branch=-1.0)
    rows = four_bar_loads(four_bar_state(m), Loads(output_torque=5.0))
    np.testing.assert_allclose(rows.input_torque, -5.0, rtol=1e-12)
    assert load_cycle(rows, [20.0, 50.0, 80.0])["input_torque"]["at_input"] == 20.0


def test_no_loads_gives_exact_zeros():
    phi = np.radians(np.arange(0.0, 360.0, 30.0))
    m = four_bar_motion(LENGTHS, phi, 3.0, 0.0)
    rows = four_bar_loads(four_bar_state(m))
    listed = forces_rows(rows, np.degrees(phi))
    assert all(r["input_torque"] == 0.0 and r["pins"]["A"]["magnitude"] == 0.0 for r in listed)


def test_bad_arguments_are_value_errors():
    with pytest.raises(ValueError):
        LinkMass(-1.0)
    with pytest.raises(ValueError):
        LinkMass(1.0, inertia=-0.1)
    m = four_bar_motion(LENGTHS, np.radians([10.0]), 1.0, 0.0)
    with pytest.raises(ValueError):
        four_bar_loads(four_bar_state(m), Loads(coupler_force=(0.0, -1.0)))   # no point
    s = slider_crank_motion(CRANK, ROD, OFFSET, np.radians([10.0]), 1.0, 0.0)
    with pytest.raises(ValueError):
        slider_crank_loads(slider_crank_state(s), Loads(output_torque=1.0))
