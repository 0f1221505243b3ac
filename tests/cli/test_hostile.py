"""Hostile input (issue 21): special files, huge integers, terminal escapes and the other
ways a file or an option can break the CLI contract (exit 2, one located line, no hang)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT, run_cli

SRC = str(ROOT / "src")


def _cli(*args: str, timeout: float = 120):
    """Run linkcli in a subprocess (a hang fails the test through the timeout)."""
    env = dict(os.environ, PYTHONPATH=SRC)
    done = subprocess.run([sys.executable, "-m", "linkcli", *args], capture_output=True,
                          text=True, timeout=timeout, env=env, cwd=ROOT)
    return done.returncode, done.stdout, done.stderr


# -- 1. special and huge files -----------------------------------------------------

@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
@pytest.mark.parametrize("command,extra", [("check", ()), ("synth", ()), ("synth", ("--jobs", "2")),
                                           ("analyze", ()), ("bench", ("--seeds", "1"))])
@pytest.mark.slow
def test_a_fifo_and_dev_zero_are_refused_and_the_batch_goes_on(tmp_path, command, extra):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    good = "problems/firedoor_motion.toml" if command == "analyze" else "problems/firedoor.toml"
    files = [str(fifo), "/dev/zero", good] + ([good] if "--jobs" in extra else [])
    code, out, err = _cli(command, *files, *extra)
    assert code == 2
    lines = err.splitlines()
    assert f"{fifo}: expected a regular problem file, found a FIFO (named pipe)" in lines
    assert "/dev/zero: expected a regular problem file, found a character device" in lines
    if command == "check":
        assert out == f"{good}: ok\n"  # the verdict on stdout, the errors on stderr
    elif command == "bench":
        assert "firedoor" in out
    else:
        assert "solved" in err.splitlines()[-1] and not err.splitlines()[-1].startswith("0 solved")
        assert out.strip()


def test_a_file_beyond_the_size_cap_is_refused_without_reading_it(tmp_path):
    from linkcli.io.safe_read import MAX_FILE_BYTES
    big = tmp_path / "big.toml"
    with open(big, "wb") as fh:  # sparse: 200 MB of size, no disk or memory used
        fh.truncate(200 * 1024 * 1024)
    code, out, err = _cli("check", str(big))
    assert code == 2 and out == ""
    assert err == (f"{big}: expected a problem file of at most {MAX_FILE_BYTES} bytes (4 MiB), "
                   f"found {200 * 1024 * 1024} bytes\n")


def test_a_file_at_the_cap_is_read(tmp_path):
    from linkcli.io.safe_read import MAX_FILE_BYTES, read_problem_bytes
    text = Path(ROOT / "problems" / "firedoor.toml").read_bytes()
    padded = text + b"#" * (MAX_FILE_BYTES - len(text))
    p = tmp_path / "padded.toml"
    p.write_bytes(padded)
    assert read_problem_bytes(str(p)) == padded


def test_a_folder_is_refused(tmp_path):
    code, _, err = _cli("check", str(tmp_path))
    assert code == 2 and err == f"{tmp_path}: expected a regular problem file, found a folder\n"


# -- 3. terminal escapes and giant keys --------------------------------------------

def _titled(tmp_path, title_toml: str, name: str = "titled.toml") -> Path:
    text = (ROOT / "problems" / "firedoor.toml").read_text()
    p = tmp_path / name
    p.write_text(f"title = {title_toml}\n" + "\n".join(l for l in text.splitlines()
                                                       if not l.startswith("title")) + "\n")
    return p


def test_a_title_with_terminal_escapes_is_shown_escaped_in_the_table(tmp_path):
    p = _titled(tmp_path, '"\\u001b[2J\\u001b[31mRED\\u0007"')
    code, out, err = run_cli("synth", str(p))
    assert code == 0, err
    assert "\x1b" not in out and "\x07" not in out
    assert out.splitlines()[0].startswith("\\x1b[2J\\x1b[31mRED\\x07")  # (the file may wrap below it)


def test_a_file_name_with_escapes_is_shown_escaped_in_errors(tmp_path):
    p = tmp_path / "bad\x1b[2J.toml"
    p.write_text("type = 1\n")
    code, out, err = run_cli("check", str(p))
    assert code == 2 and "\x1b" not in err
    assert err.startswith(str(p).replace("\x1b", "\\x1b") + ":1: type: expected one of")


NAMES = {"an escape": "red\x1b[31m.toml", "a newline": "two\nlines.toml", "a bell and markup": "b\x07[bold]x.toml"}


@pytest.mark.slow
@pytest.mark.parametrize("case", NAMES)
def test_a_file_name_with_control_characters_is_escaped_in_every_status_and_error_line(tmp_path, case):
    # `check`'s "FILE: ok" wrote the name raw (its escape sequence obeyed by the terminal, a
    # newline splitting the verdict in two); every error and status line is escaped alike
    import shutil
    good, bad = tmp_path / ("good " + NAMES[case]), tmp_path / ("bad " + NAMES[case])
    shutil.copy(ROOT / "problems" / "firedoor.toml", good)
    shutil.copy(ROOT / "tests" / "bad" / "zero_length.toml", bad)
    shown = {f: str(f).replace("\x1b", "\\x1b").replace("\n", "\\n").replace("\x07", "\\x07") for f in (good, bad)}
    for command in ("check", "synth"):
        code, out, err = _cli(command, str(good), str(bad))
        assert code == 2
        assert not any(c in out + err for c in "\x1b\x07"), (out, err)
        lines = err.splitlines()
        assert lines[0].startswith(shown[bad] + ":3: linkage.ground: expected a positive length"), lines
        if command == "check":
            assert out == f"{shown[good]}: ok\n"
        else:
            assert len(lines) == 2 and lines[1].startswith("2 files: 1 solved")


def test_the_progress_display_shows_a_file_name_escaped_and_not_as_markup():
    from rich.console import Console
    from linkcli.cli import _solving
    console = Console(record=True, width=200, color_system=None)
    console.print(_solving("a\x1b[31m[bold]b\n.toml"))
    assert console.export_text() == "solving a\\x1b[31m[bold]b\\n.toml\n"


def test_the_plot_and_export_lines_are_escaped(capsys):
    from linkcli import plot
    plot._err("x\x1b[2J.png: expected a writable picture, found a\nnewline")
    assert capsys.readouterr().err == "x\\x1b[2J.png: expected a writable picture, found a\\nnewline\n"


LONG_ECHOES = {  # a long name echoed in each part of a line: the key path, the found value,
    # a hint in the expected part, a list of the file's own names in the expected part
    "an unknown key in a table": lambda k: FIREDOOR.replace("[linkage]", f"[linkage]\n{k} = 1", 1),
    "an unknown key also at the top level (the hint names it)":
        lambda k: f"{k} = 1\n" + FIREDOOR.replace("[linkage]", f"[linkage]\n{k} = 2", 1),
    "a string value": lambda k: FIREDOOR + f'[units]\nlength = "{k}"\n',
    "a quoted key of short words": lambda k: FIREDOOR.replace("[linkage]", f'[linkage]\n"{" ".join(k[:len(k) // 2])}" = 1', 1),
    "a link name listed as the known keys": lambda k: SHAPER.replace("crank = [", f"{k} = [").replace(
        "crank = {", f"{k} = {{") + "[tolerance]\nlengths = { zzz = 0.1 }\nsamples = 10\n",
    "a joint name in a key path and a hint": lambda k: SHAPER + f"[joints.{k}]\ndiameter = 1\n",
}
FIREDOOR = (ROOT / "problems" / "firedoor.toml").read_text()
SHAPER = (ROOT / "problems" / "drawn_shaper.toml").read_text()


@pytest.mark.parametrize("size", [3000, 100_000])
@pytest.mark.parametrize("case", LONG_ECHOES)
def test_a_long_name_is_echoed_cut_to_60_characters_and_its_length(tmp_path, case, size):
    # one rule for every error line (errors.bounded, applied where an error is made):
    # a 3000-character key was echoed whole in a hint and in lists of known keys (lines of
    # 3 to 40 KB); each echoed word longer than 80 characters keeps 60 and says its length
    from linkcli.errors import ECHO_LIMIT, KEY_LIMIT, PART_LIMIT
    p = tmp_path / "long.toml"
    p.write_text(LONG_ECHOES[case]("k" * size))
    code, _, err = run_cli("check", str(p))
    assert code == 2
    lines = err.splitlines()
    assert lines and all(len(line) <= len(str(p)) + 10 + KEY_LIMIT + 2 * PART_LIMIT + 30 for line in lines), \
        [len(line) for line in lines]
    assert all(len(line) < len(str(p)) + 400 for line in lines), [len(line) for line in lines]
    import re
    told = [int(n) for n in re.findall(r'\.\.\."? \((\d+) characters\)', err)]
    assert told and max(told) >= size - 1, lines  # the length of what was cut is said
    assert "k" * (ECHO_LIMIT + 1) not in err


def test_cutting_an_error_line_twice_changes_nothing():
    # an error rebuilt from its fields (unpickled from a --jobs worker, or gathered into
    # InputErrors) keeps its text
    import pickle
    from linkcli.errors import InputErrors, SchemaError
    from linkcli.errors import bounded
    texts = ['unknown key "' + "k" * 3000 + '"', "a." + "b" * 500, " ".join(["word"] * 400),
             '"' + "q" * 81 + '"?', "x" * 81, "x" * 80, "one of: " + ", ".join(f"n{i}" for i in range(300))]
    for text in texts:
        once = bounded(text)
        assert bounded(once) == once and len(once) <= max(len(text), 300)
    error = SchemaError(texts[-1], texts[0], path="f.toml", line=3, key=texts[1])
    again = pickle.loads(pickle.dumps(InputErrors([error])))
    assert again.lines() == InputErrors([error]).lines() == [str(error)]


# -- 4. a design that misses a position is infeasible --------------------------------

def test_a_three_position_design_missing_a_position_is_infeasible_and_still_shown(tmp_path):
    import cmath
    import math
    p = tmp_path / "miss.toml"
    p.write_text('type = "precision-position"\n[linkage]\nground = 50.0\n[positions]\n'
                 "input = [45, 90, 135]\noutput = [52, 53, 200]\n")
    code, out, err = run_cli("synth", str(p), "-f", "json")
    assert code == 1 and json.loads(out)["status"] == "infeasible", err
    from linkcli.pipeline import Request, run
    from linkcli.textnum import render
    outcome = run(str(p), Request())
    code, rep = outcome.exit_code, outcome.result.report
    assert code == 1
    assert render(rep["message"]).endswith("; branch defect (see notes); infeasible: position 2 missed by up to "
                                   "87.5959 deg on the reported branch")
    # the exact solution of Freudenstein's equations is still reported: its open branch
    # (psi = arg(v) - acos(...), v = a e^{i phi} - d) meets positions 1 and 3
    lk = rep["linkage"]
    a, b, c, d = lk["input"], lk["coupler"], lk["output"], 50.0
    for row in (rep["positions"][0], rep["positions"][2]):
        v = cmath.rect(a, math.radians(row["input"])) - d
        psi = cmath.phase(v) - math.acos((abs(v) ** 2 + c * c - b * b) / (2 * abs(v) * c))
        assert abs((math.degrees(psi) - row["target"] + 180) % 360 - 180) < 1e-6
    assert abs(rep["positions"][1]["error"]) > 80


def test_the_miss_rule_uses_the_noise_floor_and_counts_order_defects():
    from linkcli.types.precision_position.verdict import MISS_FLOOR_RAD, verdict
    from linkcli.solution import Status
    from linkcli.types.precision_position.solve import TRAVEL_NOTE
    from linkcli.units import Units
    u = Units()
    assert verdict(Status.OK, "m", [], [0.0, 0.9 * MISS_FLOOR_RAD, 0.0], True, u) == (Status.OK, "m")
    status, msg = verdict(Status.OK, "m", [], [0.0, 1.1 * MISS_FLOOR_RAD, 0.0], True, u)
    assert status is Status.INFEASIBLE and msg.startswith("m; infeasible: position 2 missed")
    # least squares: residuals are the fit, not misses; an order defect still counts
    assert verdict(Status.OK, "m", [], [0.1, 0.2, 0.1, 0.3], False, u) == (Status.OK, "m")
    assert verdict(Status.OK, "m", [TRAVEL_NOTE], [0.0] * 4, False, u) == (
        Status.INFEASIBLE, "m; infeasible: the linkage cannot pass its positions in one assembly")


# -- 5. a written motion study keeps its speed and steps -------------------------------

def test_analyze_of_a_written_motion_study_reproduces_its_report(tmp_path):
    code, written, err = run_cli("synth", "problems/firedoor_motion.toml", "-f", "toml")
    assert code == 0, err
    result = tmp_path / "result.toml"
    result.write_text(written)
    _, direct, _ = run_cli("synth", "problems/firedoor_motion.toml", "-f", "json")
    code, again, err = run_cli("analyze", str(result), "-f", "json")
    assert code == 0, err
    direct, again = json.loads(direct), json.loads(again)
    assert again["motion"]["input_speed"] == 20 and again["motion"]["steps"] == 36
    assert len(again["kinematics"]) == 36
    again["file"] = direct["file"]
    assert again == direct
    # the table states the speed used
    _, table, _ = run_cli("analyze", str(result))
    assert any(l.split() == ["input", "speed", "(deg/s)", "20"] for l in table.splitlines())


# -- 7. the newcomer's small traps -------------------------------------------------------

def test_synth_of_a_result_file_is_one_line_pointing_to_analyze(tmp_path):
    _, written, _ = run_cli("synth", "problems/firedoor_motion.toml", "-f", "toml")
    result = tmp_path / "result.toml"
    result.write_text(written)
    line = written.splitlines().index(next(l for l in written.splitlines() if l.startswith("status"))) + 1
    for command in ("synth", "check"):
        code, out, err = run_cli(command, str(result))
        assert code == 2 and out == ""
        assert err == (f"{result}:{line}: expected a problem file, found a result file of linkcli synth "
                       "(analyse it with linkcli analyze)\n")


def test_a_top_level_key_after_a_table_header_gets_a_hint(tmp_path):
    p = tmp_path / "t.toml"
    p.write_text('title = "x"\n[units]\nlength = "mm"\ntype = "precision-position"\n')
    code, _, err = run_cli("check", str(p))
    assert code == 2 and err == (f"{p}:4: units.type: expected a known key (did you mean the top-level "
                                 "key type? keys after a [table] header belong to that table), found "
                                 '"type" inside [units]\n')
    q = tmp_path / "m.toml"
    q.write_text((ROOT / "problems" / "firedoor_motion.toml").read_text().replace(
        "steps = 36", 'steps = 36\ntitle = "again"'))
    code, _, err = run_cli("check", str(q))
    assert code == 2 and f'{q}:13: motion.title: expected a known key (did you mean the top-level key title?' in err


def test_a_deep_table_header_is_located(tmp_path):
    p = tmp_path / "deep.toml"
    p.write_text((ROOT / "problems" / "firedoor_motion.toml").read_text() + "\n[a.b.c.d]\nx = 1\n")
    n = p.read_text().splitlines().index("[a.b.c.d]") + 1
    code, _, err = run_cli("check", str(p))
    assert code == 2 and err.startswith(f'{p}:{n}: a: expected a known key')


@pytest.mark.parametrize("target,expected", [
    ("x.pdf", 'x.pdf: expected a .png or .svg file name, found ".pdf"'),
    ("afile/x.png", "afile/x.png: expected a plot path inside a folder, found afile is a file"),
])
def test_a_bad_plot_path_is_refused_before_solving(tmp_path, monkeypatch, target, expected):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile").write_text("")
    import linkcli.pipeline
    monkeypatch.setattr(linkcli.pipeline, "solve", lambda p: pytest.fail("solved before the check"))
    code, out, err = run_cli("synth", str(ROOT / "problems" / "firedoor.toml"), "--plot", target)
    assert code == 2 and out == "" and err == expected + "\n"


def test_the_seed_rule_is_the_same_on_the_command_line_and_in_the_file(tmp_path):
    code, _, err = run_cli("synth", "problems/firedoor.toml", "--seed", str(2 ** 70))
    assert code == 2 and err == ('linkcli synth: --seed: expected a whole number from 0 to 4294967295, '
                                 'found "1180591620717411303424"\n')
    p = tmp_path / "s.toml"
    p.write_text((ROOT / "problems" / "firedoor.toml").read_text() + "[solver]\nseed = 4294967296\n")
    code, _, err = run_cli("check", str(p))
    assert code == 2 and "solver.seed: expected an integer in [0, 4294967295], found 4294967296" in err
    p.write_text((ROOT / "problems" / "firedoor.toml").read_text() + "[solver]\nseed = 4294967295\n")
    assert run_cli("check", str(p))[0] == 0
    assert run_cli("synth", "problems/firedoor.toml", "--seed", "4294967295")[0] == 0


def test_jobs_is_clamped_to_the_files_and_the_cpus(monkeypatch):
    import os

    import linkcli.workers
    seen = []

    def solve_in_processes(files, request, jobs, work, context, lost):
        seen.append(jobs)
        return (work(path, request) for path in files)

    monkeypatch.setattr(linkcli.workers, "solve_in_processes", solve_in_processes)
    monkeypatch.setattr(os, "cpu_count", lambda: 8)
    from linkcli.pipeline import Request, executor
    for files in (["problems/firedoor.toml"] * 3, ["problems/firedoor.toml"] * 30):
        list(executor(1000, files, False)(files, Request(mode="check")))
    assert seen == [3, 8]


def test_a_transmission_a_rounding_error_outside_the_band_gives_no_warning(monkeypatch):
    # the band test compares with a relative tolerance of 1e-9: 140.00000000000006 is 140
    import math

    from linkcli.mechanisms.four_bar import sections as analyse
    from linkcli.mechanisms.four_bar.kinematics import Motion
    from linkcli.mechanisms.four_bar.model import FourBar
    from linkcli.units import Units
    fb = FourBar(ground=50, input=20, coupler=50, output=20, branch="open")
    for mx, warned in ((140.00000000000006, False), (140.001, True)):
        monkeypatch.setattr(analyse.kin, "transmission_extremes",
                            lambda *a: (math.radians(50.0), 0.0, math.radians(mx), 1.0))
        notes = []
        analyse.transmission_section(fb, Motion(assembles=True, input_arc=(0.0, 6.0)), None, Units(), notes)
        assert bool(notes) is warned, notes
