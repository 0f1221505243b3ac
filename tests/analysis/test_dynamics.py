"""Forward dynamics (issue 52) against independent references: closed forms written here, the
energy computed here from the four-bar's own kinematics, the period of the linearized motion
from finite differences, the existing statics and inverse dynamics (mechanisms.*.loads), and
the total centre of mass of a counterweighted four-bar computed here from its poses."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from linkcli.mechanisms.four_bar import kinematics as kin

DEG = math.pi / 180.0


def report(text: str, name: str = "test.toml") -> dict:
    """The report of a problem given as TOML text (the pipeline, in process)."""
    from linkcli.pipeline import Request, run
    outcome = run(name, Request(mode="synth"), text.encode())
    assert outcome.result is not None, outcome.errors
    return outcome.result.report


def history(rep: dict, key: str) -> np.ndarray:
    return np.array([row[key] for row in rep["history"]], dtype=float)


FOUR_BAR = """
[linkage]
ground = 50
input = 20
coupler = 60
output = 45
"""
SLIDER_CRANK = """
[linkage]
mechanism = "slider-crank"
input = 20
coupler = 60
offset = 5
"""
DRAWN_FOUR_BAR = """
[linkage]
mechanism = "drawn"
[joints]
A0 = { at = [0, 0], ground = true }
B0 = { at = [50, 0], ground = true }
A = { at = [14.1421356237, 14.1421356237] }
B = { at = [52.7347, 44.9245] }
[links]
input = ["A0", "A"]
coupler = ["A", "B"]
output = ["B0", "B"]
[drive]
input = { speed = 1 }
"""


def _drawn_b():
    """B of the drawn four-bar above, placed by the closed form at phi = 45 deg (open branch)."""
    p = kin.pose(20.0, 60.0, 45.0, 50.0, 45 * DEG, "open")
    return 50 + 45 * math.cos(float(p.psi)), 45 * math.sin(float(p.psi))


def drawn_four_bar() -> str:
    bx, by = _drawn_b()
    return DRAWN_FOUR_BAR.replace("B = { at = [52.7347, 44.9245] }", f"B = {{ at = [{bx!r}, {by!r}] }}")


# ---------------------------------------------------------------- closed forms

@pytest.mark.parametrize("linkage", ["four-bar", "slider-crank", "drawn"])
def test_a_crank_with_a_point_mass_and_a_torsional_spring_is_an_exact_harmonic_oscillator(linkage):
    """Only the crank has mass (a point mass m at radius r, no inertia of its own): M = m r^2
    whatever the rest does; a torsional spring k on the crank gives phi = phi0 + A cos(w t),
    w = sqrt(k / (m r^2))."""
    text = {"four-bar": FOUR_BAR, "slider-crank": SLIDER_CRANK, "drawn": drawn_four_bar()}[linkage]
    m, r, k, free, amplitude = 0.8, 20.0, 0.05, 30.0, 25.0
    rep = report(f"""type = "linkage"
{text}
[masses]
input = {{ mass = {m}, center = [{r}, 0] }}
[springs]
crank = {{ link = "input", stiffness = {k}, free_angle = {free} }}
[dynamics]
start = {{ angle = {free + amplitude} }}
duration = 1.5
steps = 301
""")
    omega = math.sqrt(k / (m * (r / 1000) ** 2))
    t = history(rep, "time")
    expected = free + amplitude * np.cos(omega * t)
    assert_allclose(history(rep, "angle"), expected, rtol=0, atol=1e-6)  # deg: 2e-8 of the swing
    assert_allclose(history(rep, "speed"), -amplitude * omega * np.sin(omega * t), rtol=0, atol=1e-5)
    assert rep["energy"]["balance"] == 0.0
    reversals = [e["time"] for e in rep["events"] if e["event"] == "reversal"]
    assert_allclose(reversals, np.arange(1, len(reversals) + 1) * math.pi / omega, rtol=1e-9)


@pytest.mark.parametrize("method", ["LSODA", "auto"])
def test_a_rotary_damper_on_a_lone_mass_decays_exponentially(method):
    """M w' = -c w: w = w0 exp(-c t / M), by the stiff method (LSODA) and by auto's."""
    m, r, c, w0 = 0.8, 20.0, 2e-4, 200.0
    rep = report(f"""type = "linkage"
{FOUR_BAR}
[masses]
input = {{ mass = {m}, center = [{r}, 0] }}
[dampers]
d = {{ link = "input", coefficient = {c} }}
[dynamics]
start = {{ angle = 0, speed = {w0} }}
duration = 2
steps = 101
method = "{method}"
""")
    big_m = m * (r / 1000) ** 2
    t = history(rep, "time")
    assert rep["simulation"]["method"] == ("LSODA" if method == "LSODA" else "DOP853")  # not stiff: c/M = 1.25/s
    assert_allclose(history(rep, "speed"), w0 * np.exp(-c * t / big_m), rtol=1e-8)
    work = rep["energy"]["damper_work"]
    assert_allclose(work, 0.5 * big_m * ((w0 * DEG) ** 2) * (math.exp(-2 * c * 2 / big_m) - 1), rtol=1e-8)


def test_coulomb_friction_in_the_crank_pin_decelerates_as_its_closed_form():
    """Only the crank has mass (point m at radius rho) and only its pin A0 carries a force: the
    friction couple mu r |F| with |F| = m rho sqrt(w^4 + a^2) gives rho a = -mu r sqrt(w^4 + a^2),
    so w' = -kappa w^2, kappa = mu r / sqrt(rho^2 - mu^2 r^2): w = w0 / (1 + kappa w0 t)."""
    m, rho, mu, d, w0 = 0.5, 20.0, 0.2, 10.0, 30.0  # rad/s
    rep = report(f"""type = "linkage"
{FOUR_BAR}
[units]
angle = "rad"
[joints]
A0 = {{ diameter = {d} }}
A = {{ diameter = 5 }}
B = {{ diameter = 5 }}
B0 = {{ diameter = 5 }}
[masses]
input = {{ mass = {m}, center = [{rho}, 0] }}
[dynamics]
start = {{ angle = 0, speed = {w0} }}
duration = 0.5
steps = 51
friction = {mu}
""")
    r = d / 2
    kappa = mu * r / math.sqrt(rho ** 2 - (mu * r) ** 2)
    t = history(rep, "time")
    assert_allclose(history(rep, "speed"), w0 / (1 + kappa * w0 * t), rtol=1e-7)
    assert_allclose(history(rep, "angle"), np.log1p(kappa * w0 * t) / kappa, rtol=1e-7)
    friction = [row["friction"] for row in rep["history"]]
    assert all(f["A"] == 0 and f["B"] == 0 and f["B0"] == 0 for f in friction)
    assert rep["energy"]["friction_work"] < 0 and rep["energy"]["balance"] == 0.0


