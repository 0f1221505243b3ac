"""The `--cluster` executor: run one function over many items on Dask distributed.

    map_ordered(function, items, address) -> results in argument order, streamed

The same shape as a serial map: `function` is a picklable top-level function of one item
(a file name plus options) that returns a picklable result and reports bad input in that
result instead of raising. Dask only transports items and results, so a cluster run
computes the same bytes as a serial one. Dask's scheduler does the scheduling and the
recovery (Rocklin, "Dask: Parallel computation with blocked algorithms and task
scheduling", SciPy 2015; distributed.dask.org); this module adds only ordering, fault
reporting and clean shutdown:

- a worker that dies mid-task: the scheduler reruns its tasks elsewhere; each task has its
  own key (this run's token + the item's index) and is gathered once, so no result is
  lost or duplicated; a task that kills every worker it runs on (more than
  `distributed.scheduler.allowed-failures` times) becomes an error result for its item;
- an exception escaping `function` (a bug): caught on the worker into an error result
  (`on_error`), the other items go on;
- an unreachable scheduler or a malformed address: `InputError` (exit 2), one line;
- Ctrl-C or an abandoned iteration: outstanding futures cancelled, client and local
  cluster closed, the `KeyboardInterrupt` re-raised.

dask is imported inside the functions only: importing this module imports none of it.
"""

from __future__ import annotations

import contextlib
import gc
import logging
import uuid
from collections.abc import Callable, Iterable, Iterator
from typing import Any

from linkcli.errors import InputError, LinkcliError

DEFAULT_CONNECT_TIMEOUT = 5.0  # seconds to reach a scheduler before giving up (exit 2)
LOCAL_PREFIX = "local:"
INSTALL_HINT = 'pip install "linkcli[cluster]"'
OPTION = "--cluster"  # where errors point: the option, not a file
BLAS_THREADS = ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS")
# A preload script (Dask runs text with a space in it) for local workers: a terminal's
# Ctrl-C reaches the whole process group, but it is the client's to handle (it cancels
# the tasks and closes the cluster); a worker would die of it with a traceback.
IGNORE_CTRL_C = "import signal; signal.signal(signal.SIGINT, signal.SIG_IGN)"


def internal_error(item: Any, description: str) -> tuple[int, None, list[str]]:
    """The result of an item whose run failed outside `function`'s own error handling:
    (exit code 1, no report, one error line naming the item's file)."""
    name = item[0] if isinstance(item, (tuple, list)) and item else item
    return 1, None, [f"{name}: internal error: {description}"]


def run_guarded(function: Callable[[Any], Any], on_error: Callable[[Any, str], Any],
                item: Any) -> Any:
    """`function(item)` on a worker; an exception it raises becomes `on_error(item, text)`,
    so one failing item never stops the others (top-level: Dask pickles it by name)."""
    try:
        return function(item)
    except Exception as exc:  # a bug in function: reported in its item's slot
        return on_error(item, one_line(exc))


