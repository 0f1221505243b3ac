"""The forces section end to end (issue 18): [loads] and [masses] through the CLI, checked
against physics written here, never against linkcli's own output.

The kinematics below are the test's own (complex numbers: A = a e^{i phi},
B = B0 + c e^{i psi} closed per the conventions of docs/format.md, velocities from the loop equation
a e'(t2) + b w3 e'(t3) = c w4 e'(t4) solved by Cramer's rule); checks:
- statics: the input torque equals the virtual-work value -(F . dP/dphi + T_out dpsi/dphi)
  at every row, 1e-9 relative;
- dynamics: input power T_in w2 = d/dt(kinetic + potential energy) - F . v_P - T_out w4
  at every row, d/dt by a five-point finite difference along the motion;
- the seed case: ground 4, input 1, coupler 3.5, output 3 m, coupler point (1.5, 1.0),
  force (0, -100) N at P: +36.7824 N m at input 60 deg;
- the slider-crank path at the analysis-function level, by the same two laws.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import run_cli

METRE = {"mm": 1e-3, "m": 1.0}


# ------------------------------------------------------------------ the test's own kinematics
def four_bar(a, b, c, d, phi, *, branch=-1.0, pivot=(0.0, 0.0), gamma=0.0, point=(0.0, 0.0), w2=1.0):
    """Global positions (complex) and angular velocities at input angles phi (local, rad)."""
    phi = np.asarray(phi, dtype=float)
    a_local = a * np.exp(1j * phi)
    to_a = a_local - d
    rho = np.abs(to_a)
    psi = np.angle(to_a) + branch * np.arccos((rho ** 2 + c ** 2 - b ** 2) / (2 * rho * c))
    b_local = d + c * np.exp(1j * psi)
    theta = np.angle(b_local - a_local)
    # a w2 i e^{i phi} + b w3 i e^{i theta} = c w4 i e^{i psi}: two real equations in w3, w4
    lhs = -a * w2 * 1j * np.exp(1j * phi)
    col3, col4 = b * 1j * np.exp(1j * theta), -c * 1j * np.exp(1j * psi)
    det = col3.real * col4.imag - col3.imag * col4.real
    w3 = (lhs.real * col4.imag - lhs.imag * col4.real) / det
    w4 = (col3.real * lhs.imag - col3.imag * lhs.real) / det
    turn = np.exp(1j * gamma)
    origin = complex(*pivot)
    A0, B0 = origin + 0 * phi, origin + d * turn + 0 * phi
    A, B = origin + a_local * turn, origin + b_local * turn
    P = A + complex(*point) * np.exp(1j * (theta + gamma))
    return dict(A0=A0, A=A, B=B, B0=B0, P=P, w2=w2 + 0 * phi, w3=w3, w4=w4,
                theta=theta + gamma, psi=psi + gamma, phi=phi + gamma)


def dot(u, v):
    return u.real * v.real + u.imag * v.imag


def analyse(tmp_path, text: str, *extra):
    path = tmp_path / "loads.toml"
    path.write_text(text)
    code, out, err = run_cli("analyze", str(path), "--format", "json", "--precision", "17", *extra)
    assert code == 0, err
    return json.loads(out)


LINKAGE = """type = "linkage"
[units]
length = "{unit}"
[linkage]
ground = {d}
input = {a}
coupler = {b}
output = {c}
branch = "open"
coupler_point = [{px}, {py}]
ground_pivot = [{gx}, {gy}]
ground_angle = {gamma}
[motion]
input_speed = {speed}
steps = {steps}
"""


# ------------------------------------------------------------------ the seed case
def test_seed_case_input_torque_at_60_deg(tmp_path):
    text = LINKAGE.format(unit="m", d=4, a=1, b=3.5, c=3, px=1.5, py=1.0, gx=0, gy=0, gamma=0,
                          speed=10, steps=360) + "[loads]\ncoupler_force = [0, -100]\n"
    path = tmp_path / "seed.toml"
    path.write_text(text)
    code, out, err = run_cli("analyze", str(path), "--format", "json")
    assert code == 0, err
    rows = json.loads(out)["forces"]["rows"]
    row = rows[60]
    assert row["input"] == 60
    assert row["input_torque"] == pytest.approx(36.7824, abs=5e-5)


# ------------------------------------------------------------------ statics: virtual work
@pytest.mark.parametrize("unit", ["mm", "m"])
def test_static_torque_is_the_virtual_work_value_at_every_row(tmp_path, unit):
    a, b, c, d = 27.6293, 57.2363, 41.1104, 50.0
    px, py, gx, gy, gamma = 20.0, 10.0, 5.0, -3.0, 30.0
    force, torque = (35.0, -120.0), 7.5
    text = LINKAGE.format(unit=unit, d=d, a=a, b=b, c=c, px=px, py=py, gx=gx, gy=gy, gamma=gamma,
                          speed=20, steps=72)
    text += f"[loads]\ncoupler_force = [{force[0]}, {force[1]}]\noutput_torque = {torque}\n"
    forces = analyse(tmp_path, text)["forces"]
    phi = np.radians([r["input"] for r in forces["rows"]])
    got = np.array([r["input_torque"] for r in forces["rows"]], dtype=float)
    s = METRE[unit]
    m = four_bar(a * s, b * s, c * s, d * s, phi, pivot=(gx * s, gy * s), gamma=math.radians(gamma),
                 point=(px * s, py * s), w2=1.0)  # w2 = 1: velocities are d/dphi
    dp_dphi = 1j * (m["A"] - m["A0"]) + m["w3"] * 1j * (m["P"] - m["A"])
    expected = -(dot(complex(*force), dp_dphi) + torque * m["w4"])
    floor = 1e-9 * (math.hypot(*force) * max(a, b, c, d, px, py) * s + abs(torque))
    assert np.all(np.abs(got - expected) <= 1e-9 * np.abs(expected) + floor)


# ------------------------------------------------------------------ dynamics: energy balance
def test_input_power_is_the_rate_of_energy_minus_the_loads_power(tmp_path):
    """Vertical plane, gravity, three massive links, loads: at every row
    T_in w2 = d/dt(KE + PE) - F . v_P - T_out w4 (five-point difference, step h in time)."""
    a, b, c, d = 0.12, 0.32, 0.25, 0.30      # m
    px, py, gx, gy, gamma = 0.1, 0.05, 0.02, 0.01, 15.0
    speed = 120.0                             # deg/s
    masses = {"input": (0.8, (0.05, 0.01), 2e-3), "coupler": (1.5, (0.15, -0.02), 1.3e-2),
              "output": (1.1, (0.12, 0.0), 6e-3)}
    force, torque, gravity = (20.0, -35.0), -4.0, (0.0, -9.81)
    text = LINKAGE.format(unit="m", d=d, a=a, b=b, c=c, px=px, py=py, gx=gx, gy=gy, gamma=gamma,
                          speed=speed, steps=48)
    text += (f"[loads]\ncoupler_force = [{force[0]}, {force[1]}]\noutput_torque = {torque}\n"
             f"gravity = [{gravity[0]}, {gravity[1]}]\n[masses]\n")
    for link, (mass, (cx, cy), inertia) in masses.items():
        text += f"{link} = {{ mass = {mass}, center = [{cx}, {cy}], inertia = {inertia} }}\n"
    forces = analyse(tmp_path, text)["forces"]
    phi0 = np.radians([r["input"] for r in forces["rows"]])
    got = np.array([r["input_torque"] for r in forces["rows"]], dtype=float)
    w2 = math.radians(speed)
    g = complex(*gravity)

    def state(t):
        return four_bar(a, b, c, d, phi0 + w2 * t, pivot=(gx, gy), gamma=math.radians(gamma),
                        point=(px, py), w2=w2)

    def energy(t):
        m = state(t)
        total = 0.0
        bodies = (("input", m["A0"], m["A"], m["w2"], 0.0), ("coupler", m["A"], m["B"], m["w3"],
                  m["w2"] * 1j * (m["A"] - m["A0"])), ("output", m["B0"], m["B"], m["w4"], 0.0))
        for link, origin, towards, omega, origin_velocity in bodies:
            mass, centre, inertia = masses[link]
            axis = (towards - origin) / np.abs(towards - origin)
            where = origin + complex(*centre) * axis
            velocity = origin_velocity + omega * 1j * (where - origin)
            total = total + 0.5 * mass * np.abs(velocity) ** 2 + 0.5 * inertia * omega ** 2 \
                - mass * dot(g, where)
        return total

    h = 1e-4
    rate = (energy(-2 * h) - 8 * energy(-h) + 8 * energy(h) - energy(2 * h)) / (12 * h)
    m = state(0.0)
    v_p = m["w2"] * 1j * (m["A"] - m["A0"]) + m["w3"] * 1j * (m["P"] - m["A"])
    load_power = dot(complex(*force), v_p) + torque * m["w4"]
    expected = rate - load_power
    scale = np.max(np.abs(expected))
    assert np.all(np.abs(got * w2 - expected) <= 1e-7 * scale)
    # and the dynamics matter here: the static torque alone is far from it
    static = -load_power / w2
    assert np.max(np.abs(got - static)) > 1e-2 * np.max(np.abs(got))


# ------------------------------------------------------------------ slider-crank, analysis level
def slider(a, b, e, phi, w2, point=(0.0, 0.0)):
    """The test's own slider-crank: B = (s, e), s = a cos(phi) + sqrt(b^2 - (e - a sin(phi))^2)."""
    h = e - a * np.sin(phi)
    run = np.sqrt(b * b - h * h)
    A = a * np.exp(1j * phi)
    B = a * np.cos(phi) + run + 1j * e
    theta = np.angle(B - A)
    w3 = -a * w2 * np.cos(phi) / run                  # d/dt of b sin(theta) = e - a sin(phi)
    v_s = -a * w2 * np.sin(phi) - h * w3
    P = A + complex(*point) * np.exp(1j * theta)
    v_p = w2 * 1j * A + w3 * 1j * (P - A)
    return dict(A=A, B=B, P=P, theta=theta, w3=w3, v_s=v_s, v_p=v_p)


