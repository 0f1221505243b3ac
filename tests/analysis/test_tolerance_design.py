"""Tolerance design against independent references.

- ISO 286-2 table rows (limit deviations of tolerance classes, um) and ISO 2768-1 Table 1
  rows, typed here from the published tables, against linkcli.standards.
- Fits in the Monte Carlo against a separate Monte Carlo written here: each pin's hole and
  shaft drawn within the published zones, the radial clearance half their difference, the
  journal anywhere within it, the made slider-crank assembled from its pins.
- The least-cost allocation against a brute-force search over a grid of tolerances, each
  judged by this file's own Monte Carlo of the four-bar (closed-form loop closure).
- The inverse search against a plain bisection on the same draws.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from linkcli.standards import iso286, iso2768

ROOT = Path(__file__).resolve().parents[2]

# ---------------------------------------------------------------- ISO 286-2 rows

# (class, nominal size mm, lower deviation um, upper deviation um), ISO 286-2 tables
ISO286_ROWS = [
    ("H6", 12, 0, 11), ("H7", 10, 0, 15), ("H7", 25, 0, 21), ("H7", 40, 0, 25), ("H7", 100, 0, 35),
    ("H7", 200, 0, 46), ("H7", 450, 0, 63), ("H8", 50, 0, 39), ("H9", 100, 0, 87), ("H11", 8, 0, 90),
    ("F8", 25, 20, 53), ("G7", 10, 5, 20), ("E9", 20, 40, 92), ("D10", 50, 80, 180), ("C11", 8, 80, 170),
    ("K6", 8, -7, 2), ("K7", 25, -15, 6), ("M7", 25, -21, 0), ("N7", 25, -28, -7), ("P7", 25, -35, -14),
    ("S7", 20, -48, -27), ("S7", 110, -101, -66), ("T7", 35, -64, -39), ("U7", 20, -54, -33),
    ("M6", 300, -41, -9), ("JS7", 8, -7.5, 7.5), ("P7", 2, -16, -6),
    ("g6", 10, -14, -5), ("g6", 25, -20, -7), ("f7", 50, -50, -25), ("f7", 2, -16, -6), ("e8", 20, -73, -40),
    ("d9", 100, -207, -120), ("c11", 8, -170, -80), ("b11", 20, -290, -160), ("a11", 20, -430, -300),
    ("h6", 40, -16, 0), ("h11", 8, -90, 0), ("js6", 8, -4.5, 4.5), ("k6", 25, 2, 15), ("k6", 2, 0, 6),
    ("m6", 25, 8, 21), ("n6", 25, 15, 28), ("p6", 25, 22, 35), ("r6", 60, 41, 60), ("s6", 150, 100, 125),
    ("t6", 35, 48, 64), ("u6", 20, 41, 54),
]


@pytest.mark.parametrize("cls, size, lower, upper", ISO286_ROWS)
def test_iso286_zones_match_published_rows(cls, size, lower, upper):
    letter, grade = cls.rstrip("0123456789"), int(cls[len(cls.rstrip("0123456789")):])
    zone = (iso286.hole if letter[0].isupper() else iso286.shaft)(letter, grade, size)
    assert (zone.lower, zone.upper) == (lower, upper)


@pytest.mark.parametrize("fit, size, kind, least, largest", [
    ("H7/g6", 25, "clearance", 7, 41),       # the example of ISO 286 and the issue
    ("H7/h6", 40, "clearance", 0, 41),
    ("H8/f7", 50, "clearance", 25, 89),
    ("H11/c11", 8, "clearance", 80, 260),
    ("H7/k6", 25, "transition", -15, 19),
    ("H7/p6", 25, "interference", -35, -1),
])
def test_fits_clearance_and_kind(fit, size, kind, least, largest):
    f = iso286.limits(fit, size)
    assert f.kind == kind
    assert f.clearance == (least, largest)


@pytest.mark.parametrize("text, size, says", [
    ("H7/g6", 600, "up to 500 mm"), ("H7/z6", 10, "shaft letter"), ("J7/g6", 10, "hole letter"),
    ("H7g6", 10, '"HOLE/shaft"'), ("H19/g6", 10, "grade from 1 to 18"), ("H7/t6", 20, "over 24 mm"),
    ("A11/h11", 0.8, "over 1 mm"),
])
def test_fits_outside_the_tables_are_refused(text, size, says):
    with pytest.raises(iso286.FitError, match=says.replace('"', '.')):
        iso286.limits(text, size)


# ---------------------------------------------------------------- ISO 2768-1 rows

@pytest.mark.parametrize("cls, size, dev", [
    ("f", 2, 0.05), ("m", 2, 0.1), ("c", 2, 0.2), ("f", 5, 0.05), ("m", 5, 0.1), ("c", 5, 0.3),
    ("v", 5, 0.5), ("m", 20, 0.2), ("m", 30, 0.2), ("m", 30.5, 0.3), ("f", 100, 0.15), ("c", 100, 0.8),
    ("v", 100, 1.5), ("m", 300, 0.5), ("m", 800, 0.8), ("c", 1500, 3.0), ("v", 3000, 8.0), ("m", 3000, 2.0),
    ("f", 0.5, 0.05), ("m", -47, 0.3),
])
def test_iso2768_matches_table_1(cls, size, dev):
    assert iso2768.deviation(cls, size) == dev


@pytest.mark.parametrize("cls, size", [("m", 0.3), ("v", 2), ("f", 3000), ("m", 5000), ("m", 0)])
def test_iso2768_has_no_general_tolerance_there(cls, size):
    with pytest.raises(iso2768.GeneralToleranceError):
        iso2768.deviation(cls, size)


# ---------------------------------------------------------------- files and the CLI

def run_cli(*args):
    from typer.testing import CliRunner

    from linkcli.cli import app
    result = CliRunner().invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def synth_json(path):
    import json
    code, out, err = run_cli("synth", str(path), "--format", "json", "--precision", "15")
    return code, (json.loads(out) if code in (0, 1) else None), err


SLIDER = (47.2812, 104.9139, 30.0)  # the textbook quick-return slider-crank (mm)
# published zones (um) of the fits used below, ISO 286-2: hole (EI, ES), shaft (ei, es)
ZONES = {("H7/g6", 12): ((0, 18), (-17, -6)), ("H7/g6", 10): ((0, 15), (-14, -5)),
         ("H8/f7", 10): ((0, 22), (-28, -13)), ("H7/f7", 20): ((0, 21), (-41, -20)),
         ("H6/g5", 10): ((0, 9), (-11, -5)), ("H6/g5", 12): ((0, 11), (-14, -6)),
         ("H6/g5", 20): ((0, 13), (-16, -7)), ("H9/d9", 10): ((0, 36), (-76, -40)),
         ("H9/d9", 12): ((0, 43), (-93, -50)), ("H9/d9", 20): ((0, 52), (-117, -65)),
         ("H8/f7", 12): ((0, 27), (-34, -16)), ("H8/f7", 20): ((0, 33), (-41, -20)),
         ("H7/g6", 20): ((0, 21), (-20, -7))}
SIZES = {"A0": 12, "A": 10, "B": 10, "guide": 20}


def slider_file(tmp_path, fits: dict, tolerance: str, name="fits.toml"):
    joints = "\n".join(f'{j} = {{ diameter = {SIZES[j]}, fit = "{f}" }}' for j, f in fits.items())
    a, b, e = SLIDER
    text = (f'type = "linkage"\n[linkage]\nmechanism = "slider-crank"\ninput = {a}\ncoupler = {b}\n'
            f'offset = {e}\n[joints]\n{joints}\n{tolerance}\n[report]\nsections = ["tolerance"]\n')
    path = tmp_path / name
    path.write_text(text)
    return path


def ref_slider(a, b, e, phi):
    return a * np.cos(phi) + np.sqrt(b * b - (e - a * np.sin(phi)) ** 2)


def reference_fits_mc(fits: dict, lengths, n, seed, distribution="uniform"):
    """Slider error over 36 crank angles every 10 deg (the nominal slider there the target):
    crank, rod, offset each +- `lengths`; each pin's hole and shaft drawn within their
    published zones (uniform, or normal with the half zone as 3 sigma), the journal anywhere
    in the radial clearance (hole - shaft) / 2 at each angle; the slider shifted normal to
    its guide by up to the guide's radial clearance. inf where a shaft beats its hole."""
    rng = np.random.default_rng(seed)
    a, b, e = SLIDER
    phi = np.arange(36) * (2 * math.pi / 36)
    nominal = ref_slider(a, b, e, phi)

    def within(lo, hi, size):
        if distribution == "normal":
            return (lo + hi) / 2 + (hi - lo) / 6 * rng.standard_normal(size)
        return rng.uniform(lo, hi, size)

    da, db, de = (within(-lengths, lengths, (n, 1)) for _ in range(3))
    radius = {}
    for joint in ("A0", "A", "B", "guide"):
        (h0, h1), (s0, s1) = ZONES[(fits[joint], SIZES[joint])]
        radius[joint] = (within(h0, h1, (n, 1)) - within(s0, s1, (n, 1))) / 2000.0  # um -> mm, radial
    jammed = np.any(np.hstack([radius[j] for j in radius]) < 0, axis=1)

    def journal(r):
        rho = np.maximum(r, 0) * np.sqrt(rng.random((n, 36)))
        t = rng.random((n, 36)) * 2 * math.pi
        return rho * np.cos(t), rho * np.sin(t)

    (x1, y1), (x2, y2), (x3, y3) = journal(radius["A0"]), journal(radius["A"]), journal(radius["B"])
    g = np.maximum(radius["guide"], 0) * rng.uniform(-1, 1, (n, 36))
    am, bm, em = a + da, b + db, e + de
    ax = x1 + am * np.cos(phi) + x2
    ay = y1 + am * np.sin(phi) + y2
    rise = (em + g - y3) - ay
    s = ax + np.sqrt(bm * bm - rise * rise) + x3
    err = np.max(np.abs(s - nominal), axis=1)
    return np.where(jammed, np.inf, err)


