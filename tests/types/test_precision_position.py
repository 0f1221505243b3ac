"""Freudenstein precision-position synthesis against the seed paper and known linkages.

Positions are generated here from a known linkage with an independent complex-number
closure, so recovering that linkage is an independent check.
"""

from __future__ import annotations

import cmath
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from conftest import run_cli

from linkcli.errors import InputError
from linkcli.pipeline import solve
from linkcli.reading.load import load


def psi_of(a, b, c, d, phi, branch="open"):
    v = cmath.rect(a, phi) - d
    cos_alpha = (abs(v) ** 2 + c * c - b * b) / (2 * abs(v) * c)
    if 1.0 < abs(cos_alpha) <= 1.0 + 1e-12:  # a position at a dead centre, up to round-off
        cos_alpha = math.copysign(1.0, cos_alpha)
    alpha = math.acos(cos_alpha)
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
    code = ("import sys; from linkcli.pipeline import Request, run; "
            "o = run('problems/firedoor.toml', Request()); "
            "assert o.exit_code == 0, o.errors; assert 'scipy' not in sys.modules, 'scipy imported'")
    subprocess.run([sys.executable, "-c", code], check=True)


# --- least squares over 4+ positions: the best assembling fit, not a local one -------------

def spec_closure(a, b, c, d, phi, psi, branch_sign):
    """the conventions of docs/format.md with numpy over arrays of lengths (..., ) and positions (n,):
    A = a e^{i phi}, rho = |A - B0|, cos alpha = (rho^2 + c^2 - b^2) / (2 rho c),
    psi = arg(A - B0) -+ alpha. Returns (sum of squared wrapped errors, assembles everywhere)."""
    a, b, c = (np.asarray(v, dtype=float)[..., None] for v in (a, b, c))
    v = a * np.exp(1j * np.asarray(phi)) - d
    rho = np.abs(v)
    with np.errstate(all="ignore"):
        cos_alpha = (rho ** 2 + c ** 2 - b ** 2) / (2 * rho * c)
    ok = np.all(np.abs(cos_alpha) <= 1.0 + 1e-12, axis=-1)
    out = np.angle(v) + branch_sign * np.arccos(np.clip(cos_alpha, -1, 1))
    err = np.angle(np.exp(1j * (out - np.asarray(psi))))
    return np.sum(err ** 2, axis=-1), ok


ORIENTED = [(ta, tc, s) for ta in (0.0, math.pi) for tc in (0.0, math.pi) for s in (-1.0, 1.0)]


def best_reference(phi_deg, psi_deg, d, candidates=(), grid=36):
    """Best objective of assembling fits found independently: the given lengths and a
    log grid of lengths from d/100 to 20 d, each link either way round, on both branches."""
    phi, psi = np.radians(phi_deg), np.radians(psi_deg)
    g = np.exp(np.linspace(math.log(d / 100), math.log(20 * d), grid))
    grid_abc = [m.ravel() for m in np.meshgrid(g, g, g, indexing="ij")]
    best = np.inf
    for ta, tc, s in ORIENTED:
        for abc in [grid_abc] + [[np.array([x]) for x in cand] for cand in candidates]:
            f, ok = spec_closure(*abc, d, phi + ta, psi + tc, s)
            best = min(best, float(np.min(np.where(ok, f, np.inf))))
    return best


