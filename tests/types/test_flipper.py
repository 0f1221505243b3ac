"""flipper-cylinder: the cylinder force against independent references.

References written here, not taken from the code under test:
- `ref_force`: static balance about the hinge, one angle at a time with the math module:
  F (r_A x e) = m g G_x, e = (A - C) / |A - C|, A and G turned by t - start.
- `vw_force`: the principle of virtual work, F dL = m g dG_y, with dL/dt by a central
  finite difference of the cylinder length and dG_y/dt = G_x (a different route to F).
- the seed paper's value: 33,815 N at 90 deg for A = (350, 320), C = (1400, 50).
- brute force: the peak by a dense per-angle scan, and the best design of a grid over the
  pivot bounds (numpy, written in this file).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import run_cli

from linkcli.pipeline import analyse, solve
from linkcli.reading.load import load
from linkcli.textnum import render
from linkcli.types.flipper_cylinder.statics import Statics

M, G, COM = 2000.0, 9.8, (830.0, 500.0)
PAPER_A, PAPER_C = (350.0, 320.0), (1400.0, 50.0)


def rotate(p, t):
    c, s = math.cos(t), math.sin(t)
    return p[0] * c - p[1] * s, p[0] * s + p[1] * c


def ref_force(a0, c, deg, start=0.0, mass=M, g=G, com=COM):
    """Cylinder force (N, push > 0) at platform angle `deg` from the moment balance about B."""
    t = math.radians(deg - start)
    ax, ay = rotate(a0, t)
    gx, _ = rotate(com, t)
    length = math.hypot(ax - c[0], ay - c[1])
    ex, ey = (ax - c[0]) / length, (ay - c[1]) / length
    return mass * g * gx / (ax * ey - ay * ex)


def vw_force(a0, c, deg, start=0.0, mass=M, g=G, com=COM, h=1e-6):
    """Virtual work: the cylinder's work F dL equals the lift of the weight m g dG_y."""
    t = math.radians(deg - start)

    def length(tt):
        ax, ay = rotate(a0, tt)
        return math.hypot(ax - c[0], ay - c[1])

    dl = (length(t + h) - length(t - h)) / (2 * h)
    gx, _ = rotate(com, t)  # d/dt of (R(t) G)_y is (R(t) G)_x
    return mass * g * gx / dl


def ref_peak(a0, c, start, end, n=90001, **load):
    """(|F| max, angle, signed F) by a per-angle scan with both ends."""
    best = (-1.0, None, None)
    for i in range(n):
        deg = start + (end - start) * i / (n - 1)
        f = ref_force(a0, c, deg, start, **load)
        if abs(f) > best[0]:
            best = (abs(f), deg, f)
    return best


def text(rod, base, *, start=0, end=90, cylinder="", objective="", extra="", units="", com=COM):
    return (f'type = "flipper-cylinder"\n{units}[load]\nmass = {M}\ncenter_of_mass = [{com[0]}, {com[1]}]\n'
            f"gravity = {G}\n[motion]\nstart = {start}\nend = {end}\n[bounds]\n"
            f"rod_pivot = {rod}\nbase_pivot = {base}\n{cylinder}{objective}{extra}")


PAPER = text("{ x = 350, y = 320 }", "{ x = 1400, y = 50 }")
SEED = text("{ x = [0, 350], y = [320, 1380] }", "{ x = [400, 1400], y = 50 }")


def report_of(source: str):
    problem = load("test.toml", source)
    sol = solve(problem)
    return problem, sol, analyse(problem, sol)


# ----------------------------------------------------------------------- the paper's design
def test_reference_reproduces_the_papers_force_at_90_deg():
    f90 = ref_force(PAPER_A, PAPER_C, 90.0)
    assert abs(f90) == pytest.approx(33815.0, rel=1e-4)  # the paper, to 0.01 %
    assert f90 < 0  # the rod pulls at 90 deg
    assert vw_force(PAPER_A, PAPER_C, 90.0) == pytest.approx(f90, rel=1e-7)
    assert vw_force(PAPER_A, PAPER_C, 0.0) == pytest.approx(ref_force(PAPER_A, PAPER_C, 0.0), rel=1e-7)


def test_papers_design_forces_at_0_and_90_deg():
    _, sol, rep = report_of(PAPER)
    rows = {r["angle"]: r for r in rep["cylinder"]["forces"]}
    assert rows[90.0]["force"] == pytest.approx(-33815.0, rel=1e-4)
    assert rows[90.0]["force"] == pytest.approx(ref_force(PAPER_A, PAPER_C, 90.0), rel=1e-12)
    assert rows[0.0]["force"] == pytest.approx(ref_force(PAPER_A, PAPER_C, 0.0), rel=1e-12)
    assert rows[0.0]["force"] == pytest.approx(40968.857, rel=1e-6)  # pushes harder than it pulls
    assert sol.solver.method == "evaluate" and sol.solver.evaluations == 1


def test_papers_design_true_peak_over_the_sweep():
    _, sol, rep = report_of(PAPER)
    cyl = rep["cylinder"]
    peak, at, signed = ref_peak(PAPER_A, PAPER_C, 0.0, 90.0)
    assert cyl["peak_force"] == pytest.approx(peak, rel=1e-4)
    assert cyl["peak_angle"] == pytest.approx(at, abs=1e-3)
    assert cyl["peak_kind"] == ("push" if signed > 0 else "pull") == "push"
    assert cyl["pull_force"] == pytest.approx(33815.0, rel=1e-4)
    assert sol.status.value == "ok" and sol.objective == pytest.approx(peak, rel=1e-4)


def test_every_table_row_matches_both_references():
    _, _, rep = report_of(PAPER)
    rows = rep["cylinder"]["forces_full"]
    assert rows[0]["angle"] == 0.0 and rows[-1]["angle"] == 90.0
    for r in rows:
        assert r["force"] == pytest.approx(ref_force(PAPER_A, PAPER_C, r["angle"]), rel=1e-9)
        assert r["force"] == pytest.approx(vw_force(PAPER_A, PAPER_C, r["angle"]), rel=1e-6)
        a = rotate(PAPER_A, math.radians(r["angle"]))
        length = math.hypot(a[0] - PAPER_C[0], a[1] - PAPER_C[1])
        assert r["length"] == pytest.approx(length, rel=1e-12)
        arm = abs(PAPER_C[0] * a[1] - PAPER_C[1] * a[0]) / length  # distance from B to line C-A
        assert r["arm"] == pytest.approx(arm, rel=1e-12)


