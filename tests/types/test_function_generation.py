"""Function generation by optimization against independent references.

References written here, not taken from linkcli:
- the output angle by circle-circle intersection for the joint B, the branch picked by
  the sign of a cross product (docs/format.md: open puts B clockwise of B0 -> A, seen from B0);
- the extended dead-centre from the triangle A0 B0 B with |A0 B| = input + coupler (law
  of cosines), the side of the ground line picked by the same cross product;
- the seed's objective as a plain sum over the points with the math module;
- the exact constrained optimum of the seed problem (31 points, mu <= 135 deg active):
  coupler 412.865, output 232.246, f = 0.0075924 (issue 3);
- target laws generated from a known linkage (optimum zero, the linkage recovered);
- the three-point Chebyshev design of Freudenstein's equation (the precision-position
  solver fed the three Chebyshev points), its error measured densely with the math module;
- Freudenstein's equation solved in the test (numpy least squares, three points or all),
  its designs checked for assembly, branch, bounds and transmission with the math module:
  at given start angles, and over a 24 x 24 grid of start angles for free ones (the
  optimizer must never be worse than a feasible classical design);
- random linkages written as laws (their output angle by the half-angle form of atan2),
  recovered exactly in their own Grashof class whichever link is fixed.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import tomli_w
from conftest import run_cli

from linkcli.errors import InputError
from linkcli.expr import ExpressionError, compile_expression
from linkcli.pipeline import solve
from linkcli.reading.load import load

CRANK_ROCKER = "problems/crank_rocker.toml"
LOG_GENERATOR = "problems/log_generator.toml"
DEG = math.pi / 180


# ---------------------------------------------------------------- the references

def ref_joint_b(a, b, c, d, phi, branch):
    """B from the circles (A, b) and (B0, c); None if they do not meet."""
    ax, ay = a * math.cos(phi), a * math.sin(phi)
    dx, dy = d - ax, -ay
    r = math.hypot(dx, dy)
    along = (b * b - c * c + r * r) / (2 * r)
    if b * b - along * along < 0:
        return None
    h = math.sqrt(b * b - along * along)
    mx, my = ax + along * dx / r, ay + along * dy / r
    for sgn in (1, -1):
        bx, by = mx + sgn * h * (-dy) / r, my + sgn * h * dx / r
        cross = (ax - d) * by - ay * (bx - d)  # (A - B0) x (B - B0)
        if (cross < 0) == (branch == "open"):
            return bx, by
    return None


def ref_psi(a, b, c, d, phi, branch):
    bx, by = ref_joint_b(a, b, c, d, phi, branch)
    return math.atan2(by, bx - d)


def ref_extended(a, b, c, d, branch):
    """(phi0, psi0) where crank and coupler are collinear and extended, on the branch."""
    ab = a + b
    g = math.acos((ab * ab + d * d - c * c) / (2 * ab * d))
    for phi0 in (g, -g):
        bx, by = ab * math.cos(phi0), ab * math.sin(phi0)
        cross = (a * math.cos(phi0) - d) * by - a * math.sin(phi0) * (bx - d)
        if (cross < 0) == (branch == "open"):
            return phi0, math.atan2(by, bx - d)
    raise AssertionError("no extended position on the branch")


def wrap(x):
    return (x + math.pi) % (2 * math.pi) - math.pi


def ref_seed_objective(b, c, a=100.0, d=500.0, points=31, sweep=math.pi / 2, branch="open"):
    phi0, psi0 = ref_extended(a, b, c, d, branch)
    total = 0.0
    for k in range(points):
        phi = phi0 + k / (points - 1) * sweep
        target = psi0 + 2 / (3 * math.pi) * (phi - phi0) ** 2
        total += wrap(ref_psi(a, b, c, d, phi, branch) - target) ** 2
    return total


def ref_transmission_full_turn(a, b, c, d):
    """(mu_min, mu_max) of a crank over its full turn, rho = d - a and d + a (deg)."""
    mu = [math.degrees(math.acos((b * b + c * c - r * r) / (2 * b * c))) for r in (d - a, d + a)]
    return min(mu), max(mu)


def law_of(a, b, c, d, var="phi", branch="open"):
    """psi(var) of a linkage with a < d (A0 A points left of B0: A - B0 has x < 0) as an
    expression of the whitelist: theta_rho = pi + atan(ry / rx), psi = theta_rho -+ alpha."""
    rho2 = f"({a * a + d * d} - {2 * a * d}*cos({var}))"
    alpha = f"acos(({rho2} + {c * c - b * b})/({2 * c}*sqrt({rho2})))"
    sign = "-" if branch == "open" else "+"
    return f"pi + atan({a}*sin({var})/({a}*cos({var}) - {d})) {sign} {alpha}"


def write(tmp_path, data, name="fg.toml"):
    path = tmp_path / name
    path.write_text(tomli_w.dumps(data))
    return str(path)


def solved(path, **solver):
    problem = load(path)
    if solver:
        from dataclasses import replace
        problem = replace(problem, meta=replace(problem.meta, solver=replace(problem.meta.solver, **solver)))
    return problem, solve(problem)


# ---------------------------------------------------------------- the seed problem

def test_reference_optimum_is_what_the_issue_says():
    # the reference implementation itself, at the published optimum: f = 0.0075924 with
    # the 135 deg limit active (within the 3 decimals printed)
    assert ref_seed_objective(412.865, 232.246) == pytest.approx(0.0075924, abs=1e-7)
    assert ref_transmission_full_turn(100, 412.865, 232.246, 500)[1] == pytest.approx(135.0, abs=1e-3)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(10))
def test_crank_rocker_reaches_the_constrained_optimum_from_every_seed(seed):
    _, sol = solved(CRANK_ROCKER, seed=seed)
    fb = sol.linkage
    assert sol.status.value == "ok", sol.message
    assert sol.objective <= 0.007593
    assert (fb.coupler, fb.output) == pytest.approx((412.865, 232.246), abs=0.01)
    assert (fb.input, fb.ground, fb.branch) == (100.0, 500.0, "open")
    mu_min, mu_max = ref_transmission_full_turn(fb.input, fb.coupler, fb.output, fb.ground)
    assert 45.0 <= mu_min and mu_max <= 135.0 + 1e-5
    # crank-rocker by the three inequalities (input shortest, Grashof)
    a, b, c, d = fb.input, fb.coupler, fb.output, fb.ground
    assert a + b < c + d and a + c < b + d and a + d < b + c
    # the reported objective is the independent one at the reported lengths
    assert sol.objective == pytest.approx(ref_seed_objective(b, c), rel=1e-9)
    assert sol.solver.evaluations <= 8000 and sol.solver.converged


def test_positions_and_extended_start_match_the_reference():
    problem, sol = solved(CRANK_ROCKER)
    fb = sol.linkage
    a, b, c, d = fb.input, fb.coupler, fb.output, fb.ground
    phi0, psi0 = ref_extended(a, b, c, d, "open")
    pos = sol.positions
    assert len(pos.input) == 31
    assert pos.input[0] == pytest.approx(phi0, abs=1e-12)
    assert pos.input[-1] - pos.input[0] == pytest.approx(math.pi / 2, abs=1e-12)
    for k in range(31):
        phi = pos.input[k]
        target = psi0 + 2 / (3 * math.pi) * (phi - phi0) ** 2
        assert wrap(pos.target[k] - target) == pytest.approx(0.0, abs=1e-12)
        assert wrap(pos.achieved[k] - ref_psi(a, b, c, d, phi, "open")) == pytest.approx(0.0, abs=1e-10)
    assert abs(pos.error[0]) < 1e-12  # the law starts where the linkage is
    assert sol.working_span == pytest.approx((phi0, math.pi / 2))


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_model_objective_matches_the_reference_at_random_linkages(branch):
    from linkcli.types.function_generation.model import BRANCH_SIGN, Model
    model = Model(load(CRANK_ROCKER))
    rng = np.random.default_rng(7)
    values = np.column_stack([rng.uniform(300, 600, 60), rng.uniform(150, 400, 60)])  # coupler, output
    b_, c_ = values.T
    values = values[(b_ + c_ > 600) & (b_ < c_ + 400)][:20]  # crank-rockers: they assemble everywhere
    batch = model.evaluate(values, BRANCH_SIGN[branch])
    assert len(values) == 20 and np.all(batch.violation[:, 0] == 0)  # travel
    for (b, c), f in zip(values, batch.f):
        assert f == pytest.approx(ref_seed_objective(b, c, branch=branch), rel=1e-9, abs=1e-12)


def test_report_sections(tmp_path):
    code, out, err = run_cli("synth", CRANK_ROCKER, "--format", "json")
    assert code == 0, err
    rep = json.loads(out)
    assert rep["grashof"]["class"] == "crank-rocker"
    assert rep["transmission"]["max"] == pytest.approx(135.0, abs=1e-4)
    assert rep["transmission"]["min"] >= 45.0
    assert rep["error"]["objective"] == pytest.approx(0.0075924, abs=1e-7)
    rows = rep["positions"]
    errors = [r["error"] for r in rows]
    assert rep["error"]["max"] == pytest.approx(max(abs(e) for e in errors), rel=1e-5)
    assert rep["error"]["rms"] == pytest.approx(math.sqrt(sum(e * e for e in errors) / len(errors)), rel=1e-5)
    # objective (rad^2) and the errors (deg) tell the same story
    assert rep["error"]["objective"] == pytest.approx(sum((e * DEG) ** 2 for e in errors), rel=1e-4)
    se = rep["structural_error"]
    assert se["max"] >= rep["error"]["max"] - 1e-9 and len(se["curve"]) > 10
    assert rep["target"]["input_start"] == pytest.approx(rows[0]["input"])
    assert set(rep["solver"]) >= {"method", "seed", "evaluations", "converged"}
    assert rep["motion"]["input_full_turn"] is True


@pytest.mark.slow
def test_same_seed_gives_the_same_bytes():
    outs = [run_cli("synth", CRANK_ROCKER, "--format", "json", "--seed", "4")[1] for _ in range(2)]
    assert outs[0] == outs[1]
    outs = [run_cli("synth", LOG_GENERATOR, "--format", "json", "--seed", "2")[1] for _ in range(2)]
    assert outs[0] == outs[1]


@pytest.mark.parametrize("method", ["auto", "slsqp", "differential-evolution", "dual-annealing"])
@pytest.mark.parametrize("budget", [1, 7, 50, 300])
def test_budget_caps_the_evaluations(method, budget):
    _, sol = solved(CRANK_ROCKER, method=method, budget=budget, seed=1)
    assert 1 <= sol.solver.evaluations <= budget
    assert sol.status.value in ("ok", "infeasible", "not-converged")
    assert sol.linkage is not None and math.isfinite(sol.objective)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["slsqp", "differential-evolution", "dual-annealing"])
def test_a_spent_budget_is_not_converged(method):
    # 60 evaluations do not settle these searches (differential evolution once reported
    # scipy's (success, x) tuple, always true); with 200 `auto` reaches the optimum, but
    # not from two independent batches of starts: it does not claim it is the optimum
    # (found twice) until its default budget
    _, sol = solved(CRANK_ROCKER, method=method, budget=60, seed=0)
    assert sol.solver.converged is False and sol.status.value == "not-converged"
    _, sol = solved(CRANK_ROCKER, method="auto", budget=60, seed=0)
    assert sol.status.value == "not-converged"
    _, sol = solved(CRANK_ROCKER, method="auto", budget=200, seed=0)
    assert sol.objective == pytest.approx(ref_seed_objective(sol.linkage.coupler, sol.linkage.output), rel=1e-9)
    assert sol.objective <= 0.0075923737  # the constrained optimum (test above)
    assert sol.status.value == "not-converged" and "no second local search ended at it" in sol.message
    _, sol = solved(CRANK_ROCKER, method="auto", seed=0)
    assert sol.solver.converged is True and sol.status.value == "ok" and sol.objective <= 0.0075925


@pytest.mark.parametrize("method", ["slsqp", "differential-evolution"])
def test_other_methods_reach_the_optimum(method):
    _, sol = solved(CRANK_ROCKER, method=method)
    assert sol.status.value == "ok" and sol.objective <= 0.0075925


def test_a_fixed_design_is_evaluated_and_its_violation_named(tmp_path):
    # the published lengths rounded to 3 decimals exceed the 135 deg limit slightly
    data = {"type": "function-generation",
            "linkage": {"input": 100, "ground": 500, "coupler": 412.865, "output": 232.246},
            "target": {"output": "psi0 + 2/(3*pi)*(phi - phi0)**2", "start": "extended", "input_sweep": 90},
            "constraints": {"transmission": [45, 135], "grashof": "crank-rocker"}}
    path = write(tmp_path, data)
    code, out, err = run_cli("synth", path, "--format", "json")
    rep = json.loads(out)
    assert code == 1 and rep["status"] == "infeasible"
    excess = ref_transmission_full_turn(100, 412.865, 232.246, 500)[1] - 135
    assert "transmission" in rep["message"] and "above the maximum 135" in rep["message"]
    assert f"{excess:.6g} deg" in rep["message"]
    assert rep["error"]["objective"] == pytest.approx(ref_seed_objective(412.865, 232.246), rel=1e-6)


# ---------------------------------------------------------------- known linkages: optimum zero

KNOWN = (30.0, 80.0, 60.0, 70.0)  # a, b, c, d: a crank-rocker with a < d


@pytest.mark.parametrize("branch,start,sweep,units", [
    ("open", 40.0, 100.0, "deg"),
    ("crossed", -140.0, 120.0, "deg"),
    ("open", 2.5, -1.5, "rad"),  # clockwise, in radians
])
@pytest.mark.slow
def test_output_law_of_a_known_linkage_is_recovered(tmp_path, branch, start, sweep, units):
    a, b, c, d = KNOWN
    data = {"type": "function-generation", "units": {"angle": units},
            "linkage": {"ground": d},
            "target": {"output": law_of(a, b, c, d, branch=branch), "input_start": start,
                       "input_sweep": sweep, "points": 25},
            "bounds": {"input": [10, 200], "coupler": [10, 200], "output": [10, 200]}}
    _, sol = solved(write(tmp_path, data))
    fb = sol.linkage
    assert sol.status.value == "ok", sol.message
    assert fb.branch == branch
    assert (fb.input, fb.coupler, fb.output) == pytest.approx((a, b, c), rel=1e-5)
    assert sol.objective < 1e-12
    # the positions run the way the sweep says, clockwise when negative
    steps = np.diff(sol.positions.input)
    assert np.all(np.sign(steps) == np.sign(sweep))


def test_function_form_of_a_known_linkage_is_recovered_with_free_starts(tmp_path):
    # y = psi(x) with x the input angle itself: the law maps onto the sweeps exactly when
    # input_start = x0 and output_start = psi(x0), which the solver must find
    a, b, c, d = KNOWN
    x0, x1 = 30 * DEG, 150 * DEG
    psi0, psi1 = ref_psi(a, b, c, d, x0, "open"), ref_psi(a, b, c, d, x1, "open")
    data = {"type": "function-generation", "linkage": {"ground": d},
            "target": {"function": law_of(a, b, c, d, var="x"), "x": [x0, x1], "input_sweep": 120.0,
                       "output_sweep": math.degrees(psi1 - psi0), "spacing": "chebyshev", "points": 15},
            "bounds": {"input": [10, 200], "coupler": [10, 200], "output": [10, 200],
                       "input_start": [0, 60], "output_start": [-180, 180]},
            "constraints": {"branch": "either"}}
    problem, sol = solved(write(tmp_path, data))
    fb = sol.linkage
    assert sol.status.value == "ok", sol.message
    assert fb.branch == "open"
    assert (fb.input, fb.coupler, fb.output) == pytest.approx((a, b, c), rel=1e-5)
    assert sol.objective < 1e-12
    assert sol.sections["target"]["input_start"] == pytest.approx(30.0, abs=1e-4)
    assert sol.sections["target"]["output_start"] == pytest.approx(math.degrees(psi0), abs=1e-4)
    # Chebyshev nodes: ends excluded, x_k = mid - half cos((2k - 1) pi / 2n)
    n = 15
    nodes = [30 + 60 * (1 - math.cos((2 * k - 1) * math.pi / (2 * n))) for k in range(1, n + 1)]
    assert np.degrees(sol.positions.input) == pytest.approx(nodes, abs=1e-4)


@pytest.mark.slow
def test_scale_and_units_do_not_change_the_shape(tmp_path):
    data = json.loads(run_cli("synth", CRANK_ROCKER, "--format", "json")[1])
    text = open(CRANK_ROCKER).read()
    text = text.replace("input = 100", "input = 0.1").replace("ground = 500", "ground = 0.5")
    text = text.replace("[100, 1000]", "[0.1, 1.0]").replace("input_sweep = 90 ", "input_sweep = 1.5707963267948966 ")
    text = text.replace("transmission = [45, 135]", "transmission = [0.7853981633974483, 2.356194490192345]")
    text = text.replace("[reference]", '[units]\nlength = "m"\nangle = "rad"\n[reference]')
    path = tmp_path / "metres.toml"
    path.write_text(text)
    rep = json.loads(run_cli("synth", str(path), "--format", "json")[1])
    assert rep["linkage"]["coupler"] == pytest.approx(data["linkage"]["coupler"] / 1000, rel=1e-5)
    assert rep["linkage"]["output"] == pytest.approx(data["linkage"]["output"] / 1000, rel=1e-5)
    assert rep["error"]["objective"] == pytest.approx(data["error"]["objective"], rel=1e-5)


# ---------------------------------------------------------------- log10 against Freudenstein

def dense_max_error(a, b, c, d, branch, phi_start, psi_start, flip_a=False, flip_c=False):
    """Largest |psi - target| (deg) over x in [1, 2] (2001 points), math module only."""
    worst = 0.0
    for k in range(2001):
        x = 1 + k / 2000
        phi = phi_start + (x - 1) * 60 * DEG
        target = psi_start + math.log10(x) / math.log10(2) * 90 * DEG
        psi = ref_psi(a, b, c, d, phi + (math.pi if flip_a else 0.0), branch) - (math.pi if flip_c else 0.0)
        worst = max(worst, abs(math.degrees(wrap(psi - target))))
    return worst


@pytest.fixture(scope="module")
def log_result():
    return solved(LOG_GENERATOR)


@pytest.mark.slow
def test_log_generator_beats_the_three_point_chebyshev_design(log_result):
    problem, sol = log_result
    assert sol.status.value == "ok", sol.message
    fb = sol.linkage
    phi_s = math.radians(sol.sections["target"]["input_start"])
    psi_s = math.radians(sol.sections["target"]["output_start"])
    optimized = dense_max_error(fb.input, fb.coupler, fb.output, fb.ground, fb.branch, phi_s, psi_s)
    # the report's structural error is the same figure
    assert sol.sections["structural_error"]["max"] == pytest.approx(optimized, rel=2e-3)
    # Freudenstein through the three Chebyshev points, same start angles and sweeps
    xs = [1.5 - 0.5 * math.cos((2 * j - 1) * math.pi / 6) for j in (1, 2, 3)]
    phi = [math.degrees(phi_s) + 60 * (x - 1) for x in xs]
    psi = [math.degrees(psi_s) + 90 * math.log10(x) / math.log10(2) for x in xs]
    text = (f'type = "precision-position"\n[linkage]\nground = {fb.ground}\n[positions]\n'
            f"input = {phi}\noutput = {psi}\n")
    free = solve(load("chebyshev.toml", text))
    fl = free.linkage
    flip_a = any("K1 < 0" in n for n in free.notes)
    flip_c = any("K2 < 0" in n for n in free.notes)
    chebyshev = dense_max_error(fl.input, fl.coupler, fl.output, fl.ground, fl.branch, phi_s, psi_s,
                                flip_a, flip_c)
    assert free.objective < 1e-20  # exact at its three points
    assert optimized < chebyshev
    assert optimized < 0.1 and chebyshev > 0.1  # 0.073 vs 0.145 deg when measured


def test_log_generator_objective_matches_the_reference(log_result):
    _, sol = log_result
    fb = sol.linkage
    phi_s = math.radians(sol.sections["target"]["input_start"])
    psi_s = math.radians(sol.sections["target"]["output_start"])
    total = 0.0
    for k in range(31):
        x = 1 + k / 30
        phi = phi_s + (x - 1) * 60 * DEG
        target = psi_s + math.log10(x) / math.log10(2) * 90 * DEG
        total += wrap(ref_psi(fb.input, fb.coupler, fb.output, fb.ground, phi, fb.branch) - target) ** 2
    assert sol.objective == pytest.approx(total, rel=1e-6)
    assert sol.objective == pytest.approx(1.10867e-05, rel=1e-4)  # the best of seeds 0..9


# ---------------------------------------------------------------- other laws, wide bounds, free starts

def law_any(a, b, c, d, branch, var="phi"):
    """psi(var) of any linkage as a whitelist expression: theta_rho = atan2(ry, rx) by the
    half-angle form pi - 2 atan(ry / (rho - rx)) (singular only at theta_rho = 0), and
    psi = theta_rho -+ alpha (the conventions of docs/format.md)."""
    rho2 = f"({a}**2 + {d}**2 - 2*{a}*{d}*cos({var}))"
    theta = f"(pi - 2*atan({a}*sin({var})/(sqrt({rho2}) - ({a}*cos({var}) - {d}))))"
    alpha = f"acos(({rho2} + {c}**2 - {b}**2)/(2*{c}*sqrt({rho2})))"
    return f"{theta} {'-' if branch == 'open' else '+'} {alpha}"


def ref_class(a, b, c, d):
    links = {"input": a, "coupler": b, "output": c, "ground": d}
    s_, p_, q_, l_ = sorted(links.values())
    if abs(s_ + l_ - p_ - q_) <= 1e-9 * (s_ + l_):
        return "change-point"
    if s_ + l_ > p_ + q_:
        return "triple-rocker"
    return {"input": "crank-rocker", "output": "rocker-crank", "ground": "double-crank",
            "coupler": "double-rocker"}[min(links, key=links.get)]


def ref_assembles(a, b, c, d, phi):
    rho = math.sqrt(a * a + d * d - 2 * a * d * math.cos(phi))
    return abs(b - c) * (1 - 1e-9) <= rho <= (b + c) * (1 + 1e-9)


def random_known_case(seed):
    """A random linkage (lengths 1..10, no change-point), branch, start and a sweep of 30 deg
    or more over which it assembles; one random link fixed, the others in random bounds."""
    import random
    rng = random.Random(seed)
    while True:
        a, b, c, d = (round(rng.uniform(1, 10), 1) for _ in range(4))
        if ref_class(a, b, c, d) == "change-point":
            continue
        start, direction = rng.uniform(-math.pi, math.pi), rng.choice([1, -1])
        reach = 0.0
        while reach < 5.0 and ref_assembles(a, b, c, d, start + direction * (reach + 0.02)) \
                and ref_assembles(a * 1.001, b, c, d, start + direction * (reach + 0.02)):
            reach += 0.02
        if reach >= 0.6:
            break
    links = {"input": a, "coupler": b, "output": c, "ground": d}
    fixed = rng.choice(sorted(links))
    bounds = {k: [v / rng.uniform(1.2, 3), v * rng.uniform(1.2, 3)] for k, v in links.items() if k != fixed}
    return links, fixed, bounds, rng.choice(["open", "crossed"]), start, direction * rng.uniform(0.5, reach)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [3, 11, 12, 29])
def test_random_known_linkages_are_recovered_in_their_own_class(tmp_path, seed):
    links, fixed, bounds, branch, start, sweep = random_known_case(seed)
    a, b, c, d = (links[k] for k in ("input", "coupler", "output", "ground"))
    data = {"type": "function-generation", "units": {"angle": "rad"}, "linkage": {fixed: links[fixed]},
            "target": {"output": law_any(a, b, c, d, branch), "input_start": start, "input_sweep": sweep,
                       "points": 21, "spacing": "chebyshev"},
            "bounds": bounds, "constraints": {"grashof": ref_class(a, b, c, d), "branch": "either"}}
    _, sol = solved(write(tmp_path, data))
    fb = sol.linkage
    assert sol.status.value == "ok", sol.message
    assert fb.branch == branch and sol.objective < 1e-14
    assert (fb.input, fb.coupler, fb.output, fb.ground) == pytest.approx((a, b, c, d), rel=1e-6)


def test_extended_start_with_a_law_defined_on_part_of_the_turn(tmp_path):
    # psi0 + F(phi) - F(phi0), F the output angle of a triple-rocker: acos(...) is defined
    # only where that linkage assembles, so most sampled candidates leave some points
    # undefined; the problem is still solvable (optimum zero at the known linkage)
    a, b, c, d = 3, 2.5, 6, 4  # a triple-rocker: from its extended start, 225 deg of travel
    law = f"psi0 + {law_any(a, b, c, d, 'open')} - ({law_any(a, b, c, d, 'open', 'phi0')})"
    phi0, _ = ref_extended(a, b, c, d, "open")
    data = {"type": "function-generation", "linkage": {"input": a},
            "target": {"output": law, "start": "extended", "input_sweep": 200, "points": 41},
            "bounds": {"ground": [1.5, 10], "coupler": [1, 8], "output": [2, 12]},
            "constraints": {"branch": "open"}}
    assert ref_class(a, b, c, d) == "triple-rocker"
    assert all(ref_assembles(a, b, c, d, phi0 + k / 40 * 200 * DEG) for k in range(41))
    _, sol = solved(write(tmp_path, data))
    fb = sol.linkage
    assert sol.status.value == "ok", sol.message
    assert (fb.ground, fb.coupler, fb.output) == pytest.approx((d, b, c), rel=1e-6) and sol.objective < 1e-14


def test_a_law_undefined_at_some_points_only_is_left_to_the_search():
    from linkcli.types.function_generation.model import Model
    from linkcli.types.function_generation.solve import check_law
    text = open(CRANK_ROCKER).read().replace('"psi0 + 2/(3*pi)*(phi - phi0)**2"', '"psi0 + sqrt(phi - 0.5)"')
    model = Model(load("partial.toml", text))
    u = np.random.default_rng(0).random((20, model.n_variables))
    check_law(model, u)  # phi0 near 0.46 rad: the first points are undefined for some candidates
    with pytest.raises(InputError):  # undefined for every start angle: refused when read
        check_law(Model(load("none.toml", text.replace("sqrt(phi - 0.5)", "sqrt(phi - 100)"))), u)


def freudenstein_design(phis, psis, d):
    """Freudenstein's equation through the points (exact for three, least squares beyond),
    derived in the file format's frame from |B - A| = b with A = a(cos phi, sin phi), B = (d + c cos psi,
    c sin psi): K1 cos psi - K2 cos phi + K3 = cos(phi - psi), K1 = d/a, K2 = d/c,
    K3 = (a^2 + c^2 + d^2 - b^2)/(2ac). (a, b, c) or None (a negative ratio)."""
    rows = np.array([[math.cos(s), -math.cos(p), 1.0] for p, s in zip(phis, psis)])
    rhs = np.array([math.cos(p - s) for p, s in zip(phis, psis)])
    k1, k2, k3 = np.linalg.lstsq(rows, rhs, rcond=None)[0]
    if k1 <= 0 or k2 <= 0:
        return None
    a, c = d / k1, d / k2
    b2 = a * a + c * c + d * d - 2 * a * c * k3
    return (a, math.sqrt(b2), c) if b2 > 0 else None


def design_objective(design, d, phis, psis, dense, window=None, bounds=None):
    """The seed's objective of a design at the points, None unless it assembles on one
    branch at every point and every dense angle of the sweep, within the bounds and the
    transmission window over the sweep (deg)."""
    a, b, c = design
    if bounds and not all(lo <= v <= hi for v, (lo, hi) in zip(design, bounds)):
        return None
    branches = set()
    for phi, psi in zip(phis, psis):
        ax, ay = a * math.cos(phi), a * math.sin(phi)
        bx, by = d + c * math.cos(psi), c * math.sin(psi)
        branches.add("open" if (ax - d) * by - ay * (bx - d) < 0 else "crossed")
    if len(branches) != 1 or not all(ref_assembles(a, b, c, d, phi) for phi in dense):
        return None
    branch = branches.pop()
    if window:
        mus = [math.degrees(math.acos((b * b + c * c - a * a - d * d + 2 * a * d * math.cos(p)) / (2 * b * c)))
               for p in dense]
        if min(mus) < window[0] or max(mus) > window[1]:
            return None
    return sum(wrap(ref_psi(a, b, c, d, p, branch) - s) ** 2 for p, s in zip(phis, psis))


def chebyshev_fractions(n):
    return [(1 - math.cos((2 * k - 1) * math.pi / (2 * n))) / 2 for k in range(1, n + 1)]


def test_wide_bounds_and_given_starts_beat_the_freudenstein_designs(tmp_path):
    # y = sin(x) on [0, pi/2], input -15 deg + 30 deg, output 101.3 deg - 30 deg, lengths
    # free in [0.02, 20] (ground 1): the optimum lies in the first 3 % of a linear box
    # (a linear search found 4.64 rad^2, 50 000 times the Freudenstein designs' error)
    phi_s, psi_s, dphi, dpsi = -15 * DEG, 101.3 * DEG, 30 * DEG, -30 * DEG
    data = {"type": "function-generation", "linkage": {"ground": 1.0},
            "target": {"function": "sin(x)", "x": [0, math.pi / 2], "input_sweep": 30, "output_sweep": -30,
                       "points": 31, "spacing": "chebyshev", "input_start": -15, "output_start": 101.3},
            "bounds": {k: [0.02, 20.0] for k in ("input", "coupler", "output")},
            "constraints": {"transmission": [30, 150]}}
    _, sol = solved(write(tmp_path, data))

    def law(ts):
        return ([phi_s + t * dphi for t in ts], [psi_s + math.sin(t * math.pi / 2) * dpsi for t in ts])

    phis, psis = law(chebyshev_fractions(31))
    dense = [phi_s + k / 400 * dphi for k in range(401)]
    bounds = [(0.02, 20.0)] * 3
    found = {}
    for name, ts in (("three Chebyshev points", chebyshev_fractions(3)), ("least squares", chebyshev_fractions(31))):
        design = freudenstein_design(*law(ts), 1.0)
        found[name] = design_objective(design, 1.0, phis, psis, dense, (30, 150), bounds)
    assert None not in found.values()  # both classical designs are feasible here
    assert sol.status.value == "ok", sol.message
    assert sol.objective <= min(found.values())
    fb = sol.linkage
    assert sol.objective == pytest.approx(design_objective((fb.input, fb.coupler, fb.output), 1.0, phis, psis,
                                                           dense, (30, 150), bounds), rel=1e-9)


EXP_SWEEPS = (-60 * DEG, 45 * DEG)


def exp_law(phi_s, psi_s, ts):
    """y = e^x on [0, 1] mapped onto the sweeps: (phi, psi target) at fractions ts."""
    dphi, dpsi = EXP_SWEEPS
    return ([phi_s + t * dphi for t in ts], [psi_s + (math.exp(t) - 1) / (math.e - 1) * dpsi for t in ts])


@pytest.fixture(scope="module")
def exp_grid_best():
    """The best feasible Freudenstein design (through the three Chebyshev points, or fitted
    to all 31) over 24 x 24 start pairs, by its objective at the 31 Chebyshev points."""
    best = math.inf
    for i in range(24):
        for j in range(24):
            phi_s, psi_s = (i + 0.5) * 15 * DEG - math.pi, (j + 0.5) * 15 * DEG - math.pi
            phis, psis = exp_law(phi_s, psi_s, chebyshev_fractions(31))
            dense = [phi_s + k / 60 * EXP_SWEEPS[0] for k in range(61)]
            for ts in (chebyshev_fractions(3), chebyshev_fractions(31)):
                design = freudenstein_design(*exp_law(phi_s, psi_s, ts), 1.0)
                if design is not None:
                    f = design_objective(design, 1.0, phis, psis, dense, bounds=[(0.05, 20.0)] * 3)
                    best = min(best, f if f is not None else math.inf)
    return best


@pytest.mark.slow
def test_free_starts_beat_every_freudenstein_design_on_a_grid_of_starts(tmp_path, exp_grid_best):
    # y = e^x on [0, 1], input -60 deg, output +45 deg, both start angles free: the
    # classical designs on a grid of starts give 1.11e-6 at best; the search must do at
    # least as well (seeds 1, 7 and 8 used to stop at 6.89e-6; the optimum is 5.607e-8)
    data = {"type": "function-generation", "linkage": {"ground": 1.0},
            "target": {"function": "exp(x)", "x": [0, 1], "input_sweep": -60, "output_sweep": 45,
                       "points": 31, "spacing": "chebyshev"},
            "bounds": {"input": [0.05, 20.0], "coupler": [0.05, 20.0], "output": [0.05, 20.0],
                       "input_start": [-180, 180], "output_start": [-180, 180]},
            "solver": {"seed": 7}}
    _, sol = solved(write(tmp_path, data))
    assert exp_grid_best == pytest.approx(1.1097e-6, rel=1e-3)  # the grid itself (independent of linkcli)
    assert sol.status.value == "ok", sol.message
    assert sol.objective < exp_grid_best
    fb = sol.linkage
    phis, psis = exp_law(math.radians(sol.sections["target"]["input_start"]),
                         math.radians(sol.sections["target"]["output_start"]), chebyshev_fractions(31))
    assert sol.objective == pytest.approx(sum(wrap(ref_psi(fb.input, fb.coupler, fb.output, 1.0, p, fb.branch) - s) ** 2
                                              for p, s in zip(phis, psis)), rel=1e-6)


@pytest.mark.slow
def test_an_impossible_transmission_window_is_infeasible_with_the_amount(tmp_path):
    text = open(CRANK_ROCKER).read().replace("transmission = [45, 135]", "transmission = [80, 100]")
    path = tmp_path / "window.toml"
    path.write_text(text)
    code, out, err = run_cli("synth", str(path), "--format", "json", "--precision", "12")
    rep = json.loads(out)
    assert code == 1 and rep["status"] == "infeasible"
    fb = rep["linkage"]
    mu_min, mu_max = ref_transmission_full_turn(fb["input"], fb["coupler"], fb["output"], fb["ground"])
    assert mu_min < 80 - 1 or mu_max > 100 + 1  # no crank-rocker of input 100, ground 500 fits
    assert "transmission: mu falls to" in rep["message"] and "over the full turn" in rep["message"]
    shown = float(rep["message"].split("mu falls to ")[1].split(" deg")[0])
    below = float(rep["message"].split("deg over the full turn, ")[1].split(" deg below")[0])
    assert shown == pytest.approx(mu_min, abs=1e-5) and below == pytest.approx(80 - mu_min, abs=1e-5)


def test_multi_line_expressions_are_read(tmp_path):
    text = open(CRANK_ROCKER).read().replace('"psi0 + 2/(3*pi)*(phi - phi0)**2"',
                                             '"""\npsi0\n    + 2/(3*pi)\n    * (phi - phi0)**2\n"""')
    law = load("multiline.toml", text).law
    assert law.scalar(phi=1.0, phi0=0.5, psi0=0.25) == pytest.approx(0.25 + 2 / (3 * math.pi) * 0.25, rel=1e-15)


@pytest.mark.parametrize("method", ["auto", "slsqp", "differential-evolution", "dual-annealing"])
def test_budget_caps_a_free_start_function_problem(method):
    for budget in (1, 10, 100):
        _, sol = solved(LOG_GENERATOR, method=method, budget=budget, seed=5)
        assert 1 <= sol.solver.evaluations <= budget
        assert sol.status.value in ("ok", "infeasible", "not-converged") and math.isfinite(sol.objective)


# ---------------------------------------------------------------- hostile and broken expressions

LAW_KEYS = {"linkage": {"input": 100, "ground": 500},
            "target": {"start": "extended", "input_sweep": 90},
            "bounds": {"coupler": [100, 1000], "output": [100, 1000]}}

HOSTILE = [
    ("__import__('os')", '"__import__"'),
    ("().__class__", '".__class__"'),
    ("phi0.__class__.__bases__", '".__bases__"'),
    ("lambda: 1", '"lambda"'),
    ("x.real", '".real"'),
    ("[1][0]", '"[1][0]"'),
    ("9**9**9", "exponent 387420489"),
    ("phi**1000", "exponent 1000"),
    ("phi + " * 120 + "phi", "at most 500 characters"),
    ("open('/etc/passwd')", '"open"'),
    ("eval('1')", '"eval"'),
    ("foo(phi)", '"foo"'),
    ("ph + 1", 'unknown name "ph" (did you mean "phi"?)'),
    ("phi if phi else psi0", "a conditional"),
    ("[x for x in (1,)]", "a comprehension"),
    ("'text'", "a string"),
    ("sin(phi, 2)", "sin takes one"),
    ("log(-1)", '"log(-1)" = nan'),
    ("sqrt(-1) + phi", '"sqrt(-1)" = nan'),
    ("1/0 + phi", '"1/0" = inf'),
    ("10.0**400", "exponent 400"),
    ("phi +", "a syntax error"),
    ("-" * 400 + "phi", "nested more than 250 operations deep"),  # was a RecursionError
    ("not phi", 'the operator "not"'),
    ("~phi", 'the operator "~"'),
]


@pytest.mark.parametrize("text,token", HOSTILE, ids=[h[0][:20] for h in HOSTILE])
def test_hostile_expressions_are_input_errors(tmp_path, text, token):
    data = json.loads(json.dumps(LAW_KEYS))
    data["target"]["output"] = text
    path = write(tmp_path, {"type": "function-generation", **data})
    for command in ("check", "synth"):
        code, out, err = run_cli(command, path)
        assert code == 2 and out == ""
        lines = err.splitlines()
        assert len(lines) == 1, err
        assert lines[0].startswith(f"{path}:")
        assert ": target.output: expected an expression" in lines[0] and token in lines[0], lines[0]


@pytest.mark.parametrize("law,where,command", [
    # extended start: no start angle makes the law finite at a point, refused when read
    ("psi0 + sqrt(phi - 100)", "found nan at point 1 of 31 (phi = phi0 + 0 deg) for every start angle", "check"),
    ("psi0 + log(phi0 - 10)", "found nan at point 1 of 31", "check"),
    ("psi0 + 1/(phi - phi0)", "found inf at point 1 of 31", "check"),
    ("psi0 + 1e300*phi*1e300", "inf at point 1 of 31", "check"),
    # finite but beyond 1e6 rad: no fraction of a turn left (the targets were noise)
    ("psi0 + 1e300*(phi - phi0)", "5.23599e+298 at point 2 of 31 (phi = phi0 + 3 deg)", "check"),
    # finite only where phi < 0.0138 rad, but every sampled open crank-rocker's extended
    # start is beyond (its sweep 90 deg long): refused when solving begins (a linkage with
    # no extended dead-centre, whose start angle is a clipped 0, is no evidence for the law)
    ("psi0 + exp(1000*phi)", "found nan at phi = 16.7936 deg (and at every point for every sampled linkage)",
     "synth"),
    # finite over part of every sweep: the search ends with a design the law fails at
    ("psi0 + sqrt(0.5 - phi)", "found nan at 21 of 31 points of the best design found, first at phi = 30 deg "
     "(point 11)", "synth"),
])
def test_laws_undefined_at_the_points_are_input_errors(tmp_path, law, where, command):
    data = json.loads(json.dumps(LAW_KEYS))
    data["target"]["output"] = law
    if command == "synth":
        data["constraints"] = {"grashof": "crank-rocker", "branch": "open"}
    path = write(tmp_path, {"type": "function-generation", **data})
    code, out, err = run_cli(command, path)
    assert code == 2 and (out == "" or command == "check")
    lines = err.splitlines()
    assert len(lines) == 1 and "target.output: expected a law finite at every evaluation point" in lines[0]
    line = open(path).read().splitlines().index(f"output = {json.dumps(law)}") + 1
    assert where in lines[0] and lines[0].startswith(f"{path}:{line}:")


def test_a_function_ending_where_it_starts_is_refused(tmp_path):
    # sin over a whole period: f(x1) - f(x0) = -2.4e-16 is round-off, the shape would be noise
    data = {"type": "function-generation", "linkage": {"ground": 100},
            "target": {"function": "sin(x)", "x": [0, 2 * math.pi], "input_sweep": 60, "output_sweep": 90},
            "bounds": {"input": [10, 400], "coupler": [10, 400], "output": [10, 400],
                       "input_start": [-180, 180], "output_start": [-180, 180]}}
    code, _, err = run_cli("check", write(tmp_path, data))
    assert code == 2 and len(err.splitlines()) == 1
    assert "target.function: expected a function with f(x1) != f(x0)" in err and "equal within round-off" in err


def test_law_with_given_start_is_checked_when_read(tmp_path):
    data = {"type": "function-generation", "linkage": {"input": 100, "ground": 500},
            "target": {"output": "log(phi - 1)", "input_start": 10, "input_sweep": 90},
            "bounds": {"coupler": [100, 1000], "output": [100, 1000]}}
    path = write(tmp_path, data)
    code, _, err = run_cli("check", path)
    assert code == 2 and "found nan at phi = 10 deg" in err and len(err.splitlines()) == 1


# ---------------------------------------------------------------- the expression compiler

def test_expression_evaluates_like_the_math_module():
    law = compile_expression("psi0 + 2/(3*pi)*(phi - phi0)**2 - abs(sin(phi))*e + log10(exp(phi0 + 3))",
                             ("phi", "phi0", "psi0"))
    rng = np.random.default_rng(0)
    phi = rng.uniform(-3, 3, 50)
    phi0, psi0 = 0.3, 1.1
    got = law(phi=phi, phi0=phi0, psi0=psi0)
    want = [psi0 + 2 / (3 * math.pi) * (p - phi0) ** 2 - abs(math.sin(p)) * math.e + math.log10(math.exp(phi0 + 3))
            for p in phi]
    assert got == pytest.approx(want, rel=1e-13)
    assert law.scalar(phi=phi[0], phi0=phi0, psi0=psi0) == pytest.approx(want[0], rel=1e-13)
    # broadcasting: lengths (N, 1) against angles (M,)
    assert law(phi=phi, phi0=np.zeros((4, 1)), psi0=np.ones((4, 1))).shape == (4, 50)
    assert law.uses("phi0") and not compile_expression("phi", ("phi", "phi0")).uses("phi0")


def test_expression_never_raises_on_bad_values():
    law = compile_expression("sqrt(x) + 1/x + log(x) + x**x + asin(x)", ("x",))
    with np.errstate(all="raise"):
        out = law(x=np.array([-1.0, 0.0, 0.5, 1e300]))
    assert not np.isfinite(out[0]) and not np.isfinite(out[1]) and np.isfinite(out[2])
    assert not math.isfinite(law.scalar(x=-1.0)) and not math.isfinite(law.scalar(x=0.0))


def test_expression_errors_are_input_errors():
    with pytest.raises(ExpressionError) as exc:
        compile_expression("__import__('os').system('true')", ("x",))
    assert isinstance(exc.value, InputError)


def test_tolerance_study_runs_on_the_result(tmp_path):
    path = tmp_path / "tolerance.toml"
    path.write_text(open(CRANK_ROCKER).read() + "[tolerance]\nlengths = 0.1\nsamples = 2000\nallowed_error = 2.5\n")
    code, out, err = run_cli("synth", str(path), "--format", "json")
    rep = json.loads(out)
    assert code == 0, err
    tol = rep["tolerance"]
    assert tol["nominal_error"] == pytest.approx(rep["error"]["max"], rel=1e-6)
    assert tol["samples"] == 2000 and tol["assembly_failures"] == 0
    assert tol["error_max"] >= tol["error_p95"] >= tol["nominal_error"] * 0.9


def test_fixed_lengths_beyond_the_link_ratio_are_refused(tmp_path):
    data = json.loads(json.dumps(LAW_KEYS))
    data["target"]["output"] = "psi0 + 2/(3*pi)*(phi - phi0)**2"
    data["linkage"] = {"input": 1e-9, "ground": 1e9}
    code, _, err = run_cli("check", write(tmp_path, {"type": "function-generation", **data}))
    assert code == 2 and len(err.splitlines()) == 1
    assert "linkage.ground: expected fixed lengths whose longest is at most 1e+06 times the shortest" in err


def test_a_large_offset_is_not_round_off(tmp_path):
    # f(0) = 1e9 and f(1) = 1e9 + 1 differ by 1e7 round-off units: a valid law
    text = open(LOG_GENERATOR).read().replace('function = "log10(x)"', 'function = "1e9 + x"')
    text = text.replace("x = [1, 2]", "x = [0, 1]")
    path = tmp_path / "offset.toml"
    path.write_text(text)
    code, _, err = run_cli("check", str(path))
    assert code == 0, err


def test_the_batched_stage_slopes_match_differences_and_penalize_only_violations():
    """`auto`'s field (types/function_generation/field.py): its forward-difference slopes
    against central differences of its own residuals taken here with a smaller step; a
    penalty row is the quadratic penalty's sqrt(W) min(g, 0), its slope the constraint's
    where it is violated and exactly 0 where it holds (never half a kink)."""
    from linkcli.types.function_generation.field import Field
    from linkcli.types.function_generation.model import Model
    from linkcli.types.function_generation.search import Search
    model = Model(load(LOG_GENERATOR))
    rng = np.random.default_rng(3)
    z = 0.1 + 0.8 * rng.random((40, model.n_variables))
    signs = np.where(rng.random(40) < 0.5, -1.0, 1.0)
    field = Field(Search(model, 10**6, ("open", "crossed")), signs, 1e4)
    r0 = field.residuals(z, slice(None))
    jac = field.jacobian(z, slice(None), r0)
    points = len(model.t)
    penalty = r0[:, points:-1]
    assert np.all(penalty <= 0.0) and np.any(penalty < 0.0) and np.any(penalty == 0.0)
    h = 1e-6
    for k in range(model.n_variables):
        step = np.zeros(model.n_variables)
        step[k] = h
        plus, minus = field.residuals(z + step, slice(None)), field.residuals(z - step, slice(None))
        central = (plus - minus) / (2 * h)
        np.testing.assert_allclose(jac[:, :points, k], central[:, :points], rtol=1e-3, atol=1e-4)
        one_side = (plus[:, points:-1] < 0) & (minus[:, points:-1] < 0)  # the step stays violated
        np.testing.assert_allclose(jac[:, points:-1, k][one_side], central[:, points:-1][one_side],
                                   rtol=1e-4, atol=1e-2)
        assert np.all(jac[:, points:-1, k][penalty == 0.0] == 0.0)



def test_auto_claims_a_best_only_after_claim_rounds(monkeypatch):
    """The first round's two batches can both end in one basin: a best found twice ends the
    rounds only once CLAIM_ROUNDS (2) have run, and is then `ok`; an exact fit ends them at
    once."""
    from conftest import ROOT

    from linkcli.io.safe_read import read_problem_bytes
    from linkcli.pipeline import solve
    from linkcli.reading.load import load
    from linkcli.types.function_generation import auto as fg_auto

    calls = []
    original = fg_auto.one_round

    def counted(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(fg_auto, "one_round", counted)
    path = str(ROOT / "problems" / "bench" / "crank_rocker.toml")
    sol = solve(load(path, read_problem_bytes(path)))
    assert sol.status.value == "ok"
    assert len(calls) >= fg_auto.CLAIM_ROUNDS >= 2


def test_a_flat_sum_as_long_as_an_expression_may_be_is_taken():
    """The longest expression text (500 characters) written as a flat sum nests 249 operations
    (two characters each): it is taken and evaluates to its sum; stacked signs deeper than
    MAX_DEPTH are refused as nested, not as too long."""
    from linkcli.expr import MAX_DEPTH, MAX_LENGTH
    text = "phi" + "+phi" * ((MAX_LENGTH - 3) // 4) + "-1" * ((MAX_LENGTH - 3) % 4 // 2)
    assert len(text) <= MAX_LENGTH
    law = compile_expression("phi" + "-1" * ((MAX_LENGTH - 3) // 2), ("phi",))
    assert law.scalar(phi=3.0) == 3.0 - (MAX_LENGTH - 3) // 2
    law = compile_expression(text, ("phi",))
    assert law.scalar(phi=2.0) == 2.0 * (1 + (MAX_LENGTH - 3) // 4) - (MAX_LENGTH - 3) % 4 // 2
    with pytest.raises(ExpressionError, match="nested more than"):
        compile_expression("-" * (MAX_DEPTH + 1) + "phi", ("phi",))
