"""The five-bar's path generation (types/path_generation/five_bar_design*.py): the reported
design checked by this test's own closure (law of cosines, SVD), its optimality probed by
seeded perturbations, its digits against other seeds, and the trade-off table's properties."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import run_cli
from test_five_bar import ref_inverse


def report(*args):
    code, out, err = run_cli(*args, "--format", "json", "--precision", "15")
    assert "Traceback" not in err
    return code, json.loads(out), err


def worst_condition(lengths, pivot, path, modes=(1.0, -1.0)):
    """max over the path of cond(J) by SVD, J from finite differences of the closure."""
    p = np.array([complex(*q) for q in path]) - complex(*pivot)
    phi1, phi2 = ref_inverse(lengths, p, modes)
    d, a1, a2, b1, b2 = lengths
    out = []
    for f1, f2 in zip(phi1, phi2):
        a, b = a1 * np.exp(1j * f1), d + a2 * np.exp(1j * f2)
        u, v = p[len(out)] - a, p[len(out)] - b
        # J = Jx^-1 Jq (Gosselin & Angeles 1990), written here with numpy's solve
        jx = np.array([[u.real, u.imag], [v.real, v.imag]])
        jq = np.diag([(u.conjugate() * 1j * a).real, (v.conjugate() * 1j * (b - d)).real])
        out.append(np.linalg.cond(np.linalg.solve(jx, jq)))
    return max(out)


@pytest.fixture(scope="module")
def design():
    code, rep, err = report("synth", "problems/five_bar_design.toml")
    assert code == 0, err
    return rep


def lengths_of(lk):
    return tuple(lk[k] for k in ("ground", "input", "input2", "coupler", "coupler2"))


@pytest.mark.slow
def test_the_design_reaches_the_line_with_its_reported_conditioning(design):
    lk = design["linkage"]
    path = [r["target"] for r in design["positions"]]
    got = worst_condition(lengths_of(lk), lk["ground_pivot"], path)
    assert design["design"]["worst_condition"] == pytest.approx(got, rel=1e-9)
    assert design["transmission"]["condition_max"] == pytest.approx(got, rel=1e-9)
    assert all(r["error"] == 0 for r in design["positions"])


def test_no_nearby_design_within_the_bounds_is_better_conditioned(design):
    """2000 seeded perturbations (1e-4 .. 1e-2 of each range, inside the bounds) of the free
    variables: none improves the worst condition number by more than round-off."""
    lk = design["linkage"]
    path = [r["target"] for r in design["positions"]]
    x = np.array(lengths_of(lk) + (lk["ground_pivot"][0],))
    lo = np.array([20, 20, 20, 30, 30, -20.0])
    hi = np.array([80, 60, 60, 90, 90, 10.0])
    best = worst_condition(tuple(x[:5]), (x[5], 0.0), path)
    rng = np.random.default_rng(99)
    for scale in (1e-2, 1e-3, 1e-4):
        for _ in range(60):
            y = np.clip(x + scale * (hi - lo) * rng.uniform(-1, 1, 6), lo, hi)
            with np.errstate(invalid="ignore"):
                k = worst_condition(tuple(y[:5]), (y[5], 0.0), path)
            assert not k < best * (1 - 1e-9), (scale, y, k, best)


@pytest.mark.slow
def test_the_digits_do_not_follow_the_seed(design):
    code, other, err = report("synth", "problems/five_bar_design.toml", "--seed", "7")
    assert code == 0, err
    for key in ("ground", "input", "input2", "coupler", "coupler2"):
        assert other["linkage"][key] == pytest.approx(design["linkage"][key], rel=1e-7)


@pytest.mark.slow
def test_the_tradeoff_table(tmp_path):
    code, rep, err = report("synth", "problems/five_bar_reliable.toml")
    assert code == 0, err
    rows = rep["tradeoff"]
    limits = [r["max_condition"] for r in rows]
    assert limits == sorted(limits) and limits[-1] == pytest.approx(2.0)
    for r in rows:
        path = [q["target"] for q in rep["positions"]]
        got = worst_condition(lengths_of(r), r["ground_pivot"], path)
        assert r["worst_condition"] == pytest.approx(got, rel=1e-9)
        assert got <= r["max_condition"] * (1 + 1e-9)
    sigma = [r["sigma_max"] for r in rows]
    assert all(b <= a * (1 + 1e-9) for a, b in zip(sigma, sigma[1:]))  # a looser limit never costs accuracy
    fail = [r["largest_failure_probability"] for r in rows]
    chosen = rows[fail.index(min(fail))]
    assert rep["design"]["chosen_by"] == "failure-probability"
    assert lengths_of(rep["linkage"]) == pytest.approx(lengths_of(chosen), rel=1e-12)
    # the tolerance section studies the chosen design with the same draws
    per_row = max(r["failure_probability"] for r in rep["tolerance"]["rows"])
    assert per_row == pytest.approx(chosen["largest_failure_probability"])


def test_first_order_sigma_against_finite_differences():
    """synthesis.first_order_sigma at one design and row against this test's finite
    differences of P in the lengths and in the shifted elbows."""
    from test_five_bar import ref_forward

    from linkcli.mechanisms.five_bar import kinematics as kin
    from linkcli.mechanisms.five_bar.synthesis import first_order_sigma
    L = (50.0, 40.0, 40.0, 60.0, 60.0)
    phi1, phi2 = math.radians(110.0), math.radians(60.0)
    pose = kin.forward(L, np.array([phi1]), np.array([phi2]), 1.0)
    var = np.array([1.0, 2.0, 3.0, 4.0, 5.0]) * 1e-4
    pin = 2e-5
    got = first_order_sigma(pose, var, pin)[0]
    h = 1e-6
    total = 0.0
    for i in range(5):
        up, down = list(L), list(L)
        up[i] += h
        down[i] -= h
        total += var[i] * abs((ref_forward(up, phi1, phi2) - ref_forward(down, phi1, phi2)) / (2 * h)) ** 2
    # an elbow shifted by e moves P by G e; the pins A0, A shift A, the pins B0, B, P shift B
    a = L[1] * np.exp(1j * phi1)
    b = L[0] + L[2] * np.exp(1j * phi2)

    def p_of(a, b):
        c = abs(b - a)
        alpha = math.acos((L[3] ** 2 + c * c - L[4] ** 2) / (2 * L[3] * c))
        return a + L[3] * np.exp(1j * (np.angle(b - a) + alpha))

    for shift, count in ((lambda e: (a + e, b), 2), (lambda e: (a, b + e), 3)):
        for e in (h, 1j * h):
            g = (p_of(*shift(e)) - p_of(*shift(-e))) / (2 * h)
            total += count * pin * abs(g) ** 2
    assert got == pytest.approx(math.sqrt(total), rel=1e-7)


def test_any_modes_picks_the_best_pair(tmp_path):
    text = """type = "path-generation"
