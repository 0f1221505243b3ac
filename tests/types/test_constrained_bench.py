"""The constrained bench variants (problems/bench/*_window, *_short, *_grashof): their
constraint binds at the reported optimum, their objective recomputes with this file's own
kinematics, and a seed says `ok` only at the best known (issue: "any seed that fails is
reported not-converged, never ok").

Independent references: the path closure of tests/types/test_path_generation.py (complex numbers),
the output angle of tests/types/test_function_generation.py (law of cosines), the transmission
angle from the law of cosines, cos mu = (b^2 + c^2 - rho^2) / (2 b c), rho = |A B0|.
"""

from __future__ import annotations

import json
import math
import tomllib

import pytest
from conftest import ROOT, run_cli
from test_function_generation import ref_psi, wrap
from test_path_generation import recomputed

pytestmark = pytest.mark.slow  # the bench and study cases: the full suite runs them, the fast lane does not

BENCH = ROOT / "problems" / "bench"
WITHIN = 1e-6  # relative gap to the best known that counts as reaching it


def best_known(name: str) -> float:
    return tomllib.loads((BENCH / name).read_text())["reference"]["objective"]


def report(name: str, seed: int) -> dict:
    code, out, err = run_cli("synth", str(BENCH / name), "--format", "json", "--precision", "15",
                             "--seed", str(seed))
    assert code in (0, 1) and "Traceback" not in err, err
    return json.loads(out)


def mu_deg(b: float, c: float, rho: float) -> float:
    return math.degrees(math.acos((b * b + c * c - rho * rho) / (2 * b * c)))


def honest(rep: dict, best: float, objective: float) -> None:
    """`ok` only within WITHIN of the best known; never below it by more than WITHIN (a
    stale best known); infeasible never (the variants are feasible)."""
    assert rep["status"] in ("ok", "not-converged"), rep["message"]
    assert objective >= best * (1 - WITHIN)
    if rep["status"] == "ok":
        assert objective <= best * (1 + WITHIN), (objective, best)


@pytest.mark.parametrize("seed", [0, 1])
def test_arc6_window_holds_its_window_at_the_upper_edge(seed):
    rep = report("arc6_window.toml", seed)
    lk = rep["linkage"]
    d, a, b, c = lk["ground"], lk["input"], lk["coupler"], lk["output"]
    total, _ = recomputed(rep)
    assert rep["error"]["objective"] == pytest.approx(total, rel=1e-9)
    assert mu_deg(b, c, abs(d - a)) >= 40.0 - 1e-9
    assert mu_deg(b, c, d + a) <= 140.0 + 1e-9
    if rep["status"] == "ok":  # at the optimum the upper edge binds and the ground is at 50
        assert mu_deg(b, c, d + a) == pytest.approx(140.0, abs=1e-6) and d == pytest.approx(50.0)
    honest(rep, best_known("arc6_window.toml"), total)


@pytest.mark.parametrize("seed", [0, 1])
def test_kunjur5_short_ends_on_its_coupler_bound(seed):
    rep = report("kunjur5_short.toml", seed)
    total, _ = recomputed(rep)
    assert rep["error"]["objective"] == pytest.approx(total, rel=1e-9)
    assert rep["linkage"]["coupler"] <= 3.5
    honest(rep, best_known("kunjur5_short.toml"), total)
    if rep["status"] == "ok":
        assert rep["linkage"]["coupler"] == pytest.approx(3.5, rel=1e-12)
        assert total < best_known("kunjur5_short.toml") * 2  # and the unconstrained 7.4e-7 below it
        assert best_known("kunjur5.toml") < total


def log_objective(rep: dict) -> float:
    """sum over 31 points of (psi - target)^2, y = log10(x) on [1, 2], 60 deg of input,
    90 deg of output, uniform spacing (problems/bench/log_generator.toml)."""
    lk, tg = rep["linkage"], rep["target"]
    phi_s, psi_s = math.radians(tg["input_start"]), math.radians(tg["output_start"])
    total = 0.0
    for k in range(31):
        x = 1 + k / 30
        phi = phi_s + (x - 1) * math.radians(60)
        target = psi_s + math.log10(x) / math.log10(2) * math.radians(90)
        psi = ref_psi(lk["input"], lk["coupler"], lk["output"], lk["ground"], phi, lk["branch"])
        total += wrap(psi - target) ** 2
    return total


@pytest.mark.parametrize("seed", [0, 1])
def test_log_generator_short_ends_on_its_input_bound(seed):
    rep = report("log_generator_short.toml", seed)
    total = log_objective(rep)
    assert rep["error"]["objective"] == pytest.approx(total, rel=1e-6)
    assert rep["linkage"]["input"] <= 150.0
    honest(rep, best_known("log_generator_short.toml"), total)
    if rep["status"] == "ok":
        assert rep["linkage"]["input"] == pytest.approx(150.0, rel=1e-9)


@pytest.mark.parametrize("seed", [0, 1])
def test_log_generator_grashof_sits_on_the_grashof_limit(seed):
    rep = report("log_generator_grashof.toml", seed)
    lk = rep["linkage"]
    total = log_objective(rep)
    assert rep["error"]["objective"] == pytest.approx(total, rel=1e-6)
    s, p, q, l = sorted((lk["ground"], lk["input"], lk["coupler"], lk["output"]))
    assert s + l <= (p + q) * (1 + 1e-9) and lk["coupler"] == s  # a Grashof double-rocker
    honest(rep, best_known("log_generator_grashof.toml"), total)
    if rep["status"] == "ok":
        assert s + l == pytest.approx(p + q, rel=1e-6)  # the limit binds


def test_every_bench_file_has_an_eight_digit_best_known():
    """A rounded best known (7.4157e-7 for 7.41575131e-7) makes every seed miss 1e-6."""
    for path in sorted(BENCH.glob("*.toml")):
        ref = tomllib.loads(path.read_text())["reference"]
        value = ref["objective"]
        if value != 0:
            digits = len(f"{value:.12e}".split("e")[0].replace(".", "").rstrip("0"))
            assert digits >= 7, (path.name, value)
        assert "provisional" not in ref["source"], path.name


def test_a_small_budget_never_calls_a_local_optimum_ok(tmp_path):
    """On 1000 evaluations log_generator_grashof's local searches see few basins: some
    seeds found 0.2023 twice (and 6.08 once) and said ok against the optimum 0.1072. A
    best found twice by searches that have not begun to repeat themselves is not-converged;
    any `ok` must be the best known (objective recomputed by the test's own closure)."""
    text = (BENCH / "log_generator_grashof.toml").read_text() + "\n[solver]\nbudget = 1000\n"
    best = best_known("log_generator_grashof.toml")
    path = tmp_path / "small_budget_grashof.toml"
    path.write_text(text)
    statuses = []
    for seed in range(10):
        code, out, err = run_cli("synth", str(path), "--format", "json", "--precision", "15",
                                 "--seed", str(seed))
        assert code in (0, 1) and "Traceback" not in err, err
        rep = json.loads(out)
        total = log_objective(rep)
        assert rep["error"]["objective"] == pytest.approx(total, rel=1e-6)
        honest(rep, best, total)
        statuses.append(rep["status"])
    assert "not-converged" in statuses  # the budget is too small for every seed
