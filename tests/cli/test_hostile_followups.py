"""Independent verification of issue 47 on main (after the merge of hostile4 with the drawn
designs): what the verification found still broken, each with the command that showed it."""

from __future__ import annotations

import pytest
from conftest import ROOT, run_cli


def test_bench_takes_a_drawn_design_whose_settings_are_its_own():
    """A drawn design lists its own bench settings as (method, budget) pairs, as a problem type
    does; bench unpacked them as (method, budget, atlas) and `linkcli bench` with no arguments
    (the packaged set holds bench/drawn_six_bar_path.toml) was a traceback at once:
    `ValueError: not enough values to unpack (expected 3, got 2)`."""
    from linkcli.bench import runs_of, settings_for
    from linkcli.reading.load import load
    path = str(ROOT / "problems" / "bench" / "drawn_six_bar_path.toml")
    assert settings_for(load(path)) == [("auto", None, None)]
    runs = runs_of(path, 2)
    assert [(r.method, r.budget, r.seed, r.atlas) for r in runs] == [("auto", None, 0, None), ("auto", None, 1, None)]


def _small_files():
    import resource
    import signal
    resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # the write fails (EFBIG) instead of killing


def _run(args, stdout=None, **env):
    import os
    import subprocess
    import sys
    environment = {**os.environ, "PYTHONPATH": str(ROOT / "src"), **env}
    return subprocess.run([sys.executable, "-m", "linkcli", *args], stdout=stdout or subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, env=environment, cwd=ROOT, timeout=300,
                          preexec_fn=_small_files)


def test_a_result_file_that_cannot_be_written_whole_leaves_nothing_behind(tmp_path):
    """--out DIR wrote each result straight into its file: a write that failed midway (here a
    file-size limit of 4096 bytes; a full disk or a quota alike) left the first 4096 bytes
    of firedoor_motion.json behind, a truncated result file -- as issue 47 found of GIFs and
    DXFs. Each format's file now appears whole or not at all."""
    for fmt, name in (("json", "firedoor_motion.json"), ("toml", "firedoor_motion.toml"),
                      ("table", "firedoor_motion.txt"), ("csv", "firedoor_motion.kinematics.csv")):
        folder = tmp_path / fmt
        done = _run(["analyze", "problems/firedoor_motion.toml", "--format", fmt, "--out", str(folder)])
        assert done.returncode == 2, done.stderr
        assert done.stderr.splitlines()[-1] == f"{folder / name}: expected a writable result file, found File too large"
        assert list(folder.iterdir()) == []


def test_a_report_cut_by_a_full_output_file_is_exit_2_also_unbuffered(tmp_path):
    """Standard output into a file that stops taking bytes midway (a file-size limit of 4096
    bytes; a disk filling or a quota alike). With PYTHONUNBUFFERED=1 (or python -u: common in
    containers and CI) stdout's buffer is the raw file, whose write takes part of the text
    and TextIOWrapper drops the rest without a word: the report was cut at 4096 bytes and
    the exit code 0. Buffered, the same run was already exit 2 and one line."""
    for unbuffered in ("1", ""):
        target = tmp_path / f"report{unbuffered}.json"
        with open(target, "w") as handle:
            done = _run(["analyze", "problems/firedoor_motion.toml", "--format", "json"], stdout=handle,
                        PYTHONUNBUFFERED=unbuffered)
        assert done.returncode == 2, (unbuffered, done.stderr)
        assert done.stderr.splitlines() == ["standard output: expected an output that takes the report, found File too large"]


def test_atlas_build_names_an_empty_out_as_empty_not_as_the_current_folder():
    """Issue 47 named empty paths for synth and analyze's options and new's FILE; atlas build's
    --out was still a Path, read by pathlib as ".": `.: expected a file name for the atlas,
    found a folder`."""
    code, out, err = run_cli("atlas", "build", "--out", "")
    assert (code, out, err) == (2, "", "--out: expected a file name for the atlas, found an empty argument\n")


def test_a_cluster_address_without_a_host_is_not_blamed_on_its_port():
    """`tcp://:8786` has a port and no host; it was reported as `found no port in
    'tcp://:8786'`."""
    from linkcli.cluster import address_problem
    for address in ("tcp://:8786", ":8786", "tcp://[]:8786"):
        assert address_problem(address, 5) == f"no host in {address!r} (an address is tcp://HOST:PORT)"
    for address in ("tcp://127.0.0.1", "127.0.0.1:", "tcp://localhost"):
        assert address_problem(address, 5) == f"no port in {address!r} (an address is tcp://HOST:PORT)"
    assert address_problem("tcp://127.0.0.1:8786", 5) is None