def one_line(exc: BaseException) -> str:
    """`Type: message`, first line of the message only (error output is one line per item)."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__


def map_ordered(function: Callable[[Any], Any], items: Iterable[Any], address: str, *,
                progress: Callable[[int, int], None] | None = None,
                connect_timeout: float = DEFAULT_CONNECT_TIMEOUT,
                on_error: Callable[[Any, str], Any] = internal_error) -> Iterator[Any]:
    """Yield `function(item)` for each item, in argument order, computed on the Dask
    cluster at `address` (`tcp://host:port`, `host:port`, or `local:N` for a LocalCluster
    of N single-threaded worker processes that lives as long as the iteration).

    Result k is yielded as soon as results 0..k are in; `progress(done, total)` is called
    as each result arrives, in completion order. Connects on the first `next()`.
    Raises InputError if dask is not installed or the scheduler cannot be reached within
    `connect_timeout` seconds, LinkcliError if the scheduler is lost mid-run; re-raises
    KeyboardInterrupt after cancelling everything. A caller that may stop early (or be
    interrupted between results) should iterate inside `contextlib.closing(...)` so that
    the cleanup runs at once, not when the generator is garbage-collected.
    """
    items = list(items)
    total = len(items)
    _require_distributed()  # before the log filter: importing it installs dask's handlers
    with _quiet_dask_logs():
        cluster, client = _connect(address, connect_timeout, total)
        futures: list[Any] = []
        try:
            from distributed import as_completed

            run = uuid.uuid4().hex  # two runs sharing a scheduler never share a key
            futures = client.map(run_guarded, [function] * total, [on_error] * total, items,
                                 key=[f"linkcli-{run}-{index}" for index in range(total)],
                                 pure=False, retries=0)
            index_of = {future.key: index for index, future in enumerate(futures)}
            arrived: dict[int, Any] = {}
            next_index = 0
            done = 0
            for future, outcome in as_completed(futures, loop=client.loop, with_results=True,
                                                raise_errors=False):
                index = index_of[future.key]
                arrived[index] = _result_of(future, outcome, items[index], address, on_error)
                done += 1
                if progress is not None:
                    progress(done, total)
                while next_index in arrived:
                    result = arrived.pop(next_index)
                    futures[next_index] = None  # the scheduler may forget it now
                    next_index += 1
                    yield result
        finally:
            outstanding = [future for future in futures if future is not None]
            _close(client, cluster, outstanding)


def _result_of(future: Any, outcome: Any, item: Any, address: str,
               on_error: Callable[[Any, str], Any]) -> Any:
    """A finished future's result; a failed task's error result; a cancelled one (the
    scheduler went away: nothing else cancels our keys) is fatal for the run."""
    if future.status == "finished":
        return outcome
    if future.status == "error":
        from distributed import KilledWorker

        _, exc, _ = outcome
        if isinstance(exc, KilledWorker):
            return on_error(item, "every worker that ran it died (a crash or out of memory)")
        return on_error(item, one_line(exc))
    raise LinkcliError(f"{OPTION}: the Dask scheduler at {address} was lost mid-run "
                       f"(its tasks were {future.status})")


def _connect(address: str, timeout: float, items: int = 1) -> tuple[Any, Any]:
    """(LocalCluster or None, Client) for `address`; InputError for a malformed address,
    or when no Dask scheduler answers there within `timeout` seconds (nothing listening,
    or a listener of another kind: probe_scheduler). `items`: how many tasks a `local:N`
    cluster will run (it starts no more workers than that)."""
    from distributed import Client

    address = address.strip()
    if not address:
        raise InputError("a scheduler address (tcp://HOST:PORT) or local:N", "nothing",
                         path=OPTION)
    if address.startswith(LOCAL_PREFIX):
        cluster = start_local_cluster(local_workers(address, items))
        try:
            return cluster, Client(cluster, set_as_default=False, timeout=timeout)
        except BaseException:
            cluster.close()
            raise
    reason = address_problem(address, timeout) or probe_scheduler(address, timeout)
    if reason is None:
        try:
            return None, Client(address, set_as_default=False, timeout=timeout)
        except (OSError, ValueError, TypeError) as exc:  # refused, timed out, bad address
            reason = one_line(exc)
    # The half-built Client sits in a reference cycle; collected at interpreter exit, after
    # its event loop has stopped, its __del__ would wait 10 s and print a traceback.
    gc.collect()
    raise InputError(f"a Dask scheduler answering at {address} within {timeout:g} s", reason,
                     path=OPTION)


def start_local_cluster(workers: int) -> Any:
    """A LocalCluster of `workers` single-threaded worker processes, as `local:N` starts.

    Dask's nanny sets OMP/MKL/OPENBLAS_NUM_THREADS=1 in its workers; a few solvers' last
    digits follow the BLAS thread count, so these workers keep this process's environment
    instead (None unsets a variable of that config): the bytes of a serial run and of
    --jobs, whose processes inherit it too. The workers ignore Ctrl-C (IGNORE_CTRL_C) and
    log only CRITICAL records: their stderr is the CLI's, and a worker whose scheduler went
    away first (Ctrl-C) logged its failed heartbeat with a traceback at ERROR."""
    import dask
    from distributed import LocalCluster

    inherit = {f"distributed.nanny.pre-spawn-environ.{name}": None for name in BLAS_THREADS}
    with dask.config.set(inherit):
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                            # no dashboard port to collide over (8787)
                            dashboard_address="127.0.0.1:0", silence_logs=logging.CRITICAL,
                            preload=[IGNORE_CTRL_C])


def _require_distributed() -> None:
    """Import Dask distributed, or say which extra installs it (InputError, exit 2)."""
    try:
        import distributed  # noqa: F401
    except ImportError as exc:
        raise InputError(f"the Dask distributed package ({INSTALL_HINT})",
                         f"it is not installed ({exc.name or 'distributed'})",
                         path=OPTION) from None


def local_workers(address: str, items: int = 1) -> int:
    """How many worker processes `local:N` starts: N (a whole number >= 1) limited, as
    `--jobs` is, to the number of tasks and of CPUs: more processes cannot run at once,
    and each costs a Python process's start and memory."""
    import os

    from linkcli.io.terminal_text import shown
    text = address[len(LOCAL_PREFIX):]
    if not (text.isascii() and text.isdigit() and len(text) <= 18 and int(text) >= 1):
        raise InputError("local:N with N a whole number of worker processes >= 1",
                         shown(repr(address), 60), path=OPTION)
    return max(1, min(int(text), items, os.cpu_count() or 1))


NETWORK_SCHEMES = ("tcp", "tls", "ws", "wss")  # addresses of a host and a port


