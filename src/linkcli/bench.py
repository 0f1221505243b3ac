"""`linkcli bench`: run time against error for each problem, solver setting and seed.

Each row: problem, method, budget, seed, seconds (wall clock of the solve alone, scipy
already imported),
evaluations, objective, best_known (the file's `[reference] objective`), gap
((objective - best_known) / |best_known|), status. A problem type's schema module may list
`bench_settings` as (method, budget) pairs (linkcli.registry.ProblemType); otherwise every
method in its `methods` is run with the file's own budget.

Each run (problem x setting x seed) is one picklable `Run` and one call of `run_one`, in
this process or, with `--cluster`, on Dask workers (linkcli.cluster): the rows are the
same but for `seconds`, and come back in the same order.
"""

from __future__ import annotations

import contextlib
import os
import sys
import time
from collections.abc import Iterator
from dataclasses import replace
from typing import NamedTuple

from linkcli.errors import LinkcliError
from linkcli.io.terminal_text import one_line, write_error

COLUMNS = ("problem", "method", "budget", "seed", "seconds", "evaluations", "objective",
           "best_known", "gap", "status")


NO_ATLAS = " (no atlas)"  # the method column of a run with [solver] atlas = false (docs/atlas.md)


def settings_for(problem) -> list[tuple[str, int | None, bool | None]]:
    """(method, budget, atlas) of each setting: the type's settings (atlas as the file
    says), and for a search that uses the coupler-curve atlas, `auto` once more with
    atlas = false, so that the bench shows both sides. Of those, only the methods the
    problem accepts when a problem narrows its type's (`methods`: a five-bar path's one
    search, which `synth` refuses any other method for)."""
    from linkcli.registry import problem_type
    own = getattr(problem, "bench_settings", None)  # a problem solved by a strategy of its own
    if own:  # (method, budget) pairs, as a type's: the atlas as the file says
        return [(m, b, None) for m, b in own]
    spec = problem_type(problem.meta.type)
    if spec.bench_settings:
        out = [(m, b, None) for m, b in spec.bench_settings]
    else:
        out = [(m, problem.meta.solver.budget, None) for m in spec.methods]
    if spec.atlas and spec.module("solve").uses_atlas(problem):
        out.insert(1, ("auto", None, False))
    accepted = getattr(problem, "methods", None)
    return [s for s in out if accepted is None or s[0] in accepted]


class Run(NamedTuple):
    """One bench run: a problem file (its name and content, read once by the client: the
    file's bytes, or the text of a packaged bench problem), a solver setting and a seed.
    Pickles, so it can run on a --cluster worker."""

    path: str
    source: bytes | str
    method: str
    budget: int | None
    seed: int
    debug: bool = False
    atlas: bool | None = None  # [solver] atlas for this run (None: as the file says)


class RunOutcome(NamedTuple):
    """A run's row, or the error lines and exit code that took its place."""

    path: str
    row: dict | None
    errors: tuple[str, ...] = ()
    exit_code: int = 0


def runs_of(path: str, seeds: int, debug: bool = False, text: str | None = None) -> list[Run]:
    """Every setting x seed of one problem file (`text`: its content, when it is not read
    from `path`, as for the packaged bench set; loaded here to learn its settings);
    InputError if the file is bad."""
    from linkcli.io.safe_read import read_problem_bytes
    from linkcli.reading.load import load
    source = read_problem_bytes(path) if text is None else text
    problem = load(path, source)
    return [Run(path, source, method, budget, seed, debug, atlas)
            for method, budget, atlas in settings_for(problem) for seed in range(seeds)]


def run_one(run: Run) -> RunOutcome:
    """Solve one run and time the solve alone: a row (expected failures become error
    lines, a bug one line too, unless `run.debug`). Top-level: Dask pickles it by name."""
    try:
        return RunOutcome(run.path, solve_run(run))
    except LinkcliError as exc:
        if run.debug:
            raise
        return RunOutcome(run.path, None, tuple(exc.lines()), exc.exit_code)
    except Exception as exc:  # a bug: one line, not a traceback (--debug shows it)
        if run.debug:
            raise
        return run_failed(run, f"{type(exc).__name__}: {exc} (run with --debug for the traceback)")


def run_failed(run: Run, description: str) -> RunOutcome:
    """The outcome of a run whose task failed outside `run_one` (its workers died)."""
    return RunOutcome(run.path, None, (f"{run.path}: internal error: {description}",), 1)