def slider_rows(masses, loads, phi, speed, a=0.08, b=0.25, e=0.03, point=(0.1, 0.04)):
    from linkcli import mechanisms
    from linkcli.mechanisms.slider_crank.model import SliderCrank
    from linkcli.model import LoadCase
    linkage = SliderCrank(a * 1000, b * 1000, e * 1000, "open", tuple(v * 1000 for v in point))
    return mechanisms.of(linkage).load_rows(phi, speed, LoadCase(loads, masses), 1e-3)  # given in mm: scale to m


def test_slider_crank_static_torque_by_virtual_work():
    from linkcli.model import Loads, Masses
    phi = np.linspace(0.05, 2 * np.pi, 97)
    loads = Loads(coupler_force=(40.0, -25.0), output_force=-300.0)
    rows = slider_rows(Masses(), loads, phi, 1.0)
    m = slider(0.08, 0.25, 0.03, phi, 1.0, (0.1, 0.04))   # w2 = 1: velocities are d/dphi
    expected = -(dot(complex(*loads.coupler_force), m["v_p"]) + loads.output_force * m["v_s"])
    assert set(rows.pins) == {"A0", "A", "B", "guide"}
    assert np.allclose(rows.input_torque, expected, rtol=1e-9, atol=1e-9 * 300 * 0.25)
    # the guide pushes across the guide only, and balances the rod's push on the slider
    assert np.all(rows.pins["guide"][:, 0] == 0)
    assert np.allclose(rows.pins["guide"][:, 1], -rows.pins["B"][:, 1], rtol=1e-12, atol=1e-9)


