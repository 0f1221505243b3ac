"""The five-bar (mechanisms/five_bar/): every number against a reference written here,
independently of the home's own construction (law-of-cosines closures, finite differences,
SVD, the four-bar's closed form, first-order error propagation)."""

from __future__ import annotations

import json
import math
import tomllib

import numpy as np
import pytest
from conftest import run_cli

L = (50.0, 40.0, 40.0, 60.0, 60.0)  # ground, input, input2, coupler, coupler2 of the examples


# ---------------------------------------------------------------- independent references

def ref_forward(lengths, phi1, phi2, side=1.0):
    """P by the triangle A-B-P: the angle at A from the law of cosines, turned from the
    direction A -> B towards `side` (+1 left)."""
    d, a1, a2, b1, b2 = lengths
    a = a1 * np.exp(1j * np.asarray(phi1, dtype=float))
    b = d + a2 * np.exp(1j * np.asarray(phi2, dtype=float))
    c = np.abs(b - a)
    alpha = np.arccos((b1 * b1 + c * c - b2 * b2) / (2 * b1 * c))
    return a + b1 * np.exp(1j * (np.angle(b - a) + side * alpha))


def ref_inverse(lengths, p, modes=(1.0, -1.0)):
    """(phi1, phi2) putting P (complex, local frame) with each elbow `modes` (+1 left of
    the line from its pivot to P): the chain's angle at its pivot by the law of cosines."""
    d, a1, a2, b1, b2 = lengths
    out = []
    for pivot, a, b, m in ((0.0, a1, b1, modes[0]), (d, a2, b2, modes[1])):
        r = p - pivot
        beta = np.arccos(np.clip((abs(r) ** 2 + a * a - b * b) / (2 * abs(r) * a), -1.0, 1.0))
        out.append(np.angle(r) + m * beta)
    return out


def numeric_jacobian(lengths, phi1, phi2, h=1e-6):
    c1 = (ref_forward(lengths, phi1 + h, phi2) - ref_forward(lengths, phi1 - h, phi2)) / (2 * h)
    c2 = (ref_forward(lengths, phi1, phi2 + h) - ref_forward(lengths, phi1, phi2 - h)) / (2 * h)
    return np.array([[c1.real, c2.real], [c1.imag, c2.imag]])


def length_slopes(phi, h=1e-5):
    """dP/dl (complex, per row) of each link of L at drive angles phi (rows of [phi1, phi2])
    by central differences of ref_forward."""
    out = []
    for i in range(5):
        up, down = list(L), list(L)
        up[i] += h
        down[i] -= h
        out.append((ref_forward(up, phi[:, 0], phi[:, 1]) - ref_forward(down, phi[:, 0], phi[:, 1])) / (2 * h))
    return out


def report(*args):
    code, out, err = run_cli(*args, "--format", "json", "--precision", "15")
    assert "Traceback" not in err
    return code, (json.loads(out) if out else None), err


def write(tmp_path, text, name="p.toml"):
    f = tmp_path / name
    f.write_text(text)
    return str(f)


HEAD = ('type = "linkage"\n[linkage]\nmechanism = "five-bar"\nground = 50\ninput = 40\ninput2 = 40\n'
        'coupler = 60\ncoupler2 = 60\n')


# ---------------------------------------------------------------- kinematics

ROWS = np.radians(np.array([[125.0, 60.0], [110.0, 60.0], [95.0, 75.0], [80.0, 40.0], [140.0, 100.0]]))


def test_forward_matches_the_law_of_cosines_on_both_branches():
    from linkcli.mechanisms.five_bar import kinematics as kin
    for side in (1.0, -1.0):
        p = kin.forward(L, ROWS[:, 0], ROWS[:, 1], side)
        want = ref_forward(L, ROWS[:, 0], ROWS[:, 1], side)
        assert p.valid.all()
        np.testing.assert_allclose(p.px + 1j * p.py, want, rtol=0, atol=1e-12)
        assert np.all(p.side() == side)


