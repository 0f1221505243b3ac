"""Freudenstein precision-position synthesis against the seed paper and known linkages.

Positions are generated here from a known linkage with an independent complex-number
closure, so recovering that linkage is an independent check.
"""

from __future__ import annotations

import cmath
import math
import subprocess
import sys

import numpy as np
import pytest

from linkcli.errors import InputError
from linkcli.problemfile import load
from linkcli.solvers import solve


def psi_of(a, b, c, d, phi, branch="open"):
    v = cmath.rect(a, phi) - d
    alpha = math.acos((abs(v) ** 2 + c * c - b * b) / (2 * abs(v) * c))
    return cmath.phase(v) + (-alpha if branch == "open" else alpha)


def problem_text(phi, psi, ground=50.0, extra=""):
    return (f'type = "precision-position"\n[linkage]\nground = {ground}\n[positions]\n'
            f"input = {list(phi)}\noutput = {list(psi)}\n{extra}")


def solve_text(text):
    return solve(load("test.toml", text))


def test_fire_door_matches_the_seed_paper():
    sol = solve(load("problems/firedoor.toml"))
    fb = sol.linkage
    # seed: input 27.6293, coupler 57.2363, output 41.1104 (4 decimals printed)
    assert fb.input == pytest.approx(27.6293, abs=6e-5)
    assert fb.coupler == pytest.approx(57.2363, abs=6e-5)
    assert fb.output == pytest.approx(41.1104, abs=6e-5)
    assert fb.ground == 50.0 and fb.branch == "open"
    assert sol.status.value == "ok" and sol.objective < 1e-20


@pytest.mark.parametrize("abcd,branch", [((2.0, 4.5, 3.5, 4.0), "open"), ((1.0, 3.0, 2.2, 2.6), "crossed"),
                                         ((3.0, 2.0, 3.5, 1.5), "open")])
@pytest.mark.parametrize("n", [3, 5, 8])
def test_recovers_a_known_linkage(abcd, branch, n):
    a, b, c, d = abcd
    phi = np.radians(np.linspace(20, 20 + 12 * (n - 1), n))
    psi = [psi_of(a, b, c, d, p, branch) for p in phi]
    text = problem_text(np.degrees(phi).tolist(), np.degrees(psi).tolist(), ground=d)
    sol = solve_text(text)
    fb = sol.linkage
    assert (fb.input, fb.coupler, fb.output) == pytest.approx((a, b, c), rel=1e-7)
    assert fb.branch == branch
    assert np.max(np.abs(sol.positions.error)) < 1e-8


def test_least_squares_is_refined_on_the_true_angle_error():
    a, b, c, d = 2.0, 4.5, 3.5, 4.0
    rng = np.random.default_rng(3)
    phi = np.radians(np.linspace(10, 130, 9))
    psi = np.array([psi_of(a, b, c, d, p) for p in phi]) + rng.normal(0, 0.01, len(phi))
    sol = solve_text(problem_text(np.degrees(phi).tolist(), np.degrees(psi).tolist(), ground=d))
    fb = sol.linkage
    # independent true angle error of the reported linkage
    err = np.array([psi_of(fb.input, fb.coupler, fb.output, d, p) for p in phi]) - psi
    assert sol.objective == pytest.approx(float(err @ err), rel=1e-9)
    # the linear Freudenstein least squares (residual of the equation, not of the angle)
    m = np.column_stack([np.cos(psi), -np.cos(phi), np.ones_like(phi)])
    k = np.linalg.lstsq(m, np.cos(phi - psi), rcond=None)[0]
    a0, c0 = d / k[0], d / k[1]
    b0 = math.sqrt(a0 * a0 + c0 * c0 + d * d - 2 * a0 * c0 * k[2])
    err0 = np.array([psi_of(a0, b0, c0, d, p) for p in phi]) - psi
    assert float(err @ err) < float(err0 @ err0)
    assert "refined" in sol.message


def test_negative_ratio_gives_positive_lengths_and_a_note():
    a, b, c, d = 2.0, 4.5, 3.5, 4.0
    phi = np.radians([30.0, 50.0, 70.0])
    psi = [psi_of(a, b, c, d, p) for p in phi]
    # the same linkage described with the input angle measured on the crank's far side
    text = problem_text((np.degrees(phi) + 180).tolist(), np.degrees(psi).tolist(), ground=d)
    sol = solve_text(text)
    assert (sol.linkage.input, sol.linkage.coupler, sol.linkage.output) == pytest.approx((a, b, c), rel=1e-7)
    assert any("input link points opposite" in n for n in sol.notes)
    assert np.max(np.abs(sol.positions.error)) < 1e-8


def test_singular_positions_name_the_positions():
    text = problem_text([30, -30, 60], [50, 50, 70])
    with pytest.raises(InputError) as exc:
        solve_text(text)
    assert "positions 1, 2, 3" in str(exc.value) and "singular" in str(exc.value)


def test_branch_defect_is_reported():
    # positions taken from the open and the crossed assembly of one linkage
    a, b, c, d = 2.0, 4.5, 3.5, 4.0
    phi = np.radians([30.0, 60.0, 90.0])
    psi = [psi_of(a, b, c, d, phi[0], "open"), psi_of(a, b, c, d, phi[1], "crossed"),
           psi_of(a, b, c, d, phi[2], "open")]
    sol = solve_text(problem_text(np.degrees(phi).tolist(), np.degrees(psi).tolist(), ground=d))
    assert (sol.linkage.input, sol.linkage.coupler, sol.linkage.output) == pytest.approx((a, b, c), rel=1e-7)
    assert any(n.startswith("branch defect") for n in sol.notes)
    assert "branch defect" in sol.message


def test_radians_and_metres_give_the_same_shape():
    text = problem_text([math.radians(x) for x in (45, 90, 135)], [math.radians(x) for x in (52, 82, 112)],
                        ground=0.05, extra='[units]\nlength = "m"\nangle = "rad"\n')
    fb = solve_text(text).linkage
    assert (fb.input, fb.coupler, fb.output) == pytest.approx((0.0276293, 0.0572363, 0.0411104), abs=6e-8)


def test_closed_form_path_does_not_import_scipy():
    code = ("import sys; from linkcli.cli import run_one; "
            "c, r, e = run_one('problems/firedoor.toml', 'synth', None, False); "
            "assert c == 0, e; assert 'scipy' not in sys.modules, 'scipy imported'")
    subprocess.run([sys.executable, "-c", code], check=True)