def test_interior_peak_is_found_to_1e_4():
    """A sweep from -60 to 60 deg whose centre of mass is level with the hinge at 58 deg
    past the start: the peak lies inside the sweep, between grid angles."""
    a0, c, com = (397.0, 128.0), (1422.0, -142.0), (500.0, -800.0)
    src = text("{ x = 397, y = 128 }", "{ x = 1422, y = -142 }", start=-60, end=60, com=com)
    _, _, rep = report_of(src)
    peak, at, _ = ref_peak(a0, c, -60.0, 60.0, n=120001, com=com)
    assert -59.0 < at < 59.0  # the test case really has an interior maximum
    assert rep["cylinder"]["peak_force"] == pytest.approx(peak, rel=1e-4)
    assert rep["cylinder"]["peak_angle"] == pytest.approx(at, abs=0.01)


@pytest.mark.slow
def test_refined_peak_against_a_very_dense_grid():
    """1e-4 relative (in fact far better) for many designs, against 400001 angles each."""
    rng = np.random.default_rng(7)
    st = Statics(M * G, COM, math.radians(120.0))
    designs = np.column_stack([rng.uniform(-400, 400, 400), rng.uniform(100, 1400, 400),
                               rng.uniform(300, 1500, 400), rng.uniform(-400, 200, 400)])
    crosses, _ = st.crossing(designs)
    designs = designs[~crosses][:30]
    assert len(designs) >= 10
    got = st.peaks(designs)
    t = np.linspace(0.0, math.radians(120.0), 400001)
    for d, peak in zip(designs, got["peak"]):
        ax, ay = d[0] * np.cos(t) - d[1] * np.sin(t), d[0] * np.sin(t) + d[1] * np.cos(t)
        gx = COM[0] * np.cos(t) - COM[1] * np.sin(t)
        length = np.hypot(ax - d[2], ay - d[3])
        f = M * G * gx * length / (d[2] * ay - d[3] * ax)
        dense = np.max(np.abs(f))
        assert peak >= dense * (1 - 1e-12)
        assert peak == pytest.approx(dense, rel=1e-4)


def test_start_position_and_nonzero_start_angle():
    """Pivots and the centre of mass are given at the start position: X(t) = R(t - start) X."""
    src = text("{ x = 350, y = 320 }", "{ x = 1400, y = 50 }", start=30, end=120)
    _, _, rep = report_of(src)
    rows = {r["angle"]: r["force"] for r in rep["cylinder"]["forces"]}
    assert rows[30.0] == pytest.approx(ref_force(PAPER_A, PAPER_C, 30.0, start=30.0), rel=1e-12)
    assert rows[30.0] == pytest.approx(ref_force(PAPER_A, PAPER_C, 0.0), rel=1e-12)
    assert rows[120.0] == pytest.approx(ref_force(PAPER_A, PAPER_C, 120.0, start=30.0), rel=1e-12)


def test_cylinder_line_through_the_hinge_is_infeasible():
    """C = (0, -500): A_x(t) = 350 cos t - 320 sin t vanishes at tan t = 350/320, where C, B
    and A are in line and no force can hold the platform."""
    src = text("{ x = 350, y = 320 }", "{ x = 0, y = -500 }")
    _, sol, rep = report_of(src)
    assert sol.status.value == "infeasible"
    assert "passes through the hinge" in render(sol.message)
    zero = math.degrees(math.atan2(350.0, 320.0))
    assert f"{zero:.6g} deg" in render(sol.message)
    assert rep["cylinder"]["peak_force"] == math.inf and rep["cylinder"]["peak_kind"] == "unbounded"
    code, out, err = run_cli("synth", "problems/flipper_check.toml")
    assert code == 0


def test_pressures_on_bore_and_annulus():
    src = text("{ x = 350, y = 320 }", "{ x = 1400, y = 50 }", cylinder="[cylinder]\nbore = 80\nrod = 45\n")
    _, _, rep = report_of(src)
    cyl = rep["cylinder"]
    push = ref_force(PAPER_A, PAPER_C, 0.0)
    pull = -ref_force(PAPER_A, PAPER_C, 90.0)
    assert cyl["push_pressure"] == pytest.approx(push / (math.pi / 4 * 80 ** 2), rel=1e-6)
    assert cyl["pull_pressure"] == pytest.approx(pull / (math.pi / 4 * (80 ** 2 - 45 ** 2)), rel=1e-6)
    # the same cylinder in metres: the same pressures (areas converted to mm^2)
    src_m = text("{ x = 0.35, y = 0.32 }", "{ x = 1.4, y = 0.05 }", units='[units]\nlength = "m"\n',
                 cylinder="[cylinder]\nbore = 0.08\nrod = 0.045\n").replace("[830.0, 500.0]", "[0.83, 0.5]")
    _, _, rep_m = report_of(src_m)
    assert rep_m["cylinder"]["push_pressure"] == pytest.approx(cyl["push_pressure"], rel=1e-9)
    assert rep_m["cylinder"]["pull_pressure"] == pytest.approx(cyl["pull_pressure"], rel=1e-9)


# ------------------------------------------------------------------------- optimization
def grid_peaks(x1, y1, x2, y2=50.0, degs=np.linspace(0.0, 90.0, 181)):
    """Peak |F| (and closed, open lengths) of every design of a pivot grid, test-local numpy."""
    t = np.radians(degs)[None, :]
    a0x, a0y, cx = x1.ravel()[:, None], y1.ravel()[:, None], x2.ravel()[:, None]
    ax, ay = a0x * np.cos(t) - a0y * np.sin(t), a0x * np.sin(t) + a0y * np.cos(t)
    gx = COM[0] * np.cos(t) - COM[1] * np.sin(t)
    length = np.hypot(ax - cx, ay - y2)
    k = cx * ay - y2 * ax
    f = M * G * gx * length / k
    ok = np.all(k > 0, axis=1) | np.all(k < 0, axis=1)
    peak = np.where(ok, np.max(np.abs(f), axis=1), np.inf)
    return peak, length[:, 0], length[:, -1]


@pytest.fixture(scope="module")
def seed_result():
    problem = load("problems/flipper.toml")
    sol = solve(problem)
    return problem, sol, analyse(problem, sol)