@pytest.mark.slow
@pytest.mark.parametrize("distribution, allowed", [("uniform", 0.07), ("normal", 0.05)])
def test_fits_agree_with_a_separate_monte_carlo(tmp_path, distribution, allowed):
    fits = {"A0": "H7/g6", "A": "H7/g6", "B": "H8/f7", "guide": "H7/f7"}
    path = slider_file(tmp_path, fits, f'[tolerance]\nlengths = 0.02\nclearance = "fits"\ndistribution = "{distribution}"\n'
                       f"allowed_error = {allowed}\nsamples = 20000\n")
    code, rep, err = synth_json(path)
    assert code == 0, err
    tol = rep["tolerance"]
    ref = reference_fits_mc(fits, 0.02, 40000, 99, distribution)
    good = ref[np.isfinite(ref)]
    n = tol["samples"]
    p_ref = float(np.mean(ref > allowed))
    assert 0.05 < p_ref < 0.95  # not vacuous
    p_se = math.sqrt(p_ref * (1 - p_ref) * (1 / len(ref) + 1 / n))
    assert tol["failure_probability"] == pytest.approx(p_ref, abs=5 * p_se)
    mean_se = math.sqrt(good.var() * (1 / len(good) + 1 / n))
    assert tol["error_mean"] == pytest.approx(good.mean(), abs=5 * mean_se)
    assert tol["error_p95"] == pytest.approx(np.percentile(good, 95), rel=0.03)
    rows = {r["joint"]: r for r in tol["fits"]}
    for joint, fit in fits.items():
        (h0, h1), (s0, s1) = ZONES[(fit, SIZES[joint])]
        assert rows[joint]["hole_um"] == [h0, h1] and rows[joint]["shaft_um"] == [s0, s1]
        assert rows[joint]["radial_clearance"] == pytest.approx([(h0 - s1) / 2000, (h1 - s0) / 2000], rel=1e-12)


