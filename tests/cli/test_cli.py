"""The command line as users and scripts drive it: exit codes, formats, batches,
determinism, round trips, and what `--version` and `check` import."""

from __future__ import annotations

import json
import subprocess
import sys
import tomllib

import pytest

from conftest import run_cli


def test_version_and_help():
    code, out, _ = run_cli("--version")
    assert code == 0 and out.startswith("linkcli ")
    for cmd in ("synth", "analyze", "check", "bench"):
        code, out, _ = run_cli(cmd, "--help")
        assert code == 0 and "Usage" in out


@pytest.mark.parametrize("args", [["--version"], ["check", "problems/firedoor.toml"], ["--help"]])
def test_light_commands_import_neither_numpy_nor_scipy(args):
    code = ("import sys; from linkcli.cli import app\n"
            "try:\n    app(%r, prog_name='linkcli')\nexcept SystemExit as e:\n    assert e.code == 0, e.code\n"
            "heavy = [m for m in ('numpy', 'scipy') if m in sys.modules]\n"
            "assert not heavy, heavy" % (args,))
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)


def test_module_entry_point():
    res = subprocess.run([sys.executable, "-m", "linkcli", "synth", "problems/firedoor.toml", "-f", "json"],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout)["linkage"]["input"] == pytest.approx(27.6293)


def test_json_keys_follow_the_spec():
    code, out, _ = run_cli("synth", "problems/firedoor.toml", "--format", "json")
    rep = json.loads(out)
    for key in ("file", "title", "type", "status", "message", "units", "linkage", "grashof",
                "transmission", "motion", "positions", "error", "solver"):
        assert key in rep
    assert set(rep["transmission"]) >= {"min", "max", "input_at_min", "input_at_max", "working_min", "working_max"}
    assert rep["grashof"]["class"] == "crank-rocker"
    assert rep["transmission"]["input_at_min"] == 0 and rep["transmission"]["input_at_max"] == 180
    # working range 45..135: mu extremes at its ends (rho grows with phi there)
    assert rep["transmission"]["working_min"] == pytest.approx(39.0173, abs=1e-4)
    assert set(rep["solver"]) >= {"method", "seed", "evaluations", "converged"}


def test_precision_option_rounds_every_number():
    _, out, _ = run_cli("synth", "problems/firedoor.toml", "--format", "json", "--precision", "3")
    assert json.loads(out)["linkage"]["coupler"] == 57.2


def test_batch_keeps_order_reports_each_file_and_exits_with_the_worst():
    code, out, err = run_cli("synth", "problems/firedoor.toml", "tests/bad/zero_length.toml",
                             "problems/firedoor_motion.toml", "--format", "json")
    assert code == 2
    reps = json.loads(out)
    assert [r["file"] for r in reps] == ["problems/firedoor.toml", "tests/bad/zero_length.toml",
                                         "problems/firedoor_motion.toml"]
    assert reps[1]["status"] == "bad-input"
    assert "tests/bad/zero_length.toml:3: linkage.ground" in err
    assert err.strip().splitlines()[-1] == "3 files: 2 solved, 0 infeasible or not converged, 1 bad input"


def test_jobs_give_the_same_bytes_as_a_serial_run():
    files = ["problems/firedoor.toml", "problems/firedoor_motion.toml", "tests/bad/syntax.toml"]
    serial = run_cli("synth", *files, "--format", "json")
    parallel = run_cli("synth", *files, "--format", "json", "--jobs", "2")
    assert serial == parallel


def test_same_input_same_bytes():
    first = run_cli("synth", "problems/firedoor.toml", "problems/firedoor_motion.toml")
    second = run_cli("synth", "problems/firedoor.toml", "problems/firedoor_motion.toml")
    assert first == second and first[0] == 0


def test_toml_result_round_trips_through_analyze(tmp_path):
    code, _, err = run_cli("synth", "problems/firedoor.toml", "--format", "toml", "--out", str(tmp_path))
    assert code == 0, err
    result = tmp_path / "firedoor.toml"
    data = tomllib.loads(result.read_text())
    assert data["linkage"]["input"] == pytest.approx(27.6293)
    code, out, err = run_cli("analyze", str(result), "--format", "json")
    assert code == 0, err
    rep = json.loads(out)
    assert rep["linkage"] == {k: data["linkage"][k] for k in rep["linkage"]}
    assert rep["grashof"]["class"] == "crank-rocker"