# ---------------------------------------------------------------- energy over ten turns

MASSES = {"input": (0.2, (25.0, 3.0), 1e-4), "coupler": (0.5, (100.0, 10.0), 2e-3),
          "output": (0.4, (75.0, -5.0), 1e-3)}
A, B, C, D = 50.0, 200.0, 150.0, 180.0


def four_bar_energy(phi, w, gravity):
    """Kinetic + gravity potential of the crank-rocker above, from its closed-form poses and
    velocities (the test's own rigid-body sums; lengths in m)."""
    p = kin.pose(A, B, C, D, phi, "open")
    w3, w4 = kin.velocities(A, B, C, p, w)
    def frame(origin, angle, centre):
        e = np.array([math.cos(angle), math.sin(angle)])
        n = np.array([-e[1], e[0]])
        return origin + centre[0] * e + centre[1] * n, n * centre[0] - e * centre[1]
    a_pin = np.array([A * math.cos(phi), A * math.sin(phi)])
    bodies = [((0, 0), phi, w, "input", np.zeros(2)), (a_pin, float(p.theta), float(w3), "coupler",
              A * w * np.array([-math.sin(phi), math.cos(phi)])), ((D, 0), float(p.psi), float(w4), "output", np.zeros(2))]
    energy = 0.0
    for origin, angle, omega, name, v_origin in bodies:
        m, centre, inertia = MASSES[name]
        g_pos, lever_perp = frame(np.asarray(origin, dtype=float), angle, centre)
        v = (v_origin + omega * lever_perp) / 1000.0
        energy += 0.5 * m * float(v @ v) + 0.5 * inertia * omega ** 2 - m * float(np.dot(gravity, g_pos / 1000.0))
    return energy


def masses_toml() -> str:
    return "\n".join(f"{k} = {{ mass = {m}, center = [{c[0]}, {c[1]}], inertia = {i} }}"
                     for k, (m, c, i) in MASSES.items())