def test_slider_crank_energy_balance():
    from linkcli.model import LinkMass, Loads, Masses
    a, b, e, point, w2 = 0.08, 0.25, 0.03, (0.1, 0.04), 30.0
    masses = Masses(input=LinkMass(0.4, (40.0, 5.0), 3e-4), coupler=LinkMass(0.9, (120.0, 0.0), 5e-3),
                    output=LinkMass(1.2))   # centres in mm, as a problem file gives them
    loads = Loads(coupler_force=(10.0, -5.0), output_force=-50.0, gravity=(0.0, -9.81))
    phi0 = np.linspace(0.1, 2 * np.pi, 61)
    rows = slider_rows(masses, loads, phi0, w2, a, b, e, point)

    def energy(t):
        m = slider(a, b, e, phi0 + w2 * t, w2, point)
        total = 0.0
        A0 = 0.0 * m["A"]
        for mass, origin, towards, omega, v0 in ((masses.input, A0, m["A"], w2, 0.0),
                                                 (masses.coupler, m["A"], m["B"], m["w3"], w2 * 1j * m["A"])):
            axis = (towards - origin) / np.abs(towards - origin)
            where = origin + complex(*mass.center) * 1e-3 * axis
            v = v0 + omega * 1j * (where - origin)
            total = total + 0.5 * mass.mass * np.abs(v) ** 2 + 0.5 * mass.inertia * omega ** 2 \
                - mass.mass * dot(complex(*loads.gravity), where)
        return total + 0.5 * masses.output.mass * m["v_s"] ** 2 - masses.output.mass * dot(
            complex(*loads.gravity), m["B"])

    h = 1e-5
    rate = (energy(-2 * h) - 8 * energy(-h) + 8 * energy(h) - energy(2 * h)) / (12 * h)
    m = slider(a, b, e, phi0, w2, point)
    expected = rate - (dot(complex(*loads.coupler_force), m["v_p"]) + loads.output_force * m["v_s"])
    assert np.allclose(rows.input_torque * w2, expected, rtol=0, atol=1e-7 * np.max(np.abs(expected)))