@pytest.mark.slow
def test_optimized_peak_is_true_and_beats_a_brute_force_grid(seed_result):
    _, sol, rep = seed_result
    cyl = rep["cylinder"]
    a0, c = tuple(cyl["rod_pivot"]), tuple(cyl["base_pivot"])
    assert 0 <= a0[0] <= 350 and 320 <= a0[1] <= 1380 and 400 <= c[0] <= 1400 and c[1] == 50
    peak, _, _ = ref_peak(a0, c, 0.0, 90.0, n=9001)
    assert cyl["peak_force"] == pytest.approx(peak, rel=1e-4)
    x1, y1, x2 = np.meshgrid(np.linspace(0, 350, 36), np.linspace(320, 1380, 107),
                             np.linspace(400, 1400, 51), indexing="ij")
    best = np.inf
    for i in range(0, x1.size, 40000):  # chunks keep memory small
        p, _, _ = grid_peaks(x1.ravel()[i:i + 40000], y1.ravel()[i:i + 40000], x2.ravel()[i:i + 40000])
        best = min(best, float(p.min()))
    assert cyl["peak_force"] <= best
    assert sol.status.value == "ok" and sol.solver.converged


def test_optimized_peak_is_a_local_minimum(seed_result):
    """No feasible nearby design (within the bounds) has a lower independent peak."""
    _, _, rep = seed_result
    cyl = rep["cylinder"]
    a0, c = cyl["rod_pivot"], cyl["base_pivot"]
    rng = np.random.default_rng(3)
    for scale in (1e-3, 1e-1, 3.0):
        for _ in range(20):
            dx1, dy1, dx2 = rng.normal(0, scale, 3)
            x1, x2 = min(350.0, a0[0] + dx1), min(1400.0, c[0] + dx2)
            p, _, _ = ref_peak((x1, a0[1] + dy1), (x2, 50.0), 0.0, 90.0, n=91)
            assert p >= cyl["peak_force"] * (1 - 1e-7)


def test_seed_reference_and_balance(seed_result):
    """The minimax balances the push at 0 deg against the pull at 90 deg (the reference in
    problems/flipper.toml is the 1-D root of F(0) + F(90) = 0 at x1 = 350, x2 = 1400)."""
    problem, sol, rep = seed_result
    cyl = rep["cylinder"]
    lo, hi = 320.0, 400.0
    for _ in range(200):  # bisection on y1, test-local
        mid = 0.5 * (lo + hi)
        h = ref_force((350, mid), (1400, 50), 0.0) + ref_force((350, mid), (1400, 50), 90.0)
        lo, hi = (mid, hi) if h > 0 else (lo, mid)
    y1 = 0.5 * (lo + hi)
    assert cyl["rod_pivot"] == pytest.approx([350.0, y1], rel=1e-6)
    assert cyl["base_pivot"] == pytest.approx([1400.0, 50.0], rel=1e-9)
    assert cyl["peak_force"] == pytest.approx(ref_force((350, y1), (1400, 50), 0.0), rel=1e-8)
    assert cyl["push_force"] == pytest.approx(cyl["pull_force"], rel=1e-6)
    assert problem.meta.reference.objective == pytest.approx(cyl["peak_force"], rel=1e-7)


@pytest.mark.parametrize("method", ["auto", "differential-evolution", "slsqp"])
def test_each_method_reaches_the_minimax(method):
    src = SEED + f'[solver]\nmethod = "{method}"\n'
    _, sol, rep = report_of(src)
    assert rep["cylinder"]["peak_force"] == pytest.approx(34761.665, rel=1e-5)
    assert sol.solver.method == method and sol.solver.evaluations <= 4000


@pytest.mark.slow
def test_cylinder_length_respects_max_force_and_dead_length():
    problem = load("problems/flipper_length.toml")
    sol = solve(problem)
    rep = analyse(problem, sol)
    cyl = rep["cylinder"]
    a0, c = tuple(cyl["rod_pivot"]), tuple(cyl["base_pivot"])
    peak, _, _ = ref_peak(a0, c, 0.0, 90.0, n=9001)
    assert peak <= 40000.0 * (1 + 1e-9)
    l0 = math.hypot(a0[0] - c[0], a0[1] - c[1])
    a90 = rotate(a0, math.pi / 2)
    l90 = math.hypot(a90[0] - c[0], a90[1] - c[1])
    closed, stroke = min(l0, l90), abs(l90 - l0)
    assert closed >= stroke + 300.0 - 1e-6
    assert cyl["min_length"] == pytest.approx(closed, rel=1e-12)
    assert sol.objective == pytest.approx(closed, rel=1e-12)
    # no design of a grid over the bounds is shorter within both limits
    x1, y1, x2 = np.meshgrid(np.linspace(0, 350, 36), np.linspace(320, 1380, 107),
                             np.linspace(400, 1400, 51), indexing="ij")
    shortest = np.inf
    for i in range(0, x1.size, 40000):
        p, ls, le = grid_peaks(x1.ravel()[i:i + 40000], y1.ravel()[i:i + 40000], x2.ravel()[i:i + 40000])
        cl = np.minimum(ls, le)
        ok = (p <= 40000.0) & (cl >= np.abs(le - ls) + 300.0)
        if ok.any():
            shortest = min(shortest, float(cl[ok].min()))
    assert closed <= shortest
    assert sol.status.value == "ok"


def test_cylinder_length_optimum_is_the_vertex_of_its_three_limits():
    """At the shortest cylinder the push at 0 deg and the pull at 90 deg both reach 40 kN and
    the dead length binds: three equations in (x1, y1, x2), solved here by fsolve on the
    reference statics (the bench reference of problems/bench/flipper_length.toml)."""
    from scipy.optimize import fsolve

    def length(a0, c, deg):
        a = rotate(a0, math.radians(deg))
        return math.hypot(a[0] - c[0], a[1] - c[1])

    def equations(v):
        a0, c = (v[0], v[1]), (v[2], 50.0)
        return [ref_force(a0, c, 0.0) / 40000 - 1, ref_force(a0, c, 90.0) / 40000 + 1,
                (2 * length(a0, c, 0.0) - length(a0, c, 90.0) - 300.0) / 1000]

    v = fsolve(equations, [300.0, 330.0, 1170.0], xtol=1e-13)
    closed = length((v[0], v[1]), (v[2], 50.0), 0.0)
    assert max(abs(e) for e in equations(v)) < 1e-10
    _, _, rep = report_of(SEED + "[cylinder]\ndead_length = 300\nmax_force = 40000\n"
                          '[objective]\nminimize = "cylinder-length"\n')
    cyl = rep["cylinder"]
    assert cyl["rod_pivot"] + [cyl["base_pivot"][0]] == pytest.approx(list(v), rel=1e-6)
    assert cyl["min_length"] == pytest.approx(closed, rel=1e-6)
    assert load("problems/bench/flipper_length.toml").meta.reference.objective == pytest.approx(closed, rel=1e-7)