@pytest.mark.slow
def test_schemes_agree_with_a_separate_monte_carlo_and_rank_by_cost(tmp_path):
    schemes = {"precision": ("H6/g5", 0.02), "close": ("H8/f7", 0.01), "free": ("H9/d9", 0.01),
               "sliding": ("H7/g6", 0.03)}
    text = ('[tolerance]\nclearance = "fits"\nallowed_error = 0.1\nmax_failure_probability = 0.01\nsamples = 20000\n'
            '[tolerance.cost]\nmodel = "reciprocal-power"\na = 0.5\nb = 0.02\nk = 1.0\nbounds = [0.005, 0.3]\n'
            'guide = { b = 0.04 }\n')
    for name, (fit, t) in schemes.items():
        fits = ", ".join(f'{j} = "{fit}"' for j in SIZES)
        text += f'[[tolerance.schemes]]\nname = "{name}"\nfits = {{ {fits} }}\nlengths = {t}\n'
    base = {"A0": "H7/g6", "A": "H7/g6", "B": "H7/g6", "guide": "H7/f7"}
    code, rep, err = synth_json(slider_file(tmp_path, base, text))
    assert code == 0, err
    rows = {r["scheme"]: r for r in rep["tolerance"]["schemes"]}
    n = rep["tolerance"]["samples"]
    for k, (name, (fit, t)) in enumerate(schemes.items()):
        fits = {j: fit for j in SIZES}
        ref = reference_fits_mc(fits, t, 40000, 100 + k)
        p_ref = float(np.mean(ref > 0.1))
        p_se = math.sqrt(max(p_ref * (1 - p_ref), 1e-4) * (1 / len(ref) + 1 / n))
        assert rows[name]["failure_probability"] == pytest.approx(p_ref, abs=5 * p_se)
        # cost: a + b / t per link, and per joint its hole and shaft at their half zones (um -> mm)
        cost = 3 * (0.5 + 0.02 / t)
        for joint in SIZES:
            (h0, h1), (s0, s1) = ZONES[(fit, SIZES[joint])]
            b = 0.04 if joint == "guide" else 0.02
            cost += (0.5 + b / ((h1 - h0) / 2000)) + (0.5 + b / ((s1 - s0) / 2000))
        assert rows[name]["cost"] == pytest.approx(cost, rel=1e-12)
    ranked = rep["tolerance"]["schemes"]
    assert [r["rank"] for r in ranked] == [1, 2, 3, 4]
    meeting = [r for r in ranked if r["meets"]]
    assert meeting and [r["cost"] for r in meeting] == sorted(r["cost"] for r in meeting)
    assert all(r["meets"] for r in ranked[:len(meeting)])  # those that meet the limit come first
    assert {r["scheme"] for r in meeting} == {"precision", "close"}  # H9/d9 and +-0.03 miss 0.1 mm


