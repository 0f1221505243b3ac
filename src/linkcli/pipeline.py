"""Load -> solve -> analyse, once per file, and the executors that run it over files.

    problem.toml --load--> Problem --solve--> Solution --analyse--> report (dict)

`run(path, request)` returns an `Outcome`: the exit code, the `Result(problem, solution,
report)` when the file was solved, and the error lines when it was not. Everything in
it pickles (errors too), so an executor may run `run` in another process or on a Dask
cluster: an executor is a function `(files, request) -> Outcome per file, in argument
order`; three exist, `serial`, `processes(jobs)` (`--jobs`, linkcli.workers) and `on_cluster(address)`
(`--cluster`). numpy, scipy and the type modules are imported only inside `run`, dask
only inside `on_cluster`'s executor. The records are
NamedTuples (immutable, picklable, and about 7 times cheaper to define at start-up than
frozen dataclasses).
"""

from __future__ import annotations

import contextlib
import sys
import time
from collections.abc import Iterator
from dataclasses import replace
from typing import Any, NamedTuple

from linkcli.errors import InputError, LinkcliError, located

MODES = ("synth", "analyze", "check")
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                "VECLIB_MAXIMUM_THREADS")


class Request(NamedTuple):
    """What to do with each file: `mode` (synth, analyze or check), a seed overriding
    the file's, `debug` (let tracebacks through), `timing` (add the solve's seconds to
    the report) and `plot` (the plot's sections must be in the Result)."""

    mode: str = "synth"
    seed: int | None = None
    debug: bool = False
    timing: bool = False
    plot: bool = False
    front: tuple = ()  # where a Pareto front's levels are solved: () here, ("jobs", N), ("cluster",)


class Result(NamedTuple):
    """One solved file: the frozen problem, the solver's Solution and the report built
    from them (problem and solution None in an outcome that crossed from a worker process
    with what is printed only, `printed`). `drawing` is the report a plot draws from: the report itself, or, when
    `[report] sections` left out what the plot needs, a report with those sections."""

    problem: Any
    solution: Any
    report: dict
    drawing: dict | None = None

    @property
    def exit_code(self) -> int:
        return report_exit_code(self.report)


class Outcome(NamedTuple):
    """What became of one file: exit code (0 solved, 1 infeasible or not converged,
    2 bad input), its Result (None unless solved) and the error lines for stderr."""

    path: str
    exit_code: int
    result: Result | None = None
    errors: tuple[str, ...] = ()


def load(path: str, mode: str, source: bytes | InputError | None = None):
    """The frozen problem of one file: any problem type for synth and check, a linkage
    or a result file for analyze. `source`: the file's bytes read elsewhere (a cluster
    client), or the InputError reading them raised there; None reads `path` here."""
    from linkcli.reading.load import load as load_problem
    from linkcli.reading.load import load_for_analysis
    if isinstance(source, InputError):
        raise source
    return load_for_analysis(path, source) if mode == "analyze" else load_problem(path, source)


def with_seed(problem, seed: int | None):
    """The problem with its [solver] seed replaced (None: unchanged)."""
    if seed is None:
        return problem
    meta = problem.meta
    return replace(problem, meta=replace(meta, solver=replace(meta.solver, seed=seed)))


def solve(problem):
    """Solve one validated problem with its type's strategy; non-convergence is a status."""
    from linkcli.registry import problem_type
    return problem_type(problem.meta.type).module("solve").solve(problem)


def quiet_numerics():
    """No RuntimeWarning of numpy on stderr while solving (an overflow or 0/0 in a
    degenerate case is handled as a status or an error line, never printed raw)."""
    import numpy as np
    return np.errstate(all="ignore")


def analyse(problem, solution) -> dict:
    """The report of one solved problem (linkcli.analysis)."""
    from linkcli.analysis.sections import build
    return build(problem, solution)