def test_inverse_is_reproduced_by_the_forward_solve():
    from linkcli.mechanisms.five_bar import kinematics as kin
    x, y = np.linspace(0, 50, 11), np.full(11, 70.0)
    for modes in ((1.0, -1.0), (1.0, 1.0), (-1.0, -1.0)):
        q, r1, r2 = kin.inverse(L, x, y, *modes)
        assert r1.all() and r2.all()
        phi1, phi2 = ref_inverse(L, x + 1j * y, modes)
        np.testing.assert_allclose(np.exp(1j * q.phi1), np.exp(1j * phi1), atol=1e-12)
        np.testing.assert_allclose(np.exp(1j * q.phi2), np.exp(1j * phi2), atol=1e-12)
        again = ref_forward(L, q.phi1, q.phi2, float(np.sign(q.det[0])))
        np.testing.assert_allclose(again, x + 1j * y, atol=1e-10)
        m1, m2 = q.modes()
        assert np.all(m1 == modes[0]) and np.all(m2 == modes[1])


def test_jacobian_velocity_and_condition_against_finite_differences_and_svd():
    from linkcli.mechanisms.five_bar import kinematics as kin
    p = kin.forward(L, ROWS[:, 0], ROWS[:, 1], 1.0)
    (j11, j21), (j12, j22) = kin.jacobian(p)
    for k in range(len(ROWS)):
        want = numeric_jacobian(L, ROWS[k, 0], ROWS[k, 1])
        got = np.array([[j11[k], j12[k]], [j21[k], j22[k]]])
        np.testing.assert_allclose(got, want, rtol=1e-7, atol=1e-7)
        assert kin.condition(p)[k] == pytest.approx(np.linalg.cond(want), rel=1e-6)
    vx, vy = kin.velocity(p, 0.3, -0.7)
    np.testing.assert_allclose(vx, 0.3 * j11 - 0.7 * j12, rtol=1e-12)
    np.testing.assert_allclose(vy, 0.3 * j21 - 0.7 * j22, rtol=1e-12)


def test_acceleration_against_the_second_difference_of_the_motion():
    from linkcli.mechanisms.five_bar import kinematics as kin
    w, al, h = (0.8, -1.3), (2.0, 0.5), 1e-4
    p = kin.forward(L, ROWS[:, 0], ROWS[:, 1], 1.0)
    ax, ay = kin.acceleration(p, *w, *al)

    def at(t):
        return ref_forward(L, ROWS[:, 0] + w[0] * t + al[0] * t * t / 2, ROWS[:, 1] + w[1] * t + al[1] * t * t / 2)

    want = (at(h) - 2 * at(0.0) + at(-h)) / (h * h)
    np.testing.assert_allclose(ax + 1j * ay, want, rtol=1e-5, atol=1e-5)


def test_transmission_angles_are_the_angles_between_the_links():
    from linkcli.mechanisms.five_bar import kinematics as kin
    p = kin.forward(L, ROWS[:, 0], ROWS[:, 1], 1.0)
    P = ref_forward(L, ROWS[:, 0], ROWS[:, 1])
    A = L[1] * np.exp(1j * ROWS[:, 0])
    B = L[0] + L[2] * np.exp(1j * ROWS[:, 1])

    def angle(u, v):
        return np.arccos((u * v.conjugate()).real / (abs(u) * abs(v)))

    mu_p, mu_a, mu_b = p.transmissions()
    np.testing.assert_allclose(mu_p, angle(A - P, B - P), atol=1e-12)
    np.testing.assert_allclose(mu_a, angle(-A, P - A), atol=1e-12)
    np.testing.assert_allclose(mu_b, angle(L[0] - B, P - B), atol=1e-12)


