"""quick-return through the CLI, against references written here: the family by brute force
(the crank pivot placed on the circles that see the rocker's extreme-pin chord under theta,
lengths by distances, transmission by the plain cosine rule), and the time ratio, swing and
stroke of the reported linkage by a dense crank sweep of its own closure with a
golden-section refinement of each extreme."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from conftest import run_cli

DEG = math.pi / 180
GOLDEN = (math.sqrt(5) - 1) / 2


def synth(tmp_path, text: str, *args):
    path = tmp_path / "p.toml"
    path.write_text('type = "quick-return"\n' + text, encoding="utf-8")
    code, out, err = run_cli("synth", str(path), "--format", "json", *args)
    return code, (json.loads(out) if out.strip() else None), err


def crank_rocker_text(K=1.25, swing=45, scale="ground = 1", extra=""):
    return (f'mechanism = "crank-rocker"\ntime_ratio = {K}\nswing = {swing}\n[linkage]\n{scale}\n'
            f"{extra}")


# ---- independent references -------------------------------------------------------------------

def circle_family(K, swing, t):
    """(a, b, c, d) scaled to ground 1, worst transmission, valid mask for crank pivots at
    angles t on both circles through B1, B2 whose major arcs see the chord under theta."""
    theta = math.pi * (K - 1) / (K + 1)
    b1, b2 = np.array([math.cos(swing), math.sin(swing)]), np.array([1.0, 0.0])
    mid, chord = (b1 + b2) / 2, np.linalg.norm(b1 - b2)
    n = np.array([-(b1 - b2)[1], (b1 - b2)[0]]) / chord
    R = chord / (2 * math.sin(theta))
    cols = []
    for side in (1.0, -1.0):
        c0 = mid + side * n * R * math.cos(theta)
        x, y = c0[0] + R * np.cos(t), c0[1] + R * np.sin(t)
        major = side * ((x - mid[0]) * n[0] + (y - mid[1]) * n[1]) > 0
        r1, r2 = np.hypot(x - b1[0], y - b1[1]), np.hypot(x - b2[0], y - b2[1])
        same = (x * b1[1] - y * b1[0]) * (x * b2[1] - y * b2[0]) > 0
        d = np.hypot(x, y)
        a, b = np.abs(r1 - r2) / 2 / d, (r1 + r2) / 2 / d
        c = 1 / d
        mu0 = np.arccos(np.clip((b * b + c * c - (1 - a) ** 2) / (2 * b * c), -1, 1))
        mu1 = np.arccos(np.clip((b * b + c * c - (1 + a) ** 2) / (2 * b * c), -1, 1))
        cols.append((a, b, c, mu0, mu1, major & same & (a > 0)))
    return [np.concatenate(z) for z in zip(*cols)]


def brute_best(K, swing, score, n=200001, zooms=6):
    """Maximize score(a, b, c, mu0, mu1) (-inf where not allowed) over the circle family."""
    lo, hi = -math.pi, math.pi
    best = None
    for _ in range(zooms):
        t = np.linspace(lo, hi, n)
        a, b, c, mu0, mu1, ok = circle_family(K, swing, t)
        s = np.where(ok, score(a, b, c, mu0, mu1), -np.inf)
        k = int(np.argmax(s))
        best = (float(s[k]), float(a[k]), float(b[k]), float(c[k]))
        step = (hi - lo) / (n - 1)
        lo, hi = t[k] - 50 * step, t[k] + 50 * step
    return best


def worst(a, b, c, mu0, mu1):
    return np.minimum(np.minimum(mu0, np.pi - mu0), np.minimum(mu1, np.pi - mu1))


def golden_extreme(f, lo, hi, sign):
    """The extreme value of f on [lo, hi] (sign +1 max, -1 min) and where."""
    x1, x2 = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
    for _ in range(200):
        if sign * f(x1) > sign * f(x2):
            hi, x2 = x2, x1
            x1 = hi - GOLDEN * (hi - lo)
        else:
            lo, x1 = x1, x2
            x2 = lo + GOLDEN * (hi - lo)
    x = (lo + hi) / 2
    return f(x), x


def sweep_extremes(f, n=20001):
    """(min value, its phi, max value, its phi) of a 2 pi-periodic f by a dense sweep and
    golden refinement."""
    phi = np.linspace(0, 2 * math.pi, n)
    v = f(phi)
    h = phi[1] - phi[0]
    out = []
    for sign, k in ((-1, int(np.argmin(v))), (1, int(np.argmax(v)))):
        out += list(golden_extreme(lambda x: float(f(np.array([x]))[0]), phi[k] - h, phi[k] + h, sign))
    return out


def simulated_four_bar(a, b, c, d):
    """(K, swing) of a crank-rocker: rocker angle psi(phi) of the open closure, its extremes,
    and the crank angles between them."""
    def psi(phi):
        ax, ay = a * np.cos(phi), a * np.sin(phi)
        dx, dy = d - ax, -ay
        f = np.hypot(dx, dy)
        beta = np.arccos(np.clip((c * c + f * f - b * b) / (2 * c * f), -1, 1))
        return np.arctan2(-dy, -dx) + beta
    unwrapped = lambda phi: np.mod(psi(phi), 2 * math.pi)  # noqa: E731 (the rocker never crosses 0)
    lo, at_lo, hi, at_hi = sweep_extremes(unwrapped)
    t = (at_hi - at_lo) % (2 * math.pi)
    return max(t, 2 * math.pi - t) / min(t, 2 * math.pi - t), hi - lo


def simulated_slider(a, b, e):
    """(stroke, K) from s(phi) = a cos(phi) + sqrt(b^2 - (e - a sin(phi))^2)."""
    s = lambda phi: a * np.cos(phi) + np.sqrt(b * b - (e - a * np.sin(phi)) ** 2)  # noqa: E731
    lo, at_lo, hi, at_hi = sweep_extremes(s)
    t = (at_hi - at_lo) % (2 * math.pi)
    return hi - lo, max(t, 2 * math.pi - t) / min(t, 2 * math.pi - t)


# ---- must show --------------------------------------------------------------------------------

def test_example_matches_brute_force_and_recomputes_by_simulation(tmp_path):
    code, rep, err = synth(tmp_path, crank_rocker_text())
    assert code == 0, err
    L = rep["linkage"]
    assert L["ground"] == 1
    assert (L["input"], L["coupler"], L["output"]) == pytest.approx((0.3457, 0.8336, 0.9666), abs=5e-5)
    assert rep["design"]["worst_transmission"] == pytest.approx(41.81, abs=5e-3)
    code, full, _ = synth(tmp_path, crank_rocker_text(), "--precision", "15")  # every digit
    value, a, b, c = brute_best(1.25, 45 * DEG, worst)
    L = full["linkage"]
    assert full["design"]["worst_transmission"] == pytest.approx(math.degrees(value), abs=1e-7)
    assert full["design"]["worst_transmission"] >= math.degrees(value) - 1e-9  # nothing beats it
    assert (L["input"], L["coupler"], L["output"]) == pytest.approx((a, b, c), abs=2e-6)
    K, swing = simulated_four_bar(*(full["linkage"][k] for k in ("input", "coupler", "output", "ground")))
    assert K == pytest.approx(1.25, abs=1e-6) and math.degrees(swing) == pytest.approx(45, abs=1e-6)
    assert full["design"]["time_ratio"] == pytest.approx(K, abs=1e-6)
    assert full["motion"]["time_ratio"] == pytest.approx(K, abs=1e-6)
    assert full["design"]["swing"] == pytest.approx(math.degrees(swing), abs=1e-6)


def test_slider_crank_with_offset_and_its_simulation(tmp_path):
    text = 'mechanism = "slider-crank"\ntime_ratio = 1.25\nstroke = 100\n[linkage]\noffset = 30\n'
    code, rep, err = synth(tmp_path, text, "--precision", "15")
    assert code == 0, err
    L = rep["linkage"]
    assert L["mechanism"] == "slider-crank" and L["offset"] == 30
    assert (L["input"], L["coupler"]) == pytest.approx((47.2812, 104.9139), abs=5e-5)
    stroke, K = simulated_slider(L["input"], L["coupler"], 30.0)
    assert stroke == pytest.approx(100, abs=1e-6) and K == pytest.approx(1.25, abs=1e-6)
    assert rep["design"]["stroke"] == pytest.approx(stroke, abs=1e-6)
    assert rep["motion"]["stroke"] == pytest.approx(stroke, abs=1e-6)
    # transmission over the full turn: mu = arccos(|e - a sin phi| / b) by a dense sweep
    phi = np.linspace(-math.pi, math.pi, 200001)
    mu = np.degrees(np.arccos(np.abs(30 - L["input"] * np.sin(phi)) / L["coupler"]))
    assert rep["transmission"]["min"] == pytest.approx(mu.min(), abs=1e-6)
    assert rep["transmission"]["max"] == pytest.approx(mu.max(), abs=1e-3)  # a cusp: the grid stays below
    assert rep["transmission"]["max"] == 90  # a > e: the rod is normal to the guide somewhere (h = 0)
    assert rep["transmission"]["input_at_min"] == pytest.approx(-90, abs=1e-9)


def test_free_slider_crank_beats_every_offset_on_a_grid(tmp_path):
    code, rep, err = synth(tmp_path, 'mechanism = "slider-crank"\ntime_ratio = 1.25\nstroke = 100\n',
                           "--precision", "15")
    assert code == 0, err
    theta = math.pi * 0.25 / 2.25
    e = np.linspace(1e-6, 100 / math.tan(theta) * (1 - 1e-9), 400001)
    t = math.tan(theta / 2)
    a, b = np.sqrt(100 ** 2 - 200 * e * t) / 2, np.sqrt(100 ** 2 + 200 * e / t) / 2  # area + cosine rule
    mu_min = np.degrees(np.arccos((a + e) / b))
    k = int(np.argmax(mu_min))
    assert rep["design"]["worst_transmission"] >= mu_min[k] - 1e-7
    assert rep["linkage"]["offset"] == pytest.approx(e[k], rel=1e-4)


def test_scipy_is_not_imported_and_check_imports_no_numpy():
    code = ("import sys; from linkcli.pipeline import Request, run; "
            "o = run('problems/quick_return.toml', Request()); "
            "assert o.exit_code == 0, o.errors; assert 'scipy' not in sys.modules, 'scipy imported'")
    subprocess.run([sys.executable, "-c", code], check=True)
    code = ("import sys; from linkcli.pipeline import Request, run; "
            "o = run('problems/quick_return_slider.toml', Request(mode='check')); "
            "assert o.exit_code == 0, o.errors; assert 'numpy' not in sys.modules, 'numpy imported'")
    subprocess.run([sys.executable, "-c", code], check=True)


# ---- the transmission window -------------------------------------------------------------------

def test_window_the_best_misses_reports_the_best_inside(tmp_path):
    lo, hi = 35 * DEG, 92 * DEG
    code, rep, err = synth(tmp_path, crank_rocker_text(extra="[constraints]\ntransmission = [35, 92]\n"),
                           "--precision", "15")
    assert code == 0, err

    def inside_score(a, b, c, mu0, mu1):
        m = np.minimum(mu0, mu1), np.maximum(mu0, mu1)
        return np.where((m[0] >= lo) & (m[1] <= hi), worst(a, b, c, mu0, mu1), -np.inf)
    value, a, b, c = brute_best(1.25, 45 * DEG, inside_score)
    assert rep["design"]["worst_transmission"] == pytest.approx(math.degrees(value), abs=1e-5)
    assert rep["design"]["worst_transmission"] < 41.81  # not the unconstrained best
    assert rep["transmission"]["min"] >= 35 - 1e-9 and rep["transmission"]["max"] <= 92 + 1e-6
    assert any("leaves the window" in n for n in rep["notes"])
    chosen = [r for r in rep["family"] if r["chosen"]]
    assert len(chosen) == 1 and chosen[0]["inside_window"]


def test_window_no_member_meets_is_infeasible_with_the_amount(tmp_path):
    lo, hi = 60 * DEG, 100 * DEG
    code, rep, err = synth(tmp_path, crank_rocker_text(extra="[constraints]\ntransmission = [60, 100]\n"),
                           "--precision", "15")
    assert code == 1 and rep["status"] == "infeasible"

    def minus_miss(a, b, c, mu0, mu1):
        return -np.maximum(np.maximum(lo - np.minimum(mu0, mu1), np.maximum(mu0, mu1) - hi), 0)
    value, *_ = brute_best(1.25, 45 * DEG, minus_miss)
    amount = float(rep["message"].split("misses it by ")[1].split(" deg")[0])
    assert amount == pytest.approx(-math.degrees(value), abs=1e-4)


# ---- edges --------------------------------------------------------------------------------------

def test_time_ratio_one_is_limited_by_the_documented_ratio_or_bounds(tmp_path):
    code, rep, _ = synth(tmp_path, crank_rocker_text(K=1, scale="ground = 100"))
    assert code == 0
    L = rep["linkage"]
    lengths = [L[k] for k in ("ground", "input", "coupler", "output")]
    assert max(lengths) / min(lengths) == pytest.approx(1000, rel=1e-5)
    assert any("at infinity" in n for n in rep["notes"])
    assert rep["design"]["worst_transmission"] < 90 - 22.5  # the limit at infinity, not reached
    code, rep, _ = synth(tmp_path, crank_rocker_text(K=1, scale="output = 100",
                                                     extra="[bounds]\nground = [100, 500]\n"))
    assert code == 0 and rep["linkage"]["ground"] == pytest.approx(500, rel=1e-9)
    assert any("[bounds] (ground)" in n for n in rep["notes"])


@pytest.mark.parametrize("K, swing", [(4.3333, 45), (2.999, 90), (1.25, 1e-6), (1.25, 179.9999),
                                      (1.0000001, 45), (4.33, 45)])
@pytest.mark.slow
def test_edges_give_a_design_or_a_located_exit_2(tmp_path, K, swing):
    code, rep, err = synth(tmp_path, crank_rocker_text(K=K, swing=swing, scale="ground = 100"))
    assert "Traceback" not in err and "internal error" not in err
    if code == 2:
        assert err.count("\n") == 1 and ":" in err.split(": ")[0]
        assert err.split(": ")[1] in ("swing", "time_ratio")
        return
    assert code == 0
    values = [rep["linkage"][k] for k in ("ground", "input", "coupler", "output")]
    assert all(math.isfinite(v) and v > 0 for v in values)
    assert rep["design"]["time_ratio"] == pytest.approx(K, rel=1e-6)
    assert rep["design"]["swing"] == pytest.approx(swing, rel=1e-5, abs=1e-4)


def test_bounds_no_member_meets_is_exit_2_at_the_bounds_line(tmp_path):
    code, rep, err = synth(tmp_path, crank_rocker_text(extra="[bounds]\ncoupler = [5, 6]\n"))
    assert code == 2
    assert ":7: bounds: expected bounds that admit a member of the family, found coupler [5, 6]" in err


def test_family_rows_are_members_and_the_chosen_is_best(tmp_path):
    code, rep, _ = synth(tmp_path, crank_rocker_text(), "--precision", "15")
    rows = rep["family"]
    assert [r["parameter"] for r in rows] == sorted(r["parameter"] for r in rows)
    assert sum(r["chosen"] for r in rows) == 1
    best = max(r["worst_transmission"] for r in rows)
    assert [r for r in rows if r["chosen"]][0]["worst_transmission"] == best
    for r in rows:  # each row is a crank-rocker of K 1.25 and swing 45 (dead centres, cosine rule)
        a, b, c, d = r["input"], r["coupler"], r["output"], r["ground"]
        ang = lambda f: math.acos((d * d + f * f - c * c) / (2 * d * f))  # noqa: E731
        rock = lambda f: math.acos((d * d + c * c - f * f) / (2 * d * c))  # noqa: E731
        theta = abs(ang(b - a) - ang(b + a))
        assert (math.pi + theta) / (math.pi - theta) == pytest.approx(1.25, abs=1e-9)
        assert math.degrees(abs(rock(b + a) - rock(b - a))) == pytest.approx(45, abs=1e-8)


@pytest.mark.slow
def test_result_file_round_trips_and_the_plot_is_drawn(tmp_path):
    code, out, err = run_cli("synth", "problems/quick_return.toml", "--format", "toml", "--out", str(tmp_path),
                             "--plot", str(tmp_path / "qr.png"))
    assert code == 0, err
    assert (tmp_path / "qr.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    result = next(tmp_path.glob("*.toml"))
    code, out, err = run_cli("analyze", str(result), "--format", "json")
    assert code == 0, err
    _, synthesized, _ = run_cli("synth", "problems/quick_return.toml", "--format", "json")
    assert json.loads(out)["linkage"] == json.loads(synthesized)["linkage"]


def test_a_quick_return_slider_crank_has_the_shared_slider_sections(tmp_path):
    """The chosen slider-crank is reported as a linkage: class, motion and, when asked,
    kinematics rows whose slider positions follow the closed form
    s = a cos(phi) + sqrt(b^2 - (e - a sin(phi))^2) (open branch)."""
    text = ('mechanism = "slider-crank"\ntime_ratio = 1.4\nstroke = 80\n'
            "[linkage]\noffset = 20\n"
            '[report]\nsections = ["lengths", "grashof", "motion", "kinematics"]\n')
    code, rep, err = synth(tmp_path, text, "--precision", "15")
    assert code == 0, err
    lk = rep["linkage"]
    a, b, e = lk["input"], lk["coupler"], lk["offset"]
    assert rep["grashof"]["class"] == "slider-crank" and a + abs(e) < b
    assert rep["motion"]["stroke"] == pytest.approx(80, rel=1e-9)
    rows = rep["kinematics"]
    assert len(rows) == 360  # no [motion] in a quick-return file: 360 steps
    phi = np.radians([r["input"] for r in rows])
    s = a * np.cos(phi) + np.sqrt(b * b - (e - a * np.sin(phi)) ** 2)
    assert [r["slider"] for r in rows] == pytest.approx(s.tolist(), rel=1e-9, abs=1e-9 * b)