def run(path: str, request: Request, source: bytes | InputError | None = None) -> Outcome:
    """Load, solve and analyse one file (from `source` when given: see `load`); expected
    failures become error lines (a bug becomes one line too, unless `request.debug`)."""
    try:
        problem = with_seed(load(path, request.mode, source), request.seed)
        if request.mode == "check":
            return Outcome(path, 0)
        started = time.perf_counter()
        with quiet_numerics(), front_levels(request.front):
            solution = solve(problem)
        seconds = time.perf_counter() - started
        from linkcli.reading.meta import refuse_oversized
        refuse_oversized(problem, solution.linkage)  # a result no file could hold
        report = analyse(problem, solution)
        if request.timing and "solver" in report:
            report["solver"]["seconds"] = seconds
        drawing = drawing_report(problem, report) if request.plot else None
        return Outcome(path, report_exit_code(report), Result(problem, solution, report, drawing))
    except LinkcliError as exc:
        located(exc, path)
        if request.debug:  # where it was raised, then its lines and exit code as without --debug (bad input: 2)
            import traceback
            traceback.print_exc(file=sys.stderr)
        return Outcome(path, exc.exit_code, errors=tuple(exc.lines()))
    except Exception as exc:  # a bug: one line, not a traceback (--debug shows it)
        if request.debug:
            raise
        return Outcome(path, 1, errors=(f"{path}: internal error: {type(exc).__name__}: {exc} "
                                        "(run with --debug for the traceback)",))


def front_levels(where: tuple):
    """The map a Pareto front's chains of levels run through (linkcli.pareto.spread): in this
    process (()), in N processes (("jobs", N)), on the cluster this worker belongs to
    (("cluster",): tasks launched from the task, linkcli.cluster.worker_map)."""
    from linkcli.pareto.spread import using
    if not where:
        return using(None)
    if where[0] == "cluster":
        from linkcli.cluster import worker_map
        return using(worker_map)
    return using(process_map(int(where[1])))


def process_map(jobs: int):
    """A map over `jobs` processes (forked where the system can: they share what this one
    imported), results in order."""
    def mapper(function, items):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor
        context = multiprocessing.get_context("fork") if "fork" in multiprocessing.get_all_start_methods() else None
        with ProcessPoolExecutor(max_workers=min(jobs, len(items)), mp_context=context) as pool:
            return list(pool.map(function, items))
    return mapper


def report_exit_code(report: dict) -> int:
    """0 for a report whose status is ok, else 1: the solver's status, or the analysis's
    verdict on it (a part whose strength falls short makes an ok solution infeasible)."""
    return 0 if report["status"] == "ok" else 1


def drawing_report(problem, report: dict) -> dict:
    """The report a plot draws from: `report` when it holds the sections the type's plot
    needs (or when the file asked for them and the solution has none: the plot says so);
    otherwise the problem solved and analysed again with those sections asked for
    (deterministic: the same problem and seed)."""
    from linkcli.reading.meta import ALL_SECTIONS
    from linkcli.registry import problem_type
    needs = problem_type(problem.meta.type).module("plot").NEEDS
    if all(k in report for k in needs) or not report.get("file"):
        return report
    meta = problem.meta
    asked = {"lengths" if k == "linkage" else k for k in needs}  # report keys -> section names
    if asked <= set(meta.sections):
        return report
    wanted = tuple(s for s in ALL_SECTIONS if s in set(meta.sections) | asked)
    again = replace(problem, meta=replace(meta, sections=wanted, tolerance=None))
    return analyse(again, solve(again))


def serial(files: list[str], request: Request) -> Iterator[Outcome]:
    """Each file in turn, in this process."""
    for path in files:
        yield run(path, request)


def processes(jobs: int):
    """An executor that runs files in `jobs` worker processes (linkcli.workers); outcomes
    keep argument order, and each comes back with what is printed only (`printed`). A
    worker that dies mid-file (the out-of-memory killer) costs that file alone: one error
    line in its slot, the other files' results kept. On systems that fork, this process
    imports what `run` needs first (numpy included, with the BLAS threads
    `single_threaded_blas` set): the forked workers share it instead of each importing it
    again."""
    def execute(files: list[str], request: Request) -> Iterator[Outcome]:
        import multiprocessing

        from linkcli.workers import solve_in_processes
        if "fork" in multiprocessing.get_all_start_methods():
            import linkcli.reading.load  # noqa: F401  (numpy and the reader, shared by the forks)
            context = multiprocessing.get_context("fork")
        else:
            context = multiprocessing.get_context()
        yield from solve_in_processes(files, request, jobs, run_printed, context, _lost)
    return execute