def test_without_damping_or_friction_energy_is_conserved_to_1e_8_over_ten_turns():
    gravity = np.array([0.0, -9.81])
    w0 = 60.0  # rad/s: over the top of gravity
    rep = report(f"""type = "linkage"
[units]
angle = "rad"
[linkage]
ground = {D}
input = {A}
coupler = {B}
output = {C}
[loads]
gravity = [0, -9.81]
[masses]
{masses_toml()}
[dynamics]
start = {{ angle = 0, speed = {w0} }}
stop = {{ angle = {20 * math.pi} }}
duration = 100
steps = 11
""")
    assert rep["simulation"]["end"] == "stop" and rep["simulation"]["method"] == "DOP853"
    last = rep["history"][-1]
    start = four_bar_energy(0.0, w0, gravity)
    end = four_bar_energy(last["angle"], last["speed"], gravity)
    assert last["angle"] == pytest.approx(20 * math.pi, rel=1e-12)
    assert abs(end - start) / abs(start) < 1e-8


# ---------------------------------------------------------------- the linearized period

def test_a_small_oscillation_about_a_stable_equilibrium_has_the_period_of_its_linearization():
    """Gravity on the crank-rocker: V(phi) and the generalized inertia M(phi) by finite
    differences of the poses (the test's own), the equilibrium where V' = 0 and V'' > 0, and
    T = 2 pi sqrt(M / V'')."""
    from scipy.optimize import brentq
    g = np.array([0.0, -9.81])

    def centres(phi):
        p = kin.pose(A, B, C, D, phi, "open")
        out = []
        for name, origin, angle in (("input", (0.0, 0.0), phi),
                                    ("coupler", (A * math.cos(phi), A * math.sin(phi)), float(p.theta)),
                                    ("output", (D, 0.0), float(p.psi))):
            m, c, inertia = MASSES[name]
            e = np.array([math.cos(angle), math.sin(angle)])
            n = np.array([-e[1], e[0]])
            out.append((m, inertia, (np.asarray(origin) + c[0] * e + c[1] * n) / 1000.0, angle))
        return out

    def potential(phi):
        return sum(-m * float(g @ pos) for m, _, pos, _ in centres(phi))

    h = 1e-5
    dv = lambda phi: (potential(phi + h) - potential(phi - h)) / (2 * h)
    grid = np.linspace(0, 2 * math.pi, 721)
    values = [dv(x) for x in grid]
    roots = [brentq(dv, grid[i], grid[i + 1], xtol=1e-15) for i in range(720) if values[i] < 0 <= values[i + 1]]
    phi0 = roots[0]
    h2 = 1e-4
    stiffness = (potential(phi0 + h2) - 2 * potential(phi0) + potential(phi0 - h2)) / h2 ** 2
    plus, minus = centres(phi0 + h), centres(phi0 - h)
    inertia = sum(m * float(np.sum(((pp - pm) / (2 * h)) ** 2)) + i * ((ap - am) / (2 * h)) ** 2
                  for (m, i, pp, ap), (_, _, pm, am) in zip(plus, minus))
    period = 2 * math.pi * math.sqrt(inertia / stiffness)
    rep = report(f"""type = "linkage"
[units]
angle = "rad"
[linkage]
ground = {D}
input = {A}
coupler = {B}
output = {C}
[loads]
gravity = [0, -9.81]
[masses]
{masses_toml()}
[dynamics]
start = {{ angle = {phi0 + 1e-4!r} }}
duration = {6 * period}
steps = 11
""")
    reversals = [e["time"] for e in rep["events"] if e["event"] == "reversal"]
    assert len(reversals) >= 10
    measured = (reversals[-1] - reversals[0]) / ((len(reversals) - 1) / 2)
    assert measured == pytest.approx(period, rel=1e-6)


# ---------------------------------------------------------------- statics and inverse dynamics