def test_solve_time_errors_are_located(tmp_path):
    a, b, e = SLIDER
    zero = tmp_path / "zero.toml"
    zero.write_text(f'type = "linkage"\n[linkage]\nmechanism = "slider-crank"\ninput = {a}\ncoupler = {b}\n'
                    'offset = 0\n[tolerance]\nlengths = "ISO 2768-m"\nallowed_error = 0.1\nsamples = 100\n')
    code, out, err = run_cli("synth", str(zero))
    assert code == 2
    assert err.startswith(f"{zero}:8: tolerance.lengths: expected a nominal size from 0.5 to 4000 mm for ISO 2768-m")
    assert "offset 0 mm" in err
    missing = slider_file(tmp_path, {"A0": "H7/g6", "A": "H7/g6"}, '[tolerance]\nclearance = "fits"\nsamples = 100\n',
                          name="missing.toml")
    code, out, err = run_cli("synth", str(missing))
    assert code == 2
    assert 'tolerance.clearance: expected a fit for every pin (A0, A, B): B = { diameter = ..., fit = "H7/g6" }' in err
    assert err.startswith(f"{missing}:")


# ---------------------------------------------------------------- least-cost allocation

FIRE = {"ground": 50.0, "input": 27.6293, "coupler": 57.2363, "output": 41.1104}
PHI = np.radians([45.0, 90.0, 135.0])


def reference_four_bar_errors(t: dict, u: np.ndarray) -> np.ndarray:
    """Largest output-angle error (deg) over the three fire-door positions of four-bars made
    with lengths + t * u (u: unit draws, columns ground, input, coupler, output), assembled on
    the open branch by the convention of docs/format.md: psi = theta_rho - alpha with rho the
    vector B0 -> A; inf where one cannot assemble."""
    d, a, b, c = (FIRE[k] + t[k] * u[:, j:j + 1] for j, k in enumerate(("ground", "input", "coupler", "output")))
    nd, na, nb, nc = (FIRE[k] for k in ("ground", "input", "coupler", "output"))

    def psi(a, b, c, d):
        rx, ry = a * np.cos(PHI) - d, a * np.sin(PHI)
        rho = np.hypot(rx, ry)
        cos_alpha = (rho * rho + c * c - b * b) / (2 * rho * c)
        with np.errstate(invalid="ignore"):
            return np.arctan2(ry, rx) - np.arccos(cos_alpha), np.abs(cos_alpha) <= 1

    made, ok = psi(a, b, c, d)
    nominal, _ = psi(na, nb, nc, nd)
    dev = np.degrees(np.abs((made - nominal + np.pi) % (2 * np.pi) - np.pi))
    return np.where(np.all(ok, axis=1), dev.max(axis=1), np.inf)


