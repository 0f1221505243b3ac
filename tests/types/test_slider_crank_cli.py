"""The slider-crank through the CLI (issue 15): analysis, precision positions, tolerances,
round trip. References written here: the slider position as the root of
|B - A|^2 = b^2, s^2 - 2 s a cos(phi) + a^2 + e^2 - 2 a e sin(phi) - b^2 = 0; stroke and
time ratio by a dense crank sweep (simulation); an independent Monte Carlo."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
from conftest import run_cli

TEXTBOOK = (47.2812, 104.9139, 30.0)


def ref_slider(a, b, e, phi, sign=1.0):
    p = a * np.cos(phi)
    q = a * a + e * e - 2 * a * e * np.sin(phi) - b * b
    return p + sign * np.sqrt(p * p - q)


def simulated_stroke_and_ratio(a, b, e, n=2_000_000):
    """Sweep the crank through one turn: the slider's extremes and the crank angle spent
    going from its nearest to its farthest position (outward) and back."""
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    s = ref_slider(a, b, e, phi)
    i_max, i_min = int(np.argmax(s)), int(np.argmin(s))
    outward = (phi[i_max] - phi[i_min]) % (2 * math.pi)
    back = 2 * math.pi - outward
    return s[i_max] - s[i_min], max(outward, back) / min(outward, back)


def linkage_file(tmp_path, a, b, e, extra=""):
    f = tmp_path / "sc.toml"
    f.write_text(f'type = "linkage"\n[linkage]\nmechanism = "slider-crank"\ninput = {a!r}\n'
                 f"coupler = {b!r}\noffset = {e!r}\n{extra}")
    return str(f)


def report(*args):
    code, out, err = run_cli(*args, "--format", "json")
    return code, (json.loads(out) if out else None), err


def test_textbook_slider_crank_stroke_100_and_time_ratio_1_25():
    code, rep, err = report("synth", "problems/slider_crank.toml", "--precision", "12")
    assert code == 0, err
    stroke, k = simulated_stroke_and_ratio(*TEXTBOOK)
    assert f"{rep['motion']['stroke']:.3f}" == "100.000"
    assert f"{rep['motion']['time_ratio']:.4f}" == "1.2500"
    assert rep["motion"]["stroke"] == pytest.approx(stroke, abs=1e-6)
    assert rep["motion"]["time_ratio"] == pytest.approx(k, abs=1e-5)  # sweep step 3e-6 rad
    assert rep["motion"]["slow_stroke"] == "return"  # e > 0, crank ccw: the return is slower
    assert rep["grashof"]["class"] == "slider-crank"
    lo, hi = rep["motion"]["slider_range"]
    phi = np.linspace(0, 2 * math.pi, 400_001)
    s = ref_slider(*TEXTBOOK, phi)
    assert (lo, hi) == pytest.approx((s.min(), s.max()), abs=1e-6)


def test_kinematics_rows_against_finite_differences(tmp_path):
    a, b, e = TEXTBOOK
    f = linkage_file(tmp_path, a, b, e, "[motion]\ninput_speed = 90\nsteps = 24\n")
    code, rep, err = report("synth", f, "--precision", "15")
    assert code == 0, err
    rows = rep["kinematics"]
    w = math.radians(90)
    for row in rows:
        phi = math.radians(row["input"])
        h = 1e-5
        s0, sp, sm = (float(ref_slider(a, b, e, phi + d)) for d in (0.0, h, -h))
        assert row["slider"] == pytest.approx(s0, rel=1e-12)
        assert row["slider_velocity"] == pytest.approx((sp - sm) / (2 * h) * w, rel=1e-6, abs=1e-6)
        assert row["slider_acceleration"] == pytest.approx((sp - 2 * s0 + sm) / h**2 * w * w, rel=1e-4, abs=1e-3)
        mu = math.degrees(math.acos(abs(a * math.sin(phi) - e) / b))
        assert row["transmission"] == pytest.approx(mu, abs=1e-9)


def test_centred_slider_crank_time_ratio_exactly_one(tmp_path):
    code, rep, err = report("synth", linkage_file(tmp_path, 30.0, 95.0, 0.0))
    assert code == 0, err
    assert rep["motion"]["time_ratio"] == 1.0
    assert rep["motion"]["slow_stroke"] == "neither"
    assert rep["motion"]["stroke"] == pytest.approx(60.0, rel=1e-12)  # 2a when e = 0


def test_rocking_slider_reports_its_range(tmp_path):
    a, b, e = 50.0, 40.0, 20.0  # a + |e| > b: the crank rocks
    code, rep, err = report("synth", linkage_file(tmp_path, a, b, e), "--precision", "12")
    assert code == 0, err
    assert rep["grashof"]["class"] == "rocking-slider"
    assert rep["motion"]["input_full_turn"] is False
    lo, hi = (math.radians(x) for x in rep["motion"]["input_range"])
    # both ends where |e - a sin(phi)| = b: sin(phi) = (e - b)/a ((e + b)/a > 1 is no limit)
    assert a * math.sin(lo) == pytest.approx(e - b, abs=1e-9)
    assert a * math.sin(hi) == pytest.approx(e - b, abs=1e-9)
    assert lo != pytest.approx(hi)


def test_three_positions_reproduce_the_generating_slider_crank(tmp_path):
    a, b, e = 37.3, 111.7, -12.4
    phi = np.radians([20.0, 75.0, 140.0])
    s = ref_slider(a, b, e, phi)
    f = tmp_path / "p.toml"
    f.write_text('type = "precision-position"\n[linkage]\nmechanism = "slider-crank"\n[positions]\n'
                 f"input = [20, 75, 140]\noutput = [{', '.join(repr(float(x)) for x in s)}]\n")
    code, rep, err = report("synth", str(f), "--precision", "15")
    assert code == 0, err
    lk = rep["linkage"]
    assert (lk["input"], lk["coupler"], lk["offset"]) == pytest.approx((a, b, e), rel=1e-9)
    assert lk["branch"] == "open"
    assert [r["error"] for r in rep["positions"]] == pytest.approx([0, 0, 0], abs=1e-9)


def test_a_branch_that_misses_a_position_is_infeasible(tmp_path):
    a, b, e = 30.0, 80.0, 10.0
    phi = np.radians([10.0, 100.0, 200.0])
    s = ref_slider(a, b, e, phi, np.array([1.0, 1.0, -1.0]))  # the third on the crossed branch
    f = tmp_path / "p.toml"
    f.write_text('type = "precision-position"\n[linkage]\nmechanism = "slider-crank"\n[positions]\n'
                 f"input = [10, 100, 200]\noutput = [{', '.join(repr(float(x)) for x in s)}]\n")
    code, rep, err = report("synth", str(f), "--precision", "15")
    assert code == 1, err
    assert rep["status"] == "infeasible" and "position 3 missed" in rep["message"]
    lk = rep["linkage"]
    assert (lk["input"], lk["coupler"], lk["offset"]) == pytest.approx((a, b, e), rel=1e-9)


def test_result_file_round_trips_through_analyze(tmp_path):
    code, out, err = run_cli("synth", "problems/slider_crank.toml", "--format", "toml", "--precision", "15",
                             "--out", str(tmp_path))
    assert code == 0, err
    code, again, err = report("analyze", str(tmp_path / "slider_crank.toml"), "--precision", "15")
    assert code == 0, err
    _, first, _ = report("synth", "problems/slider_crank.toml", "--precision", "15")
    first.pop("file"), again.pop("file")
    assert again == first


def independent_monte_carlo(a, b, e, tol, clearance, play, n, seed):
    """Slider position error of made slider-cranks over 36 crank angles every 10 deg: each
    pin journal displaced uniformly over a disc of radius `clearance` (crank pivot, crank
    pin, slider pin), the slider shifted normal to its guide by up to `play`; the rod joins
    the displaced crank pin to the displaced slider pin."""
    rng = np.random.default_rng(seed)
    phi = np.arange(36) * (2 * math.pi / 36)
    nominal = ref_slider(a, b, e, phi)
    da, db, de = (rng.uniform(-tol, tol, (n, 1)) for _ in range(3))
    def disc():
        r = clearance * np.sqrt(rng.random((n, 36)))
        t = rng.random((n, 36)) * 2 * math.pi
        return r * np.cos(t), r * np.sin(t)
    (x1, y1), (x2, y2), (x3, y3) = disc(), disc(), disc()
    g = rng.uniform(-play, play, (n, 36))
    am, bm, em = a + da, b + db, e + de
    ax = x1 + am * np.cos(phi) + x2  # the rod's end at the crank
    ay = y1 + am * np.sin(phi) + y2
    # the slider pin sits at (s, em + g); the rod's other end is the pin minus the journal offset
    rise = (em + g - y3) - ay
    s = ax + np.sqrt(bm * bm - rise * rise) + x3
    return np.max(np.abs(s - nominal), axis=1)


def test_tolerance_agrees_with_an_independent_monte_carlo(tmp_path):
    a, b, e = TEXTBOOK
    f = linkage_file(tmp_path, a, b, e, "[tolerance]\nlengths = 0.05\nclearance = 0.02\n"
                     "clearance_slider = 0.03\nallowed_error = 0.15\nsamples = 20000\n"
                     '[report]\nsections = ["tolerance"]\n')
    code, rep, err = report("synth", f, "--precision", "12")
    assert code == 0, err
    tol = rep["tolerance"]
    ref = independent_monte_carlo(a, b, e, 0.05, 0.02, 0.03, 40000, seed=12345)
    n = tol["samples"]
    mean_se = math.sqrt(ref.var() / len(ref) + ref.var() / n)
    assert tol["error_mean"] == pytest.approx(ref.mean(), abs=5 * mean_se)
    p_ref = float(np.mean(ref > 0.15))
    p_se = math.sqrt(p_ref * (1 - p_ref) / len(ref) + p_ref * (1 - p_ref) / n)
    assert tol["failure_probability"] == pytest.approx(p_ref, abs=5 * p_se)
    assert 0.02 < p_ref < 0.98  # the comparison is not vacuous
    assert tol["error_p95"] == pytest.approx(np.percentile(ref, 95), rel=0.03)
    # sensitivity: max over the 36 angles of |ds/dx| by central differences
    phi = np.arange(36) * (2 * math.pi / 36)
    h = 1e-6
    fd = {"input": (ref_slider(a + h, b, e, phi) - ref_slider(a - h, b, e, phi)) / (2 * h),
          "coupler": (ref_slider(a, b + h, e, phi) - ref_slider(a, b - h, e, phi)) / (2 * h),
          "offset": (ref_slider(a, b, e + h, phi) - ref_slider(a, b, e - h, phi)) / (2 * h)}
    for key, d in fd.items():
        assert tol["sensitivity"][key] == pytest.approx(float(np.max(np.abs(d))), rel=1e-6)


def test_inverse_mode_finds_a_tolerance_at_the_level(tmp_path):
    a, b, e = TEXTBOOK
    f = linkage_file(tmp_path, a, b, e, "[tolerance]\nallowed_error = 0.1\nmax_failure_probability = 0.05\n"
                     'samples = 4000\n[report]\nsections = ["tolerance"]\n')
    code, rep, err = report("synth", f, "--precision", "12")
    assert code == 0, err
    tol = rep["tolerance"]
    t = tol["largest_tolerance"]
    assert tol["failure_probability_at_largest"] <= 0.05
    # independently: at t the failure share is near the level, at 1.2 t clearly above
    at_t = np.mean(independent_monte_carlo(a, b, e, t, 0.0, 0.0, 40000, 7) > 0.1)
    above = np.mean(independent_monte_carlo(a, b, e, 1.2 * t, 0.0, 0.0, 40000, 8) > 0.1)
    assert at_t == pytest.approx(0.05, abs=0.015)
    assert above > 0.05


@pytest.mark.slow
@pytest.mark.parametrize("name", ["slider_crank", "slider_positions"])
def test_plot_is_drawn_and_deterministic(tmp_path, name):
    pytest.importorskip("matplotlib")
    pictures = []
    for k in range(2):
        target = tmp_path / f"{name}_{k}.png"
        code, _, err = run_cli("synth", f"problems/{name}.toml", "--plot", str(target))
        assert code == 0, err
        pictures.append(target.read_bytes())
    assert pictures[0].startswith(b"\x89PNG") and pictures[0] == pictures[1]


def test_check_of_slider_crank_files_imports_neither_numpy_nor_scipy():
    import subprocess
    import sys
    args = ["check", "problems/slider_crank.toml", "problems/slider_positions.toml", "problems/slider_tolerance.toml"]
    code = ("import sys; from linkcli.cli import app\n"
            "try:\n    app(%r, prog_name='linkcli')\nexcept SystemExit as e:\n    assert e.code == 0, e.code\n"
            "heavy = [m for m in ('numpy', 'scipy') if m in sys.modules]\n"
            "assert not heavy, heavy" % (args,))
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)


@pytest.mark.slow
def test_solving_slider_crank_files_does_not_import_scipy():
    import subprocess
    import sys
    args = ["synth", "problems/slider_crank.toml", "problems/slider_positions.toml", "problems/slider_tolerance.toml"]
    code = ("import sys; from linkcli.cli import app\n"
            "try:\n    app(%r, prog_name='linkcli')\nexcept SystemExit as e:\n    assert e.code == 0, e.code\n"
            "assert 'scipy' not in sys.modules" % (args,))
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)


SLIDER_POSITIONS = ('type = "precision-position"\n[linkage]\nmechanism = "slider-crank"\n'
                    "[positions]\ninput = {phi}\noutput = {s}\n")


@pytest.mark.parametrize("phi, s, found", [
    ([30, 150, 90], [10, -10, 5], "positions 1, 2, 3 give a singular system"),
    ([0, 40, 100, 200], [7, 7, 7, 7], "positions 1, 2, 3, 4 give a zero crank"),
    ([0, 90, 180], [0, 0, 0], "positions 1, 2, 3 all at s = 0"),
])
def test_check_refuses_impossible_slider_positions_as_synth_does(tmp_path, phi, s, found):
    path = tmp_path / "p.toml"
    path.write_text(SLIDER_POSITIONS.format(phi=phi, s=s))
    outputs = {command: run_cli(command, str(path)) for command in ("check", "synth")}
    assert outputs["check"] == outputs["synth"]
    code, out, err = outputs["check"]
    assert (code, out) == (2, "") and found in err and err.startswith(f"{path}:5: positions: expected")


@pytest.mark.parametrize("s, index, found", [
    ("[-1e308, 117.366946, 85.254772]", 0, "-1e+308"),  # passed check; synth blamed `linkage`
    ("[40, 1000000001, 85]", 1, "1000000001"),
])
def test_a_slider_position_beyond_the_sizes_is_refused_on_its_item(tmp_path, s, index, found):
    path = tmp_path / "p.toml"
    path.write_text(SLIDER_POSITIONS.format(phi=[30, 90, 150], s=s))
    outputs = {command: run_cli(command, str(path)) for command in ("check", "synth")}
    assert outputs["check"] == outputs["synth"]
    code, out, err = outputs["check"]
    assert (code, out) == (2, "")
    assert err == (f"{path}:6: positions.output[{index}]: expected a slider position of magnitude at most "
                   f"1e+09 (length unit), found {found}\n")


@pytest.mark.slow
def test_check_and_synth_agree_on_random_slider_positions(tmp_path):
    """Random position sets (three to six, some near-degenerate): `check` refuses exactly
    the files `synth` refuses (exit 2), with the same line."""
    rng = np.random.default_rng(11)
    for trial in range(40):
        n = int(rng.integers(3, 7))
        phi = np.round(rng.uniform(-180, 180, n), 1).tolist()
        s = np.round(rng.uniform(-5, 5, n) if trial % 4 else np.full(n, rng.uniform(1, 5)), 2).tolist()
        path = tmp_path / f"r{trial}.toml"
        path.write_text(SLIDER_POSITIONS.format(phi=phi, s=s))
        code, _, err = run_cli("check", str(path))
        synth_code, _, synth_err = run_cli("synth", str(path), "--format", "json")
        assert (code == 2) == (synth_code == 2), (phi, s, err, synth_err)
        if code == 2:
            assert err == synth_err


def test_pure_python_least_squares_against_numpy():
    from linkcli.types.precision_position.slider_system import least_squares, subset_combinations
    rng = np.random.default_rng(2)
    for n in (3, 4, 9):
        for _ in range(20):
            m, b = rng.normal(size=(n, 3)), rng.normal(size=n)
            assert least_squares(m.tolist(), b.tolist()) == pytest.approx(
                np.linalg.lstsq(m, b, rcond=None)[0], rel=1e-10, abs=1e-12)
    for n in (3, 6, 7, 12):  # every triple up to 20 of them, else 20 spread from first to last
        combos = subset_combinations(n)
        every = list(itertools.combinations(range(n), 3))
        assert combos == every if len(every) <= 20 else (
            len(combos) == 20 and combos[0] == every[0] and combos[-1] == every[-1]
            and all(a < b for a, b in zip(combos, combos[1:])))


@pytest.mark.parametrize("mechanism", ["slider-crank", "four-bar"])
def test_a_written_zero_length_tolerance_is_exact_parts_for_both_mechanisms(tmp_path, mechanism):
    """Inverse tolerance (max_failure_probability): without `lengths` the study runs at the
    largest tolerance found; `lengths = 0` written is exact parts, studied as written."""
    linkage = ('mechanism = "slider-crank"\ninput = 47.2812\ncoupler = 104.9139\noffset = 30\n'
               if mechanism == "slider-crank" else
               "ground = 50\ninput = 27.6293\ncoupler = 57.2363\noutput = 41.1104\n")
    allowed = "0.2" if mechanism == "slider-crank" else "0.5"
    studies = {}
    for name, written in (("absent", ""), ("zero", "lengths = 0\n")):
        path = tmp_path / f"{name}.toml"
        path.write_text(f'type = "linkage"\n[linkage]\n{linkage}[tolerance]\n{written}'
                        f"clearance = 0.02\nallowed_error = {allowed}\n"
                        "max_failure_probability = 0.01\nsamples = 2000\n")
        code, out, err = run_cli("analyze", str(path), "--format", "json")
        assert code == 0, err
        studies[name] = json.loads(out)["tolerance"]
    largest = studies["absent"]["largest_tolerance"]
    assert largest > 0 and studies["zero"]["largest_tolerance"] == largest
    assert set(studies["absent"]["lengths"].values()) == {largest}
    assert set(studies["zero"]["lengths"].values()) == {0.0}
    assert studies["zero"]["failure_probability"] <= studies["absent"]["failure_probability"]
