"""Forward dynamics of the five-bar (two drives, issue 52) against independent references: the
five-bar's poses computed here (two circles' intersection), its kinetic and potential energy from
them by finite differences, the linearized modes of a small oscillation from a 2 x 2 eigenproblem
K v = w^2 M v written here, closed forms of decoupled cranks, and the existing inverse dynamics
(five_bar.loads, checked by virtual work in tests/mechanisms/test_five_bar_loads.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

DEG = math.pi / 180.0
GROUND, A1, A2, B1, B2 = 50.0, 40.0, 40.0, 60.0, 60.0  # mm

LINKAGE = f"""type = "linkage"
[linkage]
mechanism = "five-bar"
ground = {GROUND}
input = {A1}
input2 = {A2}
coupler = {B1}
coupler2 = {B2}
[motion]
inputs = [[120, 60], [115, 65]]
"""

# link: (mass kg, centre in its frame mm, inertia kg m^2)
MASSES = {"input": (0.05, (20.0, 2.0), 1.2e-5), "input2": (0.06, (18.0, -1.5), 1.5e-5),
          "coupler": (0.30, (50.0, 4.0), 6e-5), "coupler2": (0.08, (30.0, -2.0), 3e-5)}


def masses_toml(masses=MASSES) -> str:
    rows = [f"{k} = {{ mass = {m}, center = [{c[0]}, {c[1]}], inertia = {i} }}" for k, (m, c, i) in masses.items()]
    return "[masses]\n" + "\n".join(rows) + "\n"


def report(text: str) -> dict:
    from linkcli.pipeline import Request, run
    outcome = run("test.toml", Request(mode="synth"), text.encode())
    assert outcome.result is not None, outcome.errors
    return outcome.result.report


def per_drive(rep: dict, key: str) -> np.ndarray:
    """(n, 2) of a history column per drive (input, input2)."""
    return np.array([[row["drives"][d][key] for d in ("input", "input2")] for row in rep["history"]], dtype=float)


def times(rep: dict) -> np.ndarray:
    return np.array([row["time"] for row in rep["history"]], dtype=float)


# ---------------------------------------------------------------- the test's own five-bar (m)

def frames(q1, q2):
    """Every link's frame (origin (2,), angle) at drive angles q1, q2 (rad), lengths in m: the
    cranks from A0 = 0 and B0 = (ground, 0); P where the distal links meet, left of A -> B."""
    g, a1, a2, b1, b2 = (v / 1000 for v in (GROUND, A1, A2, B1, B2))
    a = np.array([a1 * math.cos(q1), a1 * math.sin(q1)])
    b0 = np.array([g, 0.0])
    b = b0 + np.array([a2 * math.cos(q2), a2 * math.sin(q2)])
    d = b - a
    c = math.hypot(*d)
    x = (c * c + b1 * b1 - b2 * b2) / (2 * c)
    h = math.sqrt(b1 * b1 - x * x)
    t = d / c
    p = a + x * t + h * np.array([-t[1], t[0]])
    return {"input": (np.zeros(2), q1), "input2": (b0, q2),
            "coupler": (a, math.atan2(*(p - a)[::-1])), "coupler2": (b, math.atan2(*(p - b)[::-1]))}, p


def centre(origin, angle, local):
    lx, ly = (v / 1000 for v in local)
    return origin + np.array([lx * math.cos(angle) - ly * math.sin(angle), lx * math.sin(angle) + ly * math.cos(angle)])


def centres(q, masses=MASSES):
    """Each massive link's (centre (2,), angle) and P at q = (q1, q2)."""
    f, p = frames(*q)
    return {k: (centre(*f[k], masses[k][1]), f[k][1]) for k in masses}, p


def jacobians(q, masses=MASSES, h=1e-6):
    """Central finite differences of every centre and angle with respect to q1 and q2."""
    out = {}
    for j in range(2):
        dq = np.zeros(2)
        dq[j] = h
        plus, _ = centres(np.asarray(q) + dq, masses)
        minus, _ = centres(np.asarray(q) - dq, masses)
        for k in masses:
            gp, tp = plus[k]
            gm, tm = minus[k]
            dtheta = math.remainder(tp - tm, 2 * math.pi)
            out.setdefault(k, [np.zeros((2, 2)), np.zeros(2)])
            out[k][0][:, j] = (gp - gm) / (2 * h)
            out[k][1][j] = dtheta / (2 * h)
    return out


