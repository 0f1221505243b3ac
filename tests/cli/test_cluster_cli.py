"""`--cluster` through the command line, on a LocalCluster of two worker processes:
synth and bench give the bytes of a serial run (bench: all but the seconds), a bad file
reports in its slot, a worker killed mid-batch loses nothing, an unreachable scheduler or
a missing dask is one line and exit 2, Ctrl-C is "interrupted" and exit 130 with the
local workers ended, and nothing of dask is imported without --cluster."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

distributed = pytest.importorskip(
    "distributed", reason='Dask distributed is not installed (pip install "linkcli[cluster]")')

from conftest import ROOT, run_cli  # noqa: E402

from linkcli.cluster import INSTALL_HINT, start_local_cluster  # noqa: E402

pytestmark = pytest.mark.slow  # Dask clusters: the full suite runs them, the fast lane does not

EXAMPLES = sorted(str(path.relative_to(ROOT)) for path in (ROOT / "problems").glob("*.toml"))
BENCH_FILES = ["problems/bench/firedoor.toml", "problems/bench/crank_rocker.toml"]
DASK_MODULES = ("dask", "distributed", "tornado", "cloudpickle", "msgpack")


@pytest.fixture(scope="module", autouse=True)
def _keep_environment():
    """Dask's nanny writes its worker environment (OMP/MKL/OPENBLAS_NUM_THREADS=1, ...)
    into this process's os.environ as it starts a local worker; restore it after the
    module, so that later modules' worker processes inherit the usual environment."""
    saved = dict(os.environ)
    yield
    os.environ.clear()
    os.environ.update(saved)


@pytest.fixture(scope="module")
def cluster():
    """Two single-threaded worker processes (as `--cluster local:2` starts them), shared
    by the module's tests; the CLI reaches it by its scheduler's address."""
    local = start_local_cluster(2)
    yield local
    local.close()


@pytest.fixture(scope="module")
def batch(tmp_path_factory) -> list[str]:
    """The examples, random linkage files of several scales, and a bad file (its slot)."""
    folder = tmp_path_factory.mktemp("cluster_batch")
    rng = np.random.default_rng(20)
    files = list(EXAMPLES)
    for index in range(4):
        scale = 10.0 ** rng.uniform(-2, 2)
        ground, crank, coupler, output = (float(x) for x in rng.uniform(0.2, 1.0, 4) * scale)
        path = folder / f"random{index}.toml"
        path.write_text(f'type = "linkage"\n[linkage]\nground = {ground!r}\ninput = {crank!r}\n'
                        f'coupler = {coupler!r}\noutput = {output!r}\n'
                        f'branch = "{"open" if index % 2 else "crossed"}"\n[motion]\n'
                        f'input_speed = 10\nsteps = 36\n[report]\nsections = ["lengths", '
                        f'"grashof", "transmission", "motion", "kinematics"]\n')
        files.insert(2 * index + 1, str(path))  # mixed with the examples
    bad = folder / "bad.toml"
    bad.write_text('type = "linkage"\n[linkage]\nground = "fifty"\n')
    files.insert(3, str(bad))
    return files


def bad_lines(err: str) -> list[str]:
    return [line for line in err.splitlines() if "bad.toml" in line]


@pytest.mark.parametrize("fmt", ["json", "table"])
def test_synth_on_the_cluster_gives_the_bytes_of_a_serial_run(cluster, batch, fmt):
    serial = run_cli("synth", *batch, "--format", fmt)
    on_cluster = run_cli("synth", *batch, "--format", fmt, "--cluster", cluster.scheduler_address)
    assert on_cluster == serial
    code, out, err = on_cluster
    assert code == 2  # the bad file; every other file still reported
    assert f'{batch[3]}:3: linkage.ground: expected a positive length, found "fifty" (string)' \
        in bad_lines(err)
    summary = err.splitlines()[-1]
    assert summary.startswith(f"{len(batch)} files: ") and summary.endswith(", 1 bad input")
    if fmt == "json":
        reports = json.loads(out)
        assert [r["file"] for r in reports] == batch
        assert reports[3]["status"] == "bad-input"
        assert all("type" in r for i, r in enumerate(reports) if i != 3)


def test_bench_on_the_cluster_gives_the_rows_of_a_serial_run_but_the_seconds(cluster):
    args = ("bench", *BENCH_FILES, "--seeds", "2", "--format", "json", "--precision", "17")
    code, out, err = run_cli(*args)
    code_c, out_c, err_c = run_cli(*args, "--cluster", cluster.scheduler_address)
    rows, rows_c = json.loads(out), json.loads(out_c)
    for row in rows + rows_c:
        assert row.pop("seconds") > 0
    assert (code_c, rows_c, err_c) == (code, rows, err)
    methods = {(r["problem"], r["method"], r["budget"]) for r in rows}
    assert len(rows) == 2 * len(methods)  # every setting x seed, once
    assert [(r["problem"], r["seed"]) for r in rows][:2] == [(BENCH_FILES[0], 0),
                                                              (BENCH_FILES[0], 1)]


