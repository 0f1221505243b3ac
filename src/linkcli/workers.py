"""`--jobs N`: files solved in N worker processes that linkcli supervises itself.

    solve_in_processes(files, request, jobs, work, context, lost) -> one outcome per file, in argument order

Each worker is a process with a pipe of its own: it is handed one file at a time, runs
`work(path, request)` (pipeline.run_printed) and sends the Outcome back. The supervisor
(this process) knows which file each worker holds, which a pool of anonymous workers
(concurrent.futures) does not, so:

- a worker that dies mid-file (SIGKILL from the out-of-memory killer, a crash inside a C
  library) costs that file alone: its slot gets one error line and exit code 1, a new
  worker takes the dead one's place and the batch goes on; every finished result is kept
  (a process pool marks itself broken and fails every file still in it);
- outcomes come back as files finish and are yielded in argument order;
- closing the iteration (Ctrl-C, SIGTERM, a reader gone) ends the workers at once: SIGTERM,
  then SIGKILL for one that has not ended within STOP_SECONDS;
- a supervisor that dies without closing it (SIGKILL, SIGHUP) leaves no worker behind: each
  watches its parent and ends within WATCH_SECONDS of its death, and an idle one sees its
  pipe closed (a forked worker closes the supervisor's ends it inherits).

Workers ignore SIGINT (a terminal's Ctrl-C reaches the whole process group: it is the
supervisor's to handle, as a --cluster worker's) and take SIGTERM's default action (the
command's own SIGTERM handler, inherited through fork, is for the supervisor only). Where
the system forks, the workers are forked after this process has imported what `work` needs
(pipeline.processes), and share it. One file at a time costs a round trip of a few tens of
microseconds per file through the pipe: nothing beside a solve.
"""

from __future__ import annotations

import os
import signal
from collections import deque
from collections.abc import Callable, Iterator
from typing import NamedTuple

STOP_SECONDS = 2.0  # a worker asked to end (SIGTERM) is killed after this
WATCH_SECONDS = 0.5  # how often a worker checks that its supervisor is alive


class Worker(NamedTuple):
    """A worker process and the supervisor's end of its pipe."""

    process: object
    conn: object


def _serve(conn, request, work: Callable, inherited: tuple = ()) -> None:
    """A worker's loop: (index, path) in, (index, Outcome) out, until None or the pipe closes.
    `inherited`: the supervisor's ends of the pipes, which a forked worker holds copies of;
    closed first, so that the supervisor's death (SIGKILL, SIGHUP: no chance to stop its
    workers) closes this worker's pipe and the worker ends after its file, not waiting for
    a next one forever."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    for end in inherited:
        end.close()
    _end_with(os.getppid())
    while True:
        try:
            item = conn.recv()
        except (EOFError, OSError):
            return
        if item is None:
            return
        index, path = item
        outcome = work(path, request)
        try:
            conn.send((index, outcome))
        except OSError:  # the supervisor is gone
            return


def _end_with(parent: int) -> None:
    """A watch thread: when the supervisor `parent` is gone (this process reparented), end
    this worker at once with SIGTERM's default action, mid-file (the file's result has no
    one to go to). Checked every WATCH_SECONDS."""
    import threading
    import time

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(WATCH_SECONDS)
        os.kill(os.getpid(), signal.SIGTERM)

    threading.Thread(target=watch, name="linkcli-supervisor-watch", daemon=True).start()


def died(path: str, exitcode: int | None) -> str:
    """The error line of a file whose worker process ended without an answer: it names the
    file and how the process ended (the caller's `lost` makes it an exit-code-1 outcome, an
    internal error as a bug is)."""
    if exitcode is not None and exitcode < 0:
        try:
            how = f"was killed by {signal.Signals(-exitcode).name}"
        except ValueError:
            how = f"was killed by signal {-exitcode}"
    else:
        how = f"exited with code {exitcode}"
    return (f"{path}: internal error: the worker process solving it {how} "
            "(out of memory, or killed; the other files are not affected)")


def solve_in_processes(files: list[str], request, jobs: int, work: Callable, context,
                       lost: Callable[[str, str], object]) -> Iterator:
    """`work(path, request)` of every file in `jobs` worker processes of the multiprocessing
    `context`; the Outcomes in argument order (module docstring). `lost(path, line)` is the
    outcome of a file whose worker died (`line`: `died`'s)."""
    from multiprocessing.connection import wait

    pending = deque(enumerate(files))
    arrived: dict[int, object] = {}
    holding: dict[int, tuple[int, str]] = {}  # worker slot -> (index, path) it runs
    workers: list[Worker] = []
    next_index = 0

    def start() -> Worker:
        mine, theirs = context.Pipe()
        forked = context.get_start_method() == "fork"  # a forked child inherits every open end
        inherited = tuple(w.conn for w in workers) + (mine,) if forked else ()
        process = context.Process(target=_serve, args=(theirs, request, work, inherited), daemon=True)
        process.start()
        theirs.close()
        return Worker(process, mine)

    def replace(slot: int) -> None:
        """A new worker in a dead one's place."""
        old = workers[slot]
        old.process.join()
        old.conn.close()
        workers[slot] = start()

    def give(slot: int) -> None:
        """The next file to the worker in `slot` (a worker found dead idle is replaced first)."""
        while pending:
            try:
                workers[slot].conn.send(pending[0])
            except OSError:  # it died while idle: its pipe is broken
                replace(slot)
                continue
            holding[slot] = pending.popleft()
            return

    finished = False
    try:
        for slot in range(max(1, min(jobs, len(files)))):
            workers.append(start())
            give(slot)
        while next_index < len(files):
            while next_index in arrived:
                yield arrived.pop(next_index)
                next_index += 1
            if next_index >= len(files):
                break
            busy = list(holding)
            ready = set(wait([workers[s].conn for s in busy] + [workers[s].process.sentinel for s in busy]))
            for slot in busy:
                worker = workers[slot]
                if worker.conn not in ready and worker.process.sentinel not in ready:
                    continue
                answer = None
                try:
                    if worker.conn.poll():
                        answer = worker.conn.recv()
                except (EOFError, OSError):  # it died while sending
                    answer = None
                if answer is None and worker.process.is_alive():
                    continue  # woken by its pipe, its answer not complete yet
                index, path = holding.pop(slot)
                if answer is not None:
                    arrived[answer[0]] = answer[1]
                else:
                    arrived[index] = lost(path, died(path, _exitcode(worker.process)))
                if not worker.process.is_alive() and pending:
                    replace(slot)
                give(slot)
        finished = True
    finally:
        stop(workers, at_once=not finished)


def _exitcode(process) -> int | None:
    process.join()
    return process.exitcode


def stop(workers: list[Worker], at_once: bool) -> None:
    """End every worker and join it (no zombie, no orphan left computing): at the end of the
    batch each is told to stop; else (Ctrl-C, SIGTERM, an abandoned iteration) each gets
    SIGTERM at once, and SIGKILL when still alive STOP_SECONDS later."""
    import time
    for worker in workers:
        if not at_once:
            try:
                worker.conn.send(None)
            except (OSError, ValueError):
                pass
        elif worker.process.is_alive():
            worker.process.terminate()
    deadline = time.monotonic() + STOP_SECONDS
    for worker in workers:
        worker.process.join(max(0.0, deadline - time.monotonic()))
        if worker.process.is_alive():
            worker.process.kill()
            worker.process.join()
        worker.conn.close()