def test_singularities_are_infinite_and_named():
    """A row with the left chain stretched (P at input + coupler from A0), one with the
    distal links stretched in line (|A B| = coupler + coupler2): condition inf, rates inf,
    and the nearest singularity named."""
    from linkcli.mechanisms.five_bar import kinematics as kin
    from linkcli.mechanisms.five_bar import sections, track
    from linkcli.mechanisms.five_bar.model import FiveBar, FiveBarMotion
    stretched = 100.0 * np.exp(1j * np.radians(60.0))  # |A0 P| = 40 + 60, |B0 P| = 86.6
    phi1, phi2 = ref_inverse(L, stretched)
    # A = (-40, 0), B = (50 + 40 cos psi, 40 sin psi) with |A B|^2 = 9700 + 7200 cos psi = 120^2
    psi = math.acos((120.0 ** 2 - 9700.0) / 7200.0)
    inputs = ((float(phi1), float(phi2)), (math.pi, psi))
    fb = FiveBar(*L, branch="left", motion=FiveBarMotion(inputs=inputs))
    t = track.solve(fb)
    kappa = kin.condition(t.pose)
    assert kappa[0] > 1e6 and kappa[1] > 1e4
    names = sections.singularity_names(t, *sections.margins(t)[1:3], sections.margins(t)[4])
    assert names == ["I left stretched", "II distal in line"]


def test_type_two_curve_points_are_singular_in_their_modes():
    from linkcli.mechanisms.five_bar import kinematics as kin
    for lengths in (L, (60.0, 40.0, 45.0, 70.0, 62.0)):
        for modes in ((1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)):
            xs, ys = kin.type_two_curve(lengths, np.linspace(-np.pi, np.pi, 721), *modes)
            ok = np.isfinite(xs)
            assert ok.any()
            p = xs[ok] + 1j * ys[ok]
            phi1, phi2 = ref_inverse(lengths, p, modes)
            a = lengths[1] * np.exp(1j * phi1)
            b = lengths[0] + lengths[2] * np.exp(1j * phi2)
            sine = ((p - a).conjugate() * (p - b)).imag / (lengths[3] * lengths[4])
            assert np.max(np.abs(sine)) < 1e-9


def test_ting_class():
    """s1 + s2 + l against p + q (Ting 1986), by hand."""
    from linkcli.mechanisms.five_bar import kinematics as kin
    g = kin.grashof((50, 20, 25, 60, 70))  # 20 + 25 + 70 = 115 < 50 + 60 = 110? no: 115 > 110
    assert g["class"] == "non-grashof" and g["shortest"] == ["input", "input2"] and g["longest"] == "coupler2"
    g = kin.grashof((80, 20, 25, 60, 70))  # 20 + 25 + 80 = 125 < 130
    assert g["class"] == "grashof" and g["two_shortest_plus_longest"] == 125 and g["other_two"] == 130
    assert kin.grashof((85, 20, 25, 60, 70))["class"] == "change-point"  # 130 = 130


# ---------------------------------------------------------------- the metamorphic phase

def test_a_phase_is_the_four_bar_left_and_p_runs_on_its_coupler_curve():
    """Over rows 0..10 of the metamorphic example the right drive is held: P is the output
    pin of the four-bar A0 (input 40) - A - P - B_held (output 60) on the ground A0 B_held,
    and its transmission angle is that four-bar's; the class follows by hand."""
    from linkcli.mechanisms.four_bar import kinematics as four
    code, rep, err = report("synth", "problems/five_bar_metamorphic.toml")
    assert code == 0, err
    held = L[0] + L[2] * np.exp(1j * np.radians(60.0))
    d = abs(held)
    beta = np.angle(held)
    rows = rep["kinematics"][:11]
    phi = np.radians([r["input"] for r in rows]) - beta
    fb = four.pose(40.0, 60.0, 60.0, d, phi, "open")
    pin = (d + 60.0 * np.exp(1j * fb.psi)) * np.exp(1j * beta)
    got = np.array([complex(*r["point"]) for r in rows])
    np.testing.assert_allclose(got, pin, atol=1e-9)
    np.testing.assert_allclose(np.abs(got - held), 60.0, atol=1e-9)
    np.testing.assert_allclose(np.radians([r["transmission"] for r in rows]), fb.mu, atol=1e-9)
    phase = rep["grashof"]["phases"][0]
    s, l_, others = 40.0, d, (60.0, 60.0)  # d = 78.1 is the longest, 40 the shortest: the input
    assert s + l_ < sum(others) and phase["class"] == "crank-rocker" and phase["branch"] == "open"
    assert phase["ground"] == pytest.approx(d, rel=1e-12)
    # the phase's transmission extremes over the driven input's span, by dense sampling
    dense = np.radians(np.linspace(95.0, 125.0, 300001)) - beta
    mu = four.pose(40.0, 60.0, 60.0, d, dense, "open").mu
    tr = rep["transmission"]["phases"][0]
    assert math.radians(tr["min"]) == pytest.approx(mu.min(), abs=1e-9)
    assert math.radians(tr["max"]) == pytest.approx(mu.max(), abs=1e-9)
    # the held drive stands still: P's velocity on the phase is the left column alone
    for r in rows:
        np.testing.assert_allclose(r["velocity"], np.array(r["dpoint_dinput"]) * -20.0, rtol=1e-12, atol=1e-12)