def mass_matrix(q, masses=MASSES):
    """M = sum m J_G^T J_G + I J_theta^T J_theta, from the finite-difference Jacobians."""
    m = np.zeros((2, 2))
    for k, (jg, jt) in jacobians(q, masses).items():
        mass, _, inertia = masses[k]
        m += mass * jg.T @ jg + inertia * np.outer(jt, jt)
    return m


def kinetic(q, w, masses=MASSES):
    return 0.5 * w @ mass_matrix(q, masses) @ w


# ---------------------------------------------------------------- energy

SPRINGS = """[springs]
left = { link = "input", stiffness = 0.6, free_angle = 120 }
right = { link = "input2", stiffness = 0.5, free_angle = 60 }
pull = { between = ["P", [0, 140]], stiffness = 0.02, free_length = 30, preload = 0.3 }
twist = { links = ["coupler", "coupler2"], stiffness = 0.05, free_angle = -70 }
"""


def potential(q, masses=MASSES, gravity=-9.81):
    """Gravity and the springs of SPRINGS at q (J), from the test's own poses."""
    c, p = centres(q, masses)
    v = -sum(masses[k][0] * gravity * c[k][0][1] for k in masses)
    f, _ = frames(*q)
    v += 0.5 * 0.6 * (q[0] - 120 * DEG) ** 2 + 0.5 * 0.5 * (q[1] - 60 * DEG) ** 2
    length = math.hypot(p[0] - 0.0, p[1] - 0.140)
    v += 0.3 * (length - 0.030) + 0.5 * 20.0 * (length - 0.030) ** 2
    twist = math.remainder(f["coupler2"][1] - f["coupler"][1], 2 * math.pi)  # near -70 deg here
    v += 0.5 * 0.05 * (twist + 70 * DEG) ** 2
    return v


def test_without_damping_or_friction_energy_is_conserved_to_1e_8_over_a_long_run():
    """Both drives free, gravity, four springs (torsional on each crank, linear from P to an
    anchor with a preload, torsional between the distal links): kinetic + potential, computed
    here from the reported angles and speeds, stays constant to 1e-8 of the kinetic energy's
    swing over 10 s (more than 100 reversals); the energy section's balance is 0."""
    rep = report(LINKAGE + masses_toml() + """[loads]
gravity = [0, -9.81]
""" + SPRINGS + """[dynamics]
duration = 10
steps = 501
[dynamics.input]
start = { angle = 128, speed = 40 }
[dynamics.input2]
start = { angle = 55, speed = -60 }
""")
    assert rep["simulation"]["end"] == "duration"
    q = per_drive(rep, "angle") * DEG
    w = per_drive(rep, "speed") * DEG
    t_energy = np.array([kinetic(qq, ww) for qq, ww in zip(q, w)])
    v_energy = np.array([potential(qq) for qq in q])
    total = t_energy + v_energy
    reversals = [e for e in rep["events"] if e["event"] == "reversal"]
    assert len(reversals) == 100  # the first 100 listed: many oscillations of both drives
    swing = np.ptp(t_energy)
    assert np.max(np.abs(total - total[0])) < 1e-8 * swing
    assert rep["energy"]["balance"] == 0.0
    assert rep["energy"]["drive_work"] == 0.0 and rep["energy"]["damper_work"] == 0.0


def test_released_under_gravity_the_five_bar_runs_into_its_dead_point_as_an_event():
    """No springs: the payload falls and the distal links straighten; the run ends at the
    dead-point event, where the angle at P (computed here from the reported cranks' angles)
    is dead_point from a straight line."""
    rep = report(LINKAGE + masses_toml() + """[loads]
gravity = [0, -9.81]
[dynamics]
duration = 5
steps = 11
dead_point = 3
[dynamics.input]
start = { angle = 120 }
[dynamics.input2]
start = { angle = 60 }
""")
    assert rep["simulation"]["end"] == "dead-point"
    event = rep["events"][-1]
    assert event["event"] == "dead-point" and event["time"] == pytest.approx(rep["simulation"]["end_time"], rel=1e-12)
    q = [event["drives"][d]["angle"] * DEG for d in ("input", "input2")]
    f, p = frames(*q)
    u, v = p - f["coupler"][0], p - f["coupler2"][0]
    angle_at_p = math.degrees(math.acos(u @ v / (np.linalg.norm(u) * np.linalg.norm(v))))
    assert min(angle_at_p, 180 - angle_at_p) == pytest.approx(3.0, abs=1e-6)


