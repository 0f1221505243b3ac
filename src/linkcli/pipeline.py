"""Load -> solve -> analyse, once per file, and the executors that run it over files.

    problem.toml --load--> Problem --solve--> Solution --analyse--> report (dict)

`run(path, request)` returns an `Outcome`: the exit code, the `Result(problem, solution,
report)` when the file was solved, and the error lines when it was not. Everything in
it pickles, so an executor may run `run` in another process (or, later, on a cluster):
an executor is a function `(files, request) -> Outcome per file, in argument order`.
numpy, scipy and the type modules are imported only inside `run`. The records are
NamedTuples (immutable, picklable, and about 7 times cheaper to define at start-up than
frozen dataclasses).
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any, Iterator, NamedTuple

from linkcli.errors import LinkcliError

MODES = ("synth", "analyze", "check")


class Request(NamedTuple):
    """What to do with each file: `mode` (synth, analyze or check), a seed overriding
    the file's, `debug` (let tracebacks through), `timing` (add the solve's seconds to
    the report) and `plot` (the plot's sections must be in the Result)."""

    mode: str = "synth"
    seed: int | None = None
    debug: bool = False
    timing: bool = False
    plot: bool = False


class Result(NamedTuple):
    """One solved file: the frozen problem, the solver's Solution and the report built
    from them. `drawing` is the report a plot draws from: the report itself, or, when
    `[report] sections` left out what the plot needs, a report with those sections."""

    problem: Any
    solution: Any
    report: dict
    drawing: dict | None = None

    @property
    def exit_code(self) -> int:
        return self.solution.status.exit_code


class Outcome(NamedTuple):
    """What became of one file: exit code (0 solved, 1 infeasible or not converged,
    2 bad input), its Result (None unless solved) and the error lines for stderr."""

    path: str
    exit_code: int
    result: Result | None = None
    errors: tuple[str, ...] = ()


def load(path: str, mode: str):
    """The frozen problem of one file: any problem type for synth and check, a linkage
    or a result file for analyze."""
    from linkcli.io.load import load as load_problem, load_for_analysis
    return load_for_analysis(path) if mode == "analyze" else load_problem(path)


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


def analyse(problem, solution) -> dict:
    """The report of one solved problem (linkcli.analysis)."""
    from linkcli.analysis.sections import build
    return build(problem, solution)


def run(path: str, request: Request) -> Outcome:
    """Load, solve and analyse one file; expected failures become error lines (a bug
    becomes one line too, unless `request.debug`)."""
    try:
        problem = with_seed(load(path, request.mode), request.seed)
        if request.mode == "check":
            return Outcome(path, 0)
        started = time.perf_counter()
        solution = solve(problem)
        seconds = time.perf_counter() - started
        report = analyse(problem, solution)
        if request.timing and "solver" in report:
            report["solver"]["seconds"] = seconds
        drawing = drawing_report(problem, report) if request.plot else None
        return Outcome(path, solution.status.exit_code, Result(problem, solution, report, drawing))
    except LinkcliError as exc:
        if request.debug:
            raise
        return Outcome(path, exc.exit_code, errors=tuple(exc.lines()))
    except Exception as exc:  # a bug: one line, not a traceback (--debug shows it)
        if request.debug:
            raise
        return Outcome(path, 1, errors=(f"{path}: internal error: {type(exc).__name__}: {exc} "
                                        "(run with --debug for the traceback)",))


def drawing_report(problem, report: dict) -> dict:
    """The report a plot draws from: `report` when it holds the sections the type's plot
    needs (or when the file asked for them and the solution has none: the plot says so);
    otherwise the problem solved and analysed again with those sections asked for
    (deterministic: the same problem and seed)."""
    from linkcli.io.meta import ALL_SECTIONS
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
    """An executor that runs files in `jobs` processes; outcomes keep argument order."""
    def execute(files: list[str], request: Request) -> Iterator[Outcome]:
        from concurrent.futures import ProcessPoolExecutor
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            yield from pool.map(run, files, [request] * len(files))
    return execute


def executor(jobs: int, files: list[str], debug: bool):
    """`--jobs N`: processes for a batch (not with --debug: tracebacks stay in this
    process), otherwise serial. More processes than files or CPUs cannot help: `jobs` is
    silently limited to both."""
    import os
    jobs = min(jobs, len(files), os.cpu_count() or 1)
    return processes(jobs) if jobs > 1 and not debug else serial