def test_a_path_on_the_phase_circle_gives_the_phase_its_four_bar(tmp_path):
    """The metamorphic example's P at its rows, as a path with the same phase: the inverse
    kinematics finds the same drive angles (the held one constant) and the same four-bar."""
    code, rep, err = report("synth", "problems/five_bar_metamorphic.toml")
    path = [r["point"] for r in rep["kinematics"]]
    text = HEAD + (f'[motion]\npath = {path}\ninput_speeds = [-20, -20]\n[[motion.phases]]\nrows = [0, 10]\n'
                   'locked = "input2"\n')
    code, again, err = report("synth", write(tmp_path, text))
    assert code == 0, err
    for a, b in zip(again["kinematics"], rep["kinematics"]):
        assert (a["input"], a["input2"]) == pytest.approx((b["input"], b["input2"]), abs=1e-9)
    assert again["grashof"]["phases"] == rep["grashof"]["phases"]
    assert again["linkage"]["branch"] == "left"


def test_a_path_off_the_phase_circle_is_infeasible(tmp_path):
    path = [[22.7632, 71.6368], [24.0941, 73.2759], [26.0, 75.0], [28.0, 76.5]]
    text = HEAD + f'[motion]\npath = {path}\n[[motion.phases]]\nrows = [0, 3]\nlocked = "input2"\n'
    code, rep, err = report("synth", write(tmp_path, text))
    assert code == 1, err
    assert "rows 0..3 (input2 held)" in rep["message"] and "coupler curve" in rep["message"]


# ---------------------------------------------------------------- the report through the CLI

def test_line_example_rows_reproduce_the_path_and_the_jacobian():
    code, rep, err = report("synth", "problems/five_bar_line.toml")
    assert code == 0, err
    path = tomllib.load(open("problems/five_bar_line.toml", "rb"))["motion"]["path"]
    rows = rep["kinematics"]
    assert len(rows) == len(path)
    for row, target in zip(rows, path):
        phi1, phi2 = math.radians(row["input"]), math.radians(row["input2"])
        assert ref_forward(L, phi1, phi2) == pytest.approx(complex(*target), abs=1e-9)
        jac = numeric_jacobian(L, phi1, phi2) * math.pi / 180  # per degree
        np.testing.assert_allclose(row["dpoint_dinput"], jac[:, 0], rtol=1e-6, atol=1e-9)
        np.testing.assert_allclose(row["dpoint_dinput2"], jac[:, 1], rtol=1e-6, atol=1e-9)
        assert row["condition"] == pytest.approx(np.linalg.cond(jac), rel=1e-6)
        assert row["modes"] == "+-"
    assert rep["linkage"]["branch"] == "left"