# ---------------------------------------------------------------- small oscillations

def _equilibrium():
    from scipy.optimize import minimize
    result = minimize(lambda x: potential(x), np.array([120 * DEG, 60 * DEG]), method="Nelder-Mead",
                      options={"xatol": 1e-12, "fatol": 1e-16, "maxiter": 20000})
    q = result.x
    for _ in range(20):  # Newton on the finite-difference gradient and Hessian
        grad, hess = _gradient(q), _hessian(q)
        q = q - np.linalg.solve(hess, grad)
    return q


def _gradient(q, h=1e-6):
    return np.array([(potential(q + h * e) - potential(q - h * e)) / (2 * h) for e in np.eye(2)])


def _hessian(q, h=1e-4):
    out = np.zeros((2, 2))
    for i, ei in enumerate(np.eye(2)):
        for j, ej in enumerate(np.eye(2)):
            out[i, j] = (potential(q + h * ei + h * ej) - potential(q + h * ei - h * ej)
                         - potential(q - h * ei + h * ej) + potential(q - h * ei - h * ej)) / (4 * h * h)
    return out


@pytest.mark.parametrize("mode", [0, 1])
def test_a_small_oscillation_about_a_stable_equilibrium_has_the_period_of_its_linearization(mode):
    """The equilibrium of gravity and the springs found here (the potential's minimum); K its
    Hessian by finite differences, M the mass matrix from finite-difference Jacobians of the
    poses; each mode of K v = w^2 M v, started at q* + eps v from rest, oscillates with period
    2 pi / w: both drives reverse together every half period."""
    from scipy.linalg import eigh
    q_star = _equilibrium()
    k, m = _hessian(q_star), mass_matrix(q_star)
    values, vectors = eigh(k, m)
    assert np.all(values > 0)  # stable
    omega = math.sqrt(values[mode])
    v = vectors[:, mode] / np.max(np.abs(vectors[:, mode]))
    q0 = q_star + 1e-4 * v
    period = 2 * math.pi / omega
    rep = report(LINKAGE + masses_toml() + """[loads]
gravity = [0, -9.81]
""" + SPRINGS + f"""[dynamics]
duration = {float(6 * period)!r}
steps = 11
[dynamics.input]
start = {{ angle = {float(q0[0] / DEG)!r} }}
[dynamics.input2]
start = {{ angle = {float(q0[1] / DEG)!r} }}
""")
    for drive in ("input", "input2"):
        ts = np.array([e["time"] for e in rep["events"] if e["event"] == "reversal" and e["drive"] == drive])
        assert len(ts) >= 10
        assert_allclose(np.diff(ts), period / 2, rtol=2e-5)
    # the other mode is not excited: the drives keep the mode's ratio
    q = per_drive(rep, "angle") * DEG - q_star
    ratio = v[1 - np.argmax(np.abs(v))] / v[np.argmax(np.abs(v))]
    big = q[:, np.argmax(np.abs(v))]
    assert_allclose(q[:, 1 - np.argmax(np.abs(v))], ratio * big, rtol=0, atol=1e-3 * 1e-4)


# ---------------------------------------------------------------- decoupled cranks: closed forms

POINT_CRANKS = """[masses]
input = { mass = 0.8, center = [30, 0] }
input2 = { mass = 0.5, center = [25, 0] }
"""


def test_two_cranks_carrying_point_masses_with_springs_are_two_harmonic_oscillators():
    """Only the cranks have mass (point masses m at radius r, no inertia): M = diag(m r^2), no
    coupling through the massless distal links; a torsional spring on each crank makes each an
    exact harmonic oscillator, q_j = free_j + A_j cos(w_j t), w_j = sqrt(k_j / (m_j r_j^2))."""
    rep = report(LINKAGE + POINT_CRANKS + """[springs]
left = { link = "input", stiffness = 0.05, free_angle = 110 }
right = { link = "input2", stiffness = 0.02, free_angle = 70 }
[dynamics]
duration = 1.5
steps = 301
[dynamics.input]
start = { angle = 125 }
[dynamics.input2]
start = { angle = 62 }
""")
    t = times(rep)
    w1 = math.sqrt(0.05 / (0.8 * 0.030 ** 2))
    w2 = math.sqrt(0.02 / (0.5 * 0.025 ** 2))
    q = per_drive(rep, "angle")
    assert_allclose(q[:, 0], 110 + 15 * np.cos(w1 * t), rtol=0, atol=1e-6)
    assert_allclose(q[:, 1], 70 - 8 * np.cos(w2 * t), rtol=0, atol=1e-6)
    assert_allclose(per_drive(rep, "speed")[:, 0], -15 * w1 * np.sin(w1 * t), rtol=0, atol=1e-5)
    rev = [e["time"] for e in rep["events"] if e["event"] == "reversal" and e["drive"] == "input2"]
    assert_allclose(rev, np.arange(1, len(rev) + 1) * math.pi / w2, rtol=1e-9)