def test_the_spring_loaded_closers_equilibrium_is_the_existing_statics():
    """A constant torque on the input against a torsional spring on the output, damped until it
    rests: at the angle it rests at, the existing statics (four_bar_loads at rest, the spring's
    torque as the output torque) needs exactly that input torque."""
    from linkcli import mechanisms
    from linkcli.mechanisms.four_bar.model import FourBar
    from linkcli.model import LoadCase, Loads
    k, free, torque = 30.0, 20.0, 12.0
    rep = report(f"""type = "linkage"
[linkage]
ground = 50
input = 27.6293
coupler = 57.2363
output = 41.1104
[masses]
input = {{ mass = 30, center = [400, 0], inertia = 5 }}
[springs]
closer = {{ link = "output", stiffness = {k}, free_angle = {free} }}
[dampers]
valve = {{ link = "output", coefficient = 40 }}
[dynamics]
drive = {{ torque = {torque} }}
start = {{ angle = 60 }}
duration = 60
steps = 2
""")
    last = rep["history"][-1]
    assert abs(last["speed"]) < 1e-6
    phi = last["angle"] * DEG
    fb = FourBar(ground=50, input=27.6293, coupler=57.2363, output=41.1104)
    p = kin.pose(*fb.abcd, phi, "open")
    spring = -k * (float(p.psi) - free * DEG)
    rows = mechanisms.of(fb).load_rows(np.array([phi]), 0.0, LoadCase(loads=Loads(output_torque=spring)), 1e-3)
    assert float(rows.input_torque[0]) == pytest.approx(torque, rel=1e-7)
    assert last["elements"]["closer"] == pytest.approx(-spring, rel=1e-9)


@pytest.mark.parametrize("linkage", ["four-bar", "slider-crank"])
def test_a_friction_free_run_gives_the_torque_and_pins_of_the_existing_inverse_dynamics(linkage):
    """A motor drives the linkage under gravity, a coupler force and an output load; at every
    history row (angle, speed, acceleration) the existing Newton-Euler solve (four_bar_loads,
    slider_crank_loads with the input's acceleration) needs the motor's torque, and gives the
    same pin forces."""
    from linkcli.mechanisms.four_bar.loads import FourBarState, four_bar_loads
    from linkcli.mechanisms.newton_euler import in_metres
    from linkcli.mechanisms.slider_crank import kinematics as sc
    from linkcli.mechanisms.slider_crank.loads import SliderCrankState, slider_crank_loads
    from linkcli.model import LinkMass, Loads, Masses
    four = linkage == "four-bar"
    text = (FOUR_BAR if four else SLIDER_CRANK).replace("[linkage]", "[linkage]\ncoupler_point = [25, 8]")
    load = "output_torque = -0.8" if four else "output_force = -30"
    out_mass = "output = { mass = 0.3, center = [20, -2], inertia = 1e-3 }" if four else "slider = { mass = 0.3 }"
    rep = report(f"""type = "linkage"
{text}
[loads]
gravity = [0, -9.81]
coupler_force = [3, -2]
{load}
[masses]
input = {{ mass = 0.2, center = [8, 1], inertia = 1e-4 }}
coupler = {{ mass = 0.5, center = [25, 3], inertia = 2e-3 }}
{out_mass}
[dynamics]
drive = {{ torque_speed = [[0, 2.0], [1000, 1.5], [3000, 0]] }}
start = {{ angle = 10, speed = 100 }}
duration = 0.6
steps = 41
""")
    phi = history(rep, "angle") * DEG
    w = history(rep, "speed") * DEG
    alpha = history(rep, "acceleration") * DEG
    masses = in_metres(Masses(input=LinkMass(0.2, (8, 1), 1e-4), coupler=LinkMass(0.5, (25, 3), 2e-3),
                              output=LinkMass(0.3, (20, -2), 1e-3) if four else LinkMass(0.3)), 1e-3)
    if four:
        loads = Loads(coupler_force=(3, -2), output_torque=-0.8, gravity=(0, -9.81))
        p = kin.pose(20, 60, 45, 50, phi, "open")
        w3, w4 = kin.velocities(20, 60, 45, p, w)
        a3, a4 = kin.accelerations(20, 60, 45, p, w, alpha)
        state = FourBarState.from_angles(ground_length=0.05, input_length=0.02, coupler_length=0.06,
                                         output_length=0.045, phi=phi, psi=p.psi, omega_input=w,
                                         omega_coupler=w3, omega_output=w4, alpha_input=alpha,
                                         alpha_coupler=a3, alpha_output=a4, coupler_point=(0.025, 0.008))
        rows = four_bar_loads(state, loads, masses)
    else:
        loads = Loads(coupler_force=(3, -2), output_force=-30, gravity=(0, -9.81))
        p = sc.pose(20, 60, 5, phi)
        _, w3 = sc.velocities(20, 60, p, w)
        _, a3 = sc.accelerations(20, 60, p, w, alpha)
        state = SliderCrankState.from_angles(input_length=0.02, coupler_length=0.06, phi=phi, theta=p.theta,
                                             omega_input=w, omega_coupler=w3, alpha_input=alpha,
                                             alpha_coupler=a3, coupler_point=(0.025, 0.008))
        rows = slider_crank_loads(state, loads, masses)
    torque = history(rep, "drive_torque")
    assert np.ptp(w) > 0 and np.max(np.abs(alpha)) > 0  # it does accelerate
    assert_allclose(rows.input_torque, torque, rtol=0, atol=1e-7 * np.max(np.abs(torque)))
    scale = max(np.max(np.abs(v)) for v in rows.pins.values())
    for name in ("A0", "A", "B"):
        got = np.array([[r["pins"][name]["x"], r["pins"][name]["y"]] for r in rep["history"]])
        assert_allclose(got, rows.pins[name], rtol=0, atol=1e-7 * scale)
    if not four:
        got = np.array([r["pins"]["guide"]["y"] for r in rep["history"]])
        assert_allclose(got, rows.pins["guide"][:, 1], rtol=0, atol=1e-7 * scale)


