"""A batch of 40 random linkages from 1e-3 to 1e3 in scale, through the command line,
classified and measured against implementations written here (not linkcli's)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import run_cli
from test_kinematics import ref_grashof


def ref_transmission(a, b, c, d):
    """mu extremes from the reachable interval of rho = |A B0|: rho runs over
    [|a - d|, a + d] as the crank turns and must lie in [|b - c|, b + c] to assemble;
    mu grows with rho. Also dense samples (complex numbers), which must lie inside."""
    lo, hi = max(abs(a - d), abs(b - c)), min(a + d, b + c)
    mu = lambda r: math.degrees(math.acos(max(-1.0, min(1.0, (b * b + c * c - r * r) / (2 * b * c)))))
    phi = np.linspace(-math.pi, math.pi, 20001)
    rho = np.abs(a * np.exp(1j * phi) - d)
    ok = (rho <= b + c) & (rho >= abs(b - c))
    sampled = np.degrees(np.arccos(np.clip((b * b + c * c - rho[ok] ** 2) / (2 * b * c), -1, 1)))
    return mu(lo), mu(hi), bool(ok.all()), sampled


@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    rng = np.random.default_rng(2026)
    folder = tmp_path_factory.mktemp("batch")
    linkages = []
    for i in range(40):
        scale = 10.0 ** rng.uniform(-3, 3)
        abcd = [float(x) for x in rng.uniform(0.2, 1.0, 4) * scale]
        a, b, c, d = abcd
        linkages.append(abcd)
        (folder / f"l{i:02d}.toml").write_text(
            f'type = "linkage"\n[linkage]\nground = {d!r}\ninput = {a!r}\ncoupler = {b!r}\n'
            f'output = {c!r}\n[report]\nsections = ["lengths", "grashof", "transmission", "motion"]\n')
    files = [str(folder / f"l{i:02d}.toml") for i in range(40)]
    code, out, err = run_cli("synth", *files, "--format", "json", "--precision", "12", "--jobs", "2")
    return linkages, json.loads(out), code, err


def test_batch_runs_every_file_in_order(batch):
    linkages, reps, code, err = batch
    assert len(reps) == 40
    assert [r["file"].rsplit("/", 1)[-1] for r in reps] == [f"l{i:02d}.toml" for i in range(40)]
    assert err.strip().splitlines()[-1].startswith("40 files:")
    assert code == max(0 if r["status"] == "ok" else 1 for r in reps)


def test_batch_classes_and_transmission_match_independent_references(batch):
    linkages, reps, _, _ = batch
    for (a, b, c, d), rep in zip(linkages, reps):
        assert rep["grashof"]["class"] == ref_grashof(a, b, c, d), rep["file"]
        if rep["status"] != "ok":  # cannot assemble anywhere: say so, no numbers
            rho_lo, rho_hi = abs(a - d), a + d
            assert rho_hi < abs(b - c) or rho_lo > b + c, rep["file"]
            assert "transmission" not in rep
            continue
        mn, mx, full, sampled = ref_transmission(a, b, c, d)
        assert rep["transmission"]["min"] <= sampled.min() + 1e-6
        assert rep["transmission"]["max"] >= sampled.max() - 1e-6
        assert rep["motion"]["input_full_turn"] == full, rep["file"]
        assert rep["transmission"]["min"] == pytest.approx(mn, abs=2e-3), rep["file"]
        assert rep["transmission"]["max"] == pytest.approx(mx, abs=2e-3), rep["file"]