@pytest.mark.slow
def test_allocation_against_a_brute_force_search(tmp_path):
    # Two free tolerances (input, coupler), ground and output held near 0.02 mm by their
    # bounds; the coupler's tolerance costs twice the input's: c = b / t.
    path = tmp_path / "alloc.toml"
    path.write_text('type = "precision-position"\n[linkage]\nground = 50.0\n[positions]\n'
                    "input = [45, 90, 135]\noutput = [52, 82, 112]\n[tolerance]\nallowed_error = 0.25\n"
                    "max_failure_probability = 0.01\nsamples = 20000\n[tolerance.cost]\n"
                    'model = "reciprocal"\nb = 0.05\nbounds = [0.005, 0.2]\ncoupler = { b = 0.1 }\n'
                    "ground = { bounds = [0.0199, 0.02] }\noutput = { bounds = [0.0199, 0.02] }\n[solver]\nseed = 3\n")
    code, rep, err = synth_json(path)
    assert code == 0, err
    alloc = rep["tolerance"]["allocation"]
    t = {row["link"]: row["tolerance"] for row in alloc["links"]}
    assert alloc["meets"] and alloc["failure_probability_ci95"][1] <= 0.01
    assert t["ground"] == pytest.approx(0.02) and t["output"] == pytest.approx(0.02)
    cost = lambda tol: sum((0.1 if k == "coupler" else 0.05) / v for k, v in tol.items())  # noqa: E731
    assert alloc["cost"] == pytest.approx(cost(t), rel=1e-9)
    u = np.random.default_rng(2024).uniform(-1, 1, (50000, 4))  # this test's own draws
    p_alloc = float(np.mean(reference_four_bar_errors(t, u) > 0.25))
    assert p_alloc <= 0.0105  # its own Monte Carlo agrees that the allocation meets the limit
    best = math.inf
    for ti in np.geomspace(0.01, 0.1, 41):
        for tc in np.geomspace(0.01, 0.1, 41):
            trial = {"ground": t["ground"], "input": ti, "coupler": tc, "output": t["output"]}
            if cost(trial) < best and np.mean(reference_four_bar_errors(trial, u) > 0.25) <= p_alloc:
                best = cost(trial)
    # no grid point as reliable is cheaper (beyond the sampling scatter), and the best is near
    assert alloc["cost"] <= best * 1.005
    assert best <= alloc["cost"] * 1.03
    # the cost makes the expensive coupler looser than the input, relative to their sensitivity
    assert t["coupler"] > t["input"] * 0.5


def test_inverse_search_equals_a_plain_bisection_on_the_same_draws():
    from linkcli.analysis import inverse_search
    from linkcli.analysis import tolerance as tolmod
    from linkcli.analysis.made_parts import Parts
    from linkcli.mechanisms.four_bar import tolerance as four_bar
    from linkcli.mechanisms.four_bar.model import FourBar
    from linkcli.solution import Positions, Solution, Status
    fb = FourBar(**FIRE, branch="open")
    psi = np.radians([52.0, 82.0, 112.0])
    sol = Solution(status=Status.OK, linkage=fb, positions=Positions("angle", PHI, psi, psi, np.zeros(3)),
                   working_span=(float(PHI[0]), float(PHI[-1] - PHI[0])))

    class P:
        meta = None
    model = four_bar.Model(fb, four_bar.targets(P, sol))
    for clearance, distribution, level, start in ((0.02, "uniform", 0.01, 0.05), (0.0, "normal", 0.05, 0.01),
                                                  (0.01, "uniform", 0.2, 0.001)):
        parts = Parts(np.zeros(6), clearance, 0.0)
        plan = tolmod.plan_of(model, parts, 8000, distribution)
        search = inverse_search.Search(model, parts, plan, 5, math.radians(0.25))
        got = inverse_search.largest_tolerance(search, level, start, model.cap)

        def prob(x):  # every sample assembled at every step
            err, ok = tolmod.run(model, tolmod.chunks(5, plan), parts.with_scale(search.unit * x))
            return float(np.mean(~ok | (err > math.radians(0.25))))
        lo, hi = 0.0, max(start, 1e-3 * model.cap)  # doubling from the start (at least 1e-3 of the cap)
        while prob(hi) <= level:
            lo, hi = hi, 2 * hi
        while hi - lo > inverse_search.BISECTION_RTOL * hi:
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if prob(mid) <= level else (lo, mid)
        assert got == (lo, prob(lo))
        if clearance == 0.02:  # the work: two passes over every sample, the bisection on a few
            assert search.full_passes == 2 and search.partial_samples < 0.1 * 8000 * 14