# ---------------------------------------------------------------- the named and the drawn four-bar

def test_a_drawn_four_bar_runs_as_the_named_one():
    common = """[masses]
input = { mass = 0.2, center = [8, 1], inertia = 1e-4 }
coupler = { mass = 0.5, center = [25, 3], inertia = 2e-3 }
output = { mass = 0.3, center = [20, -2], inertia = 1e-3 }
[loads]
gravity = [0, -9.81]
[springs]
s = { between = ["A0", "B"], stiffness = 0.5, free_length = 30 }
[dampers]
d = { link = "output", coefficient = 0.002 }
[dynamics]
start = { angle = 45, speed = 0 }
duration = 1
steps = 21
"""
    named = report(f'type = "linkage"\n{FOUR_BAR}\n{common}')
    drawn = report(f'type = "linkage"\n{drawn_four_bar()}\n{common}')
    for key in ("angle", "speed", "acceleration"):
        expected = history(named, key)  # two integrations of one motion, each to rtol 1e-10
        assert_allclose(history(drawn, key), expected, rtol=0, atol=1e-6 * np.max(np.abs(expected)))
    for pin in ("A0", "A", "B", "B0"):
        for comp in ("x", "y"):
            a = np.array([r["pins"][pin][comp] for r in named["history"]])
            b = np.array([r["pins"][pin][comp] for r in drawn["history"]])
            assert_allclose(b, a, rtol=1e-6, atol=1e-7 * np.max(np.abs(a)))


# ---------------------------------------------------------------- dead points

def test_a_released_double_rocker_runs_into_its_dead_point_as_an_event():
    """A non-Grashof linkage swung towards the end of its input's range: the run ends at the
    dead-point event, where (the test's own transmission angle) mu is within dead_point of 0."""
    rep = report("""type = "linkage"
[linkage]
ground = 60
input = 40
coupler = 30
output = 45
[masses]
input = { mass = 1, center = [40, 0] }
[dynamics]
start = { angle = 60, speed = 400 }
duration = 5
dead_point = 2
steps = 11
""")
    assert rep["simulation"]["end"] == "dead-point"
    event = [e for e in rep["events"] if e["event"] == "dead-point"][-1]
    p = kin.pose(40, 30, 45, 60, event["angle"] * DEG, "open")
    assert abs(math.sin(float(p.mu))) == pytest.approx(math.sin(2 * DEG), rel=1e-6)


# ---------------------------------------------------------------- balancing