def _refused(p) -> bool:
    """A flipper's result (no linkage) and a drawn linkage's analysis (no drawing kept); a drawn
    design's result keeps its drawing and is analysed."""
    analysis = 'type = "linkage"' in p.read_text(encoding="utf-8")
    return p.name.startswith(("flipper", "watt_")) or (p.name.startswith("drawn_") and analysis)


ANALYSABLE = sorted(p.name for p in __import__("pathlib").Path("problems").glob("*.toml") if not _refused(p))


@pytest.mark.slow
@pytest.mark.parametrize("name", ANALYSABLE)
def test_every_genuine_result_file_is_accepted_unchanged(tmp_path, name):
    """Every key `synth --format toml` writes is one `analyze` accepts (result files are
    checked, reading.result_check), for every example whose result has a [linkage]."""
    code, _, err = run_cli("synth", f"problems/{name}", "--format", "toml", "--out", str(tmp_path))
    assert code in (0, 1), err
    code, _, err = run_cli("analyze", str(tmp_path / name), "--format", "json")
    assert code in (0, 1) and err == "", err


VARIANTS = sorted(p.name for p in __import__("pathlib").Path("tests/data/result_keys").glob("*.toml"))
TEMPLATES = ["function-generation", "linkage", "motion-generation", "path-generation",
             "precision-position", "quick-return"]  # (a flipper-cylinder result has no linkage)


def _written(tmp_path, name: str) -> tuple[str, str]:
    """(source, result file name) of a variant or a template ("template TYPE")."""
    if name.startswith("template "):
        (tmp_path / "t.toml").write_text(run_cli("new", name.split()[1])[1])
        return str(tmp_path / "t.toml"), "t.toml"
    return name, __import__("pathlib").Path(name).name


@pytest.mark.parametrize("name", [f"tests/data/result_keys/{v}" for v in VARIANTS]
                         + [f"template {t}" for t in TEMPLATES])
@pytest.mark.slow
def test_a_genuine_result_with_the_writers_optional_keys_is_accepted(tmp_path, name):
    """The variants that reach the writer's optional keys (a dead point under load, general
    tolerances, an allocation that misses its limit, candidate counts, a five-bar's mode
    pairs, a timing offset: tests/result_keys_corpus.py) and the templates give results
    `analyze` accepts unchanged."""
    source, result = _written(tmp_path, name)
    code, _, err = run_cli("synth", source, "--format", "toml", "--out", str(tmp_path / "out"))
    assert code in (0, 1), err
    code, _, err = run_cli("analyze", str(tmp_path / "out" / result), "--format", "json")
    assert code in (0, 1) and err == "", err


REFUSED = sorted(set(__import__("pathlib").Path(p).name for p in __import__("glob").glob("problems/*.toml"))
                 - set(ANALYSABLE))


@pytest.mark.slow
@pytest.mark.parametrize("name", [f"problems/{r}" for r in REFUSED] + ["template flipper-cylinder"])
def test_a_result_analyze_refuses_is_refused_for_its_kind_not_for_its_keys(tmp_path, name):
    """A flipper-cylinder result (no linkage) and a drawn linkage's analysis (read from its
    drawing) are refused, and for that alone: none of the keys the writer wrote is called
    unknown."""
    source, result = _written(tmp_path, name)
    code, _, err = run_cli("synth", source, "--format", "toml", "--out", str(tmp_path / "out"))
    assert code in (0, 1), err
    code, _, err = run_cli("analyze", str(tmp_path / "out" / result))
    assert code == 2
    assert ("a result with a [linkage] table" in err or "reads a drawn linkage from its problem file" in err), err
    assert "unknown key" not in err, err


def _firedoor_result(tmp_path, edit) -> tuple[str, str]:
    code, out, _ = run_cli("synth", "problems/firedoor.toml", "--format", "toml")
    assert code == 0
    result = tmp_path / "result.toml"
    result.write_text(edit(out))
    code, out, err = run_cli("analyze", str(result))
    assert code == 2 and out == "", err
    return str(result), err


