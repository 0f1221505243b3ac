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
        assert f"{good}: ok" in lines
    elif command == "bench":
        assert "firedoor" in out
    else:
        assert "solved" in err.splitlines()[-1] and not err.splitlines()[-1].startswith("0 solved")
        assert out.strip()


def test_a_file_beyond_the_size_cap_is_refused_without_reading_it(tmp_path):
    from linkcli.safe_read import MAX_FILE_BYTES
    big = tmp_path / "big.toml"
    with open(big, "wb") as fh:  # sparse: 200 MB of size, no disk or memory used
        fh.truncate(200 * 1024 * 1024)
    code, out, err = _cli("check", str(big))
    assert code == 2 and out == ""
    assert err == (f"{big}: expected a problem file of at most {MAX_FILE_BYTES} bytes (4 MiB), "
                   f"found {200 * 1024 * 1024} bytes\n")


def test_a_file_at_the_cap_is_read(tmp_path):
    from linkcli.safe_read import MAX_FILE_BYTES, read_problem_bytes
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
    assert out.splitlines()[0].startswith("\\x1b[2J\\x1b[31mRED\\x07  (")


def test_a_file_name_with_escapes_is_shown_escaped_in_errors(tmp_path):
    p = tmp_path / "bad\x1b[2J.toml"
    p.write_text("type = 1\n")
    code, out, err = run_cli("check", str(p))
    assert code == 2 and "\x1b" not in err
    assert err.startswith(str(p).replace("\x1b", "\\x1b") + ":1: type: expected one of")


def test_a_100k_character_key_gives_a_short_line(tmp_path):
    from linkcli.terminal_text import SHOWN_LIMIT
    p = tmp_path / "longkey.toml"
    key = "k" * 100_000
    p.write_text((ROOT / "problems" / "firedoor.toml").read_text().replace("[linkage]", f"[linkage]\n{key} = 1", 1))
    code, _, err = run_cli("check", str(p))
    assert code == 2
    lines = err.splitlines()
    assert all(len(l) < len(str(p)) + 3 * SHOWN_LIMIT for l in lines), [len(l) for l in lines]
    assert any(("k" * (SHOWN_LIMIT - 20) + "...: expected") in l for l in lines), lines


# -- 4. a design that misses a position is infeasible --------------------------------

def test_a_three_position_design_missing_a_position_is_infeasible_and_still_shown(tmp_path):
    import cmath
    import math
    p = tmp_path / "miss.toml"
    p.write_text('type = "precision-position"\n[linkage]\nground = 50.0\n[positions]\n'
                 "input = [45, 90, 135]\noutput = [52, 53, 200]\n")
    code, out, err = run_cli("synth", str(p), "-f", "json")
    assert code == 1 and json.loads(out)["status"] == "infeasible", err
    from linkcli.cli import run_one
    code, rep, _ = run_one(str(p), "synth", None, False)  # full precision
    assert code == 1
    assert rep["message"].endswith("; branch defect (see notes); infeasible: position 2 missed by up to "
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
    from linkcli.position_verdict import MISS_FLOOR_RAD, verdict
    from linkcli.result import Status
    from linkcli.solvers.precision_position import TRAVEL_NOTE
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