def test_counterweights_cancel_the_shaking_force_of_a_four_bar():
    """The total centre of mass (the test's own sums over the closed-form poses) of the linkage
    with the reported counterweights stays put to 1e-9 of how far the unbalanced one moves."""
    rep = report(f"""type = "linkage"
[linkage]
ground = {D}
input = {A}
coupler = {B}
output = {C}
[motion]
input_speed = 600
steps = 72
[masses]
{masses_toml()}
[dynamics]
counterweights = {{ output = 120 }}
""")
    cw = rep["balance"]["counterweights"]
    assert cw["output"]["radius"] == 120 and cw["input"]["radius"] == A

    def com(phi, extra):
        p = kin.pose(A, B, C, D, phi, "open")
        total, weight = 0.0, 0.0
        zero = np.zeros_like(phi)
        frames = {"input": ((zero, zero), phi), "coupler": ((A * np.cos(phi), A * np.sin(phi)), p.theta),
                  "output": ((zero + D, zero), p.psi)}
        for name, (origin, angle) in frames.items():
            items = [MASSES[name][:2]]
            if name in extra:
                items.append(extra[name])
            for m, (cx, cy) in items:
                x = origin[0] + cx * np.cos(angle) - cy * np.sin(angle)
                y = origin[1] + cx * np.sin(angle) + cy * np.cos(angle)
                total = total + m * np.stack([x, y])
                weight += m
        return total / weight

    phi = np.linspace(0, 2 * math.pi, 361)
    extra = {k: (v["mass"], (v["radius"] * math.cos(v["angle"] * DEG), v["radius"] * math.sin(v["angle"] * DEG)))
             for k, v in cw.items()}
    unbalanced, balanced = com(phi, {}), com(phi, extra)
    assert np.ptp(balanced, axis=1).max() < 1e-9 * np.ptp(unbalanced, axis=1).max()
    assert rep["balance"]["balanced"]["shaking_force"]["max"] == 0.0
    assert rep["balance"]["unbalanced"]["shaking_force"]["max"] > 0


# ---------------------------------------------------------------- the flywheel

def test_the_flywheel_of_the_energy_method_matches_the_inverse_dynamics_and_the_integration():
    """dE from the existing inverse dynamics (the torque over a turn at the mean speed, its
    running integral by the trapezoid rule on 7200 rows), I = dE / (Cs w^2); the integration
    with that flywheel holds the fluctuation near Cs (the method neglects the linkage's own
    inertia, here 1 % of the flywheel's)."""
    from linkcli import mechanisms
    from linkcli.mechanisms.four_bar.model import FourBar
    from linkcli.model import LinkMass, LoadCase, Loads, Masses
    speed, cs = 1200.0, 0.03
    rep = report(f"""type = "linkage"
[linkage]
ground = {D}
input = {A}
coupler = {B}
output = {C}
[loads]
output_torque = -0.2
[masses]
{masses_toml()}
[dynamics]
mean_speed = {speed}
fluctuation = {cs}
""")
    fw = rep["flywheel"]
    fb = FourBar(ground=D, input=A, coupler=B, output=C)
    case = LoadCase(loads=Loads(output_torque=-0.2), masses=Masses(
        **{k: LinkMass(m, c, i) for k, (m, c, i) in MASSES.items()}))
    phi = np.linspace(0, 2 * math.pi, 7201)
    torque = mechanisms.of(fb).load_rows(phi, speed * DEG, case, 1e-3).input_torque
    mean = np.mean(torque[:-1])
    energy = np.concatenate([[0], np.cumsum(0.5 * (2 * mean - torque[1:] - torque[:-1]) * np.diff(phi))])
    d_energy = energy.max() - energy.min()
    assert fw["energy_fluctuation"] == pytest.approx(d_energy, rel=1e-5)
    assert fw["mean_torque"] == pytest.approx(mean, abs=1e-9 * np.max(np.abs(torque)))
    assert fw["inertia"] == pytest.approx(d_energy / (cs * (speed * DEG) ** 2), rel=1e-5)
    assert fw["with_flywheel"]["fluctuation"] == pytest.approx(cs, rel=0.05)
    assert fw["as_given"]["fluctuation"] > 3 * cs


# ---------------------------------------------------------------- the equation's two forms

def _system(text: str):
    from linkcli import mechanisms
    from linkcli.analysis.dynamics.system import System
    from linkcli.reading.load import load
    problem = load("t.toml", text.encode())
    meta = problem.meta
    return System(mechanisms.of(problem.linkage), meta.dynamics, meta.loads, meta.units,
                  meta.units.mm_per_length / 1000.0)


def test_the_tabulated_equation_is_the_exact_one_to_its_tolerance():
    """The integrator's tables against the home's exact coefficients at drive values between
    the nodes: the inertia, its derivative and the potential's derivative."""
    system = _system(f"""type = "linkage"
[linkage]
ground = {D}
input = {A}
coupler = {B}
output = {C}
[loads]
gravity = [0, -9.81]
[masses]
{masses_toml()}
[dynamics]
start = {{ angle = 0, speed = 100 }}
duration = 1
""")
    q = np.random.default_rng(1).uniform(0, 2 * math.pi, 200)
    exact = system.exact(q)
    values, slopes = system.table.many(q)
    assert_allclose(values[:, 0], exact.inertia, rtol=1e-10)
    assert_allclose(slopes[:, 0], exact.d_inertia, rtol=0, atol=1e-7 * np.max(np.abs(exact.d_inertia)))
    assert_allclose(slopes[:, 1], exact.d_potential, rtol=0, atol=1e-7 * np.max(np.abs(exact.d_potential)))