def test_a_rotary_damper_and_a_constant_torque_on_decoupled_cranks_follow_their_closed_forms():
    """input: a rotary damper c, M1 w1' = -c w1: w1 = w0 exp(-c t / M1); input2: a constant
    torque T from rest, q2 = q20 + T t^2 / (2 M2). The damper's work is the kinetic energy it
    took, the drive's the energy it gave."""
    c, torque = 2e-4, 1e-3
    m1, m2 = 0.8 * 0.030 ** 2, 0.5 * 0.025 ** 2
    rep = report(LINKAGE + POINT_CRANKS + f"""[dampers]
d = {{ link = "input", coefficient = {c} }}
[dynamics]
duration = 0.5
steps = 51
[dynamics.input]
start = {{ angle = 120, speed = 20 }}
[dynamics.input2]
drive = {{ torque = {torque} }}
start = {{ angle = 60 }}
""")
    t = times(rep)
    assert_allclose(per_drive(rep, "speed")[:, 0], 20 * np.exp(-c * t / m1), rtol=1e-8)
    assert_allclose(per_drive(rep, "angle")[:, 1], 60 + torque * t ** 2 / (2 * m2) / DEG, rtol=1e-9)
    e = rep["energy"]
    assert_allclose(e["damper_work"], 0.5 * m1 * (20 * DEG) ** 2 * (math.exp(-2 * c * 0.5 / m1) - 1), rtol=1e-8)
    assert_allclose(e["drive_work"], torque * torque * 0.25 / (2 * m2), rtol=1e-8)
    assert e["balance"] == 0.0


def test_pin_friction_on_two_cranks_turning_together_decelerates_as_the_closed_form():
    """Equal cranks with equal point masses, started at one speed: A and B move alike, the
    massless distal links translate and carry no force, and only A0 and B0 carry m rho w^2
    and m rho w': each crank obeys rho a = -mu r sqrt(w^4 + a^2), w = w0 / (1 + kappa w0 t),
    kappa = mu r / sqrt(rho^2 - mu^2 r^2) (the one-drive test's closed form, twice)."""
    mu, rho, d, w0 = 0.2, 20.0, 10.0, 30.0
    rep = report(LINKAGE + f"""[units]
angle = "rad"
[joints]
A0 = {{ diameter = {d} }}
A = {{ diameter = 5 }}
P = {{ diameter = 5 }}
B = {{ diameter = 5 }}
B0 = {{ diameter = {d} }}
[masses]
input = {{ mass = 0.5, center = [{rho}, 0] }}
input2 = {{ mass = 0.5, center = [{rho}, 0] }}
[dynamics]
duration = 0.5
steps = 51
friction = {mu}
[dynamics.input]
start = {{ angle = 2.0, speed = {w0} }}
[dynamics.input2]
start = {{ angle = 2.0, speed = {w0} }}
""")
    r = d / 2
    kappa = mu * r / math.sqrt(rho ** 2 - (mu * r) ** 2)
    t = times(rep)
    for j in range(2):
        assert_allclose(per_drive(rep, "speed")[:, j], w0 / (1 + kappa * w0 * t), rtol=1e-7)
        assert_allclose(per_drive(rep, "angle")[:, j], 2.0 + np.log1p(kappa * w0 * t) / kappa, rtol=1e-7)
    assert rep["energy"]["friction_work"] < 0 and rep["energy"]["balance"] == 0.0


# ---------------------------------------------------------------- the existing inverse dynamics