def test_telescopic_note_without_dead_length():
    src = SEED + '[cylinder]\nmax_force = 40000\n[objective]\nminimize = "cylinder-length"\n'
    _, sol, rep = report_of(src)
    cyl = rep["cylinder"]
    if cyl["min_length"] < cyl["stroke"]:
        assert any("telescopic" in n for n in [render(n) for n in sol.notes])
    src_short = text("{ x = 350, y = 320 }", "{ x = 500, y = 50 }")
    _, sol2, rep2 = report_of(src_short)
    assert rep2["cylinder"]["min_length"] < rep2["cylinder"]["stroke"]
    assert any("only a telescopic cylinder fits" in n for n in [render(n) for n in sol2.notes])


@pytest.mark.parametrize("end", [180, 270, 360, 400])
def test_half_turn_or_more_is_bad_input(end):
    from linkcli.errors import InputError
    with pytest.raises(InputError, match="a sweep end - start below 180 deg"):
        load("x.toml", PAPER.replace("end = 90", f"end = {end}"))


def test_cylinder_length_without_dead_length_is_shorter_and_within_force():
    src = SEED + '[cylinder]\nmax_force = 40000\n[objective]\nminimize = "cylinder-length"\n'
    _, sol, rep = report_of(src)
    cyl = rep["cylinder"]
    peak, _, _ = ref_peak(tuple(cyl["rod_pivot"]), tuple(cyl["base_pivot"]), 0.0, 90.0, n=9001)
    assert peak <= 40000.0 * (1 + 1e-9)
    assert cyl["min_length"] <= 911.0908 * (1 + 1e-9)  # the dead length was binding


def test_force_limit_that_cannot_be_met_is_infeasible():
    src = SEED + "[cylinder]\nmax_force = 30000\n"
    _, sol, _ = report_of(src)
    assert sol.status.value == "infeasible"
    over = 34761.665 - 30000.0
    assert f"exceeds max_force 30000 N by {over:.6g} N" in render(sol.message)


def test_pareto_rows_trade_force_for_length():
    problem = load("problems/flipper_length.toml")
    rep = analyse(problem, solve(problem))
    rows = rep["pareto"]
    assert len(rows) == 6
    closed = [r["closed_length"] for r in rows]
    peaks = [r["peak_force"] for r in rows]
    assert closed == sorted(closed, reverse=True)
    assert all(b >= a * (1 - 1e-7) for a, b in zip(peaks, peaks[1:]))
    assert peaks[0] == pytest.approx(34761.665, rel=1e-6)
    assert peaks[-1] <= 40000.0 * (1 + 1e-9)
    for r in rows:
        peak, _, _ = ref_peak(tuple(r["rod_pivot"]), tuple(r["base_pivot"]), 0.0, 90.0, n=901)
        assert r["peak_force"] == pytest.approx(peak, rel=1e-6)
        assert r["max_length"] == pytest.approx(r["closed_length"] + r["stroke"], rel=1e-12)


def test_units_metres_give_the_same_design_scaled():
    src_m = (SEED.replace("[830.0, 500.0]", "[0.83, 0.5]")
             .replace("{ x = [0, 350], y = [320, 1380] }", "{ x = [0, 0.35], y = [0.32, 1.38] }")
             .replace("{ x = [400, 1400], y = 50 }", "{ x = [0.4, 1.4], y = 0.05 }"))
    src_m = src_m.replace("[load]", '[units]\nlength = "m"\n[load]', 1)
    _, _, mm = report_of(SEED)
    _, _, m = report_of(src_m)
    assert m["units"]["length"] == "m"
    for key in ("rod_pivot", "base_pivot"):
        assert np.array(m["cylinder"][key]) * 1000 == pytest.approx(np.array(mm["cylinder"][key]), rel=1e-6)
    assert m["cylinder"]["peak_force"] == pytest.approx(mm["cylinder"]["peak_force"], rel=1e-9)
    assert m["cylinder"]["stroke"] * 1000 == pytest.approx(mm["cylinder"]["stroke"], rel=1e-6)


def test_angles_in_radians():
    src = text("{ x = 350, y = 320 }", "{ x = 1400, y = 50 }", end=math.pi / 2,
               units='[units]\nangle = "rad"\n')
    _, _, rep = report_of(src)
    cyl = rep["cylinder"]
    assert cyl["peak_angle"] == 0.0 and cyl["pull_angle"] == pytest.approx(math.pi / 2, rel=1e-12)
    assert cyl["forces"][-1]["angle"] == pytest.approx(math.pi / 2, rel=1e-12)


# ----------------------------------------------------------------- budget, seed, sections
@pytest.mark.parametrize("budget", [1, 7, 50, 300])
def test_budget_is_respected(budget):
    _, sol, _ = report_of(SEED + f"[solver]\nbudget = {budget}\n")
    assert 1 <= sol.solver.evaluations <= budget
    assert sol.status.value in ("ok", "not-converged")


def test_same_seed_same_bytes_and_seeds_agree():
    code1, out1, _ = run_cli("synth", "problems/flipper.toml", "--format", "json")
    code2, out2, _ = run_cli("synth", "problems/flipper.toml", "--format", "json")
    assert code1 == code2 == 0 and out1 == out2
    code3, out3, _ = run_cli("synth", "problems/flipper.toml", "--format", "json", "--seed", "5")
    a, b = json.loads(out1), json.loads(out3)
    assert b["solver"]["seed"] == 5
    assert b["cylinder"]["peak_force"] == pytest.approx(a["cylinder"]["peak_force"], rel=1e-6)


def test_sections_not_asked_for_are_absent():
    _, sol, rep = report_of(PAPER + '[report]\nsections = ["solver"]\n')
    assert "cylinder" not in rep and "cylinder" not in sol.sections and "solver" in rep
    _, _, rep2 = report_of(PAPER + '[report]\nsections = ["cylinder"]\n')
    assert "cylinder" in rep2 and "solver" not in rep2