def check_reported_fit(sol, phi_deg, psi_deg, d, local_minimum=True):
    """The reported linkage assembles at every position on its branch (independent closure),
    its objective is its true error there, and (local_minimum) no nearby assembling linkage
    does better."""
    fb = sol.linkage
    sign = -1.0 if fb.branch == "open" else 1.0
    phi_p, psi_p = np.asarray(sol.positions.input), np.asarray(sol.positions.target)
    # the physical angles are the given ones, or the given ones + 180 for a turned link
    for given, phys in ((phi_deg, phi_p), (psi_deg, psi_p)):
        turn = np.angle(np.exp(1j * (phys - np.radians(given))))
        assert np.allclose(np.abs(turn), 0, atol=1e-12) or np.allclose(np.abs(turn), math.pi, atol=1e-12)
    f, ok = spec_closure(fb.input, fb.coupler, fb.output, d, phi_p, psi_p, sign)
    assert bool(ok)
    assert sol.objective == pytest.approx(float(f), rel=1e-7)
    per_point = [psi_of(fb.input, fb.coupler, fb.output, d, p, fb.branch) for p in phi_p]
    err = np.angle(np.exp(1j * (np.array(per_point) - psi_p)))
    assert sol.objective == pytest.approx(float(err @ err), rel=1e-7)
    if not local_minimum:
        return
    rng = np.random.default_rng(0)
    for scale in (1e-2, 1e-4):
        near = np.array([fb.input, fb.coupler, fb.output]) * np.exp(scale * rng.normal(size=(4000, 3)))
        fn, okn = spec_closure(*near.T, d, phi_p, psi_p, sign)
        assert np.min(np.where(okn, fn, np.inf)) >= sol.objective * (1 - 1e-7)


def test_four_positions_find_the_best_assembling_fit():
    # adversarial probe: a single linear start gave objective 0.02025 (460/1408/1826, a
    # branch defect); the independent multi-start fit is 0.00106 at 144.365/148.145/251.852
    phi, psi, d = [30, 60, 90, 120], [40, 55, 75, 100], 50.0
    sol = solve_text(problem_text(phi, psi, ground=d))
    assert sol.status.value == "ok" and sol.linkage.branch == "open"
    ref = best_reference(phi, psi, d, candidates=[(144.365, 148.145, 251.852)])
    assert ref < 0.00106  # the probe's fit, recomputed here from the closure of docs/format.md
    assert sol.objective <= ref * (1 + 1e-6)
    check_reported_fit(sol, phi, psi, d)
    assert not any(n.startswith("branch defect") for n in sol.notes)
    assert (sol.linkage.input, sol.linkage.coupler, sol.linkage.output) == pytest.approx(
        (144.365, 148.145, 251.852), abs=2e-3)


def test_four_positions_assemble_where_the_linear_start_does_not():
    # adversarial probe: the linear start cannot assemble at position 1 and linkcli reported
    # "infeasible"; an assembling fit exists (objective 1.24 at 9.48 / 51.33 / 8.16)
    phi, psi, d = [-140, -105, 0, 125], [125, -125, 40, -140], 50.0
    sol = solve_text(problem_text(phi, psi, ground=d))
    assert sol.status.value == "ok"
    ref = best_reference(phi, psi, d, candidates=[(9.48, 51.33, 8.16)])
    assert ref < 1.33
    assert sol.objective <= ref * (1 + 1e-6)
    assert sol.objective < 1.24
    check_reported_fit(sol, phi, psi, d)


def test_least_squares_evaluations_are_counted_and_deterministic():
    text = problem_text([30, 60, 90, 120], [40, 55, 75, 100])
    first, again = solve_text(text), solve_text(text)
    assert first.solver == again.solver and first.objective == again.objective
    assert first.solver.evaluations > first.solver.starts >= 2
    small = solve_text(text + "[solver]\nbudget = 40\n")
    assert small.solver.evaluations <= 40 and small.status.value == "not-converged"  # exit 1: docs/format.md
    assert small.solver.converged is False
    check_reported_fit(small, [30, 60, 90, 120], [40, 55, 75, 100], 50.0, local_minimum=False)


def test_many_positions_stay_cheap_and_fit_a_known_linkage():
    a, b, c, d = 2.0, 4.5, 3.5, 4.0
    phi = np.radians(np.linspace(10, 130, 400))
    psi = [psi_of(a, b, c, d, p) for p in phi]
    sol = solve_text(problem_text(np.degrees(phi).tolist(), np.degrees(psi).tolist(), ground=d))
    assert (sol.linkage.input, sol.linkage.coupler, sol.linkage.output) == pytest.approx((a, b, c), rel=1e-7)
    assert sol.solver.starts <= 2 * 36


