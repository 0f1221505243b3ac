"""The five-bar's loads (mechanisms/five_bar/loads.py): both drives' torques and the five pin
forces at every row, against references written here -- the principle of virtual work per drive
(d'Alembert's inertia forces, every velocity ratio and acceleration by finite differences of the
test's own law-of-cosines positions), each link's Newton-Euler equations with the reported pin
forces, the two-force members of a massless five-bar, and the same five-bar drawn with two
drives (mechanism = "drawn", its own Newton-Euler solve)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import run_cli
from test_five_bar import ref_forward

DEG = math.pi / 180.0
L = (50.0, 40.0, 42.0, 60.0, 58.0)  # ground, input, input2, coupler, coupler2 (mm)
PIVOT, GAMMA = (12.0, -5.0), 20.0 * DEG  # A0 and the ground line, global frame
MASSES = {"input": (0.2, (20.0, 1.5), 1.1e-4), "input2": (0.25, (18.0, -2.0), 1.3e-4),
          "coupler": (0.3, (31.0, 2.5), 2.2e-4), "coupler2": (0.35, (27.0, -1.0), 2.9e-4)}
FORCE, GRAVITY, TORQUES = np.array([3.0, -10.0]), np.array([0.0, -9.81]), {"coupler2": 0.1, "input": -0.05}
ROWS = [[125.0, 60.0], [118.0, 63.0], [104.0, 70.0], [95.0, 82.0], [131.0, 48.0], [80.0, 55.0]]
SPEEDS, ACCELERATIONS = (40.0, -25.0), (60.0, 35.0)  # deg/s, deg/s^2


def problem(masses=True, loads=True, speeds=SPEEDS, accelerations=ACCELERATIONS, rows=ROWS) -> str:
    text = ('type = "linkage"\n[linkage]\nmechanism = "five-bar"\n'
            + "".join(f"{k} = {v!r}\n" for k, v in zip(("ground", "input", "input2", "coupler", "coupler2"), L))
            + f"ground_pivot = [{PIVOT[0]}, {PIVOT[1]}]\nground_angle = {math.degrees(GAMMA)!r}\n"
            + f"[motion]\ninputs = {rows}\ninput_speeds = {list(speeds)}\n"
            + f"input_accelerations = {list(accelerations)}\n")
    if loads:
        text += (f"[loads]\ncoupler_force = [{FORCE[0]}, {FORCE[1]}]\ngravity = [{GRAVITY[0]}, {GRAVITY[1]}]\n"
                 "torques = { " + ", ".join(f"{k} = {v}" for k, v in TORQUES.items()) + " }\n")
    if masses:
        text += "[masses]\n" + "".join(f"{k} = {{ mass = {m}, center = [{c[0]}, {c[1]}], inertia = {i} }}\n"
                                       for k, (m, c, i) in MASSES.items())
    return text


def report(tmp_path, text: str, name: str = "p.toml") -> dict:
    path = tmp_path / name
    path.write_text(text)
    code, out, err = run_cli("synth", str(path), "--format", "json", "--precision", "15")
    assert code == 0 and "Traceback" not in err, err
    return json.loads(out)


# ---------------------------------------------------------------- the test's own five-bar

def frames(phi1, phi2):
    """Global (in metres) frames of the four links at drive angles (rad): link -> (origin,
    angle), with P; from ref_forward's law-of-cosines P (test_five_bar)."""
    turn = np.exp(1j * GAMMA)
    pivot = complex(*PIVOT)
    a = L[1] * np.exp(1j * phi1)
    b = L[0] + L[2] * np.exp(1j * phi2)
    p = ref_forward(L, phi1, phi2)
    def g(z):
        return (pivot + turn * z) / 1000.0
    return {"input": (g(0.0), GAMMA + phi1), "input2": (g(L[0]), GAMMA + phi2),
            "coupler": (g(a), GAMMA + np.angle(p - a)), "coupler2": (g(b), GAMMA + np.angle(p - b))}, g(p)