def test_arc_example_is_placed_by_its_ground_pivot():
    code, rep, err = report("synth", "problems/five_bar_arc.toml")
    assert code == 0, err
    for row in rep["kinematics"]:
        phi1, phi2 = math.radians(row["input"]), math.radians(row["input2"])
        p = ref_forward(L, phi1, phi2) - 25.0  # A0 at (-25, 0)
        assert complex(*row["point"]) == pytest.approx(p, abs=1e-9)
        assert abs(p - 60j) == pytest.approx(15.0, abs=1e-3)


def test_rows_out_of_reach_are_named_with_exit_1(tmp_path):
    far = HEAD + "[motion]\npath = [[25, 70], [25, 95], [25, 101], [25, 110]]\n"
    code, rep, err = report("synth", write(tmp_path, far))
    assert code == 1, err
    assert rep["status"] == "infeasible"
    assert "rows 2..3" in rep["message"] and "stretched" in rep["message"]
    assert rep["kinematics"][3] == {"row": 3}
    forward = HEAD + "[motion]\ninputs = [[120, 60], [170, 10], [115, 65]]\n"
    code, rep, err = report("synth", write(tmp_path, forward, "f.toml"))
    assert code == 1 and "row 1 cannot assemble" in rep["message"]


def test_a_path_across_a_type_two_singularity_is_named(tmp_path):
    """Elbows out (+, -), P going down through the line A B: the assembly mode changes."""
    from linkcli.mechanisms.five_bar import kinematics as kin
    ys = np.linspace(70.0, 10.0, 13)
    q, _, _ = kin.inverse(L, np.full(13, 25.0), ys, 1.0, -1.0)
    flips = np.flatnonzero(np.sign(q.det) != np.sign(q.det[0]))
    assert flips.size  # the reference: the sign of cross(u, v) changes on this path
    path = [[25.0, float(y)] for y in ys]
    code, rep, err = report("synth", write(tmp_path, HEAD + f"[motion]\npath = {path}\n"))
    assert code == 1, err
    assert f"type II singularity) before row{'s' if flips.size > 1 else ''} {flips[0]}" in rep["message"]


def test_result_file_round_trips_through_analyze(tmp_path):
    code, out, err = run_cli("synth", "problems/five_bar_metamorphic.toml", "--format", "toml", "--precision",
                             "15", "--out", str(tmp_path))
    assert code == 0, err
    code, again, err = report("analyze", str(tmp_path / "five_bar_metamorphic.toml"))
    assert code == 0, err
    _, first, _ = report("synth", "problems/five_bar_metamorphic.toml")
    assert again["linkage"] == first["linkage"] and again["grashof"]["phases"] == first["grashof"]["phases"]
    assert again["motion"]["phases"] == first["motion"]["phases"]
    for a, b in zip(again["kinematics"], first["kinematics"]):
        assert a["point"] == pytest.approx(b["point"], abs=1e-9) and a["phase"] == b["phase"]


def test_check_of_a_five_bar_imports_neither_numpy_nor_scipy():
    import subprocess
    import sys
    code = ("import sys; from linkcli.cli import app\n"
            "try:\n    app(['check', 'problems/five_bar_metamorphic.toml'], prog_name='linkcli')\n"
            "except SystemExit as e:\n    assert e.code == 0, e.code\n"
            "heavy = [m for m in ('numpy', 'scipy') if m in sys.modules]\nassert not heavy, heavy")
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)


@pytest.mark.slow
def test_plot_draws_the_workspace_and_the_path(tmp_path):
    pytest.importorskip("matplotlib")
    code, _, err = run_cli("synth", "problems/five_bar_metamorphic.toml", "--plot", str(tmp_path / "p.svg"))
    assert code == 0, err
    svg = (tmp_path / "p.svg").read_text()
    for text in ("type II: distal links in line", "path of P (21 rows)", "condition number of J"):
        assert text in svg


# ---------------------------------------------------------------- tolerances

def _model(path="problems/five_bar_line.toml"):
    from linkcli import mechanisms
    from linkcli.reading.load import load
    problem = load(path)
    mech = mechanisms.of(problem.linkage)
    return mech.tolerance_model(problem, None)


