"""The --cluster executor (linkcli.cluster) on a LocalCluster of two worker processes:
results identical to a serial map and in argument order, a worker killed mid-batch, a bug
in one item, an unreachable scheduler, dask missing, Ctrl-C."""

from __future__ import annotations

import contextlib
import logging
import os
import subprocess
import sys
from pathlib import Path

import pytest

distributed = pytest.importorskip(
    "distributed", reason='Dask distributed is not installed (pip install "linkcli[cluster]")')

import cluster_items  # noqa: E402  (tests/ is on sys.path; the workers import it by name)
from cluster_items import always_crash, buggy_solve, fake_solve, logged_solve, sleep_pid  # noqa: E402

from linkcli.cluster import INSTALL_HINT, internal_error, map_ordered  # noqa: E402
from linkcli.errors import InputError, LinkcliError  # noqa: E402

pytestmark = pytest.mark.slow  # Dask clusters: the full suite runs them, the fast lane does not

SRC = Path(__file__).resolve().parents[2] / "src"


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
    """Two single-threaded worker processes, shared by the module's tests."""
    local = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                     dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR)
    yield local
    local.close()


def our_tasks(local) -> list:
    """Keys of linkcli tasks the scheduler still holds."""
    return [key for key in local.scheduler.tasks if str(key).startswith("linkcli-")]


def test_results_match_a_serial_map_in_argument_order(cluster):
    items = [(f"random-{seed}.toml", seed) for seed in range(40)] + [("bad.toml", -1)]
    serial = [fake_solve(item) for item in items]
    counts = []
    results = list(map_ordered(fake_solve, items, cluster.scheduler_address,
                               progress=lambda done, total: counts.append((done, total))))
    assert results == serial
    assert repr(results) == repr(serial)  # floats bit for bit (repr round-trips exactly)
    assert results[-1][0] == 2 and results[-1][1] is None  # bad input is a result
    assert counts == [(done, len(items)) for done in range(1, len(items) + 1)]
    assert our_tasks(cluster) == []


def test_later_items_finishing_first_are_held_back(cluster, tmp_path):
    # item a0 cannot finish before a3 has: completion order differs from argument order
    options = {"folder": str(tmp_path), "wait_for_release": "a0", "release": "a3"}
    items = [(f"a{index}", index, options) for index in range(6)]
    progress_at_yield = []
    done = []
    results = []
    for result in map_ordered(logged_solve, items, cluster.scheduler_address,
                              progress=lambda count, total: done.append(count)):
        progress_at_yield.append(len(done))
        results.append(result)
    assert results == [fake_solve((name, seed)) for name, seed, _ in items]
    assert progress_at_yield[0] >= 2  # a3 (at least) arrived before a0 was yielded


def test_a_worker_killed_mid_batch_loses_and_duplicates_nothing(cluster, tmp_path):
    options = {"folder": str(tmp_path), "die_once": "w3", "sleep": 0.1}
    items = [(f"w{index}", index, options) for index in range(12)]
    results = list(map_ordered(logged_solve, items, cluster.scheduler_address))
    assert results == [fake_solve((name, seed)) for name, seed, _ in items]
    assert (tmp_path / "died").exists()
    starts = [line.split() for line in (tmp_path / "starts.log").read_text().splitlines()]
    w3_pids = [pid for name, pid in starts if name == "w3"]
    assert len(w3_pids) == 2 and w3_pids[0] != w3_pids[1]  # rerun after its worker died
    assert our_tasks(cluster) == []


def test_a_bug_in_one_item_is_its_result_and_the_others_go_on(cluster):
    items = [("a.toml", 1), ("bug", 2), ("c.toml", 3)]
    results = list(map_ordered(buggy_solve, items, cluster.scheduler_address))
    assert results[0] == fake_solve(items[0]) and results[2] == fake_solve(items[2])
    assert results[1] == (1, None, ["bug: internal error: RuntimeError: index out of range"])


def test_an_item_that_kills_every_worker_is_an_error_result(cluster):
    scheduler = cluster.scheduler
    allowed = scheduler.allowed_failures
    # KilledWorker after the first death, not the fourth (an item queued on the same
    # worker would count a death too: the crash runs alone here)
    scheduler.allowed_failures = 0
    try:
        results = list(map_ordered(always_crash, [("crash", 2)], cluster.scheduler_address))
    finally:
        scheduler.allowed_failures = allowed
    assert results == [internal_error(
        ("crash", 2), "every worker that ran it died (a crash or out of memory)")]


def test_ctrl_c_cancels_every_outstanding_task(cluster):
    def interrupt(done, total):
        raise KeyboardInterrupt

    items = [(f"s{index}", 0.3) for index in range(8)]
    results = map_ordered(sleep_pid, items, cluster.scheduler_address, progress=interrupt)
    with pytest.raises(KeyboardInterrupt):
        next(results)
    assert our_tasks(cluster) == []
    assert not [client for client in cluster.scheduler.clients
                if client.startswith("Client-")]  # our client closed