def test_newton_euler_and_the_lagrange_form_give_one_acceleration_on_a_watt_six_bar():
    """The drawn Watt six-bar (problems/drawn_watt.toml) with a linear spring, a rotary damper
    and its loads: the acceleration from the equation of motion (virtual work) and from the
    Newton-Euler equations of every body agree at any state."""
    from conftest import ROOT

    from linkcli.analysis.dynamics.history import state
    text = (ROOT / "problems" / "drawn_watt.toml").read_text() + """[springs]
s = { between = ["O2", "D"], stiffness = 0.8, free_length = 60 }
[dampers]
d = { link = "rocker", coefficient = 0.01 }
[dynamics]
drive = { torque = 0.3 }
start = { angle = 60 }
duration = 1
"""
    system = _system(text)
    rng = np.random.default_rng(2)
    q = rng.uniform(0, 2 * math.pi, 50)
    w = rng.uniform(-20, 20, 50)
    st = state(system, q, w)
    assert_allclose(st.solved.drive, st.acceleration, rtol=1e-9, atol=1e-9 * np.max(np.abs(st.acceleration)))


@pytest.mark.parametrize("linkage", ["four-bar", "slider-crank"])
def test_the_integrators_friction_is_the_exact_newton_euler_fixed_point(linkage):
    """Pin friction (and the slider-crank's guide friction) as the integrator evaluates it, from
    tabulated unit responses, against the fixed point of the exact Newton-Euler equations of
    every body at random states: the same generalized friction force and acceleration."""
    from linkcli.analysis.dynamics import motion
    from linkcli.analysis.dynamics.history import state
    four = linkage == "four-bar"
    text = f"""type = "linkage"
{FOUR_BAR if four else SLIDER_CRANK}
[loads]
gravity = [0, -9.81]
[masses]
input = {{ mass = 0.2, center = [8, 1], inertia = 1e-4 }}
coupler = {{ mass = 0.5, center = [25, 3], inertia = 2e-3 }}
{"output = { mass = 0.3, center = [20, -2], inertia = 1e-3 }" if four else "slider = { mass = 0.3 }"}
[joints]
A0 = {{ diameter = 10 }}
A = {{ diameter = 8 }}
B = {{ diameter = 8 }}
{"B0 = { diameter = 10 }" if four else ""}
[dampers]
d = {{ between = ["A0", "B"], coefficient = 0.02 }}
[dynamics]
drive = {{ torque = 0.4 }}
start = {{ angle = 0, speed = 100 }}
duration = 1
friction = 0.15
"""
    system = _system(text)
    rhs, _ = motion.right_hand_side(system, 10**9)
    rng = np.random.default_rng(3)
    q = rng.uniform(0, 2 * math.pi, 20)
    w = rng.uniform(-30, 30, 20)
    st = state(system, q, w)
    tabulated = np.array([rhs(0.0, [qq, ww, 0, 0, 0])[1] for qq, ww in zip(q, w)])
    lost = np.array([rhs(0.0, [qq, ww, 0, 0, 0])[4] for qq, ww in zip(q, w)])
    assert np.all(st.solved.converged)
    assert_allclose(tabulated, st.acceleration, rtol=0, atol=1e-8 * np.max(np.abs(st.acceleration)))
    power = np.zeros(len(q))  # friction's power at the exact fixed point, from its couples and forces
    from linkcli.analysis.dynamics import body_forces
    a = body_forces.Assembly(system.graph, st.exact.coef, True)
    pin_rate, guide_rate = a.rates_at_pins(1.0)
    for name, couple in st.solved.pin_friction.items():
        power += couple * pin_rate[name] * w
    for name, force in st.solved.guide_friction.items():
        power += force * guide_rate[name] * w
    assert np.all(power <= 0) and np.all(lost <= 0)
    assert_allclose(lost, power, rtol=0, atol=1e-8 * np.max(np.abs(power)))