@pytest.mark.parametrize("edit, line, message", [
    (lambda t: t.replace('type = "precision-position"', "type = 5"), 3,
     "type: expected one of: precision-position, function-generation, path-generation, "
     "flipper-cylinder, linkage, motion-generation, quick-return, found 5"),
    (lambda t: t.replace("[transmission]\nmin = ", "[transmission]\nmin = nan\n# min = "), 34,
     "transmission.min: expected a finite number (a result file holds no nan or inf), found nan"),
    (lambda t: t.replace('status = "ok"', 'status = "fine"'), 4,
     "status: expected one of: ok, infeasible, not-converged, found \"fine\""),
    (lambda t: t + "\n[extra]\nx = 1\n", None, 'extra: expected a known key'),
    (lambda t: t.replace("[error]\nobjective = ", "[error]\nobjective = [" + "1," * 10_001 + "]\n# objective = "),
     None, "error.objective: expected an array of at most 10000 elements, found an array of 10001 elements"),
    (lambda t: t.replace("[linkage]", "[linkage]\nwat = 1"), None, 'linkage.wat: expected a known key'),
    (lambda t: t.replace("[transmission]\n", "[transmission]\nwat = 1\n"), 34,
     'transmission.wat: expected a known key (one of: '),
    (lambda t: t.replace("[solver]\n", "[solver]\nwat = 1\n"), None, 'solver.wat: expected a known key (one of: '),
])
def test_analyze_refuses_garbage_in_a_result_file(tmp_path, edit, line, message):
    """A result file is linkcli's output: a wrong type or status, nan, an unknown key or
    table, an overlong array is one located line (exit 2), not silently ignored."""
    path, err = _firedoor_result(tmp_path, edit)
    lines = err.splitlines()
    assert len(lines) == 1, err
    where = f"{path}:{line}: " if line else f"{path}:"
    assert lines[0].startswith(where) and message in lines[0], lines[0]


def test_analyze_rejects_a_synthesis_problem():
    code, _, err = run_cli("analyze", "problems/firedoor.toml")
    assert code == 2 and 'type: expected type = "linkage"' in err


def test_unreadable_file_is_bad_input():
    code, out, err = run_cli("synth", "does/not/exist.toml")
    assert code == 2 and out == "" and "does/not/exist.toml: expected a readable problem file" in err


def test_sections_not_asked_for_are_not_printed():
    code, out, _ = run_cli("synth", "tests/data/firedoor_lengths_only.toml", "--format", "json")
    rep = json.loads(out)
    assert code == 0
    assert "linkage" in rep and "transmission" not in rep and "positions" not in rep and "motion" not in rep


def test_seed_override_is_reported():
    _, out, _ = run_cli("synth", "problems/firedoor.toml", "--format", "json", "--seed", "7")
    assert json.loads(out)["solver"]["seed"] == 7


def test_bench_rows_and_summary():
    """bench times each setting and seed of a problem; the fire door's exact design
    (objective 0 within round-off, [reference] 0) is found by both of its methods."""
    code, out, _ = run_cli("bench", "problems/bench/firedoor.toml", "--seeds", "2", "-f", "json")
    assert code == 0
    rows = json.loads(out)
    assert {(r["method"], r["seed"]) for r in rows} == {(m, s) for m in ("auto", "freudenstein") for s in (0, 1)}
    for r in rows:
        assert r["status"] == "ok" and r["seconds"] > 0 and r["best_known"] == 0.0
        assert abs(r["objective"]) < 1e-20 and abs(r["gap"]) < 1e-20
    from linkcli.bench import SUMMARY_COLUMNS, markdown, summary
    rows[0]["status"] = "not-converged"
    table = summary(rows)
    assert [(t["method"], t["within 1e-6"], t["not converged"]) for t in table] == [
        ("auto", "2/2", 1), ("freudenstein", "2/2", 0)]
    text = markdown(table, 5, SUMMARY_COLUMNS)
    assert text.splitlines()[0] == "| " + " | ".join(SUMMARY_COLUMNS) + " |"
    assert len(text.splitlines()) == 4


def bench_row(problem, method, seed, objective, best, status, seconds, evaluations=100):
    from linkcli.analysis.sections import gap
    return {"problem": problem, "method": method, "budget": None, "seed": seed, "seconds": seconds,
            "evaluations": evaluations, "objective": objective, "best_known": best,
            "gap": None if best is None else gap(objective, best), "status": status}