def test_stopping_early_cancels_the_rest(cluster):
    items = [(f"s{index}", 0.3) for index in range(8)]
    with contextlib.closing(map_ordered(sleep_pid, items, cluster.scheduler_address)) as run:
        next(run)
    assert our_tasks(cluster) == []


def test_a_scheduler_lost_mid_run_is_a_linkcli_error():
    doomed = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                      dashboard_address="127.0.0.1:0",
                                      silence_logs=logging.ERROR)
    items = [(f"s{index}", 0.2) for index in range(6)]

    def lose_scheduler(done, total):
        if done == 1:
            doomed.close()

    results = []
    with pytest.raises(LinkcliError) as caught:
        for result in map_ordered(sleep_pid, items, doomed.scheduler_address,
                                  progress=lose_scheduler):
            results.append(result)
    assert not isinstance(caught.value, InputError)  # exit 1, not bad input
    assert str(caught.value) == (f"--cluster: the Dask scheduler at {doomed.scheduler_address}"
                                 " was lost mid-run (its tasks were cancelled)")
    assert len(results) <= 1


def test_ctrl_c_closes_a_local_cluster_and_ends_its_workers(monkeypatch):
    started = []

    class RecordedCluster(distributed.LocalCluster):
        def __init__(self, **options):
            super().__init__(**options)
            started.append(self)

    worker_pids = []

    def interrupt(done, total):
        worker_pids.extend(nanny.pid for nanny in started[0].workers.values())
        raise KeyboardInterrupt

    monkeypatch.setattr(distributed, "LocalCluster", RecordedCluster)
    items = [(f"s{index}", 0.3) for index in range(8)]
    with pytest.raises(KeyboardInterrupt):
        list(map_ordered(sleep_pid, items, "local:2", progress=interrupt))
    assert len(started) == 1 and started[0].status.name == "closed"
    assert len(worker_pids) == 2
    for pid in worker_pids:
        with pytest.raises(ProcessLookupError):
            os.kill(pid, 0)


def test_local_cluster_results_match_a_serial_map():
    items = [(f"random-{seed}.toml", seed) for seed in range(100, 110)]
    results = list(map_ordered(fake_solve, items, "local:2"))
    serial = [fake_solve(item) for item in items]
    assert results == serial and repr(results) == repr(serial)


@pytest.mark.parametrize("address", ["local:0", "local:two", ""])
def test_a_malformed_address_is_input_error(address):
    with pytest.raises(InputError) as caught:
        next(map_ordered(fake_solve, [("a", 1)], address))
    assert str(caught.value).startswith("--cluster: expected ")
    assert "\n" not in str(caught.value)


def test_missing_dask_is_input_error_naming_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # `import distributed` fails
    with pytest.raises(InputError) as caught:
        next(map_ordered(fake_solve, [("a", 1)], "local:2"))
    message = str(caught.value)
    assert INSTALL_HINT in message and "\n" not in message