def test_forces_section_dispatches_on_the_slider_crank_class():
    """section() with a SliderCrank: its pins, the guide, the mechanical advantage in 1/m
    (omega_in / v_slider from the test's kinematics)."""
    from linkcli.analysis import forces
    from linkcli.mechanisms.slider_crank.kinematics import SliderCrank
    from linkcli.model import LoadCase, Loads
    from linkcli.units import Units
    notes: list = []
    sc = SliderCrank(80.0, 250.0, 30.0, "open")
    from linkcli import mechanisms
    mech = mechanisms.of(sc)
    study = mech.study()
    assert study.full_turn
    out = forces.section(mech, study, math.radians(10), 36, LoadCase(Loads(output_force=-100.0)), Units(), notes)
    assert list(out["pins"]) == ["A0", "A", "B", "guide"]
    row = out["rows"][3]
    assert row["input"] == pytest.approx(30.0)
    m = slider(0.08, 0.25, 0.03, math.radians(30.0), 1.0)
    assert row["mechanical_advantage"] == pytest.approx(1.0 / m["v_s"], rel=1e-9)
    assert row["input_torque"] == pytest.approx(100.0 * m["v_s"], rel=1e-9)


# ------------------------------------------------------------------ file and report behaviour
def test_result_file_round_trips_the_load_case(tmp_path):
    code, _, err = run_cli("synth", "problems/firedoor_loads.toml", "--format", "toml", "--out", str(tmp_path))
    assert code == 0, err
    code, again, err = run_cli("analyze", str(tmp_path / "firedoor_loads.toml"), "--format", "json")
    assert code == 0, err
    code, first, err = run_cli("synth", "problems/firedoor_loads.toml", "--format", "json")
    assert json.loads(again)["forces"]["input_torque"] == json.loads(first)["forces"]["input_torque"]
    assert json.loads(again)["loads"] == json.loads(first)["loads"]