def test_table_step_and_table_output():
    _, _, rep = report_of(PAPER.replace("end = 90", "end = 90\ntable_step = 7.5"))
    angles = [r["angle"] for r in rep["cylinder"]["forces"]]
    assert angles == [0.0, 7.5, 15.0, 22.5, 30.0, 37.5, 45.0, 52.5, 60.0, 67.5, 75.0, 82.5, 90.0]
    code, out, _ = run_cli("synth", "problems/flipper_check.toml")
    assert code == 0 and "33815.2" in out and "pull" in out and "forces_full" in out
    assert out.count("\n") < 80  # the full-resolution table stays out of the table format


def test_bounds_containing_the_hinge_are_accepted():
    """The optimizer never picks a pivot at the hinge (its force is unbounded)."""
    src = text("{ x = [-200, 350], y = [-200, 1380] }", "{ x = [400, 1400], y = 50 }")
    _, sol, rep = report_of(src + "[solver]\nbudget = 1500\n")
    assert sol.status.value == "ok"
    assert math.hypot(*rep["cylinder"]["rod_pivot"]) > 100.0


def test_bad_input_exit_code_2(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text(PAPER.replace("mass = 2000.0", "mass = -1"))
    code, out, err = run_cli("synth", str(p))
    assert code == 2 and out == "" and "load.mass: expected a positive mass (kg), found -1" in err


# ------------------------------------------------- validation: harder cases (independent refs)
def np_peak(a0, c, start, end, mass=M, g=G, com=COM, n=4001):
    """(|F| max, signed F at it) over the sweep: a numpy scan of n angles with both ends, the
    largest sample then refined by scipy's bounded scalar search between its neighbours.
    Moment balance written with the unit vector e, test-local."""
    from scipy.optimize import minimize_scalar

    def force(t):
        ax, ay = a0[0] * np.cos(t) - a0[1] * np.sin(t), a0[0] * np.sin(t) + a0[1] * np.cos(t)
        gx = com[0] * np.cos(t) - com[1] * np.sin(t)
        length = np.hypot(ax - c[0], ay - c[1])
        lever = ax * (ay - c[1]) / length - ay * (ax - c[0]) / length  # (r_A x e)_z
        return mass * g * gx / lever

    sweep = math.radians(end - start)
    t = np.linspace(0.0, sweep, n)
    f = force(t)
    i = int(np.argmax(np.abs(f)))
    r = minimize_scalar(lambda x: -abs(float(force(np.array([x]))[0])),
                        bounds=(t[max(i - 1, 0)], t[min(i + 1, n - 1)]), method="bounded",
                        options={"xatol": 1e-12})
    return (abs(f[i]), f[i]) if abs(f[i]) >= -r.fun else (-r.fun, float(force(np.array([r.x]))[0]))


@pytest.mark.slow
@pytest.mark.parametrize("method", ["auto", "slsqp", "differential-evolution"])
def test_unreachable_force_limit_on_length_is_infeasible_by_the_least_excess(method):
    """max_force 30 kN is below the least peak force within the bounds (34,761.665 N, the
    bisection reference of test_seed_reference_and_balance): status infeasible (not
    not-converged), and the excess named is the least one, 4761.665 N."""
    lo, hi = 320.0, 400.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        h = ref_force((350, mid), (1400, 50), 0.0) + ref_force((350, mid), (1400, 50), 90.0)
        lo, hi = (mid, hi) if h > 0 else (lo, mid)
    least = ref_force((350, 0.5 * (lo + hi)), (1400, 50), 0.0)
    src = SEED + ('[cylinder]\nmax_force = 30000\ndead_length = 300\n[objective]\nminimize = "cylinder-length"\n'
                  f'[solver]\nmethod = "{method}"\n')
    _, sol, rep = report_of(src)
    assert sol.status.value == "infeasible"
    over = float(render(sol.message).split("exceeds max_force 30000 N by ")[1].split(" N")[0])
    assert over == pytest.approx(least - 30000.0, rel=1e-4)
    assert rep["cylinder"]["peak_force"] == pytest.approx(least, rel=1e-6)


@pytest.mark.slow
def test_impossible_dead_length_is_infeasible_with_the_least_shortfall():
    """closed >= stroke + 5000 mm cannot hold in the seed's bounds; the least shortfall
    (stroke + dead - closed) over a test-local grid of the bounds is at a corner."""
    x1, y1, x2 = np.meshgrid(np.linspace(0, 350, 36), np.linspace(320, 1380, 107),
                             np.linspace(400, 1400, 51), indexing="ij")
    _, ls, le = grid_peaks(x1.ravel(), y1.ravel(), x2.ravel(), degs=np.array([0.0, 90.0]))
    shortfall = float(np.min(np.abs(le - ls) + 5000.0 - np.minimum(ls, le)))
    for objective in ("", '[cylinder]\nmax_force = 1e8\n[objective]\nminimize = "cylinder-length"\n'):
        src = SEED + ("[cylinder]\ndead_length = 5000\n" if not objective else
                      objective.replace("[cylinder]\n", "[cylinder]\ndead_length = 5000\n"))
        _, sol, _ = report_of(src)
        assert sol.status.value == "infeasible"
        got = float(render(sol.message).split(" short of stroke")[0].split(" is ")[-1].split(" mm")[0])
        assert got == pytest.approx(shortfall, rel=1e-5)


@pytest.mark.slow
def test_every_design_crossing_the_hinge_is_infeasible():
    """Sweep 20..170 deg with the seed's bounds: theta_A - theta_C >= atan2(320, 350) -
    atan2(50, 400) = 35.3 deg > 180 - 150 deg, so every cylinder line meets the hinge."""
    assert math.degrees(math.atan2(320, 350) - math.atan2(50, 400)) > 180.0 - 150.0
    for method in ("auto", "slsqp"):
        _, sol, _ = report_of(SEED.replace("start = 0", "start = 20").replace("end = 90", "end = 170")
                              + f'[solver]\nmethod = "{method}"\n')
        assert sol.status.value == "infeasible" and "passes through the hinge" in render(sol.message)


def test_interior_peak_that_moves_with_the_design_converges():
    """A far centre of mass puts the peak inside the sweep, where it moves as the design
    changes (many exchange rounds). The result must be `ok` and no design of a test-local
    grid over the bounds (then refined along y1) is lower."""
    com = (50000.0, -20000.0)
    src = SEED.replace("[830.0, 500.0]", "[50000.0, -20000.0]")
    _, sol, rep = report_of(src)
    assert sol.status.value == "ok" and sol.solver.converged
    cyl = rep["cylinder"]
    peak, _ = np_peak(tuple(cyl["rod_pivot"]), tuple(cyl["base_pivot"]), 0.0, 90.0, com=com)
    assert cyl["peak_force"] == pytest.approx(peak, rel=1e-9)
    from scipy.optimize import minimize_scalar
    r = minimize_scalar(lambda y: np_peak((350.0, y), (1400.0, 50.0), 0.0, 90.0, com=com, n=721)[0],
                        bounds=(700.0, 950.0), method="bounded", options={"xatol": 1e-7})
    assert cyl["peak_force"] <= r.fun * (1 + 1e-7)


def test_the_better_of_two_close_local_minima_is_found():
    """Two local minima 3e-4 apart in value and a few per cent of the bounds apart: one
    with A_y on its upper bound, the other with C_y on its lower bound. Each is found here
    by a 1-D bounded search on the test-local peak; the solver must reach the lower."""
    from scipy.optimize import minimize_scalar
    load = dict(mass=631.159056370048, g=3.71, com=(-640.53, 1378.46))
    src = ('type = "flipper-cylinder"\n[load]\nmass = 631.159056370048\ncenter_of_mass = [-640.53, 1378.46]\n'
           "gravity = 3.71\n[motion]\nstart = -41\nend = 79\n[bounds]\n"
           "rod_pivot = { x = 233.979, y = [-372.525, 4.627] }\n"
           "base_pivot = { x = 1422.403, y = [-552.941, -192.436] }\n")

    def peak(ay, cy):
        return np_peak((233.979, ay), (1422.403, cy), -41.0, 79.0, n=1441, **load)[0]

    top = minimize_scalar(lambda cy: peak(4.627, cy), bounds=(-552.941, -400.0), method="bounded",
                          options={"xatol": 1e-8}).fun
    low = minimize_scalar(lambda ay: peak(ay, -552.941), bounds=(-20.0, 4.627), method="bounded",
                          options={"xatol": 1e-8}).fun
    assert low < top * (1 - 2e-4)  # the case really has two minima this close
    _, sol, rep = report_of(src)
    assert sol.status.value == "ok"
    assert rep["cylinder"]["peak_force"] <= low * (1 + 1e-7)


def test_pivots_that_would_meet_stay_apart_and_forces_stay_exact():
    """Without dead_length the least force may ask for a cylinder of no length (the pivots
    meet at one end of the sweep, where the force is 0/0). The design keeps the pivots
    apart (1e-6 of the largest bound), says so in a note, and every force and pressure it
    reports matches an independent evaluation."""
    src = text("{ x = [-300, 300], y = [-300, 300] }", "{ x = [-300, 300], y = [-300, 300] }",
               end=120, cylinder="[cylinder]\nbore = 80\nrod = 45\n")
    _, sol, rep = report_of(src)
    cyl = rep["cylinder"]
    assert sol.status.value == "ok"
    assert cyl["min_length"] >= 300 * 1e-6
    assert any("all but meet" in n for n in [render(n) for n in sol.notes])
    a0, c = tuple(cyl["rod_pivot"]), tuple(cyl["base_pivot"])
    peak, _ = np_peak(a0, c, 0.0, 120.0)
    assert cyl["peak_force"] == pytest.approx(peak, rel=1e-7)
    for r in cyl["forces"]:
        assert r["force"] == pytest.approx(ref_force(a0, c, r["angle"]), rel=1e-7)
    t = np.linspace(0, 120, 20001)
    f = np.array([ref_force(a0, c, x) for x in t])
    assert cyl["push_pressure"] == pytest.approx(max(f.max(), 0) / (math.pi / 4 * 80 ** 2), rel=1e-6)
    assert cyl["pull_pressure"] == pytest.approx(max(-f.min(), 0) / (math.pi / 4 * (80 ** 2 - 45 ** 2)), rel=1e-6)


def test_evaluated_pivots_that_meet_are_infeasible():
    """C = R(90 deg) A: the rod pivot reaches the base pivot at the end of the sweep."""
    _, sol, rep = report_of(text("{ x = 300, y = 0 }", "{ x = 0, y = 300 }"))
    assert sol.status.value == "infeasible" and "base pivot" in render(sol.message) and "90 deg" in render(sol.message)
    code, _, err = run_cli("synth", "problems/flipper_check.toml")
    assert code == 0 and "Traceback" not in err


def test_inches_evaluated_design_against_hand_computation():
    """A gate in inches, -10..80 deg: forces at every table row by the moment balance and the
    pressures with the areas in mm^2 (1 in = 25.4 mm), all computed here."""
    a0, c, com, m, g = (5.0, 8.0), (15.0, -3.0), (20.0, 10.0), 300.0, 9.81
    src = ('type = "flipper-cylinder"\n[units]\nlength = "in"\n[load]\nmass = 300\n'
           "center_of_mass = [20, 10]\ngravity = 9.81\n[motion]\nstart = -10\nend = 80\n[bounds]\n"
           "rod_pivot = { x = 5, y = 8 }\nbase_pivot = { x = 15, y = -3 }\n[cylinder]\nbore = 2.5\nrod = 1.25\n")
    _, sol, rep = report_of(src)
    cyl = rep["cylinder"]
    for r in cyl["forces"] + cyl["forces_full"]:
        assert r["force"] == pytest.approx(ref_force(a0, c, r["angle"], start=-10.0, mass=m, g=g, com=com), rel=1e-10)
    f = [ref_force(a0, c, -10 + 90 * i / 40000, start=-10.0, mass=m, g=g, com=com) for i in range(40001)]
    bore, annulus = math.pi / 4 * (2.5 * 25.4) ** 2, math.pi / 4 * ((2.5 * 25.4) ** 2 - (1.25 * 25.4) ** 2)
    assert cyl["push_pressure"] == pytest.approx(max(f) / bore, rel=1e-6)
    assert cyl["pull_pressure"] == pytest.approx(-min(f) / annulus, rel=1e-6)
    assert cyl["peak_kind"] == "pull" and cyl["peak_force"] == pytest.approx(-min(f), rel=1e-6)


FREE4 = text("{ x = [-100, 400], y = [200, 900] }", "{ x = [300, 1500], y = [-300, 100] }", start=-30, end=60,
             com=(600.0, -250.0), cylinder="[cylinder]\ndead_length = 150\nmax_force = 60000\n")


@pytest.mark.slow
def test_same_design_in_inches_and_radians():
    """Four free coordinates and an interior optimum: mm/deg and in/rad give the same design."""
    src = FREE4 + '[objective]\nminimize = "cylinder-length"\n'
    _, _, mm = report_of(src)
    k = 1 / 25.4
    src_in = (text(f"{{ x = [{-100 * k!r}, {400 * k!r}], y = [{200 * k!r}, {900 * k!r}] }}",
                   f"{{ x = [{300 * k!r}, {1500 * k!r}], y = [{-300 * k!r}, {100 * k!r}] }}",
                   start=math.radians(-30), end=math.radians(60), com=(600.0 * k, -250.0 * k),
                   units='[units]\nlength = "in"\nangle = "rad"\n',
                   cylinder=f"[cylinder]\ndead_length = {150 * k!r}\nmax_force = 60000\n")
              + '[objective]\nminimize = "cylinder-length"\n')
    _, _, inch = report_of(src_in)
    for key in ("rod_pivot", "base_pivot"):
        got, want = np.array(inch["cylinder"][key]) * 25.4, np.array(mm["cylinder"][key])
        assert got == pytest.approx(want, rel=1e-6, abs=1e-6)
    assert inch["cylinder"]["peak_force"] == pytest.approx(mm["cylinder"]["peak_force"], rel=1e-6)
    assert inch["cylinder"]["min_length"] * 25.4 == pytest.approx(mm["cylinder"]["min_length"], rel=1e-6)
    assert math.degrees(inch["cylinder"]["peak_angle"]) == pytest.approx(mm["cylinder"]["peak_angle"], abs=1e-4)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["auto", "differential-evolution", "slsqp"])