def centres(phi1, phi2):
    """link -> (its centre of mass (complex, m), its angle); P (complex, m)."""
    fr, p = frames(phi1, phi2)
    out = {}
    for name, (origin, angle) in fr.items():
        c = complex(*MASSES[name][1]) / 1000.0
        out[name] = (origin + c * np.exp(1j * angle), angle)
    return out, p


def motion(row, t):
    """Drive angles at time t along the row's motion (constant accelerations)."""
    q = np.radians(row) + np.radians(SPEEDS) * t + 0.5 * np.radians(ACCELERATIONS) * t * t
    return q[0], q[1]


def inertia_terms(row, h=1e-4):
    """Each link's centre acceleration and angular acceleration at the row, by second central
    differences in time of the test's positions."""
    ahead, here, back = (centres(*motion(row, t))[0] for t in (h, 0.0, -h))
    out = {}
    for name in MASSES:
        acc = (ahead[name][0] - 2 * here[name][0] + back[name][0]) / h ** 2
        alpha = (np.unwrap([back[name][1], here[name][1], ahead[name][1]]) @ [1, -2, 1]) / h ** 2
        out[name] = (acc, alpha)
    return out


def rates(row, j, h=1e-6):
    """d/dq_j of every link's centre and angle, and of P, by central differences."""
    q = np.radians(row)
    e = np.zeros(2)
    e[j] = h
    (plus, p_plus), (minus, p_minus) = centres(*(q + e)), centres(*(q - e))
    out = {name: ((plus[name][0] - minus[name][0]) / (2 * h),
                  float(np.unwrap([minus[name][1], plus[name][1]]) @ [-1, 1]) / (2 * h)) for name in MASSES}
    return out, (p_plus - p_minus) / (2 * h)


def dot(z, w) -> float:
    return float(z.real * w.real + z.imag * w.imag)


# ---------------------------------------------------------------- tests

def test_both_torques_obey_virtual_work_per_drive(tmp_path):
    """d'Alembert: for a virtual motion of drive j alone, the drives' work balances the work of
    the loads and of the inertia forces, T_j = sum [m (a_G - g) . G_j + I alpha theta_j] -
    F . P_j - sum tau theta_j, every rate and acceleration from the test's own positions."""
    rep = report(tmp_path, problem())
    rows = rep["forces"]["rows"]
    for row, out in zip(ROWS, rows):
        acc = inertia_terms(row)
        expected = []
        for j in range(2):
            rate, p_rate = rates(row, j)
            total = -dot(complex(*FORCE), p_rate)
            for name, (m, _, inertia) in MASSES.items():
                g_rate, th_rate = rate[name]
                a_g, alpha = acc[name]
                total += m * dot(a_g - complex(*GRAVITY), g_rate) + inertia * alpha * th_rate
                total -= TORQUES.get(name, 0.0) * th_rate
            expected.append(total)
        got = [out["input_torque"], out["input2_torque"]]
        assert got == pytest.approx(expected, rel=1e-6, abs=1e-7 * max(map(abs, expected)))
        assert out["input"] == pytest.approx(row[0], abs=1e-9) and out["input2"] == pytest.approx(row[1], abs=1e-9)


