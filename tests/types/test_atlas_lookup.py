"""Looking targets up in the atlas: targets traced by known four-bars (with an independent
closure written here) are found, placed back onto the targets, and polished by the search
to an exact fit; [solver] atlas = false keeps the atlas out; the atlas is loaded only by
a free-timing search."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT

from linkcli.atlas import cache
from linkcli.types.path_generation import atlas_starts as lookup

FRAME = dict(scale=23.0, turn=0.7, move=(40.0, -15.0))


def _coupler(d, a, b, c, px, py, sign, phi):
    """Coupler point (complex), docs/format.md, independently of linkcli's closures."""
    A = a * np.exp(1j * np.asarray(phi, dtype=float))
    v = A - d
    alpha = np.arccos(np.clip((abs(v) ** 2 + c * c - b * b) / (2 * abs(v) * c), -1, 1))
    B = d + c * np.exp(1j * (np.angle(v) + sign * alpha))
    return A + complex(px, py) * np.exp(1j * np.angle(B - A))


def _problem(tmp_path, points, extra: str = "") -> str:
    text = ('type = "path-generation"\n[target]\ntiming = "free"\npoints = ['
            + ", ".join(f"[{float(p.real)!r}, {float(p.imag)!r}]" for p in points) + "]\n" + extra)
    path = tmp_path / "target.toml"
    path.write_text(text)
    return str(path)


def _design(path):
    from linkcli.io.safe_read import read_problem_bytes
    from linkcli.reading.load import load
    from linkcli.types.path_generation.model import build
    problem = load(path, read_problem_bytes(path))
    return problem, build(problem)


def _placed(z):
    return z * FRAME["scale"] * np.exp(1j * FRAME["turn"]) + complex(*FRAME["move"])


def _member_targets(atlas, row, n, share, start=0.3):
    """n targets on atlas curve `row` over `share` of its input's travel, in the frame FRAME."""
    from linkcli.atlas.family import rocking_range
    (a, b, c), (px, py), sign = atlas.linkages.lengths[row], atlas.linkages.point[row], atlas.linkages.sign[row]
    if row < atlas.closed:
        lo, hi = start * 2 * math.pi, start * 2 * math.pi + 2 * math.pi
    else:
        lo, hi = (float(v) for v in rocking_range(a, b, c))
        lo, hi = lo + 0.05 * (hi - lo), hi - 0.05 * (hi - lo)
    t = np.sort(np.random.default_rng(row).uniform(0, 1, n))
    t = (t - t[0]) / (t[-1] - t[0]) * (0.97 if share == 1.0 else share)
    return _placed(_coupler(1.0, a, b, c, px, py, sign, lo + t * (hi - lo)))


@pytest.fixture(scope="module")
def atlas():
    found = cache.get()
    assert found is not None
    return found


@pytest.mark.parametrize("row_share, n, share", [(0.1, 24, 1.0), (0.3, 9, 0.45), (0.45, 15, 0.7),
                                                 (0.8, 8, 0.6), (0.95, 12, 0.9)])
def test_a_member_of_the_atlas_is_found_and_placed_back(tmp_path, atlas, row_share, n, share):
    row = int(row_share * atlas.size)
    targets = _member_targets(atlas, row, n, share)
    _, design = _design(_problem(tmp_path, targets))
    x, sign, s, cost, _ = lookup.starts(design, atlas, 32)
    extent = design.scale
    assert math.sqrt(cost[0] / n) < 0.02 * extent  # the best start: within 2 % rms of the targets
    obj = design.objective(x[:1], sign[:1], s[:1])[0]
    assert math.sqrt(obj / n) < 0.02 * extent  # and it is what the design's own model says


WIDE = """[bounds]
ground = [0, 1000]
input = [0, 1000]
coupler = [0, 1000]
output = [0, 1000]
coupler_point = { x = [-1000, 1000], y = [-1000, 1000] }
ground_pivot = { x = [-1000, 1000], y = [-1000, 1000] }
"""


@pytest.mark.parametrize("row_share, start, backwards", [(0.1, 0.37, False), (0.2, 0.81, True),
                                                         (0.34, 0.55, True), (0.38, 0.2, False),
                                                         (0.5, 0.3, False)])