def test_monte_carlo_rows_are_first_order_for_tiny_tolerances():
    """Without clearance, P's deviation at each row of the line example is |sum_i S_i dl_i|
    to first order; S_i (dP/dl_i) here by central differences of the independent closure."""
    from linkcli.analysis.tolerance import unit_draws
    model = _model()
    t = 1e-7
    u, _, _ = next(unit_draws(3, 500, len(model.inputs), 5, "uniform"))
    dev, ok, _ = model.row_errors(u * t, None, None)
    assert ok.all()
    phi = np.radians([[r["input"], r["input2"]] for r in report("synth", "problems/five_bar_line.toml")[1]["kinematics"]])
    sens = length_slopes(phi)
    want = np.abs(u @ np.array(sens) * t)
    np.testing.assert_allclose(dev, want, rtol=2e-4)
    got = model.sensitivity()
    for i, name in enumerate(("ground", "input", "input2", "coupler", "coupler2")):
        assert got[name] == pytest.approx(np.abs(sens[i]).max(), rel=1e-6)


def test_reported_row_errors_against_first_order_statistics():
    """The line example's per-row mean and p95 without clearance, against the first-order
    error of 400,000 draws of this test's own (another seed, another generator)."""
    code, rep, err = report("synth", "problems/five_bar_line.toml")
    rows = rep["kinematics"]
    phi = np.radians([[r["input"], r["input2"]] for r in rows])
    sens = length_slopes(phi)
    draws = np.random.default_rng(20240611).uniform(-0.02, 0.02, (400_000, 5))
    first = np.abs(draws @ np.array(sens))
    text = open("problems/five_bar_line.toml").read().replace("clearance = 0.01", "clearance = 0")
    import os
    import tempfile
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False, dir=".") as f:
        f.write(text)
    try:
        code, rep, err = report("synth", os.path.basename(f.name))
    finally:
        os.unlink(f.name)
    assert code == 0, err
    for k, row in enumerate(rep["tolerance"]["rows"]):
        assert row["error_mean"] == pytest.approx(first[:, k].mean(), rel=0.01)
        assert row["error_p95"] == pytest.approx(np.percentile(first[:, k], 95), rel=0.015)


def test_lock_play_added_at_the_phase_end_is_the_held_column_times_the_play(tmp_path):
    """Exact parts, no clearance, a lock play beta: the error the switch adds is
    |dP/dinput2| |delta| to first order, delta uniform on [-beta, beta]."""
    text = open("problems/five_bar_metamorphic.toml").read()
    text = (text.replace("lengths = 0.02", "lengths = 0").replace("clearance = 0.01", "clearance = 0")
            .replace("lock_play = 0.05", "lock_play = 0.01"))
    code, rep, err = report("synth", write(tmp_path, text))
    assert code == 0, err
    change = rep["tolerance"]["phase_changes"][0]
    assert change["at"] == "end" and change["row"] == 10
    column = numeric_jacobian(L, math.radians(95.0), math.radians(60.0))[:, 1]
    top = np.hypot(*column) * math.radians(0.01)
    assert change["added_max"] == pytest.approx(top, rel=2e-3) and change["added_max"] <= top * (1 + 1e-3)
    assert change["added_mean"] == pytest.approx(top / 2, rel=0.02)
    # over the phase the play is P's only error, after it none
    rows = rep["tolerance"]["rows"]
    assert all(r["error_max"] > 0 for r in rows[:11]) and all(r["error_max"] == 0 for r in rows[11:])


def test_column_percentile_is_numpys_percentile_of_each_column():
    from linkcli.analysis.tolerance import column_percentile
    rng = np.random.default_rng(5)
    values = rng.random((301, 7))
    keep = rng.random((301, 7)) > 0.3
    keep[:, 6] = False
    keep[:1, 5], keep[1:, 5] = True, False
    got = column_percentile(values, keep, 95.0)
    for j in range(5):
        assert got[j] == pytest.approx(np.percentile(values[keep[:, j], j], 95), rel=1e-15)
    assert got[5] == values[0, 5] and np.isnan(got[6])