# ---------------------------------------------------------------- designs that minimize failure

def quadratic_law_errors(a, b, c, d, t, u, allowed_deg):
    """Per target, the share of four-bars made with (a, b, c, d) + t * u (u unit draws,
    columns input, coupler, output, ground) missing psi0 + 2/(3 pi) (phi - phi0)^2 at 31
    points over 90 deg from the extended dead-centre (open branch, docs/format.md: phi0 and
    psi0 from the triangle A0 B0 B with |A0 B| = a + b) by more than `allowed_deg`; and the
    share assembling at every point."""
    ab = a + b
    phi0 = math.acos((ab * ab + d * d - c * c) / (2 * ab * d))
    psi0 = math.acos((ab * ab - c * c - d * d) / (2 * c * d))
    phi = phi0 + np.linspace(0.0, math.pi / 2, 31)
    target = psi0 + 2 / (3 * math.pi) * (phi - phi0) ** 2
    am, bm, cm, dm = (x + t * u[:, j:j + 1] for j, x in enumerate((a, b, c, d)))
    rx, ry = am * np.cos(phi) - dm, am * np.sin(phi)
    rho = np.hypot(rx, ry)
    cos_alpha = (rho * rho + cm * cm - bm * bm) / (2 * rho * cm)
    with np.errstate(invalid="ignore"):
        psi = np.arctan2(ry, rx) - np.arccos(cos_alpha)
    assembles = np.abs(cos_alpha) <= 1
    dev = np.degrees(np.abs((psi - target + np.pi) % (2 * np.pi) - np.pi))
    fails = ~assembles | (dev > allowed_deg)
    return fails.mean(axis=0), float(np.mean(np.all(assembles, axis=1)))


@pytest.mark.slow
def test_robust_function_generation_against_a_separate_monte_carlo(tmp_path):
    text = (ROOT / "problems" / "robust_function.toml").read_text()
    text = text.replace("clearance = 0.1 ", "clearance = 0.0 ")  # lengths only: the reference below
    path = tmp_path / "robust.toml"
    path.write_text(text)
    code, rep, err = synth_json(path)
    assert code == 0, err
    designs = {row["design"]: row for row in rep["robust"]["designs"]}
    lsq, rob = designs["least squares"], designs["robust"]
    assert (rep["linkage"]["coupler"], rep["linkage"]["output"]) == (rob["coupler"], rob["output"])
    u = np.random.default_rng(77).uniform(-1, 1, (40000, 4))
    for row in (lsq, rob):
        per, defect_free = quadratic_law_errors(row["input"], row["coupler"], row["output"], row["ground"],
                                                0.5, u, 1.8)
        p = float(per.max())
        se = math.sqrt(max(p * (1 - p), 1e-4) * (1 / 40000 + 1 / 20000))
        assert row["largest_failure_probability"] == pytest.approx(p, abs=5 * se)
        assert row["at_target"] == int(np.argmax(per)) + 1 or abs(per[row["at_target"] - 1] - p) < 5 * se
        assert row["defect_free"] == pytest.approx(defect_free, abs=0.002)
    assert lsq["largest_failure_probability"] > 0.9 > 0.05 > rob["largest_failure_probability"]
    assert rob["defect_free"] >= 0.99
    # the least-squares design's error is the smaller in squares, the robust one's at its worst
    assert rob["error_max"] < lsq["error_max"]
    assert rep["error"]["objective"] > 0.0075924  # the least-squares optimum (problems/crank_rocker.toml)