def test_a_loop_of_the_atlas_is_found_from_any_start_and_either_way_round(tmp_path, atlas, row_share, start,
                                                                          backwards):
    """Sixty targets around a whole loop of an atlas curve (crank-rockers, small cranks at
    the edge, a double-crank: loops of distinct shapes; a near-circle matches every other
    near-circle), started anywhere, run either way, turned, scaled and moved: the start-free
    ring match ranks that curve first, in the right sense, and places it back onto the
    targets (the cosine descriptor of a stretch, stored from eight starts and matched from
    four, ranked such a loop by where its start fell)."""
    row = int(row_share * atlas.size)
    assert row < atlas.closed
    (a, b, c), (px, py), sign = atlas.linkages.lengths[row], atlas.linkages.point[row], atlas.linkages.sign[row]
    phi = 2 * math.pi * (start + np.arange(60) / 60)
    targets = _placed(_coupler(1.0, a, b, c, px, py, sign, phi[::-1] if backwards else phi))
    _, design = _design(_problem(tmp_path, targets, WIDE))  # a small crank's ground is many extents
    assert lookup.looks_closed(design.targets)
    curve, _, length, sense, _ = lookup.hits(design, atlas, lookup.allowed(design, atlas))
    assert curve[0] == row and length[0] == 1.0 and sense[0] == (-1.0 if backwards else 1.0)
    x, sign_, s, cost, _ = lookup.starts(design, atlas, 8)
    assert math.sqrt(cost[0] / 60) < 2e-3 * design.scale
    assert math.sqrt(design.objective(x[:1], sign_[:1], s[:1])[0] / 60) < 2e-3 * design.scale


@pytest.mark.parametrize("case", (0, 2))
def test_a_known_four_bar_outside_the_atlas_is_polished_to_an_exact_fit(tmp_path, case):
    """Targets of crank-rockers drawn here (not atlas members), closed and partial: the
    search from the atlas's starts ends exact, `ok`, as the independent closure checks.
    (Case 1, ten points over half a loop, ends `not-converged` at 3e-12 with or without
    the atlas: a flat valley where no two rounds agree, as docs/path_generation.md says
    of short arcs.)"""
    rng = np.random.default_rng([50, case])
    while True:
        d, a, b, c = 1.0, rng.uniform(0.15, 0.4), rng.uniform(0.8, 2.0), rng.uniform(0.8, 2.0)
        s_l, p_q = min(a, b, c, d) + max(a, b, c, d), sorted([a, b, c, d])[1] + sorted([a, b, c, d])[2]
        if a == min(a, b, c, d) and s_l < 0.95 * p_q:
            break
    px, py = rng.uniform(-1, 2), rng.uniform(-1, 1)
    n = (14, 10, 20)[case]
    span = (0.92, 0.5, 0.75)[case]
    phi = 0.4 + np.sort(rng.uniform(0, 1, n)) * span * 2 * math.pi
    targets = _placed(_coupler(d, a, b, c, px, py, -1.0, phi))
    path = _problem(tmp_path, targets, '[constraints]\ngrashof = "crank-rocker"\n')
    from linkcli.pipeline import solve
    problem, design = _design(path)
    sol = solve(problem)
    assert sol.status.value == "ok"
    lk = sol.linkage
    got = (complex(*lk.ground_pivot) + np.exp(1j * lk.ground_angle)
           * _coupler(lk.ground, lk.input, lk.coupler, lk.output, *lk.coupler_point,
                      -1.0 if lk.branch == "open" else 1.0, sol.positions.input))
    assert np.max(np.abs(got - targets)) < 1e-7 * design.scale


def test_atlas_false_never_asks_the_atlas(tmp_path, monkeypatch, atlas):
    from linkcli.pipeline import solve
    from linkcli.types.path_generation import atlas_starts

    def refuse(*args, **kwargs):
        raise AssertionError("the atlas was asked")
    monkeypatch.setattr(atlas_starts, "starts_for", refuse)
    targets = _member_targets(atlas, 10, 12, 1.0)
    problem, _ = _design(_problem(tmp_path, targets, "[solver]\natlas = false\n"))
    assert solve(problem).status.value == "ok"
    problem, _ = _design(_problem(tmp_path, targets))
    with pytest.raises(AssertionError, match="the atlas was asked"):
        solve(problem)


