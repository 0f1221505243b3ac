"""Stress across problem types: determinism across processes for the optimizing solvers,
round trips of placed linkages, positions at dead centres, and linkages at the edge of
assembly, each against an independent reference written here (math module)."""

from __future__ import annotations

import json
import math

import pytest
from conftest import run_cli


def psi_of(a, b, c, d, phi, branch="open"):
    """Output angle by the closure of the conventions of docs/format.md, one sample, math module."""
    rx, ry = a * math.cos(phi) - d, a * math.sin(phi)
    rho = math.hypot(rx, ry)
    cos_alpha = (rho * rho + c * c - b * b) / (2 * rho * c)
    alpha = math.acos(max(-1.0, min(1.0, cos_alpha)))
    return math.atan2(ry, rx) + (-alpha if branch == "open" else alpha)


@pytest.mark.slow
def test_jobs_give_the_same_bytes_for_optimizing_solvers():
    files = ["problems/crank_rocker.toml", "problems/flipper.toml", "problems/firedoor.toml",
             "problems/flipper_check.toml"]
    serial = run_cli("synth", *files, "--format", "json")
    parallel = run_cli("synth", *files, "--format", "json", "--jobs", "2")
    assert serial[0] == 0 and serial == parallel


def test_seed_changes_nothing_for_a_closed_form_and_is_reported(tmp_path):
    a = run_cli("synth", "problems/firedoor.toml", "--format", "json", "--seed", "7")
    b = run_cli("synth", "problems/firedoor.toml", "--format", "json", "--seed", "8")
    ra, rb = json.loads(a[1]), json.loads(b[1])
    assert ra["linkage"] == rb["linkage"] and ra["solver"]["seed"] == 7 and rb["solver"]["seed"] == 8


def test_placed_path_linkage_round_trips_through_analyze(tmp_path):
    """A path result keeps its coupler point, ground pivot and ground angle through
    synth --format toml -> analyze, and analyze reports the same linkage."""
    code, _, err = run_cli("synth", "problems/straight_line.toml", "--format", "toml", "--out", str(tmp_path),
                           "--precision", "17")
    assert code == 0, err
    code, out, err = run_cli("analyze", str(tmp_path / "straight_line.toml"), "--format", "json",
                             "--precision", "17")
    assert code == 0, err
    _, solved, _ = run_cli("synth", "problems/straight_line.toml", "--format", "json", "--precision", "17")
    again, first = json.loads(out), json.loads(solved)
    assert again["linkage"] == first["linkage"]
    assert again["transmission"]["min"] == pytest.approx(first["transmission"]["min"], rel=1e-12)
    assert again["grashof"] == first["grashof"]


@pytest.mark.parametrize("which", ["outer", "inner"])
def test_precision_positions_at_a_dead_centre(tmp_path, which):
    """A rocking input whose first position is its limit (a dead centre: coupler and
    output collinear, rho = |A B0| = b + c or |b - c|): the three positions still give the
    linkage back exactly."""
    a, b, c, d = 3.0, 4.5, 2.0, 5.0  # rocker-crank: the input rocks in two arcs
    r = b + c if which == "outer" else b - c
    limit = math.acos((a * a + d * d - r * r) / (2 * a * d))  # upper arc (22.3 .. 106 deg)
    step = -0.3 if which == "outer" else 0.3  # into the arc
    phis = [limit, limit + step, limit + 2 * step]
    psis = [psi_of(a, b, c, d, p) for p in phis]
    text = ("type = \"precision-position\"\n[units]\nangle = \"rad\"\n[linkage]\nground = 5\n[positions]\n"
            f"input = {phis!r}\noutput = {psis!r}\n")
    path = tmp_path / "dead.toml"
    path.write_text(text)
    code, out, err = run_cli("synth", str(path), "--format", "json", "--precision", "15")
    assert code == 0, err
    rep = json.loads(out)
    got = [rep["linkage"][k] for k in ("input", "coupler", "output")]
    assert got == pytest.approx([a, b, c], rel=1e-6)
    assert max(abs(r["error"]) for r in rep["positions"]) < 1e-6
    assert rep["motion"]["input_full_turn"] is False
    assert min(abs(x - limit) for x in rep["motion"]["input_range"]) < 1e-9  # rad, as the file


@pytest.mark.parametrize("lengths", [(1.0, 1.5, 1.5, 2.0), (1.0, 2.0, 2.0, 1.0), (2.0, 2.0, 2.0, 2.0)])
def test_change_point_linkages_report_finite_numbers(tmp_path, lengths):
    """Change-point linkages pass flat positions (mu = 0 or 180): every number in every
    output is finite or an explicit null, never NaN, and the class is change-point."""
    a, b, c, d = lengths
    path = tmp_path / "cp.toml"
    path.write_text(f"type = \"linkage\"\n[linkage]\nground = {d}\ninput = {a}\ncoupler = {b}\noutput = {c}\n"
                    "[motion]\nsteps = 72\n")
    code, out, err = run_cli("analyze", str(path), "--format", "json")
    assert code in (0, 1), err
    assert "NaN" not in out and "Infinity" not in out
    rep = json.loads(out)
    assert rep["grashof"]["class"] == "change-point"
    code, table, err = run_cli("analyze", str(path))
    assert code in (0, 1) and "nan" not in table.lower()