def test_a_friction_free_run_gives_the_torques_and_pins_of_the_existing_inverse_dynamics():
    """Two motors (torque-speed curves, steep enough to hold each crank near a constant speed)
    drive the five-bar under gravity, a force at P and a couple on a distal link; at every history
    row (angles, speeds, accelerations of both drives) the five-bar's inverse dynamics
    (five_bar.loads: one Newton-Euler solve per row) needs exactly the motors' torques and gives
    the same pin forces."""
    from linkcli.mechanisms.five_bar.loads import five_bar_loads, state
    from linkcli.mechanisms.five_bar.model import FiveBar
    from linkcli.model import LinkMass, LoadCase, Loads, Masses
    rep = report(LINKAGE + masses_toml() + """[loads]
gravity = [0, -9.81]
coupler_force = [3, -2]
torques = { coupler2 = 0.05 }
[dynamics]
duration = 0.2
steps = 41
[dynamics.input]
drive = { torque_speed = [[0, 3.0], [90, 1.5], [110, -1.5], [400, -3]] }
start = { angle = 120, speed = 100 }
[dynamics.input2]
drive = { torque_speed = [[-400, 3], [-110, 1.5], [-90, -1.5], [0, -3.0]] }
start = { angle = 60, speed = -100 }
""")
    q = per_drive(rep, "angle") * DEG
    w = per_drive(rep, "speed") * DEG
    al = per_drive(rep, "acceleration") * DEG
    torque = per_drive(rep, "torque")
    assert np.max(np.abs(al)) > 0 and np.ptp(q[:, 0]) > 10 * DEG
    assert np.all(np.abs(w / DEG - [100, -100]) < 20)  # held near a constant speed
    fb = FiveBar(ground=GROUND, input=A1, input2=A2, coupler=B1, coupler2=B2)
    case = LoadCase(loads=Loads(coupler_force=(3, -2), gravity=(0, -9.81), torques=(("coupler2", 0.05),)),
                    masses=Masses(named=tuple((k, LinkMass(m, c, i)) for k, (m, c, i) in MASSES.items())))
    rows = five_bar_loads(state(fb, q, w, al, 1e-3), case, 1e-3, q[:, 1])
    scale = np.max(np.abs(torque))
    assert_allclose(rows.input_torque, torque[:, 0], rtol=0, atol=1e-7 * scale)
    assert_allclose(rows.other_drives["input2"][1], torque[:, 1], rtol=0, atol=1e-7 * scale)
    pin_scale = max(np.max(np.abs(v)) for v in rows.pins.values())
    for name in ("A0", "A", "P", "B", "B0"):
        got = np.array([[r["pins"][name]["x"], r["pins"][name]["y"]] for r in rep["history"]])
        assert_allclose(got, rows.pins[name], rtol=0, atol=1e-7 * pin_scale)


def test_the_integrators_equation_and_the_newton_euler_rows_give_one_acceleration():
    """The right-hand side (Python floats, the equation of motion) and the history's Newton-Euler
    solve of all bodies (numpy, body_forces) agree at random states, springs and dampers on."""
    from linkcli import mechanisms
    from linkcli.analysis.dynamics.several import Several, one_row
    from linkcli.analysis.dynamics.several_rows import state
    from linkcli.reading.load import load
    text = LINKAGE + masses_toml() + """[loads]
gravity = [0, -9.81]
coupler_force = [1, 2]
""" + SPRINGS + """[dampers]
slow = { between = ["A", "B0"], coefficient = 0.01 }
[dynamics]
duration = 1
[dynamics.input]
drive = { torque = 0.2 }
start = { angle = 120 }
[dynamics.input2]
drive = { torque_speed = [[0, 0.3], [50, 0]] }
start = { angle = 60 }
"""
    problem = load("test.toml", text.encode())
    meta = problem.meta
    mech = mechanisms.of(problem.linkage)
    system = Several(mech, meta.dynamics, meta.loads, meta.units, 1e-3)
    rhs, _ = system.rhs_function(10 ** 6)
    rng = np.random.default_rng(5)
    y0 = system.start()
    for _ in range(20):
        q = y0[:2] + rng.uniform(-0.2, 0.2, 2)
        w = rng.uniform(-5, 5, 2)
        y = np.concatenate([q, w, [0, 0, 0], y0[7:]])
        fast = np.array(rhs(0.0, y))
        st = state(system, q[None], w[None], y0[None, 7:])
        scale = np.max(np.abs(st.acceleration))
        assert_allclose(fast[2:4], st.acceleration[0], rtol=0, atol=1e-10 * scale)
        inverse = st.solved.drive  # forward Newton-Euler: the accelerations
        assert_allclose(inverse[0], st.acceleration[0], rtol=0, atol=1e-9 * scale)
        row = one_row(mech.coefficients_at(q, 1e-3), q[None])  # the friction path's coefficients
        for body in ("input", "input2", "coupler", "coupler2"):
            for got, want in zip(row.origin[body] + row.angle[body], st.coef.origin[body] + st.coef.angle[body]):
                assert_allclose(got, want, rtol=1e-12, atol=1e-12)


