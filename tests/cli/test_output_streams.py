"""Where the output goes (issue 28): a full device or a closed stdout is one line and exit
2, a reader that closes the pipe ends the command quietly with exit 141 (documented in
docs/format.md), a closed stderr is no crash; on a terminal the progress display counts the solve's
evaluations on stderr, and nothing of it reaches a pipe or the JSON."""

from __future__ import annotations

import json
import os
import pty
import select
import subprocess
import sys

import pytest
from conftest import ROOT

SRC = str(ROOT / "src")
ENV = dict(os.environ, PYTHONPATH=SRC)
LONG = ('type = "linkage"\n[linkage]\nground = 50\ninput = 20\ncoupler = 60\noutput = 45\nbranch = "open"\n'
        '[motion]\ninput_speed = 10\nsteps = 20000\n[report]\nsections = ["lengths", "kinematics"]\n')


def linkcli(*args: str) -> list[str]:
    return [sys.executable, "-m", "linkcli", *args]


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full on this system")
@pytest.mark.parametrize("fmt", ["table", "json", "toml", "csv"])
def test_a_full_device_is_one_line_and_exit_2(fmt):
    args = ["synth", "problems/firedoor_motion.toml", "--format", fmt] + (["--table", "kinematics"] if fmt == "csv" else [])
    with open("/dev/full", "w") as full:
        done = subprocess.run(linkcli(*args), stdout=full, stderr=subprocess.PIPE, text=True, env=ENV,
                              cwd=ROOT, timeout=120)
    assert done.returncode == 2
    assert done.stderr == ("standard output: expected an output that takes the report, found No space "
                           "left on device\n")


@pytest.mark.parametrize("command", [["synth", "problems/firedoor.toml", "--format", "json"],
                                     ["check", "problems/firedoor.toml"], ["--version"]])
@pytest.mark.slow
def test_a_closed_stdout_is_one_line_and_exit_2(command):
    done = subprocess.run(linkcli(*command), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                          env=ENV, cwd=ROOT, timeout=120, preexec_fn=lambda: os.close(1))
    assert done.returncode == 2, done.stderr
    assert done.stderr == ("standard output: expected an output that takes the report, found no standard "
                           "output (it is closed)\n")


@pytest.mark.slow
@pytest.mark.parametrize("fmt", ["table", "json", "toml", "csv"])
def test_a_reader_that_closes_the_pipe_ends_the_batch_quietly_with_141(tmp_path, fmt):
    long = tmp_path / "long.toml"
    long.write_text(LONG)
    second = tmp_path / "second.toml"
    second.write_text(LONG.replace("ground = 50", "ground = 51"))
    files = [str(long)] if fmt == "csv" else [str(long), str(second)]  # csv to stdout: one file
    read, write = os.pipe()
    os.close(read)  # the reader is gone before anything is written
    try:
        done = subprocess.run(linkcli("synth", *files, "--format", fmt), stdout=write, stderr=subprocess.PIPE,
                              text=True, env=ENV, cwd=ROOT, timeout=120)
    finally:
        os.close(write)
    assert done.returncode == 141
    assert done.stderr == ""  # no traceback, no "Exception ignored", no batch summary: it stopped


def test_a_closed_stderr_does_not_crash_a_bad_input_run(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('type = "linkage"\n[linkage]\nground = -1\n')
    done = subprocess.run(linkcli("check", str(bad)), stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                          text=True, env=ENV, cwd=ROOT, timeout=120, preexec_fn=lambda: os.close(2))
    assert done.returncode == 2 and done.stdout == ""


def _read_all(fd: int, process: subprocess.Popen) -> bytes:
    out = b""
    while True:
        ready, _, _ = select.select([fd], [], [], 0.5)
        if ready:
            try:
                chunk = os.read(fd, 65536)
            except OSError:  # the other end closed (Linux: EIO)
                break
            if not chunk:
                break
            out += chunk
        elif process.poll() is not None:
            break
    return out


@pytest.mark.slow
def test_on_a_terminal_the_progress_counts_evaluations_and_the_json_stays_clean():
    # stderr is a terminal (a pseudo-terminal here), stdout a pipe: the display goes to
    # stderr only, and counts the evaluations of the search as it runs
    main, child = pty.openpty()
    process = subprocess.Popen(linkcli("synth", "problems/crank_rocker.toml", "--format", "json"),
                               stdout=subprocess.PIPE, stderr=child, env=dict(ENV, COLUMNS="100"), cwd=ROOT)
    os.close(child)
    try:
        shown = _read_all(main, process).decode("utf-8", "replace")
        out = process.stdout.read().decode()
        process.wait(timeout=120)
    finally:
        os.close(main)
        process.stdout.close()
    assert process.returncode == 0
    report = json.loads(out)  # stdout holds the JSON and nothing else
    assert "solving problems/crank_rocker.toml" in shown
    counts = [int(word.replace(",", "")) for word in shown.replace("\r", " ").split() if word.replace(",", "").isdigit()]
    assert " evaluations" in shown
    assert 0 < max(counts) <= report["solver"]["evaluations"]


def test_in_a_pipe_there_is_no_progress_and_no_counting(monkeypatch):
    from conftest import run_cli

    from linkcli.search import budget
    seen = []
    monkeypatch.setattr(budget, "watch", None)
    code, out, err = run_cli("synth", "problems/crank_rocker.toml", "--format", "json")
    assert code == 0 and err == ""
    assert budget.watch is None and not seen


@pytest.mark.slow
def test_the_evaluations_counted_are_those_the_solver_reports(monkeypatch):
    # the progress display's count (search.budget.watch) is the report's solver.evaluations
    from linkcli.pipeline import Request, run
    from linkcli.search import budget
    for problem in ("problems/crank_rocker.toml", "problems/straight_line.toml", "problems/motion_many.toml"):
        counted = []
        monkeypatch.setattr(budget, "watch", counted.append)
        outcome = run(problem, Request())
        assert sum(counted) == outcome.result.report["solver"]["evaluations"], problem