def test_each_link_is_in_newton_euler_equilibrium_with_the_reported_pin_forces(tmp_path):
    """Every link: the pin forces on it (as the section names them: A0 ground -> input, A input
    -> coupler, P coupler -> coupler2, B input2 -> coupler2, B0 ground -> input2), its loads and
    its weight balance m a_G, and their moments about G with the drive's torque I alpha; centres
    and accelerations from the test's own positions."""
    rep = report(tmp_path, problem())
    for row, out in zip(ROWS, rep["forces"]["rows"]):
        pins = {k: complex(v["x"], v["y"]) for k, v in out["pins"].items()}
        acc = inertia_terms(row)
        where, p = centres(*np.radians(row))
        fr, _ = frames(*np.radians(row))
        joint = {"A0": fr["input"][0], "A": fr["coupler"][0], "B": fr["coupler2"][0], "B0": fr["input2"][0], "P": p}
        on = {"input": [("A0", 1), ("A", -1)], "input2": [("B0", 1), ("B", -1)],
              "coupler": [("A", 1), ("P", -1)], "coupler2": [("B", 1), ("P", 1)]}
        couples = {"input": out["input_torque"], "input2": out["input2_torque"]}
        for name, items in on.items():
            m, _, inertia = MASSES[name]
            g = where[name][0]
            forces = [(joint[k], s * pins[k]) for k, s in items]
            if name == "coupler":
                forces.append((p, complex(*FORCE)))
            total = sum(f for _, f in forces) + m * complex(*GRAVITY)
            moment = sum(((x - g).real * f.imag - (x - g).imag * f.real) for x, f in forces)
            moment += couples.get(name, 0.0) + TORQUES.get(name, 0.0)
            scale = max(abs(f) for _, f in forces)
            assert abs(total - m * acc[name][0]) < 1e-6 * scale, name
            assert abs(moment - inertia * acc[name][1]) < 1e-6 * scale * 0.05, name


def test_a_massless_five_bar_under_a_force_at_p_has_two_force_distal_links(tmp_path):
    """Statics: without masses, the distal links carry the force at P along themselves, F =
    f1 u + f2 v (u = P - A, v = P - B): the pins A, P and B take those two forces, A0 and B0 the
    cranks' ends, and each drive holds its crank against its distal link's pull, T1 = -cross(A -
    A0, f1 u), T2 = -cross(B - B0, f2 v) (N m, lengths in m)."""
    text = problem(masses=False, loads=False, speeds=(0, 0), accelerations=(0, 0)) + (
        f"[loads]\ncoupler_force = [{FORCE[0]}, {FORCE[1]}]\n")
    rep = report(tmp_path, text)
    for row, out in zip(ROWS, rep["forces"]["rows"]):
        fr, p = frames(*np.radians(row))
        a0, a, b0, b = fr["input"][0], fr["coupler"][0], fr["input2"][0], fr["coupler2"][0]
        u, v = p - a, p - b
        f = complex(*FORCE)
        det = u.real * v.imag - u.imag * v.real
        f1 = (f.real * v.imag - f.imag * v.real) / det  # f = f1 u + f2 v, Cramer
        f2 = (u.real * f.imag - u.imag * f.real) / det
        # coupler2 is a two-force member: the pin P (coupler on coupler2) is f2 v, B (input2 on it)
        # -f2 v; the coupler then carries F - f2 v = f1 u at P, and A (input on coupler) is -f1 u
        pins = {k: complex(x["x"], x["y"]) for k, x in out["pins"].items()}
        assert abs(pins["A"] - (-f1 * u)) < 1e-9 * abs(f)
        assert abs(pins["B"] - (-f2 * v)) < 1e-9 * abs(f)
        assert abs(pins["P"] - f2 * v) < 1e-9 * abs(f)
        assert abs(pins["A0"] - pins["A"]) < 1e-9 * abs(f) and abs(pins["B0"] - pins["B"]) < 1e-9 * abs(f)
        t1 = -((a - a0).real * (f1 * u).imag - (a - a0).imag * (f1 * u).real)
        t2 = -((b - b0).real * (f2 * v).imag - (b - b0).imag * (f2 * v).real)
        assert out["input_torque"] == pytest.approx(t1, rel=1e-9, abs=1e-12)
        assert out["input2_torque"] == pytest.approx(t2, rel=1e-9, abs=1e-12)
    assert "mechanical_advantage" not in rep["forces"]["rows"][0]