def test_small_budgets_every_method_and_seed(method):
    """Budgets 1, 10, 100 (with the trade-off table, which takes its share): no crash, the
    budget is a hard cap, a design is always judged, and the same seed gives the same bytes."""
    import tempfile
    from pathlib import Path
    for budget in (1, 10, 100):
        for seed in (0, 3):
            src = FREE4 + f'[objective]\npareto = 3\n[solver]\nmethod = "{method}"\nbudget = {budget}\nseed = {seed}\n'
            _, sol, rep = report_of(src)
            assert 1 <= sol.solver.evaluations <= budget
            assert sol.status.value in ("ok", "not-converged", "infeasible")
            assert "cylinder" in rep and rep["cylinder"]["rod_pivot"] is not None
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "f.toml"
        p.write_text(FREE4 + f'[objective]\npareto = 3\n[solver]\nmethod = "{method}"\nbudget = 100\n')
        outs = [run_cli("synth", str(p), "--format", "json", "--seed", "4") for _ in range(2)]
        assert outs[0] == outs[1] and outs[0][0] in (0, 1)


# ------------------------------------- the cylinder line through the hinge (adversarial probe)
CROSS = text("{ x = 500, y = 0 }", "{ x = 700, y = 700 }", cylinder="[cylinder]\nbore = 80\n")


