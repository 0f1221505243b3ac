"""`--cluster` on a cluster started as a user starts one: `dask scheduler` and two
`dask worker ... --nthreads 1` processes on localhost (not a LocalCluster in this process).

`dask worker` runs its workers with OMP/MKL/OPENBLAS_NUM_THREADS=1, and a serial run sets
one BLAS thread itself unless the environment names a count: the examples print the same
bytes on the cluster as serially, the solver's evaluation count included; with another
thread count named for the serial run, the same bytes but for that count
(machine_fields.py; docs/cluster.md says which solvers' counts follow the BLAS threads).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time

import pytest

distributed = pytest.importorskip(
    "distributed", reason='Dask distributed is not installed (pip install "linkcli[cluster]")')

from conftest import ROOT  # noqa: E402
from machine_fields import masked  # noqa: E402

pytestmark = pytest.mark.slow  # Dask clusters: the full suite runs them, the fast lane does not

# every search type (their counts and paths are what BLAS threads could move) and a closed form
EXAMPLES = [f"problems/{name}.toml" for name in ("crank_rocker", "firedoor", "flipper", "flipper_length",
                                                  "log_generator", "motion5", "quick_return", "straight_line")]
ENVIRONMENT = dict(os.environ)  # as the shell gave it (a LocalCluster elsewhere may change os.environ)
STARTUP = 90  # seconds for the scheduler and both workers to come up on a busy machine


@pytest.fixture(scope="module")
def scheduler_file(tmp_path_factory):
    """A scheduler and two single-threaded workers, each its own process, as
    docs/cluster.md starts them; their address is in the scheduler file."""
    path = tmp_path_factory.mktemp("dask") / "scheduler.json"
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL, "env": ENVIRONMENT}
    dask = [sys.executable, "-m", "dask"]
    processes = [subprocess.Popen([*dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                                   "--scheduler-file", str(path)], **quiet)]
    try:
        deadline = time.monotonic() + STARTUP
        while not path.exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        for _ in range(2):
            processes.append(subprocess.Popen([*dask, "worker", "--scheduler-file", str(path), "--nthreads", "1",
                                               "--no-dashboard"], **quiet))
        with distributed.Client(scheduler_file=str(path), timeout=STARTUP) as client:
            client.wait_for_workers(2, timeout=STARTUP)
        yield str(path)
    finally:
        for process in reversed(processes):
            process.terminate()
        for process in processes:
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


def synth(*args: str, **environment: str):
    proc = subprocess.run([sys.executable, "-m", "linkcli", "synth", *EXAMPLES, "--format", "json", *args],
                          capture_output=True, text=True, cwd=ROOT, env={**ENVIRONMENT, **environment},
                          timeout=900)
    return proc.returncode, proc.stdout, proc.stderr


def test_real_workers_print_what_a_serial_run_prints(scheduler_file):
    import json
    address = json.loads(open(scheduler_file).read())["address"]
    code, out, err = synth("--cluster", address)
    serial_code, serial_out, serial_err = synth()
    assert code in (0, 1) and out.startswith("["), err
    assert (code, out, err) == (serial_code, serial_out, serial_err)  # one BLAS thread both sides
    threaded_code, threaded_out, threaded_err = synth(OPENBLAS_NUM_THREADS="2")
    assert (threaded_code, threaded_err) == (code, err)
    assert masked(threaded_out, "json") == masked(out, "json")