def _lost(path: str, line: str) -> Outcome:
    """The outcome of a file whose --jobs worker died: exit code 1 and its one line."""
    return Outcome(path, 1, errors=(line,))


def run_printed(path: str, request: Request) -> Outcome:
    """`run` in a worker process, its outcome trimmed to what is printed (`printed`)."""
    return printed(run(path, request), request)


def printed(outcome: Outcome, request: Request) -> Outcome:
    """The outcome with only what the command prints: the report (a plot also needs the
    problem and the solution, `request.plot`), not the problem and the solution, whose
    arrays would cross the process boundary for nothing."""
    if outcome.result is None or request.plot:
        return outcome
    return outcome._replace(result=Result(None, None, outcome.result.report))


def single_threaded_blas() -> None:
    """One BLAS thread (OpenBLAS, MKL, BLIS, OpenMP, Accelerate) unless the environment
    names a count of its own (any of BLAS_THREADS set: left as it is), before numpy is
    imported (after, it can no longer change): the searches' matrices are small (tens of
    rows), too small for threads to pay, and a thread per core fights every other
    process for the cores (docs/cluster.md, "BLAS threads"). It also keeps the last bits
    of a scipy solver's path from following the machine's core count."""
    import os
    import sys
    if "numpy" in sys.modules or any(name in os.environ for name in BLAS_THREADS):
        return
    for name in BLAS_THREADS:
        os.environ[name] = "1"


def read_source(path: str) -> bytes | InputError:
    """The bytes of one problem file, or the InputError reading it raises (it travels in
    the item and is raised where the file is loaded, as a serial run raises it)."""
    from linkcli.io.safe_read import read_problem_bytes
    try:
        return read_problem_bytes(path)
    except InputError as exc:
        return exc


def run_item(item: tuple[str, Request, bytes | InputError]) -> Outcome:
    """`run(path, request, source)` of one cluster item (top-level: Dask pickles it by name),
    trimmed to what is printed (`printed`)."""
    return printed(run(*item), item[1])


def item_failed(item: tuple, description: str) -> Outcome:
    """The Outcome of an item whose task failed outside `run` (every worker that ran it
    died): exit code 1 and one line naming the file."""
    path = item[0]
    return Outcome(path, 1, errors=(f"{path}: internal error: {description}",))


def on_cluster(address: str):
    """An executor that runs files on the Dask cluster at `address` (tcp://HOST:PORT or
    local:N; linkcli.cluster). The client reads each file and sends its bytes, so
    workers need no shared file system and relative names mean what they mean here;
    tracebacks cannot come back (`debug` is off on the workers: a bug is one line)."""
    def execute(files: list[str], request: Request) -> Iterator[Outcome]:
        from linkcli.cluster import map_ordered
        remote = request._replace(debug=False)
        items = [(path, remote, read_source(path)) for path in files]
        with contextlib.closing(map_ordered(run_item, items, address,
                                            on_error=item_failed)) as outcomes:
            yield from outcomes
    return execute


def executor(jobs: int, files: list[str], debug: bool, cluster: str | None = None):
    """`--cluster ADDRESS`: the Dask cluster (InputError with `--jobs N > 1`: the
    cluster's workers are the processes); `--jobs N`: processes for a batch (not with
    --debug: tracebacks stay in this process), otherwise serial. More processes than
    files or CPUs cannot help: `jobs` is silently limited to both. Sets the BLAS threads
    (`single_threaded_blas`) before anything imports numpy."""
    import os
    single_threaded_blas()
    if cluster is not None:
        if jobs > 1:
            raise InputError("either --cluster or --jobs N (a cluster's workers are its "
                             "processes)", f"both (--jobs {jobs})", path="--cluster")
        return on_cluster(cluster)
    jobs = min(jobs, len(files), os.cpu_count() or 1)
    return processes(jobs) if jobs > 1 and not debug else serial