def dense_lengths(a0, c, start, end, n=90001):
    """(least, largest) |A(t) - C| over the sweep by a per-angle scan, math module."""
    ls = []
    for i in range(n):
        a = rotate(a0, math.radians((end - start) * i / (n - 1)))
        ls.append(math.hypot(a[0] - c[0], a[1] - c[1]))
    return min(ls), max(ls)


def test_line_through_the_hinge_true_lengths_and_no_garbage(tmp_path):
    """A = (500, 0), C = (700, 700): C x A(t) = 0 at t = 45 deg, inside the sweep, where the
    load moment m g G_x(45 deg) = m g (830 - 500) cos 45 is not zero: no finite force holds
    the platform there. The length turns back at the crossing (d(L^2)/dt = 2 C x A), so the
    closed length is |C| - |A| there, not an end value."""
    p = tmp_path / "cross.toml"
    p.write_text(CROSS)
    code, out, err = run_cli("synth", str(p), "--format", "json", "--precision", "15")
    assert code == 1 and "Traceback" not in err and "Warning" not in err
    assert "NaN" not in out and "Infinity" not in out
    rep = json.loads(out)
    assert rep["status"] == "infeasible"
    assert "passes through the hinge B at platform angle 45 deg" in rep["message"]
    moment = M * G * (830 - 500) * math.cos(math.radians(45))
    shown = float(rep["message"].split("moment of ")[1].split(" N mm")[0])  # at --precision 15
    assert shown == pytest.approx(moment, rel=1e-12)
    cyl = rep["cylinder"]
    lo, hi = dense_lengths((500, 0), (700, 700), 0, 90)
    assert cyl["min_length"] == pytest.approx(math.hypot(700, 700) - 500, rel=1e-6)
    assert cyl["min_length"] == pytest.approx(lo, rel=1e-6)
    assert cyl["max_length"] == pytest.approx(hi, rel=1e-6)
    assert cyl["stroke"] == pytest.approx(hi - lo, rel=1e-5)
    assert cyl["rod_motion"] == "retracts, then extends"
    assert cyl["peak_force"] is None and cyl["peak_kind"] == "unbounded"
    assert cyl["push_force"] is None and cyl["pull_force"] is None and cyl["push_pressure"] is None
    for r in cyl["forces"] + cyl["forces_full"]:
        if r["angle"] == 45.0:
            assert r["force"] is None and r["arm"] == 0.0
        else:
            assert r["force"] == pytest.approx(ref_force((500, 0), (700, 700), r["angle"]), rel=1e-5)
    code, out, _ = run_cli("synth", str(p))
    assert code == 1 and "e+19" not in out and "e-14" not in out