def test_three_positions_on_two_branches_do_not_claim_an_exact_fit():
    # adversarial probe: "exact through 3 positions" while position 2 was missed by 43.6 deg
    phi, psi, d = [-100, 55, 165], [120, -140, -175], 50.0
    sol = solve_text(problem_text(phi, psi, ground=d))
    assert sol.status.value == "infeasible"  # a missed position is no design (issue 21)
    assert not sol.message.startswith("exact")
    assert "met exactly" in sol.message and "no one branch holds all" in sol.message
    assert "open branch holds positions 1, 3" in sol.message and "crossed branch 2" in sol.message
    assert "reported on the open branch" in sol.message
    # the objective and errors are those of the reported branch, recomputed independently
    fb = sol.linkage
    assert fb.branch == "open"
    per_point = [psi_of(fb.input, fb.coupler, fb.output, d, p, "open") for p in sol.positions.input]
    err = np.angle(np.exp(1j * (np.array(per_point) - np.asarray(sol.positions.target))))
    assert np.allclose(sol.positions.error, err, atol=1e-9)
    assert sol.objective == pytest.approx(float(err @ err), rel=1e-9)
    assert abs(math.degrees(err[1])) == pytest.approx(43.6, abs=0.05)
    assert max(abs(err[0]), abs(err[2])) < 1e-9
    crossed = [psi_of(fb.input, fb.coupler, fb.output, d, sol.positions.input[1], "crossed")]
    assert abs(np.angle(np.exp(1j * (crossed[0] - sol.positions.target[1])))) < 1e-9


def test_positions_across_the_seam_are_taken_in_motion_order(tmp_path):
    # [150, 180, -150] is the input turning 150 -> 180 -> 210: the working range, the
    # travel check and the branch verdict follow that motion, not a -300 deg sweep through 0
    a, b, c, d = 30.0, 80.0, 70.0, 50.0
    psis = [math.degrees(psi_of(a, b, c, d, math.radians(ph))) for ph in (150.0, 180.0, 210.0)]
    outs = []
    for inputs in ([150, 180, 210], [150, 180, -150]):
        path = tmp_path / f"p{len(outs)}.toml"
        path.write_text('type = "precision-position"\n[linkage]\nground = 50\n[positions]\n'
                        f"input = {inputs}\noutput = {[round(p, 9) for p in psis]}\n")
        code, out, err = run_cli("synth", str(path), "-f", "json")
        assert code == 0, err
        outs.append(json.loads(out))
    for rep in outs:
        assert (rep["linkage"]["input"], rep["linkage"]["coupler"], rep["linkage"]["output"]) == \
            pytest.approx((a, b, c), rel=1e-7)
        assert "branch defect" not in rep["message"]
    # reference: the transmission angle along 150..210 deg, cos mu = (b^2 + c^2 - rho^2) / (2bc)
    mus = []
    for k in range(6001):
        ph = math.radians(150 + 60 * k / 6000)
        rho2 = a * a + d * d - 2 * a * d * math.cos(ph)
        mus.append(math.degrees(math.acos((b * b + c * c - rho2) / (2 * b * c))))
    for rep in outs:
        tr = rep["transmission"]
        assert (tr["working_min"], tr["working_max"]) == pytest.approx((min(mus), max(mus)), abs=1e-3)


def test_a_spent_budget_is_not_converged(tmp_path):
    path = tmp_path / "b.toml"
    path.write_text('type = "precision-position"\n[linkage]\nground = 50\n[positions]\n'
                    "input = [45, 70, 90, 110, 135]\noutput = [52.0, 68.4, 82.0, 97.0, 112.0]\n"
                    "[solver]\nbudget = 10\n")
    code, out, _ = run_cli("synth", str(path), "-f", "json")
    rep = json.loads(out)
    assert code == 1 and rep["status"] == "not-converged" and rep["solver"]["converged"] is False
    assert rep["solver"]["evaluations"] <= 10