def solve_run(run: Run) -> dict:
    """The bench row of one run (its columns: docs/format.md, Commands)."""
    from linkcli.analysis.sections import gap
    from linkcli.pipeline import solve
    from linkcli.reading.load import load
    problem = load(run.path, run.source)
    import scipy.optimize  # noqa: F401  imported before any timing, so that no row pays for it
    best = problem.meta.reference.objective if problem.meta.reference else None
    opts = replace(problem.meta.solver, method=run.method, seed=run.seed, budget=run.budget,
                   atlas=problem.meta.solver.atlas if run.atlas is None else run.atlas)
    problem = replace(problem, meta=replace(problem.meta, solver=opts))
    t0 = time.perf_counter()
    sol = solve(problem)
    seconds = time.perf_counter() - t0
    obj = printed_objective(problem, sol)
    return {
        "problem": run.path, "method": run.method + (NO_ATLAS if run.atlas is False else ""),
        "budget": run.budget, "seed": run.seed,
        "seconds": seconds, "evaluations": sol.solver.evaluations if sol.solver is not None else None,
        "objective": obj, "best_known": best,
        "gap": gap(obj, best) if (obj is not None and best is not None) else None,
        "status": sol.status.value,
    }


def printed_objective(problem, sol) -> float | None:
    """The objective as the report prints it: round-off of an exact fit is 0 (below
    n (NOISE_FLOOR x scale)^2, analysis.sections.error_section) where the solution has
    position errors; else the solver's objective."""
    from linkcli.analysis.sections import error_section, linkage_scale
    pos = sol.positions
    if (sol.objective is None or pos is None or pos.kind not in ("angle", "point")
            or sol.linkage is None):
        return sol.objective
    return error_section(sol, problem.meta.units, None, linkage_scale(sol.linkage))["objective"]


def run_problem(path: str, seeds: int, text: str | None = None) -> list[dict]:
    """Every setting and seed of one problem file (`text`: as for runs_of), in this
    process; the first error raises."""
    return [solve_run(run) for run in runs_of(path, seeds, debug=True, text=text)]


def outcomes(runs: list[Run], cluster: str | None) -> Iterator[RunOutcome]:
    """The runs' outcomes in order: in this process, or on the Dask cluster at `cluster`
    (linkcli.cluster; the same run_one on the workers)."""
    if cluster is None:
        yield from map(run_one, runs)
        return
    from linkcli.cluster import map_ordered
    remote = [run._replace(debug=False) for run in runs]  # tracebacks cannot come back
    with contextlib.closing(map_ordered(run_one, remote, cluster, on_error=run_failed)) as done:
        yield from done


def command(files: list[str], fmt: str, seeds: int, precision: int, debug: bool,
            cluster: str | None = None, summary_only: bool = False) -> int:
    """Every problem x setting x seed, serially or on a --cluster; a file with an error
    prints its lines (once each) and gives no rows. The table view prints every run, then
    the reliability summary over the seeds (`summary`); JSON, CSV and TOML give the runs.
    `summary_only` (--summary): the summary alone, in any format. Without files, the
    packaged bench set (linkcli.bench_problems, named bench/<name>.toml)."""
    from linkcli.pipeline import single_threaded_blas
    single_threaded_blas()  # as synth: the same BLAS threads, the same bits
    if files:
        problems = [(path, None) for path in files]
    else:
        from linkcli.bench_problems import bench_files
        problems = list(bench_files())
    files = [path for path, _ in problems]
    runs: list[Run] = []
    errors: dict[str, list[str]] = {path: [] for path in files}
    worst = 0
    for path, text in problems:
        try:
            runs.extend(runs_of(path, seeds, debug, text))
        except LinkcliError as exc:
            if debug:
                raise
            errors[path].extend(exc.lines())
            worst = max(worst, exc.exit_code)
    rows_of: dict[str, list[dict]] = {path: [] for path in files}
    bar = _display(runs)  # on a terminal: the runs done of all, and the one running
    try:
        with contextlib.closing(outcomes(runs, cluster)) as done:
            for k, outcome in enumerate(done):
                if outcome.row is not None:
                    rows_of[outcome.path].append(outcome.row)
                errors[outcome.path].extend(line for line in outcome.errors
                                            if line not in errors[outcome.path])
                worst = max(worst, outcome.exit_code)
                if bar is not None:
                    bar.update(bar.task_ids[0], advance=1, description=_running(runs, k + 1))
    except LinkcliError as exc:  # the cluster itself failed (unreachable, lost)
        if debug:
            raise
        for line in exc.lines():
            write_error(line)
        return max(worst, exc.exit_code)
    finally:
        if bar is not None:
            bar.stop()
    for path in dict.fromkeys(files):  # a file named twice: its runs ran twice, in rows_of
        for line in errors[path]:
            write_error(line)
    rows = [row for path in dict.fromkeys(files) if not errors[path] for row in rows_of[path]]
    columns = SUMMARY_COLUMNS if summary_only else COLUMNS
    shown = summary(rows) if summary_only else rows
    if fmt == "json":
        from linkcli.io.export import to_json
        sys.stdout.write(to_json(shown, precision))
    elif fmt == "csv":
        from linkcli.io.csv_tables import to_csv
        sys.stdout.write(to_csv(shown, precision) if shown else ",".join(columns) + "\n")
    elif fmt == "toml":
        from linkcli.io.export import to_toml
        sys.stdout.write(to_toml({"summary" if summary_only else "bench": shown}, precision))
    else:
        from linkcli.report import console, print_table
        out = console(width=None if sys.stdout.isatty() else 400)  # tables are as wide as their cells
        if not summary_only:
            print_table(out, _table("linkcli bench: run time against error", rows, COLUMNS, precision))
        print_table(out, _table("reliability over the seeds (within 1e-6 of the best known)", summary(rows),
                                SUMMARY_COLUMNS, precision))  # on a terminal: in blocks of columns
    return worst