def test_forces_default_on_with_loads_and_other_types_take_them(tmp_path):
    """A precision-position result (no [motion]: 1 deg/s, 360 rows as its kinematics)."""
    path = tmp_path / "pp.toml"
    path.write_text('type = "precision-position"\n[linkage]\nground = 50.0\n[positions]\n'
                    "input = [45, 90, 135]\noutput = [52, 82, 112]\n[loads]\noutput_torque = -20\n")
    code, out, err = run_cli("synth", str(path), "--format", "json")
    assert code == 0, err
    report = json.loads(out)
    assert len(report["forces"]["rows"]) == 360
    # statics of a torque alone: T_in = -T_out dpsi/dphi = -T_out / MA at every row
    for row in report["forces"]["rows"][::37]:
        assert row["input_torque"] == pytest.approx(20.0 / row["mechanical_advantage"], rel=1e-5)


def test_toggle_row_is_null_and_named_in_a_note(tmp_path):
    """Input 1, coupler 7, output 10, ground 6 (a crank-rocker): at phi = 90 deg the open
    branch has B = (0, 8) (the 6-8-10 triangle A0 B B0), so A0, A and B are in line: a
    toggle, where the output stands still and the mechanical advantage is infinite."""
    text = LINKAGE.format(unit="m", d=6, a=1, b=7, c=10, px=0, py=0, gx=0, gy=0, gamma=0, speed=1, steps=4)
    text += "[loads]\noutput_torque = 1\n"
    report = analyse(tmp_path, text)
    m = four_bar(1.0, 7.0, 10.0, 6.0, np.radians([0.0, 90.0, 180.0, 270.0]))
    assert abs(m["B"][1] - 8j) < 1e-12
    ma = [r["mechanical_advantage"] for r in report["forces"]["rows"]]
    assert [x is None for x in ma] == [False, True, False, False]
    assert ma[0] == pytest.approx(m["w2"][0] / m["w4"][0], rel=1e-9)
    assert report["forces"]["rows"][1]["input_torque"] == 0  # the output cannot take the torque
    assert any("toggle" in note and "at input 90 deg" in note for note in report["notes"])


@pytest.mark.slow
def test_plot_adds_torque_and_pin_force_panels(tmp_path):
    """--plot of a result with a forces section: the type's figure on top, two panels under
    it drawn from the report's rows (torque curve through the rows' values)."""
    pytest.importorskip("matplotlib")
    from linkcli.pipeline import Request, run
    from linkcli.plot import figure
    outcome = run("problems/firedoor_loads.toml", Request(mode="synth", plot=True))
    fig = figure(outcome.result)
    bottom = fig.subfigs[1]
    torque_axes, pin_axes = bottom.axes
    rows = outcome.result.report["forces"]["rows"]
    x, y = torque_axes.lines[0].get_data()
    assert np.allclose(y, [r["input_torque"] for r in rows])
    assert [line.get_label() for line in pin_axes.lines] == ["A0", "A", "B", "B0"]
    target = tmp_path / "loads.png"
    code, _, err = run_cli("synth", "problems/firedoor_loads.toml", "--plot", str(target))
    assert code == 0, err
    assert target.read_bytes().startswith(b"\x89PNG")


def test_rocking_input_rows_are_the_kinematics_rows(tmp_path):
    """A triple-rocker (s + l > p + q): its input rocks; the forces rows sit at the same
    inputs as the kinematics rows (centres of equal cells of the arc), and the static
    torque there is the virtual-work value."""
    a, b, c, d = 3.0, 2.5, 2.0, 4.0
    text = LINKAGE.format(unit="m", d=d, a=a, b=b, c=c, px=0, py=0, gx=0, gy=0, gamma=0, speed=5, steps=24)
    text += "[loads]\noutput_torque = 3\n"
    report = analyse(tmp_path, text)
    assert report["grashof"]["class"] == "triple-rocker"
    inputs = [r["input"] for r in report["forces"]["rows"]]
    assert inputs == [r["input"] for r in report["kinematics"]]
    m = four_bar(a, b, c, d, np.radians(inputs))
    got = np.array([r["input_torque"] for r in report["forces"]["rows"]], dtype=float)
    assert np.allclose(got, -3.0 * m["w4"], rtol=1e-9, atol=1e-9 * 3.0)