def test_bench_summary_counts_the_seeds_that_reach_the_best_known():
    """Reliability over seeds, recounted here by hand: a seed within 1e-6 (relative) of the
    best known counts, one ending `ok` outside it is "ok but off", medians of an even
    count are the mean of the middle two, a problem without a best known shows None."""
    from linkcli.bench import summary
    best = 2.0
    rows = [bench_row("p/a.toml", "auto", 0, 2.0 * (1 + 5e-7), best, "ok", 0.4, 10),
            bench_row("p/a.toml", "auto", 1, 2.0 * (1 + 2e-6), best, "ok", 0.1, 20),
            bench_row("p/a.toml", "auto", 2, 2.5, best, "not-converged", 0.3, 40),
            bench_row("p/a.toml", "auto", 3, 2.0, best, "ok", 0.2, 30),
            bench_row("p/b.toml", "de", 0, 7.0, None, "infeasible", 1.0)]
    a, b = summary(rows)
    assert (a["problem"], a["seeds"], a["within 1e-6"], a["ok but off"]) == ("a", 4, "2/4", 1)
    assert (a["not converged"], a["infeasible"]) == (1, 0)
    assert a["median gap"] == pytest.approx((5e-7 + 2e-6) / 2)
    assert a["worst gap"] == pytest.approx(0.25)
    assert a["median seconds"] == pytest.approx(0.25) and a["median evaluations"] == 25
    assert a["best objective"] == 2.0 and a["best_known"] == best
    assert b["within 1e-6"] is None and b["infeasible"] == 1 and b["median gap"] is None


def test_bench_summary_option_in_every_format():
    code, out, _ = run_cli("bench", "problems/bench/firedoor.toml", "--seeds", "2", "--summary",
                           "-f", "json")
    assert code == 0
    (row,) = [r for r in json.loads(out) if r["method"] == "auto"]
    assert row["within 1e-6"] == "2/2" and row["seeds"] == 2 and row["best objective"] == 0
    code, out, _ = run_cli("bench", "problems/bench/firedoor.toml", "--seeds", "1")
    assert code == 0 and "run time against error" in out and "reliability over the seeds" in out
    code, out, _ = run_cli("bench", "problems/bench/firedoor.toml", "--seeds", "1", "--summary",
                           "-f", "csv")
    assert code == 0 and out.splitlines()[0].startswith("problem,method,budget,seeds,within 1e-6")


def test_out_folder_problems_and_repeated_stems(tmp_path):
    a_file = tmp_path / "afile"
    a_file.write_text("")
    code, out, err = run_cli("synth", "problems/firedoor.toml", "--out", str(a_file))
    assert code == 2 and out == "" and err.strip() == f"{a_file}: expected a folder for --out, found a file"
    # the same stem twice: both results kept, the second as firedoor_2
    for sub in ("x", "y"):
        (tmp_path / sub).mkdir()
        (tmp_path / sub / "firedoor.toml").write_text(open("problems/firedoor.toml").read())
    outd = tmp_path / "outd"
    code, _, _ = run_cli("synth", str(tmp_path / "x" / "firedoor.toml"), str(tmp_path / "y" / "firedoor.toml"),
                         "--out", str(outd), "-f", "json")
    assert code == 0 and sorted(p.name for p in outd.iterdir()) == ["firedoor.json", "firedoor_2.json"]
    files = [json.loads((outd / n).read_text())["file"] for n in ("firedoor.json", "firedoor_2.json")]
    assert files == [str(tmp_path / "x" / "firedoor.toml"), str(tmp_path / "y" / "firedoor.toml")]


def test_one_bad_file_prints_nothing_on_stdout_but_its_json_slot():
    for fmt in ("table", "json", "toml"):
        code, out, err = run_cli("synth", "tests/bad/coincident_positions.toml", "-f", fmt)
        assert code == 2 and err.startswith("tests/bad/coincident_positions.toml:")
        if fmt == "json":  # the slot a batch would print for it (issue 21)
            assert json.loads(out) == {"file": "tests/bad/coincident_positions.toml", "status": "bad-input",
                                       "message": "; ".join(err.splitlines())}
        else:
            assert out == ""