def test_the_five_bar_drawn_with_two_drives_gives_the_same_torques_and_pins(tmp_path):
    """The same five-bar as a drawing (two drives, the right one at its speed ratio: drawn.loads'
    own Newton-Euler solve of any linkage): its forces section prints the left drive's torque and
    the pins A0, A, P, B, B0 of the five-bar's rows; its right drive's effort (the drawn home's
    loads, which print only the leading drive's) is the five-bar's input2_torque."""
    from linkcli import mechanisms
    from linkcli.analysis.forces import metres_per_unit
    from linkcli.reading.load import load
    phi1, phi2 = 115 * DEG, 60 * DEG
    p = complex(ref_forward(L, phi1, phi2))
    a, b = complex(L[1] * np.exp(1j * phi1)), complex(L[0] + L[2] * np.exp(1j * phi2))
    drawn = ('type = "linkage"\n[linkage]\nmechanism = "drawn"\n[joints]\n'
             f'A0 = {{ at = [0, 0], ground = true }}\nB0 = {{ at = [{L[0]!r}, 0], ground = true }}\n'
             f'A = {{ at = [{a.real!r}, {a.imag!r}] }}\nB = {{ at = [{b.real!r}, {b.imag!r}] }}\n'
             f'P = {{ at = [{p.real!r}, {p.imag!r}] }}\n[links]\ninput = ["A0", "A"]\ninput2 = ["B0", "B"]\n'
             'coupler = ["A", "P"]\ncoupler2 = ["B", "P"]\n[drive]\ninput = { speed = 20 }\n'
             'input2 = { speed = -10 }\n[motion]\nsteps = 9\nspan = [-20, 20]\npoints = ["P"]\n'
             f'[loads]\ngravity = [0, -9.81]\ntorques = {{ coupler2 = 0.1 }}\nforces = {{ P = [{FORCE[0]}, {FORCE[1]}] }}\n'
             "[masses]\n" + "".join(f"{k} = {{ mass = {m}, center = [{c[0]}, {c[1]}], inertia = {i} }}\n"
                                    for k, (m, c, i) in MASSES.items()))
    one = report(tmp_path, drawn, "drawn.toml")
    inputs = [[r["input"], r["drives"]["input2"]] for r in one["kinematics"]]
    five = ('type = "linkage"\n[linkage]\nmechanism = "five-bar"\n'
            + "".join(f"{k} = {v!r}\n" for k, v in zip(("ground", "input", "input2", "coupler", "coupler2"), L))
            + f"[motion]\ninputs = {inputs}\ninput_speeds = [20, -10]\n"
            + f"[loads]\ngravity = [0, -9.81]\ntorques = {{ coupler2 = 0.1 }}\ncoupler_force = [{FORCE[0]}, {FORCE[1]}]\n"
            + "[masses]\n" + "".join(f"{k} = {{ mass = {m}, center = [{c[0]}, {c[1]}], inertia = {i} }}\n"
                                     for k, (m, c, i) in MASSES.items()))
    two = report(tmp_path, five, "five.toml")
    drawn_rows, five_rows = one["forces"]["rows"], two["forces"]["rows"]
    assert len(drawn_rows) == len(five_rows) == 9
    scale = max(abs(r["pins"]["A0"]["magnitude"]) for r in five_rows)
    for r, s in zip(drawn_rows, five_rows):
        assert s["input_torque"] == pytest.approx(r["input_torque"], abs=1e-9 * scale)
        for pin in ("A0", "A", "P", "B", "B0"):
            assert [s["pins"][pin]["x"], s["pins"][pin]["y"]] == pytest.approx(
                [r["pins"][pin]["x"], r["pins"][pin]["y"]], abs=1e-9 * scale), pin
    path = tmp_path / "drawn.toml"
    problem_ = load(str(path), drawn.encode())
    mech = mechanisms.of(problem_.linkage)
    study = mech.study(None)
    phi, _ = study.rows(9)
    efforts = mech.load_rows(phi, 0.0, problem_.meta.loads, metres_per_unit(problem_.meta.units)).efforts
    assert [s["input2_torque"] for s in five_rows] == pytest.approx(list(efforts["input2"]), abs=1e-9 * scale)


