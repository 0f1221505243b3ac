"""benchmarks/run.py writes only its own section of benchmarks/RESULTS.md: the history of the
measurements around it (moved there from the README) survives a full run and a --merge."""

from __future__ import annotations

import importlib.util
import sys

from conftest import ROOT


def _run_py():
    spec = importlib.util.spec_from_file_location("bench_run_script", ROOT / "benchmarks" / "run.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def _section(run, rows: list[tuple[str, str, str]], runs: list[tuple[str, str, str, str]]) -> str:
    summary = "| problem | method | budget | seeds |\n|---|---|---|---|\n" + "".join(
        f"| {p} | {m} | {b} | {v} |\n" for p, m, b, v in rows)
    every = "| problem | method | budget | seed | seconds |\n|---|---|---|---|---|\n" + "".join(
        f"| {p} | {m} | {b} | {s} | {v} |\n" for p, m, b, s, v in runs)
    return "## The bench set\n\nMachine: test.\n\n" + run.RELIABILITY + summary + "\n" + run.EVERY_RUN + every


def test_a_full_run_replaces_its_section_and_keeps_the_history(tmp_path):
    run = _run_py()
    path = tmp_path / "RESULTS.md"
    path.write_text("# Measurements\n\nIntro.\n\n" + run.BEGIN + "old section\n" + run.END
                    + "\n## History\n\nkunjur5 0.81 -> 0.46 s.\n", encoding="utf-8")
    fresh = _section(run, [("kunjur5", "auto", "-", "10")], [("kunjur5", "auto", "-", "0", "0.5")])
    run.write_section(str(path), fresh, None)
    text = path.read_text(encoding="utf-8")
    assert text == ("# Measurements\n\nIntro.\n\n" + run.BEGIN + fresh + run.END
                    + "\n## History\n\nkunjur5 0.81 -> 0.46 s.\n")


def test_a_merge_replaces_only_the_rows_run(tmp_path):
    run = _run_py()
    path = tmp_path / "RESULTS.md"
    old = _section(run, [("a", "auto", "-", "old"), ("b", "auto", "-", "old")],
                   [("a", "auto", "-", "0", "1.0"), ("b", "auto", "-", "0", "2.0")])
    path.write_text("# M\n\n" + run.BEGIN + old + run.END + "\n## History\n\nkept\n", encoding="utf-8")
    fresh = _section(run, [("b", "auto", "-", "new")], [("b", "auto", "-", "0", "3.0")])
    run.write_section(str(path), fresh, ["problems/bench/b.toml"])
    text = path.read_text(encoding="utf-8")
    assert text.startswith("# M\n\n" + run.BEGIN + "## The bench set\n\nMachine: test.\n\n")
    assert text.endswith(run.END + "\n## History\n\nkept\n")
    assert "| a | auto | - | old |" in text and "| b | auto | - | new |" in text and "| b | auto | - | old |" not in text
    assert "| a | auto | - | 0 | 1.0 |" in text and "| b | auto | - | 0 | 3.0 |" in text and "2.0" not in text
    assert "Rows of b run apart" in text


def test_a_file_without_the_markers_gets_the_section_at_its_end(tmp_path):
    run = _run_py()
    path = tmp_path / "RESULTS.md"
    path.write_text("# History only\n", encoding="utf-8")
    fresh = _section(run, [("a", "auto", "-", "10")], [("a", "auto", "-", "0", "1.0")])
    run.write_section(str(path), fresh, None)
    assert path.read_text(encoding="utf-8") == "# History only\n\n" + run.BEGIN + fresh + run.END
    missing = tmp_path / "new.md"
    run.write_section(str(missing), fresh, None)
    assert missing.read_text(encoding="utf-8") == run.BEGIN + fresh + run.END


def test_the_repository_results_file_has_one_section_and_a_history():
    run = _run_py()
    text = (ROOT / "benchmarks" / "RESULTS.md").read_text(encoding="utf-8")
    assert text.count(run.BEGIN) == 1 and text.count(run.END) == 1
    section = text.split(run.BEGIN, 1)[1].split(run.END, 1)[0]
    assert run.RELIABILITY in section and run.EVERY_RUN in section
    outside = text.replace(section, "")
    assert "## The constrained-variant study" in outside  # the history moved from the README