def _display(runs: list[Run]):
    """The progress display of a bench (linkcli.progress.display: a terminal only): a bar of
    the runs done, the problem, method and seed running. None elsewhere."""
    from linkcli import progress
    shown = progress.display() if runs else None
    if shown is not None:
        shown.add_task(_running(runs, 0), total=len(runs), work="")
        shown.start()
    return shown


def _running(runs: list[Run], done: int) -> str:
    """"bench: PROBLEM METHOD seed N" of the run after `done` ones (escaped: no rich markup)."""
    if done >= len(runs):
        return "bench: done"
    from rich.markup import escape
    run = runs[done]
    name = os.path.splitext(os.path.basename(run.path))[0]
    return escape(one_line(f"bench: {name} {run.method} seed {run.seed}"))


def _table(title: str, rows: list[dict], columns: tuple[str, ...], precision: int):
    """A rich table of bench rows (problem names without folder and suffix)."""
    from rich import box
    from rich.table import Table

    from linkcli.report import _compact
    from linkcli.report import fmt as fmt_value
    t = Table(title=title, title_justify="left", box=box.SIMPLE_HEAD, pad_edge=False, show_edge=False)
    for c in columns:
        t.add_column(c, justify="left" if c in ("problem", "method", "status") else "right")
    for r in rows:
        shown = dict(r, problem=one_line(os.path.splitext(os.path.basename(r["problem"]))[0]))
        t.add_row(*(fmt_value(shown[c], precision) if shown[c] is not None else "-" for c in columns))
    _compact(t)  # cells never wrap, headings at their words
    return t


SUMMARY_COLUMNS = ("problem", "method", "budget", "seeds", "within 1e-6", "ok but off",
                   "not converged", "infeasible", "median gap", "worst gap", "median seconds",
                   "median evaluations", "best objective", "best_known")
WITHIN = 1e-6  # relative gap to the best known that counts as reaching it


def within(row: dict) -> bool | None:
    """Whether a run reached the best known: gap <= WITHIN (relative; absolute for a best
    known of 0, see analysis.sections.gap); None without a best known or an objective."""
    return None if row["gap"] is None else row["gap"] <= WITHIN


def summary(rows: list[dict]) -> list[dict]:
    """One row per (problem, method, budget) over its seeds, in the order of the runs:
    how many seeds reached the best known within 1e-6 ("k/n", "-" without a best known),
    how many ended `ok` outside it (an optimum claimed that is not the best known), how
    many ended not-converged or infeasible, the median and worst gap, the median seconds
    and evaluations, and the best objective. Medians of an even count are the mean of the
    middle two (statistics.median)."""
    from statistics import median
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault((r["problem"], r["method"], r["budget"]), []).append(r)
    out = []
    for (problem, method, budget), rs in groups.items():
        objs = [r["objective"] for r in rs if r["objective"] is not None]
        gaps = [r["gap"] for r in rs if r["gap"] is not None]
        evals = [r["evaluations"] for r in rs if r["evaluations"] is not None]
        reached = [within(r) for r in rs]
        known = rs[0]["best_known"] is not None
        out.append({
            "problem": os.path.splitext(os.path.basename(problem))[0], "method": method,
            "budget": budget, "seeds": len(rs),
            "within 1e-6": f"{sum(bool(w) for w in reached)}/{len(rs)}" if known else None,
            "ok but off": sum(r["status"] == "ok" and w is False for r, w in zip(rs, reached)),
            "not converged": sum(r["status"] == "not-converged" for r in rs),
            "infeasible": sum(r["status"] == "infeasible" for r in rs),
            "median gap": median(gaps) if gaps else None,
            "worst gap": max(gaps) if gaps else None,
            "median seconds": median(r["seconds"] for r in rs),
            "median evaluations": median(evals) if evals else None,
            "best objective": min(objs) if objs else None,
            "best_known": rs[0]["best_known"],
        })
    return out


def markdown(rows: list[dict], precision: int = 4, columns: tuple[str, ...] = COLUMNS) -> str:
    """A markdown table of bench rows (for benchmarks/RESULTS.md)."""
    from linkcli.report import fmt as fmt_value
    head = "| " + " | ".join(columns) + " |\n|" + "---|" * len(columns) + "\n"
    body = "".join("| " + " | ".join(fmt_value(r[c], precision) if r[c] is not None else "-"
                                     for c in columns) + " |\n" for r in rows)
    return head + body