LOADED = """\
import sys
sys.argv = ["linkcli"] + sys.argv[1:]
from linkcli.cli import main
try:
    main()
finally:
    sys.stderr.write("\\nLOADED " + " ".join(sorted(sys.modules)) + "\\n")
"""


@pytest.mark.parametrize("args, loads", [
    (["analyze", "problems/firedoor_motion.toml"], False),
    (["synth", "problems/bench/closed18_timed.toml"], False),  # prescribed timing
    (["synth", "problems/bench/arc6_timed.toml"], False),
    (["synth", "problems/bench/closed_curve12.toml"], True),  # free timing
])
def test_the_atlas_is_loaded_by_free_timing_alone(args, loads):
    res = subprocess.run([sys.executable, "-c", LOADED] + args, capture_output=True, text=True, cwd=ROOT)
    assert res.returncode in (0, 1), res.stderr
    loaded = set(res.stderr.rsplit("LOADED ", 1)[1].split())
    assert ("linkcli.atlas.cache" in loaded) == loads
    assert ("linkcli.types.path_generation.atlas_starts" in loaded) == loads


def test_bench_runs_free_timing_with_and_without_the_atlas():
    from linkcli.bench import Run, settings_for, solve_run
    from linkcli.io.safe_read import read_problem_bytes
    from linkcli.reading.load import load
    path = "problems/bench/closed_curve12.toml"
    source = read_problem_bytes(path)
    settings = settings_for(load(path, source))
    assert settings[:2] == [("auto", None, None), ("auto", None, False)]
    assert ("auto", None, False) not in settings_for(load("problems/bench/closed18_timed.toml",
                                                          read_problem_bytes("problems/bench/closed18_timed.toml")))
    row = solve_run(Run(path, source, "auto", 30_000, 0, atlas=False))
    assert row["method"] == "auto (no atlas)" and row["objective"] is not None


STARTS_PROGRAM = """\
import hashlib, json, sys
from linkcli.pipeline import single_threaded_blas
single_threaded_blas()
from linkcli.atlas import cache
from linkcli.types.path_generation import atlas_starts as lookup
from linkcli.reading.load import load
from linkcli.io.safe_read import read_problem_bytes
from linkcli.types.path_generation.model import build
out, starts = hashlib.sha256(), []
atlas = cache.get()
for path in sys.argv[1:]:
    design = build(load(path, read_problem_bytes(path)))
    for a in lookup.hits(design, atlas, lookup.allowed(design, atlas)):
        out.update(a.tobytes())
    starts.append(lookup.starts(design, atlas, 96)[0].tolist())
sys.stdout.write(json.dumps([out.hexdigest(), starts]))
"""


def test_the_same_starts_with_other_cpu_kernels():
    """The lookup's scores are exact integer products and IEEE-rounded float32 elementwise
    work: the same stretches found, to the bit, under another OpenBLAS kernel and without
    numpy's wider vector loops; placed back by the search's own closed forms (numpy's sin,
    cos and hypot, which follow the CPU in the last bit, as for the draws), the same starts
    to round-off."""
    import json
    import os
    files = ["problems/bench/free_closed24.toml", "problems/bench/free_open40.toml",
             "problems/bench/free_rocker30.toml", "problems/straight_line.toml",
             "problems/bench/closed18_free.toml", "problems/bench/lin10_closed.toml"]
    found = []
    for extra in ({}, {"NPY_DISABLE_CPU_FEATURES": "X86_V3,X86_V4,AVX512_ICL,AVX512_SPR"},
                  {"OPENBLAS_CORETYPE": "Prescott"}):
        res = subprocess.run([sys.executable, "-c", STARTS_PROGRAM] + files, capture_output=True, text=True,
                             env=dict(os.environ, **extra), cwd=ROOT)
        assert res.returncode == 0, res.stderr
        found.append(json.loads(res.stdout))
    assert len({digest for digest, _ in found}) == 1
    for _, starts in found[1:]:
        for mine, theirs in zip(found[0][1], starts):
            np.testing.assert_allclose(np.array(theirs), np.array(mine), rtol=1e-9, atol=1e-9)