# ---------------------------------------------------------------- bad input found when solved

@pytest.mark.parametrize("q1, q2, extra, why", [
    (170, 10, "", "where the linkage does not assemble"),
    (150, 30, "dead_point = 20\n", "within dead_point (20 deg) of a dead point"),
])
def test_a_start_outside_the_assembly_range_is_one_located_line(q1, q2, extra, why, tmp_path):
    """|A B| = 128.8 mm > coupler + coupler2 = 120 (no assembly); |A B| = 119.3 (the angle at P
    12.5 deg from a straight line: within a dead_point of 20 deg)."""
    from conftest import run_cli
    path = tmp_path / "start.toml"
    text = (LINKAGE + masses_toml() + "[dynamics]\nduration = 1\n" + extra + f"[dynamics.input]\nstart = {{ angle = {q1} }}\n"
            f"[dynamics.input2]\nstart = {{ angle = {q2} }}\n")
    path.write_text(text)
    line = text.splitlines().index(f"start = {{ angle = {q2} }}") + 1
    code, out, err = run_cli("synth", str(path))
    assert code == 2 and out == ""
    assert err == (f"{path}:{line}: dynamics.input2.start.angle: expected start angles where the linkage assembles, "
                   "away from its dead points (the distal links in line), found input "
                   f"{q1}, input2 {q2} (deg), {why}\n")


def test_a_drive_no_mass_turns_with_is_one_located_line(tmp_path):
    from conftest import run_cli
    path = tmp_path / "massless.toml"
    path.write_text(LINKAGE + "[masses]\ninput = { mass = 0.1, center = [20, 0] }\n[dynamics]\nduration = 1\n"
                    "[dynamics.input]\nstart = { angle = 120 }\n[dynamics.input2]\nstart = { angle = 60 }\n")
    code, out, err = run_cli("synth", str(path))
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "dynamics.input2.start.angle: expected masses that move with every drive" in err
    assert "found no inertia for input2" in err


# ---------------------------------------------------------------- one drive locked: a four-bar