def test_cluster_with_jobs_is_one_line_and_exit_2(cluster):
    code, out, err = run_cli("synth", *EXAMPLES[:2], "--jobs", "2",
                             "--cluster", cluster.scheduler_address)
    assert (code, out) == (2, "")
    assert err == ("--cluster: expected either --cluster or --jobs N (a cluster's workers are "
                   "its processes), found both (--jobs 2)\n")


def test_without_dask_cluster_is_one_line_naming_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # `import distributed` fails
    for command in (("synth", EXAMPLES[0]), ("bench", BENCH_FILES[0], "--seeds", "1")):
        code, out, err = run_cli(*command, "--cluster", "local:2")
        assert (code, out) == (2, "")
        assert len(err.splitlines()) == 1 and INSTALL_HINT in err


def test_a_worker_killed_mid_batch_loses_no_result(cluster, batch):
    """A worker process is killed (SIGKILL) while it runs one of the batch's files: the
    scheduler reruns that file elsewhere, and the output is still the serial one."""
    serial = run_cli("synth", *batch, "--format", "json")
    killed = []

    def kill_a_busy_worker():
        deadline = time.monotonic() + 60.0
        while not killed and time.monotonic() < deadline:
            busy = {task.processing_on.address for key, task in list(cluster.scheduler.tasks.items())
                    if str(key).startswith("linkcli-") and task.processing_on is not None}
            for nanny in list(cluster.workers.values()):
                if nanny.worker_address in busy and nanny.process is not None:
                    os.kill(nanny.pid, signal.SIGKILL)
                    killed.append(nanny.pid)
                    return
            time.sleep(0.005)

    killer = threading.Thread(target=kill_a_busy_worker)
    killer.start()
    on_cluster = run_cli("synth", *batch, "--format", "json", "--cluster", cluster.scheduler_address)
    killer.join()
    assert killed, "no worker was busy with the batch"
    assert on_cluster == serial
    with distributed.Client(cluster, set_as_default=False) as client:
        client.wait_for_workers(2, timeout=60)  # the nanny restarted it


def python(code: str, *, timeout: float = 120.0) -> subprocess.CompletedProcess:
    """`python -c code` from the repository root with this tree's src/ first."""
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    return subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=timeout)


def test_an_unreachable_scheduler_is_one_line_and_exit_2():
    run = python("import sys, time\n"
                 "from linkcli.cli import main\n"
                 "sys.argv = ['linkcli', 'synth', 'problems/firedoor.toml', '--cluster', "
                 "'tcp://127.0.0.1:1']\n"
                 "start = time.perf_counter()\n"
                 "try:\n"
                 "    main()\n"
                 "except SystemExit as done:\n"
                 "    print(done.code, f'{time.perf_counter() - start:.2f}')\n")
    code, seconds = run.stdout.split()
    assert code == "2"
    assert len(run.stderr.splitlines()) == 1, run.stderr
    assert run.stderr.startswith("--cluster: expected a Dask scheduler answering at "
                                 "tcp://127.0.0.1:1 within 5 s, found ")
    print(f"exit 2 after {seconds} s")


def test_synth_without_cluster_imports_nothing_of_dask():
    run = python("import sys\n"
                 "from linkcli.cli import main\n"
                 "sys.argv = ['linkcli', 'synth', 'problems/firedoor.toml']\n"
                 "try:\n"
                 "    main()\n"
                 "except SystemExit as done:\n"
                 "    assert done.code == 0, done.code\n"
                 f"names = sorted(m for m in sys.modules if m.split('.')[0] in {DASK_MODULES!r})\n"
                 "print('dask modules:', names, file=sys.stderr)\n")
    assert run.returncode == 0, run.stderr
    assert run.stderr == "dask modules: []\n"
    assert "Fire-door closer" in run.stdout  # it did solve