def test_held_drive_rows_and_dead_points(tmp_path):
    """On a phase's rows the held drive stands still (its speed and acceleration 0: the torques
    are the statics and inertia of the four-bar left); a row with the distal links in line is a
    dead point (null forces, left out of the load cycle, a note)."""
    rows = [[125.0, 60.0], [122.0, 60.0], [119.0, 60.0], [110.0, 66.0]]
    text = problem(rows=rows) + "[[motion.phases]]\nrows = [0, 2]\nlocked = \"input2\"\n"
    rep = report(tmp_path, text)
    for row, out in zip(rows[:3], rep["forces"]["rows"][:3]):
        acc = {}
        h = 1e-4
        q = np.radians(row)
        def q_at(t):
            return q[0] + math.radians(SPEEDS[0]) * t + 0.5 * math.radians(ACCELERATIONS[0]) * t * t, q[1]
        ahead, here, back = (centres(*q_at(t))[0] for t in (h, 0.0, -h))
        for name in MASSES:
            acc[name] = ((ahead[name][0] - 2 * here[name][0] + back[name][0]) / h ** 2,
                         (np.unwrap([back[name][1], here[name][1], ahead[name][1]]) @ [1, -2, 1]) / h ** 2)
        for j, key in ((0, "input_torque"), (1, "input2_torque")):
            rate, p_rate = rates(row, j)
            total = -dot(complex(*FORCE), p_rate)
            for name, (m, _, inertia) in MASSES.items():
                total += m * dot(acc[name][0] - complex(*GRAVITY), rate[name][0]) + inertia * acc[name][1] * rate[name][1]
                total -= TORQUES.get(name, 0.0) * rate[name][1]
            assert out[key] == pytest.approx(total, rel=1e-6, abs=1e-7)
    # the distal links in line: cranks and ground stretched along one line as long as the distal
    # links together (36 + 40 + 42 = 60 + 58) at phi1 = 180, phi2 = 0 deg
    text = problem(rows=[[180.0, 0.0], [150.0, 30.0]]).replace("ground = 50.0", "ground = 36.0")
    rep = report(tmp_path, text, "dead.toml")
    assert rep["forces"]["rows"][0]["input_torque"] is None and rep["forces"]["rows"][0]["pins"]["P"]["x"] is None
    assert rep["forces"]["rows"][1]["input_torque"] is not None
    assert rep["forces"]["dead_points"] == 1
    assert any("dead point (the distal links in line)" in n for n in rep["notes"])


def test_every_links_loads_are_in_equilibrium_for_strength(tmp_path):
    """member_forces (the strength section's loads on each link): the sum of the forces and of
    the moments about the origin (couples plus r x F) of each link's loads is 0 at every row;
    the links are bars between their pins (input A0-A, input2 B0-B, coupler A-P, coupler2 B-P)
    and the pins carry the forces section's forces."""
    from linkcli import mechanisms
    from linkcli.analysis.forces import metres_per_unit
    from linkcli.reading.load import load
    path = tmp_path / "p.toml"
    path.write_text(problem())
    prob = load(str(path))
    mech = mechanisms.of(prob.linkage)
    phi, _ = mech.study().rows(0)
    metres = metres_per_unit(prob.meta.units)
    rows = mech.load_rows(phi, 1.0, prob.meta.loads, metres)
    members = mech.member_forces(phi, 1.0, prob.meta.loads, metres, rows)
    assert members.links == {"input": ("A0", "A"), "input2": ("B0", "B"), "coupler": ("A", "P"),
                             "coupler2": ("B", "P")}
    for name in ("A0", "A", "P", "B", "B0"):
        assert np.array_equal(members.pins[name], rows.pins[name])
    for link, loads in members.loads.items():
        force = sum(load.force for load in loads)
        moment = sum(load.couple + load.at[:, 0] * load.force[:, 1] - load.at[:, 1] * load.force[:, 0]
                     for load in loads)
        scale = max(np.abs(load.force).max() for load in loads)
        assert np.abs(force).max() < 1e-10 * scale, link
        assert np.abs(moment).max() < 1e-10 * scale * 0.2, link