@pytest.mark.parametrize("friction", [False, True])
def test_with_one_drive_locked_the_five_bar_moves_as_the_four_bar_it_leaves(friction):
    """input2 held at 60 deg: B stands still, and A0-A-P-B is a four-bar (ground A0 -> B,
    input, coupler A -> P, output B -> P) run by the one-drive code (tables, its own integrator
    path); the same masses (the five-bar's coupler2 is the four-bar's output, same frame),
    gravity, a torsional spring on the input and a damper between A and the ground. Both give
    the input's angle and speed over time, and the torque that holds input2 (massless here) is
    the moment about B0 of the force the four-bar's ground exerts at B: (B - B0) x F_B0 (with
    friction, plus the friction couple there, which the held crank carries)."""
    from linkcli.mechanisms.four_bar import kinematics as kin
    q2 = 60 * DEG
    b = np.array([GROUND + A2 * math.cos(q2), A2 * math.sin(q2)])
    ground, gamma = float(np.hypot(*b)), math.atan2(b[1], b[0])
    masses = {k: MASSES[k] for k in ("input", "coupler", "coupler2")}
    common = """[loads]
gravity = [0, -9.81]
[springs]
crank = { link = "input", stiffness = 0.4, free_angle = 100 }
[dampers]
slow = { between = ["A", [-20, 10]], coefficient = 0.002 }
"""
    joints = ("[joints]\n" + "\n".join(f"{j} = {{ diameter = 4 }}" for j in ("A0", "A", "P", "B", "B0")) + "\n"
              if friction else "")
    run = "duration = 1.5\nsteps = 151\n" + ("friction = 0.2\nfriction_speed = 1\n" if friction else "")
    five = report(LINKAGE + masses_toml(masses) + joints + common + f"""[dynamics]
{run}[dynamics.input]
start = {{ angle = 125, speed = 200 }}
[dynamics.input2]
start = {{ angle = 60 }}
locked = true
""")
    _, p = frames(125 * DEG, q2)
    branch = "open"
    for candidate in ("open", "crossed"):  # the four-bar's branch where its B is the five-bar's P
        pose = kin.pose(A1, B1, B2, ground, 125 * DEG - gamma, candidate)
        psi = float(pose.psi) + gamma
        if np.allclose(b / 1000 + B2 / 1000 * np.array([math.cos(psi), math.sin(psi)]), p, atol=1e-9):
            branch = candidate
    four_masses = masses_toml({"input": masses["input"], "coupler": masses["coupler"], "output": masses["coupler2"]})
    four_joints = ("[joints]\n" + "\n".join(f"{j} = {{ diameter = 4 }}" for j in ("A0", "A", "B", "B0")) + "\n"
                   if friction else "")
    four = report(f"""type = "linkage"
[linkage]
ground = {ground!r}
input = {A1}
coupler = {B1}
output = {B2}
ground_angle = {math.degrees(gamma)!r}
branch = "{branch}"
""" + four_masses + four_joints + common + f"""[dynamics]
{run}start = {{ angle = {125 - math.degrees(gamma)!r}, speed = 200 }}
""")
    angle5 = per_drive(five, "angle")
    angle4 = np.array([r["angle"] for r in four["history"]]) + math.degrees(gamma)
    assert np.ptp(angle5[:, 0]) > 20
    assert_allclose(angle5[:, 1], 60, rtol=0, atol=1e-12)  # held
    assert np.all(per_drive(five, "speed")[:, 1] == 0)
    assert_allclose(angle5[:, 0], angle4, rtol=0, atol=1e-6)
    assert_allclose(per_drive(five, "speed")[:, 0], [r["speed"] for r in four["history"]], rtol=0, atol=1e-5)
    f_b0 = np.array([[r["pins"]["B0"]["x"], r["pins"]["B0"]["y"]] for r in four["history"]])
    arm = (b - np.array([GROUND, 0.0])) / 1000
    holding = arm[0] * f_b0[:, 1] - arm[1] * f_b0[:, 0]
    if friction:  # and the friction couple of the pin B, which the held crank carries (the four-bar's at B0)
        holding = holding + np.array([r["friction"]["B0"] for r in four["history"]])
    assert_allclose(per_drive(five, "torque")[:, 1], holding, rtol=0, atol=1e-6 * np.max(np.abs(holding)))
    if friction:
        assert five["energy"]["friction_work"] < 0
        assert_allclose(five["energy"]["friction_work"], four["energy"]["friction_work"], rtol=1e-5)


def test_a_placed_five_bar_moves_as_the_unplaced_one_under_gravity_turned_back():
    """ground_pivot and ground_angle move and turn the whole five-bar; its drive angles are
    measured from its ground line. Under gravity g it moves as the unplaced five-bar under g
    turned by -ground_angle (a torsional spring's free angle, a global angle, turned with it)."""
    gamma = 30.0
    c, s = math.cos(gamma * DEG), math.sin(gamma * DEG)
    g = (-9.81 * s, -9.81 * c)  # R(-gamma) (0, -9.81)
    run = """[dynamics]
duration = 0.4
steps = 41
[dynamics.input]
drive = { torque = 0.05 }
start = { angle = 118, speed = 50 }
[dynamics.input2]
start = { angle = 62, speed = -20 }
"""
    placed = report(LINKAGE.replace(f"coupler2 = {B2}\n", f"coupler2 = {B2}\nground_pivot = [10, 5]\nground_angle = {gamma}\n")
                    + masses_toml() + "[loads]\ngravity = [0, -9.81]\n"
                    + f'[springs]\nleft = {{ link = "input", stiffness = 0.3, free_angle = {110 + gamma} }}\n' + run)
    plain = report(LINKAGE + masses_toml() + f"[loads]\ngravity = [{g[0]!r}, {g[1]!r}]\n"
                   + '[springs]\nleft = { link = "input", stiffness = 0.3, free_angle = 110 }\n' + run)
    assert np.ptp(per_drive(plain, "angle")[:, 0]) > 5
    assert_allclose(per_drive(placed, "angle"), per_drive(plain, "angle"), rtol=0, atol=1e-7)
    assert_allclose(per_drive(placed, "torque"), per_drive(plain, "torque"), rtol=0, atol=1e-12)
    for k in ("kinetic", "potential", "spring", "drive_work"):
        assert placed["energy"][k] == pytest.approx(plain["energy"][k], rel=1e-7)