def test_ctrl_c_is_interrupted_and_exit_130_with_the_local_workers_ended(tmp_path):
    psutil = pytest.importorskip("psutil")  # a dependency of distributed
    files = []
    for index in range(16):  # long enough a batch to be interrupted mid-way
        target = tmp_path / f"s{index}.toml"
        target.write_text((ROOT / "problems" / "straight_line.toml").read_text())
        files.append(str(target))
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    process = subprocess.Popen([sys.executable, "-m", "linkcli", "synth", *files,
                                "--cluster", "local:2"], cwd=ROOT, env=env, text=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               # Ctrl-C as in a terminal, also when the tests run in the
                               # background (which starts children with SIGINT ignored)
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        first = process.stdout.readline()  # the first report is out: the batch is running
        assert first, process.stderr.read()
        workers = psutil.Process(process.pid).children(recursive=True)
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 130
    assert err.splitlines()[-1] == "interrupted"
    assert "Traceback" not in err
    assert len(workers) >= 2
    gone, alive = psutil.wait_procs(workers, timeout=10)
    assert alive == []


def test_a_ctrl_c_whose_exception_was_swallowed_still_stops_the_batch_with_130(monkeypatch):
    """Python only prints a KeyboardInterrupt raised inside a garbage-collector callback
    (Dask installs one): the Ctrl-C must not be lost there. The first file's run
    receives SIGINT and swallows the exception; the batch stops before the second."""
    import linkcli.pipeline as pipeline

    solved = []

    def swallowing_serial(files, request):
        for outcome in pipeline.serial(files, request):
            solved.append(outcome)
            try:
                signal.raise_signal(signal.SIGINT)
            except KeyboardInterrupt:
                pass  # what an "Exception ignored in: <gc callback>" amounts to
            yield outcome

    monkeypatch.setattr(pipeline, "executor", lambda *args, **kwargs: swallowing_serial)
    before = signal.signal(signal.SIGINT, signal.default_int_handler)  # as in a terminal
    try:
        code, out, err = run_cli("synth", "problems/firedoor.toml", "problems/firedoor.toml")
        after = signal.getsignal(signal.SIGINT)
    finally:
        signal.signal(signal.SIGINT, before)  # a test run in the background ignores SIGINT
    assert code == 130
    assert err.splitlines()[-1] == "interrupted"
    assert len(solved) == 1 and "Fire-door" not in out  # stopped before printing
    assert after is signal.default_int_handler  # restored


def test_a_ctrl_c_inside_a_gc_callback_is_not_printed_as_an_ignored_exception(monkeypatch):
    """The real mechanism: a Ctrl-C landing in a garbage-collector callback (Dask's) is
    reported by Python through sys.unraisablehook ("Exception ignored in ... Traceback").
    It must end the batch with "interrupted" and 130, and print no traceback."""
    import gc

    import linkcli.pipeline as pipeline

    def ctrl_c_in_gc_callback(files, request):
        def callback(phase, info):
            if phase == "start":
                signal.raise_signal(signal.SIGINT)

        for outcome in pipeline.serial(files, request):
            gc.callbacks.append(callback)
            try:
                gc.collect()
            finally:
                gc.callbacks.remove(callback)
            yield outcome

    monkeypatch.setattr(pipeline, "executor", lambda *args, **kwargs: ctrl_c_in_gc_callback)
    monkeypatch.setattr(sys, "unraisablehook", sys.__unraisablehook__)  # Python's, not pytest's
    hook = sys.unraisablehook
    before = signal.signal(signal.SIGINT, signal.default_int_handler)  # as in a terminal
    try:
        code, out, err = run_cli("synth", "problems/firedoor.toml", "problems/firedoor.toml")
    finally:
        signal.signal(signal.SIGINT, before)
    assert code == 130
    assert err.splitlines()[-1] == "interrupted"
    assert "Traceback" not in err and "Exception ignored" not in err, err
    assert sys.unraisablehook is hook  # restored


def test_a_silent_listener_is_one_line_and_exit_2_in_bounded_time():
    # something accepts the connection and never answers (an HTTP server waits for a request
    # line Dask never sends): Dask alone would wait for its handshake without limit; a hang
    # here ends in the subprocess timeout, a failure
    import socket
    with socket.create_server(("127.0.0.1", 0)) as server:
        address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
        run = python("import sys\n"
                     "from linkcli.cli import main\n"
                     f"sys.argv = ['linkcli', 'synth', 'problems/firedoor.toml', '--cluster', {address!r}]\n"
                     "try:\n"
                     "    main()\n"
                     "except SystemExit as done:\n"
                     "    print(done.code)\n", timeout=60)
    assert run.stdout == "2\n"
    assert run.stderr == (f"--cluster: expected a Dask scheduler answering at {address} within 5 s, "
                          "found a listener that did not answer as Dask within 5 s\n")


def test_local_with_a_million_workers_starts_no_more_than_it_can_use():
    # local:N is limited to the files and the CPUs, as --jobs is: one file, one worker
    code, out, err = run_cli("synth", "problems/firedoor.toml", "--format", "json",
                             "--cluster", "local:1000000")
    assert code == 0, err
    assert json.loads(out)["status"] == "ok"