def test_worst_row_and_wilson_per_row():
    from linkcli.analysis.tolerance import wilson
    code, rep, err = report("synth", "problems/five_bar_metamorphic.toml")
    tol = rep["tolerance"]
    n = tol["samples"]
    probs = [r["failure_probability"] for r in tol["rows"]]
    worst = tol["worst_row"]
    assert worst["failure_probability"] == max(probs)
    assert worst["row"] == probs.index(max(probs))
    for r in tol["rows"]:
        k = round(r["failure_probability"] * n)
        assert r["failure_probability_ci95"] == pytest.approx(list(wilson(k, n)))
    assert max(probs) <= tol["failure_probability"] <= sum(probs)


def test_keys_in_an_array_of_tables_have_their_own_lines():
    """io.reader: each [[motion.phases]] element's keys are located on their own line."""
    from linkcli.io.reader import Reader
    text = ('type = "linkage"\n[motion]\ninputs = [[1, 2]]\n[[motion.phases]]\nrows = [0, 0]\n'
            'locked = "input"\n[[motion.phases]]\nrows = [0, 0]\nlocked = "input2"\n')
    r = Reader("x.toml", text)
    assert r.line_of(("motion", "phases[0]", "locked")) == 6
    assert r.line_of(("motion", "phases[1]", "rows")) == 8
    assert r.line_of(("motion", "phases[1]")) == 7
    assert r.line_of(("motion", "inputs[0]")) == 3  # an index into an array keeps its key's line


def test_a_five_bar_drawn_with_two_drives_prints_the_same_numbers(tmp_path):
    """The same five-bar as a drawing (mechanism = "drawn", two drives: issue 29's solver)
    and as the five-bar home, at the drawing's rows: P, its velocity and acceleration at the
    drives' speeds, and the transmission angle at P agree."""
    phi1, phi2 = math.radians(115.0), math.radians(60.0)
    p = complex(ref_forward(L, phi1, phi2))
    a, b = complex(L[1] * np.exp(1j * phi1)), complex(L[0] + L[2] * np.exp(1j * phi2))
    drawn = ('type = "linkage"\n[linkage]\nmechanism = "drawn"\n[joints]\n'
             f'A0 = {{ at = [0, 0], ground = true }}\nB0 = {{ at = [{L[0]!r}, 0], ground = true }}\n'
             f'A = {{ at = [{a.real!r}, {a.imag!r}] }}\nB = {{ at = [{b.real!r}, {b.imag!r}] }}\n'
             f'P = {{ at = [{p.real!r}, {p.imag!r}] }}\n[links]\nleft = ["A0", "A"]\nright = ["B0", "B"]\n'
             'left_distal = ["A", "P"]\nright_distal = ["B", "P"]\n[drive]\nleft = { speed = 20 }\n'
             'right = { speed = -10 }\n[motion]\nsteps = 9\nspan = [-20, 20]\npoints = ["P"]\n')
    code, one, err = report("synth", write(tmp_path, drawn, "drawn.toml"))
    assert code == 0, err
    rows = one["kinematics"]
    inputs = [[r["input"], r["drives"]["right"]] for r in rows]
    five = HEAD + f"[motion]\ninputs = {inputs}\ninput_speeds = [20, -10]\n"
    code, two, err = report("synth", write(tmp_path, five, "five.toml"))
    assert code == 0, err
    for r, s in zip(rows, two["kinematics"]):
        pt = r["points"]["P"]
        assert s["point"] == pytest.approx([pt["x"], pt["y"]], abs=1e-9)
        assert s["velocity"] == pytest.approx([pt["vx"], pt["vy"]], abs=1e-9)
        assert s["acceleration"] == pytest.approx([pt["ax"], pt["ay"]], abs=1e-9)
        assert s["transmission"] == pytest.approx(r["transmission"]["P"], abs=1e-9)