def test_crossing_at_an_end_is_unbounded_on_one_side_only():
    """C = (-500, 0), A = (300, 0): C x A = 0 at the start and the force runs to -infinity
    (a pull) just after it; the largest push stays finite, 1902.44 N at 60 deg."""
    _, sol, rep = report_of(text("{ x = 300, y = 0 }", "{ x = -500, y = 0 }", end=60))
    cyl = rep["cylinder"]
    assert sol.status.value == "infeasible" and "platform angle 0 deg" in render(sol.message)
    assert cyl["pull_force"] == math.inf and cyl["pull_angle"] == 0.0
    pushes = [ref_force((300, 0), (-500, 0), 60 * i / 6000) for i in range(1, 6001)]
    assert cyl["push_force"] == pytest.approx(max(pushes), rel=1e-9)
    assert cyl["forces"][0]["force"] is None
    assert cyl["forces"][1]["force"] == pytest.approx(ref_force((300, 0), (-500, 0), 5.0), rel=1e-9)


def test_crossing_where_the_load_has_no_moment_is_finite():
    """G = (500, 0), A = (300, 0), C = (0, -500): at 90 deg the cylinder line and the centre
    of mass are both over the hinge. W = m g 500 cos t and C x A = 150000 cos t, so
    F = m g L / 300 exactly (a push) and the peak is at the longest cylinder, L = 800 at 90 deg."""
    com = (500.0, 0.0)
    _, sol, rep = report_of(text("{ x = 300, y = 0 }", "{ x = 0, y = -500 }", end=120, com=com))
    cyl = rep["cylinder"]
    assert sol.status.value == "ok"
    assert cyl["peak_force"] == pytest.approx(M * G * 800 / 300, rel=1e-12) and cyl["peak_kind"] == "push"
    assert cyl["peak_angle"] == pytest.approx(90.0, abs=1e-4)
    lo, hi = dense_lengths((300, 0), (0, -500), 0, 120)
    assert (cyl["min_length"], cyl["max_length"]) == pytest.approx((lo, hi), rel=1e-9)
    assert cyl["rod_motion"] == "extends, then retracts"
    for r in cyl["forces_full"]:
        if abs(r["angle"] - 90.0) > 1e-9:
            assert r["force"] == pytest.approx(ref_force((300, 0), (0, -500), r["angle"], com=com), rel=1e-9)
        else:
            assert r["force"] == pytest.approx(M * G * 800 / 300, rel=1e-12)


def test_optimizer_never_picks_a_line_through_the_hinge():
    """Bounds where many designs cross the hinge (A_y from -300, C_y from 0): the result is
    ok and its line keeps clear of the hinge on a dense per-angle scan."""
    src = text("{ x = 500, y = [-300, 300] }", "{ x = [600, 900], y = [0, 700] }")
    _, sol, rep = report_of(src + "[solver]\nbudget = 1500\n")
    cyl = rep["cylinder"]
    assert sol.status.value in ("ok", "not-converged")
    a0, c = tuple(cyl["rod_pivot"]), tuple(cyl["base_pivot"])
    ks = []
    for i in range(9001):
        a = rotate(a0, math.radians(90 * i / 9000))
        ks.append(c[0] * a[1] - c[1] * a[0])
    assert min(ks) > 0 or max(ks) < 0
    peak, _, _ = ref_peak(a0, c, 0.0, 90.0, n=9001)
    assert cyl["peak_force"] == pytest.approx(peak, rel=1e-4)


def test_no_numpy_warning_with_pivot_boxes_that_meet(tmp_path):
    """Both pivots in [0, 350]^2: the search meets designs with A = C = B (every force 0/0).
    No warning on stderr, and the result's forces are real (independent statics)."""
    src = open("problems/flipper.toml").read()
    src = (src.replace("{ x = [0, 350], y = [320, 1380] }", "{ x = [0, 350], y = [0, 350] }")
           .replace("{ x = [400, 1400], y = 50 }", "{ x = [0, 350], y = [0, 350] }"))
    src = "\n".join(line for line in src.splitlines()
                    if not line.startswith(("bore", "rod =", "dead_length", "max_force", "[cylinder]")))
    p = tmp_path / "meet.toml"
    p.write_text(src)
    code, out, err = run_cli("synth", str(p), "--format", "json", "--precision", "17")
    assert "Warning" not in err and "Traceback" not in err and err == ""
    assert code == 0
    rep = json.loads(out)
    cyl = rep["cylinder"]
    a0, c = tuple(cyl["rod_pivot"]), tuple(cyl["base_pivot"])
    assert math.hypot(a0[0] - c[0], a0[1] - c[1]) >= 350 * 1e-6 * (1 - 1e-6) and math.hypot(*a0) > 0
    assert any("all but meet" in n for n in rep.get("notes", [])) or "all but meet" in out
    peak, _, _ = ref_peak(a0, c, 0.0, 90.0, n=9001)
    assert cyl["peak_force"] == pytest.approx(peak, rel=1e-4)


def test_nan_peak_counts_as_infeasible_in_the_search():
    """A design whose force is nan at some angle (A = C = B: 0/0) must be the worst, never
    look feasible under a force cap (max(0, nan - cap) would be 0)."""
    import warnings

    from linkcli.search.budget import Budget
    from linkcli.types.flipper_cylinder.search import FEASIBLE, Goal, Judge, Space, _excess, _grid_peak
    assert _grid_peak(np.array([[1.0, np.nan, 2.0]]))[0] == math.inf
    assert _excess(np.array([np.nan]), 1000.0)[0] > 1.0
    problem = load("x.toml", text("{ x = [0, 350], y = [0, 350] }", "{ x = [0, 350], y = [0, 350] }",
                                  cylinder="[cylinder]\nmax_force = 1e9\n"))
    st = Statics(M * G, COM, math.pi / 2)
    judge = Judge(problem, st, Space(problem), Budget(10))
    designs = np.array([[0.0, 0.0, 0.0, 0.0], [350.0, 320.0, 0.0, 0.0], [300.0, 300.0, 300.0, 300.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for goal in (Goal("peak"), Goal("length", force_cap=1e9)):
            obj, viol, _ = judge.assess(designs, goal)
            assert np.all(viol > FEASIBLE)
            if goal.kind == "peak":
                assert np.all(obj == math.inf)


def test_centre_of_mass_at_the_hinge_is_bad_input(tmp_path):
    p = tmp_path / "com.toml"
    p.write_text(PAPER.replace("center_of_mass = [830.0, 500.0]", "center_of_mass = [0, 0]"))
    code, out, err = run_cli("synth", str(p))
    assert code == 2 and out == ""
    assert err.strip() == (f"{p}:4: load.center_of_mass: expected a centre of mass off the hinge B = (0, 0) "
                           "(at the hinge the load has no moment: no force is needed and every design is "
                           "equally good), found [0, 0]")
