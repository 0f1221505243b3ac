"""Hostile input, fourth round (issue 47), process plumbing: a closed stderr changes nothing
but the missing lines; a --jobs worker killed mid-batch (as the out-of-memory killer does)
costs its own file only; SIGTERM to the command ends its workers and exits 143 saying so.

Each test runs the command line in a subprocess, as a user or a job scheduler runs it."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest
from conftest import ROOT

SRC = str(ROOT / "src")
ENV = dict(os.environ, PYTHONPATH=SRC)
# a linkage whose tolerance study takes a few seconds: a worker is busy with it long enough
LONG = ('type = "linkage"\n[linkage]\nground = 50\ninput = 27.6293\ncoupler = 57.2363\noutput = 41.1104\n'
        'branch = "open"\n[motion]\ninput_speed = 20\nsteps = 36\n[report]\nsections = ["lengths", "tolerance"]\n'
        '[tolerance]\nlengths = 0.05\nclearance = 0.02\nsamples = 300000\nallowed_error = 0.5\n'
        '[solver]\nseed = {seed}\n')


def linkcli(*args: str) -> list[str]:
    return [sys.executable, "-m", "linkcli", *args]


def long_files(folder, count: int) -> list[str]:
    names = []
    for k in range(count):
        path = folder / f"long{k}.toml"
        path.write_text(LONG.replace("{seed}", str(k)))
        names.append(str(path))
    return names


# -- a closed stderr ----------------------------------------------------------------------

CLOSED_STDERR = {
    "synth, table": ["synth", "problems/firedoor.toml"],
    "analyze, json": ["analyze", "problems/firedoor_motion.toml", "--format", "json"],
    "a json batch": ["synth", "problems/firedoor.toml", "problems/crank_rocker.toml", "--format", "json"],
    "a --jobs batch": ["synth", "problems/firedoor.toml", "problems/slider_crank.toml", "--jobs", "2",
                       "--format", "json"],
    "bench": ["bench", "problems/bench/firedoor.toml", "--seeds", "1", "--format", "json"],
}


@pytest.mark.parametrize("case", CLOSED_STDERR)
def test_a_closed_stderr_changes_neither_the_report_nor_the_exit_code(case):
    """`2>&-`: the report prints and the exit code is the one with stderr open (the
    progress display asked a stream that was None, and every run ended with exit 1)."""
    command = CLOSED_STDERR[case]
    open_ = subprocess.run(linkcli(*command), capture_output=True, text=True, env=ENV, cwd=ROOT, timeout=300)
    closed = subprocess.run(linkcli(*command), stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                            env=ENV, cwd=ROOT, timeout=300, preexec_fn=lambda: os.close(2))
    assert closed.returncode == open_.returncode == 0, open_.stderr
    if "--format" in command:  # the same data (bench: but the seconds)
        drop = (lambda rows: [{k: v for k, v in r.items() if k != "seconds"} for r in rows]) \
            if case == "bench" else (lambda x: x)
        assert drop(json.loads(closed.stdout)) == drop(json.loads(open_.stdout))
    else:
        assert closed.stdout == open_.stdout


def test_a_closed_stderr_writes_the_out_folder(tmp_path):
    done = subprocess.run(linkcli("synth", "problems/firedoor.toml", "problems/crank_rocker.toml", "--out",
                                  str(tmp_path)), stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                          env=ENV, cwd=ROOT, timeout=300, preexec_fn=lambda: os.close(2))
    assert done.returncode == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["crank_rocker.txt", "firedoor.txt"]


# -- a killed --jobs worker ---------------------------------------------------------------

def _children(pid: int, count: int, deadline: float) -> list:
    psutil = pytest.importorskip("psutil")
    while time.monotonic() < deadline:
        kids = psutil.Process(pid).children()
        if len(kids) >= count:
            return kids
        time.sleep(0.02)
    return psutil.Process(pid).children()


def test_a_killed_jobs_worker_costs_its_own_file_only(tmp_path):
    """One of the two workers is killed (SIGKILL) while it solves its first file: that file's
    slot is one error line (exit 1), every other file prints as in a serial run. Before,
    the process pool broke: a traceback, and no result at all."""
    files = long_files(tmp_path, 3) + ["problems/firedoor.toml"]
    process = subprocess.Popen(linkcli("synth", *files, "--jobs", "2", "--format", "json"), cwd=ROOT, env=ENV,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        workers = _children(process.pid, 2, time.monotonic() + 60)
        assert len(workers) == 2
        time.sleep(1.0)  # each is on its first file (a few seconds of work)
        os.kill(workers[0].pid, signal.SIGKILL)
        out, err = process.communicate(timeout=300)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 1, err
    assert "Traceback" not in err
    reports = json.loads(out)
    lost = [k for k, r in enumerate(reports) if r["status"] == "error"]
    assert len(lost) == 1 and lost[0] in (0, 1), [r["status"] for r in reports]
    line = (f"{files[lost[0]]}: internal error: the worker process solving it was killed by SIGKILL "
            "(out of memory, or killed; the other files are not affected)")
    assert err.splitlines()[0] == line
    assert err.splitlines()[-1] == "4 files: 3 solved, 0 infeasible or not converged, 0 bad input, 1 failed (internal error)"
    serial = subprocess.run(linkcli("synth", *[f for k, f in enumerate(files) if k != lost[0]], "--format", "json"),
                            capture_output=True, text=True, env=ENV, cwd=ROOT, timeout=300)
    assert [r for k, r in enumerate(reports) if k != lost[0]] == json.loads(serial.stdout)


# -- SIGTERM ------------------------------------------------------------------------------

def test_sigterm_ends_the_jobs_workers_and_exits_143(tmp_path):
    """`kill PID` of `synth --jobs 2`: "terminated", exit 143, and no worker left computing
    (before, Python died at once and both workers went on)."""
    psutil = pytest.importorskip("psutil")
    files = long_files(tmp_path, 4)
    process = subprocess.Popen(linkcli("synth", *files, "--jobs", "2"), cwd=ROOT, env=ENV,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        workers = _children(process.pid, 2, time.monotonic() + 60)
        assert len(workers) == 2
        time.sleep(0.5)
        process.send_signal(signal.SIGTERM)
        out, err = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 143
    assert err.splitlines() == ["terminated"]
    gone, alive = psutil.wait_procs(workers, timeout=10)
    assert alive == []


def test_sigterm_of_a_serial_run_is_terminated_and_143(tmp_path):
    files = long_files(tmp_path, 2)
    process = subprocess.Popen(linkcli("synth", *files), cwd=ROOT, env=ENV, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    try:
        time.sleep(2.0)  # numpy imported, the first study running
        process.send_signal(signal.SIGTERM)
        out, err = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 143
    assert err.splitlines()[-1] == "terminated" and "Traceback" not in err