[linkage]
mechanism = "five-bar"
[target]
points = [[10, 60], [20, 62], [30, 60]]
[bounds]
ground = 40
input = [25, 45]
input2 = [25, 45]
coupler = 55
coupler2 = 55
ground_pivot = { x = 0, y = 0 }
ground_angle = 0
[constraints]
modes = "any"
[objective]
maximize = "transmission"
"""
    f = tmp_path / "any.toml"
    f.write_text(text)
    code, rep, err = report("synth", str(f))
    assert code == 0, err
    pairs = rep["design"]["mode_pairs"]
    assert [p["modes"] for p in pairs] == ["+-", "++", "--", "-+"]
    best = max(p["worst_quality"] for p in pairs)
    assert "".join(rep["design"]["modes"]) == next(p["modes"] for p in pairs if p["worst_quality"] == best)
    # the worst transmission reported, by this test's dot products
    lk = rep["linkage"]
    m = tuple(1.0 if c == "+" else -1.0 for c in rep["design"]["modes"])
    p = np.array([complex(*q["target"]) for q in rep["positions"]])
    phi1, phi2 = ref_inverse(lengths_of(lk), p, m)
    a, b = lk["input"] * np.exp(1j * phi1), lk["ground"] + lk["input2"] * np.exp(1j * phi2)

    def angle(u, v):
        return np.arccos((u * v.conjugate()).real / (abs(u) * abs(v)))

    mus = np.concatenate([angle(a - p, b - p), angle(-a, p - a), angle(lk["ground"] - b, p - b)])
    assert math.radians(rep["design"]["worst_transmission"]) == pytest.approx(np.min(np.minimum(mus, np.pi - mus)),
                                                                             abs=1e-9)
    assert best == pytest.approx(np.min(np.sin(mus)), rel=1e-9)