def test_kinematic_coefficients_are_the_partial_derivatives_of_the_positions():
    """five_bar.coefficients (numpy rows and Python floats): every link's frame origin and angle
    against the test's own law-of-cosines positions, their first partials with respect to each
    drive and the mixed second partials by central differences (steps 1e-4 rad: truncation
    ~1e-9 of the link's size)."""
    from linkcli.mechanisms.five_bar.coefficients import coefficients, coefficients_at
    from linkcli.mechanisms.five_bar.model import FiveBar
    fb = FiveBar(*L, branch="left", ground_pivot=PIVOT, ground_angle=GAMMA)
    q = np.radians(np.array(ROWS))
    coef = coefficients(fb, q, 1e-3)
    assert coef.valid.all() and coef.drives == 2
    h = 1e-4

    def origin_angle(q1, q2):
        fr, _ = frames(q1, q2)
        return {k: (np.array([v[0].real, v[0].imag]), v[1]) for k, v in fr.items()}
    for r, (q1, q2) in enumerate(q):
        here = origin_angle(q1, q2)
        point = coefficients_at(fb, (q1, q2), 1e-3)
        for name, (x, th) in here.items():
            ox, dx, ddx = (a[r] for a in coef.origin[name])
            t, dt, ddt = (a[r] for a in coef.angle[name])
            assert ox == pytest.approx(x, abs=1e-15) and math.remainder(t - th, 2 * math.pi) == pytest.approx(0, abs=1e-12)
            for j in range(2):
                e = np.zeros(2)
                e[j] = h
                plus, minus = origin_angle(*(np.array([q1, q2]) + e)), origin_angle(*(np.array([q1, q2]) - e))
                assert dx[:, j] == pytest.approx((plus[name][0] - minus[name][0]) / (2 * h), abs=5e-10)
                assert dt[j] == pytest.approx(math.remainder(plus[name][1] - minus[name][1], 2 * math.pi) / (2 * h), abs=1e-7)
                for i in range(2):
                    f = np.zeros(2)
                    f[i] = h
                    pp, pm, mp, mm = (origin_angle(*(np.array([q1, q2]) + s * e + t_ * f))
                                      for s, t_ in ((1, 1), (1, -1), (-1, 1), (-1, -1)))
                    mixed = (pp[name][0] - pm[name][0] - mp[name][0] + mm[name][0]) / (4 * h * h)
                    turn = math.remainder(pp[name][1] - pm[name][1] - mp[name][1] + mm[name][1], 2 * math.pi)
                    assert ddx[:, i, j] == pytest.approx(mixed, abs=2e-7 * 0.06)
                    assert ddt[i, j] == pytest.approx(turn / (4 * h * h), abs=2e-5)
            # the floats' path: the same numbers
            px, pdx, pddx = point.origin[name]
            assert px == pytest.approx(tuple(ox), abs=1e-15)
            assert np.array(pdx).T == pytest.approx(dx, abs=1e-15)
            assert np.array(pddx).transpose(2, 0, 1) == pytest.approx(ddx, abs=1e-14)
            assert point.angle[name][0] == pytest.approx(t, abs=1e-14)
            assert np.array(point.angle[name][2]) == pytest.approx(ddt, abs=1e-13)
        mu_p = abs(math.sin(np.angle((ref_forward(L, q1, q2) - L[1] * np.exp(1j * q1))
                                     / (ref_forward(L, q1, q2) - L[0] - L[2] * np.exp(1j * q2)))))
        assert coef.lock[r] == pytest.approx(mu_p, rel=1e-9) and point.lock == pytest.approx(mu_p, rel=1e-9)
