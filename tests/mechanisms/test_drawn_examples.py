"""The drawn examples in problems/ against references written here, independently of the
solver: Jansen's lengths against his published numbers; positions against scipy's fsolve on
the loop equations (continued row to row from the drawing); velocities against central
differences of the solver's own positions (positions being checked already); the Watt
six-bar's drive torque by the power balance T w = dE/dt - P_ext (energy from positions
alone); the shaper's swing and time ratio against their closed forms.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import ROOT, run_cli

from linkcli import mechanisms
from linkcli.reading.load import load

HOLY = {"a": 38.0, "b": 41.5, "c": 39.3, "d": 40.1, "e": 55.8, "f": 39.4, "g": 36.7, "h": 65.7,
        "i": 49.0, "j": 50.0, "k": 61.9, "l": 7.8, "m": 15.0}  # Jansen, The Great Pretender (2007)


def report(name: str, precision: int = 6) -> dict:
    code, out, err = run_cli("synth", str(ROOT / "problems" / f"{name}.toml"), "--format", "json",
                             "--precision", str(precision))
    assert code == 0, err
    return json.loads(out)


def joint_at(problem, name):
    return np.array(problem.linkage.joint(name).at)


def test_jansen_is_drawn_with_the_holy_numbers():
    """The drawing's distances are Jansen's lengths (to the file's 16 digits), and the report
    prints them."""
    problem = load(str(ROOT / "problems" / "drawn_jansen.toml"))
    dist = lambda p, q: float(np.hypot(*(joint_at(problem, p) - joint_at(problem, q))))  # noqa: E731
    pairs = {("O", "A"): "m", ("A", "B"): "j", ("A", "C"): "k", ("Q", "B"): "b", ("Q", "D"): "d",
             ("B", "D"): "e", ("Q", "C"): "c", ("D", "E"): "f", ("E", "C"): "g", ("E", "F"): "h",
             ("C", "F"): "i"}
    for (p, q), letter in pairs.items():
        assert dist(p, q) == pytest.approx(HOLY[letter], abs=1e-12), letter
    assert joint_at(problem, "O") - joint_at(problem, "Q") == pytest.approx([HOLY["a"], HOLY["l"]], abs=1e-12)
    lk = report("drawn_jansen")["linkage"]
    assert lk["bde B-D"] == HOLY["e"] and lk["ghi E-F"] == HOLY["h"] and lk["m O-A"] == HOLY["m"]


def fsolve_path(equations, start, angles):
    """Positions continued from `start` (the drawing) through the crank angles, each solved
    by fsolve from the previous one: the independent reference."""
    from scipy.optimize import fsolve
    out, guess = [], np.asarray(start, dtype=float)
    for phi in angles:
        guess, info, ok, msg = fsolve(equations, guess, args=(phi,), full_output=True, xtol=1e-13)
        assert ok == 1, msg
        out.append(guess.copy())
    return np.array(out)


def sweep(start_angle, rows_inputs, step_deg=2.0):
    """Crank angles from the drawn one to each row's input, in small steps, then the rows:
    (the angles to follow, index of each row among them)."""
    angles, where = [], []
    current = start_angle
    for target in rows_inputs:
        delta = (target - current + math.pi) % (2 * math.pi) - math.pi
        n = max(1, int(abs(math.degrees(delta)) / step_deg) + 1)
        angles += list(current + delta * np.arange(1, n + 1) / n)
        where.append(len(angles) - 1)
        current = angles[-1]
    return np.array(angles), where


def test_jansen_foot_follows_the_loop_equations():
    rep = report("drawn_jansen")
    problem = load(str(ROOT / "problems" / "drawn_jansen.toml"))
    Q, O = joint_at(problem, "Q"), joint_at(problem, "O")
    H = HOLY
    names = ["B", "C", "D", "E", "F"]

    def equations(x, phi):
        B, C, D, E, F = x.reshape(5, 2)
        A = O + H["m"] * np.array([math.cos(phi), math.sin(phi)])
        dist = lambda p, q: float(np.hypot(*(p - q)))  # noqa: E731
        return [dist(A, B) - H["j"], dist(Q, B) - H["b"], dist(A, C) - H["k"], dist(Q, C) - H["c"],
                dist(Q, D) - H["d"], dist(B, D) - H["e"], dist(D, E) - H["f"], dist(C, E) - H["g"],
                dist(E, F) - H["h"], dist(C, F) - H["i"]]

    start = np.concatenate([joint_at(problem, n) for n in names])
    inputs = [math.radians(r["input"]) for r in rep["kinematics"]]
    angles, where = sweep(math.pi / 2, inputs)
    path = fsolve_path(equations, start, angles)[where]
    for row, expected in zip(rep["kinematics"], path):
        F = expected.reshape(5, 2)[4]
        assert row["points"]["F"]["x"] == pytest.approx(F[0], rel=1e-5, abs=1e-4)
        assert row["points"]["F"]["y"] == pytest.approx(F[1], rel=1e-5, abs=1e-4)


@pytest.mark.slow
def test_stephenson_triad_follows_the_loop_equations_round_a_full_turn():
    rep = report("drawn_stephenson")
    assert rep["grashof"]["groups"][1].startswith("group of 4")  # a triad, solved by Newton
    assert rep["motion"]["input_full_turn"] is True
    problem = load(str(ROOT / "problems" / "drawn_stephenson.toml"))
    at = {j.name: np.array(j.at) for j in problem.linkage.joints}
    L = lambda p, q: float(np.hypot(*(at[p] - at[q])))  # noqa: E731
    lengths = {k: L(*k) for k in [("O2", "A"), ("A", "C"), ("O1", "B"), ("O3", "D"), ("B", "C"),
                                  ("B", "D"), ("C", "D")]}

    def equations(x, phi):
        B, C, D = x.reshape(3, 2)
        A = at["O2"] + lengths[("O2", "A")] * np.array([math.cos(phi), math.sin(phi)])
        dist = lambda p, q: float(np.hypot(*(p - q)))  # noqa: E731
        return [dist(A, C) - lengths[("A", "C")], dist(at["O1"], B) - lengths[("O1", "B")],
                dist(at["O3"], D) - lengths[("O3", "D")], dist(B, C) - lengths[("B", "C")],
                dist(B, D) - lengths[("B", "D")], dist(C, D) - lengths[("C", "D")]]

    start = np.concatenate([at["B"], at["C"], at["D"]])
    inputs = [math.radians(r["input"]) for r in rep["kinematics"]]
    angles, where = sweep(math.pi / 2, inputs + [math.pi / 2])
    path = fsolve_path(equations, start, angles)
    assert np.allclose(path[-1], start, atol=1e-7)  # one turn brings the drawing back
    for row, expected in zip(rep["kinematics"], path[where[:-1]]):
        B, C, D = expected.reshape(3, 2)
        for name, p in (("C", C), ("D", D)):
            assert row["points"][name]["x"] == pytest.approx(p[0], rel=1e-5, abs=1e-4)
            assert row["points"][name]["y"] == pytest.approx(p[1], rel=1e-5, abs=1e-4)


@pytest.mark.parametrize("name,point", [("drawn_stephenson", "C"), ("drawn_jansen", "F"),
                                        ("drawn_watt", "D"), ("drawn_shaper", "C")])
def test_velocities_and_accelerations_are_the_rates_of_the_positions(name, point):
    """Central differences of the solver's positions in time (the drive at its speed)."""
    problem = load(str(ROOT / "problems" / f"{name}.toml"))
    home = mechanisms.of(problem.linkage)
    study = home.study()
    x, _ = study.rows(12)
    speed = problem.linkage.drives[0].speed
    h = 1e-4
    dt = h / speed
    mid, ahead, behind = (home.state(x + s, study) for s in (0.0, h, -h))
    p = lambda st: st.pos[point]  # noqa: E731
    velocity = (p(ahead) - p(behind)) / (2 * dt)
    acceleration = (p(ahead) - 2 * p(mid) + p(behind)) / dt ** 2
    size = home.size()
    assert np.allclose(mid.vel[point], velocity, rtol=1e-6, atol=1e-6 * size * abs(speed))
    assert np.allclose(mid.acc[point], acceleration, rtol=1e-4, atol=1e-4 * size * speed ** 2)
    for link in problem.linkage.links:
        omega = (np.unwrap(np.stack([behind.theta[link.name], ahead.theta[link.name]]), axis=0)[1]
                 - behind.theta[link.name]) / (2 * dt)
        assert np.allclose(mid.omega[link.name], omega, rtol=1e-6, atol=1e-6 * abs(speed)), link.name


def test_watt_drive_torque_is_the_power_balance():
    """T w = dE/dt - P_ext at every row: E the kinetic and potential energy of every link from
    positions alone (central differences), P_ext the power of the torque on the output."""
    rep = report("drawn_watt")
    problem = load(str(ROOT / "problems" / "drawn_watt.toml"))
    home = mechanisms.of(problem.linkage)
    case = problem.meta.loads
    study = home.study()
    x, _ = study.rows(36)
    speed = problem.linkage.drives[0].speed
    metres = 1e-3
    g = np.array(case.loads.gravity)
    torques = dict(case.loads.torques)

    def energy_and_angles(xs):
        st = home.state(xs, study, rates=False)
        centres, angles = {}, {}
        for link in problem.linkage.links:
            m = case.masses.of(link.name)
            first, second = (st.pos[j] for j in link.joints[:2])  # the link's frame: x to its second joint
            angle = np.arctan2(second[:, 1] - first[:, 1], second[:, 0] - first[:, 0])
            c, s = np.cos(angle), np.sin(angle)
            cx, cy = m.center
            centres[link.name] = (first + np.stack([c * cx - s * cy, s * cx + c * cy], axis=1)) * metres
            angles[link.name] = angle
        return centres, angles

    h = 1e-4
    dt = h / speed
    (c_a, a_a), (c_b, a_b) = energy_and_angles(x + h), energy_and_angles(x - h)
    (c_m, a_m) = energy_and_angles(x)

    def kinetic(ca, cb, aa, ab):
        total = 0.0
        for link in problem.linkage.links:
            m = case.masses.of(link.name)
            v = (ca[link.name] - cb[link.name]) / (2 * dt)
            w = np.unwrap(np.stack([ab[link.name], aa[link.name]]), axis=0)
            w = (w[1] - w[0]) / (2 * dt)
            total = total + 0.5 * m.mass * np.sum(v * v, axis=1) + 0.5 * m.inertia * w * w
        return total

    # kinetic energy at x + h and x - h (central differences there), potential at x +- h
    (c_q, a_q), (c_r, a_r) = energy_and_angles(x + 2 * h), energy_and_angles(x - 2 * h)
    k_ahead = kinetic(c_q, c_m, a_q, a_m)  # centred at x + h
    k_behind = kinetic(c_m, c_r, a_m, a_r)  # centred at x - h
    potential = lambda cs: sum(-case.masses.of(k.name).mass * (cs[k.name] @ g) for k in problem.linkage.links)  # noqa: E731
    de_dt = (k_ahead - k_behind + potential(c_a) - potential(c_b)) / (2 * dt)
    out_w = np.unwrap(np.stack([a_b["output"], a_a["output"]]), axis=0)
    out_w = (out_w[1] - out_w[0]) / (2 * dt)
    power_ext = torques["output"] * out_w
    torque = np.array([r["input_torque"] for r in rep["forces"]["rows"]])
    scale = float(np.max(np.abs(torque)))
    assert np.allclose(torque * speed, de_dt - power_ext, rtol=1e-4, atol=1e-4 * scale * abs(speed))


def test_shaper_swing_and_time_ratio_are_the_closed_forms():
    """A crank r in a slot through the rocker's pivot at distance d: the rocker swings
    2 asin(r / d) and the forward stroke takes (180 + 2 asin(r / d)) / (180 - 2 asin(r / d))
    times the return (Norton, Design of Machinery, ch. 3, the Whitworth quick return)."""
    rep = report("drawn_shaper", precision=12)
    half = math.degrees(math.asin(20 / 60))
    rocker = rep["motion"]["links"]["rocker"]
    assert rocker["swing"] == pytest.approx(2 * half, rel=1e-9)
    assert rocker["time_ratio"] == pytest.approx((180 + 2 * half) / (180 - 2 * half), rel=1e-9)
    assert rep["motion"]["sliders"]["C"]["time_ratio"] == pytest.approx((180 + 2 * half) / (180 - 2 * half), rel=1e-9)
    # the ram's extremes: the rocker tip B at 90 deg +- half from the pivot O4, the rod 40 to y = 45
    ends = []
    for sign in (-1, 1):
        angle = math.radians(90 + sign * half)
        bx, by = 100 * math.cos(angle), -60 + 100 * math.sin(angle)
        ends.append(bx + math.sqrt(40 ** 2 - (45 - by) ** 2))
    assert rep["motion"]["sliders"]["C"]["range"] == pytest.approx(sorted(ends), rel=1e-9)