def run_python(code: str, file: bool = False) -> subprocess.CompletedProcess:
    """Run `python -c code` (or `python code` if `file`) with src/ and tests/ importable."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(SRC), str(Path(cluster_items.__file__).parent)]))
    command = [sys.executable, code] if file else [sys.executable, "-c", code]
    return subprocess.run(command, env=env, capture_output=True, text=True, timeout=120)


def test_an_unreachable_scheduler_is_one_input_error_line_and_a_clean_exit():
    # a fresh process: its exit must not hang or print a traceback for the failed clients
    code = ("import sys, time\n"
            "from linkcli.cluster import map_ordered\n"
            "from linkcli.errors import InputError\n"
            "from cluster_items import fake_solve\n"
            "for address in ['tcp://127.0.0.1:1', 'nosuch://host:1']:\n"
            "    start = time.perf_counter()\n"
            "    try:\n"
            "        next(map_ordered(fake_solve, [('a', 1)], address))\n"
            "    except InputError as exc:\n"
            "        print(exc)\n"
            "        print(f'{time.perf_counter() - start:.2f}', file=sys.stderr)\n")
    run = run_python(code)
    assert run.returncode == 0
    unreachable, malformed = run.stdout.splitlines()
    assert malformed.startswith("--cluster: expected a Dask scheduler answering at "
                                "nosuch://host:1 within 5 s, found ValueError: ")
    assert unreachable.startswith("--cluster: expected a Dask scheduler answering at "
                                  "tcp://127.0.0.1:1 within 5 s, found ")
    elapsed = run.stderr.splitlines()
    assert len(elapsed) == 2, run.stderr  # nothing but the elapsed times
    print(f"InputError after {elapsed[0]} s (unreachable), {elapsed[1]} s (malformed)")


def test_a_local_run_with_a_worker_death_prints_nothing_of_dask(tmp_path):
    # a fresh process, as the CLI: dask is imported by the run itself, and its log
    # (the worker's death, its restart, the shutdown) must stay off stderr
    code = ("from linkcli.cluster import map_ordered\n"
            "from cluster_items import fake_solve, logged_solve\n"
            "if __name__ == '__main__':\n"
            f"    options = {{'folder': {str(tmp_path)!r}, 'die_once': 'w2', 'sleep': 0.05}}\n"
            "    items = [(f'w{index}', index, options) for index in range(6)]\n"
            "    results = list(map_ordered(logged_solve, items, 'local:2'))\n"
            "    print(results == [fake_solve((name, seed)) for name, seed, _ in items])\n")
    script = tmp_path / "run.py"  # worker processes are spawned: they re-import a file
    script.write_text(code)
    run = run_python(str(script), file=True)
    assert (run.returncode, run.stdout, run.stderr) == (0, "True\n", "")
    assert (tmp_path / "died").exists()


def test_importing_the_module_imports_no_dask():
    run = run_python("import sys, linkcli.cluster\n"
                     "print(sorted(m for m in sys.modules if m.split('.')[0] in "
                     "('dask', 'distributed', 'tornado', 'cloudpickle')))")
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"


class Listener:
    """A TCP listener on a free local port that is not a Dask scheduler: `banner` bytes
    sent as soon as a client connects (another protocol that speaks first, e.g. SSH), then
    whatever it receives is read and never answered (an HTTP server waiting for a request
    line Dask never sends). Runs in a daemon thread for the `with` block."""

    def __init__(self, banner: bytes = b"") -> None:
        import socket
        self.banner = banner
        self.server = socket.create_server(("127.0.0.1", 0))
        self.address = f"tcp://127.0.0.1:{self.server.getsockname()[1]}"
        self.open: list = []

    def _serve(self) -> None:
        while True:
            try:
                conn, _ = self.server.accept()
            except OSError:  # closed
                return
            self.open.append(conn)
            if self.banner:
                conn.sendall(self.banner)

    def __enter__(self) -> Listener:
        import threading
        threading.Thread(target=self._serve, daemon=True).start()
        return self

    def __exit__(self, *exc) -> None:
        self.server.close()
        for conn in self.open:
            conn.close()


@pytest.mark.parametrize("banner, found", [  # a silent listener: test_cluster_cli.py
    (b"SSH-2.0-OpenSSH_9.6p1 Ubuntu-3ubuntu13\r\n", "a listener that does not speak Dask's protocol"),
    (b"HTTP/1.0 400 Bad request\r\nContent-Type: text/html\r\n\r\n<html></html>\r\n",
     "a listener that does not speak Dask's protocol"),
    (b"\x08" + b"\x00" * 7 + b"\x01" * 8, "a listener that "),  # a plausible frame size, then junk
])
def test_a_listener_that_is_not_a_scheduler_is_one_input_error_line(banner, found):
    # Dask's own connect waits without limit for a handshake and trusts the frame sizes it
    # reads; the probe bounds the whole exchange by the connect timeout
    with Listener(banner) as listener:
        with pytest.raises(InputError) as caught:
            next(map_ordered(fake_solve, [("a", 1)], listener.address, connect_timeout=1.0))
    message = str(caught.value)
    assert message.startswith(f"--cluster: expected a Dask scheduler answering at "
                              f"{listener.address} within 1 s, found {found}"), message
    assert "\n" not in message


def test_a_worker_address_is_refused_naming_the_scheduler(cluster):
    worker = next(iter(cluster.scheduler.workers))
    with pytest.raises(InputError) as caught:
        next(map_ordered(fake_solve, [("a", 1)], worker, connect_timeout=2.0))
    assert str(caught.value) == (f"--cluster: expected a Dask scheduler answering at {worker} "
                                 "within 2 s, found a Dask worker (give its scheduler's address)")


def test_local_n_is_limited_to_the_tasks_and_cpus_like_jobs():
    from linkcli.cluster import local_workers
    cpus = os.cpu_count() or 1
    assert local_workers("local:1000000", items=3) == min(3, cpus)
    assert local_workers("local:1000000", items=10**6) == cpus
    assert local_workers("local:1", items=50) == 1
    for address in ("local:0", "local:" + "9" * 5000, "local:١"):  # zero, 5000 digits, an Arabic digit
        with pytest.raises(InputError) as caught:
            local_workers(address)
        assert str(caught.value).startswith("--cluster: expected local:N with N a whole number")
        assert len(str(caught.value)) < 200