def address_problem(address: str, timeout: float) -> str | None:
    """What is wrong with a host:port address before anything connects, in words, or None: a
    port outside 1..65535 (`tcp://127.0.0.1:99999`), a host name that does not resolve
    (looked up within `timeout` seconds). Dask would try to connect to either until its
    timeout, and the probe would then blame "a listener that did not answer". Other schemes
    (inproc://, ucx://) are left to Dask."""
    import socket
    import threading
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "tcp", address
    if scheme not in NETWORK_SCHEMES:
        return None
    rest = rest.split("/", 1)[0]
    if rest.startswith("["):  # [IPv6]:port
        host, _, port = rest[1:].partition("]")
        port = port[1:] if port.startswith(":") else ""
    else:
        host, colon, port = rest.rpartition(":")
        if not colon:  # a host alone
            host, port = rest, ""
    if not port:
        return f"no port in {address!r} (an address is tcp://HOST:PORT)"
    if not host:
        return f"no host in {address!r} (an address is tcp://HOST:PORT)"
    if not (port.isascii() and port.isdigit() and 1 <= int(port) <= 65535):
        return f"port {port[:20]}, not a port number (1 to 65535)"
    found: list = []

    def look_up() -> None:
        try:
            socket.getaddrinfo(host, int(port), type=socket.SOCK_STREAM)
            found.append(None)
        except (OSError, UnicodeError) as exc:
            found.append(getattr(exc, "strerror", None) or str(exc))

    worker = threading.Thread(target=look_up, daemon=True)  # a resolver that hangs: bounded here
    worker.start()
    worker.join(timeout)
    if not found:
        return f"host {host!r}, whose name could not be looked up within {timeout:g} s"
    if found[0] is not None:
        return f"host {host!r}, a name that does not resolve ({found[0]})"
    return None


def probe_scheduler(address: str, timeout: float) -> str | None:
    """None when a Dask scheduler answers at `address` within `timeout` seconds, else what
    was found there, in words. Dask's own connect waits without limit for the handshake
    of whatever accepts the connection (an HTTP server never answers it) and trusts the
    frame sizes it reads (another protocol's bytes ask for exabytes): this asks the
    listener's `identity` under one deadline for the whole exchange and catches whatever
    the reply makes Dask raise. The connection uses the client's security settings from
    Dask's config (TLS when configured), as the Client will."""
    import asyncio

    from distributed.comm import connect
    from distributed.security import Security

    async def identity():
        comm = await connect(address, timeout=timeout, **Security().get_connection_args("client"))
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    try:
        reply = asyncio.run(asyncio.wait_for(identity(), timeout))
    except TimeoutError:
        return f"a listener that did not answer as Dask within {timeout:g} s"
    except (OSError, ValueError, TypeError) as exc:  # refused, unreachable, bad address
        return one_line(exc)
    except Exception as exc:  # another protocol's bytes, read as Dask frames
        return f"a listener that does not speak Dask's protocol (its reply raised {type(exc).__name__})"
    kind = reply.get("type") if isinstance(reply, dict) else None
    if kind == "Scheduler":
        return None
    if kind in ("Worker", "Nanny"):
        return f"a Dask {kind.lower()} (give its scheduler's address)"
    return "a listener that does not answer as a Dask scheduler"


def _close(client: Any, cluster: Any, outstanding: list[Any]) -> None:
    """Cancel what is still queued or running, then close the client and our cluster.
    A task already executing on a remote worker runs to its end (Dask cannot stop a
    thread) but its result is dropped; a local cluster's worker processes are ended."""
    try:
        if outstanding:
            client.cancel(outstanding)
    finally:
        try:
            client.close()
        finally:
            if cluster is not None:
                cluster.close()


@contextlib.contextmanager
def _quiet_dask_logs(level: int = logging.CRITICAL) -> Iterator[None]:
    """Keep dask's log (worker restarts, a task marked failed, a lost connection) off the
    CLI's stderr for the run: every fault it reports reaches the user as a result or an
    error of ours. dask logs through its own handlers on these loggers and changes their
    levels itself (a LocalCluster's silence_logs), so a filter holds records below
    `level` back; it is removed afterwards."""
    def loud_enough(record: logging.LogRecord) -> bool:
        return record.levelno >= level

    handlers = [handler for name in ("distributed", "tornado", "bokeh")
                for handler in logging.getLogger(name).handlers]
    for handler in handlers:
        handler.addFilter(loud_enough)
    try:
        yield
    finally:
        for handler in handlers:
            handler.removeFilter(loud_enough)


def worker_map(function: Callable[[Any], Any], items: list) -> list:
    """[function(item) for item in items] on the cluster that runs the calling task (tasks
    launched from a task: distributed.worker_client, which leaves the worker's slot to them
    while it waits), results in order; outside a worker, in this process."""
    try:
        from distributed import worker_client
        from distributed.worker import get_worker
        get_worker()
    except (ImportError, ValueError):
        return [function(item) for item in items]
    with worker_client() as client:
        futures = client.map(function, items, pure=False)
        return client.gather(futures)