@pytest.mark.slow
@pytest.mark.parametrize("sig", ["SIGKILL", "SIGHUP"])
def test_a_jobs_supervisor_killed_outright_leaves_no_worker_behind(tmp_path, sig):
    """The supervisor of `synth --jobs 2` killed without a chance to stop its workers (SIGKILL,
    as the out-of-memory killer would; SIGHUP sent to it alone): both workers stayed behind
    for good, reparented, each blocked on a pipe whose other end it held itself (inherited
    through fork). They end now within about a second (each watches its parent)."""
    import signal
    import subprocess
    import time

    from test_hostile_plumbing import ENV, _children, linkcli, long_files
    psutil = pytest.importorskip("psutil")
    process = subprocess.Popen(linkcli("synth", *long_files(tmp_path, 4), "--jobs", "2"), cwd=ROOT, env=ENV,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        workers = _children(process.pid, 2, time.monotonic() + 60)
        assert len(workers) == 2
        time.sleep(0.5)
        process.send_signal(getattr(signal, sig))
        process.wait(timeout=60)
        gone, alive = psutil.wait_procs(workers, timeout=10)
    finally:
        if process.poll() is None:
            process.kill()
        for worker in psutil.Process().children(recursive=True):
            worker.kill()
    assert alive == []


def test_debug_keeps_bad_inputs_exit_code_and_lines(tmp_path):
    """--debug on bad input shows where the error was raised, then the same located lines and
    exit 2 as without it (it re-raised: a traceback and exit 1, the code of an internal error)."""
    import subprocess
    import sys
    bad = tmp_path / "bad.toml"
    bad.write_text('type = "linkage"\n[linkage]\nground = nan\ninput = 1\ncoupler = 3\noutput = 3\n')
    plain = subprocess.run([sys.executable, "-m", "linkcli", "check", str(bad)], capture_output=True, text=True)
    assert plain.returncode == 2 and plain.stderr
    for command in ("check", "synth", "analyze"):
        res = subprocess.run([sys.executable, "-m", "linkcli", command, "--debug", str(bad)], capture_output=True,
                             text=True)
        assert res.returncode == 2, (command, res.stderr)
        assert res.stderr.endswith(plain.stderr) and "Traceback" in res.stderr


def test_messages_that_sent_the_user_round_in_circles(tmp_path):
    """Three lines a hostile-input probe found pointing the wrong way: a topology in a
    `type = "linkage"` file (it added "joints: expected a table" and called topology unknown);
    synth of a drawn linkage's analysis result (it said "analyse it with linkcli analyze", which
    refuses it); analyze of a JSON result (a bare TOML syntax error)."""
    from conftest import ROOT, run_cli
    topo = tmp_path / "topo.toml"
    topo.write_text('type = "linkage"\n[linkage]\nmechanism = "drawn"\ntopology = "watt-i"\n')
    code, _, err = run_cli("check", str(topo))
    assert code == 2 and err.splitlines() == [
        f'{topo}:4: linkage.topology: expected a drawing ([joints], [links], [drive]) in a type = "linkage" file '
        '(a topology is designed: type = "path-generation", "motion-generation" or "function-generation"), '
        'found "watt-i" (string)']
    code, out, err = run_cli("analyze", str(ROOT / "problems" / "drawn_watt.toml"), "--format", "toml")
    assert code == 0, err
    result = tmp_path / "watt_result.toml"
    result.write_text(out)
    for command in ("synth", "check"):
        code, _, err = run_cli(command, str(result))
        assert code == 2 and "a drawn linkage's analysis (its problem file holds the drawing" in err
        assert "analyse it with linkcli analyze" not in err
    code, out, err = run_cli("synth", str(ROOT / "problems" / "firedoor.toml"), "--format", "json")
    assert code == 0, err
    as_json = tmp_path / "firedoor.json"
    as_json.write_text(out)
    code, _, err = run_cli("analyze", str(as_json))
    assert code == 2 and err.rstrip().endswith("(a JSON file? linkcli reads TOML: a result to analyse is written "
                                               "with --format toml)")


def test_topology_lines_say_what_to_do(tmp_path):
    """A topology without mechanism = "drawn" is one line saying so (read as the four-bar's it
    gave seven lines, none saying so); [material] or [strength] alone beside a topology is the
    topology's refusal (it asked for [loads], which the topology refuses too); a topology in a
    linkage file that has a drawing is the one line of a topology in a linkage file."""
    from conftest import ROOT, run_cli
    sweep = (ROOT / "problems" / "six_bar_dwell_sweep.toml").read_text(encoding="utf-8")
    assert 'mechanism = "drawn"\n' in sweep
    cases = {
        "nomech": (sweep.replace('mechanism = "drawn"\n', ""),
                   'linkage.topology: expected mechanism = "drawn" with a topology'),
        "material": (sweep + '\n[material]\nname = "AISI 1045 CD"\n', "material: expected no [material] with [linkage] "
                     "topology"),
        "strength": (sweep + "\n[strength]\nrequired = 2\n", "strength: expected no [strength] with [linkage] topology"),
        "linkage": ((ROOT / "problems" / "drawn_watt.toml").read_text(encoding="utf-8").replace(
            'mechanism = "drawn"', 'mechanism = "drawn"\ntopology = "watt-i"'),
            'linkage.topology: expected a drawing ([joints], [links], [drive]) in a type = "linkage" file'),
    }
    for name, (text, line) in cases.items():
        path = tmp_path / f"{name}.toml"
        path.write_text(text)
        code, _, err = run_cli("check", str(path))
        assert code == 2 and len(err.splitlines()) == 1 and line in err, (name, err)
