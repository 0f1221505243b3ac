"""The command line: synth, analyze, check, bench, new, atlas build; their options and exit codes.

The work is `linkcli.pipeline` (load -> solve -> analyse); this module catches
`LinkcliError` only and maps it to exit codes (0 solved, 1 infeasible or not
converged, 2 bad input; a batch exits with the worst of its files). numpy, scipy and
rich are imported inside the command bodies, so `--help`, `--version` and `check` stay
light. `--debug` lets a traceback through.
"""

from __future__ import annotations

import contextlib
import os
import sys
from enum import Enum
from pathlib import Path

import typer

from linkcli import __version__
from linkcli.usage_errors import OneLineErrors  # noqa: E402  (click's usage errors as one line)

app = typer.Typer(name="linkcli", add_completion=False, no_args_is_help=True, rich_markup_mode=None,
                  pretty_exceptions_enable=False, cls=OneLineErrors,
                  help="Design planar linkages from TOML problem files.")


class PlainUsage(typer.core.TyperCommand):
    """A usage line for people: `linkcli synth [OPTIONS] FILE...` (typer wraps a required
    argument in braces, `{FILE...}`, which reads like shell syntax)."""

    def collect_usage_pieces(self, ctx):
        pieces = super().collect_usage_pieces(ctx)
        return [p[1:-1] if p.startswith("{") and p.endswith("}") else p for p in pieces]


class Format(str, Enum):
    table = "table"
    json = "json"
    toml = "toml"
    csv = "csv"


EXT = {"table": "txt", "json": "json", "toml": "toml", "csv": "csv"}
MAX_SEEDS = 1000  # bench --seeds: every setting of every problem runs this many times


def _version(value: bool) -> None:
    if value:
        typer.echo(f"linkcli {__version__}")
        raise typer.Exit()


@app.callback()
def main_callback(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                 help="Show the version and exit."),
) -> None:
    """Design planar linkages from TOML problem files."""


def _err(line: str) -> None:
    """One line on stderr (terminal_text.write_error)."""
    from linkcli.io.terminal_text import write_error
    write_error(line)


def _progress(total: int):
    """A rich progress display on stderr (a spinner, the file being solved, the files
    done, the evaluations the solve has spent so far and the elapsed time) for batches and
    long solves; None (nothing shown, nothing counted) when stderr is not a terminal
    (linkcli.progress.display)."""
    from linkcli import progress
    return progress.display()


@contextlib.contextmanager
def _watched(description: str):
    """A progress display of the work linkcli.progress counts (the frames of an animation)
    while the block runs, on a terminal only (as _progress): a bar of the frames drawn."""
    prog = _progress(1)
    if prog is None:
        yield
        return
    from linkcli import progress

    task = prog.add_task(description, total=None, work="")

    def watch(what: str, done: int, total: int | None) -> None:
        prog.update(task, completed=done, total=total, work=what)

    progress.reset()
    progress.watch = watch
    prog.start()
    try:
        yield
    finally:
        progress.watch = None
        prog.stop()


def _solving(name: str, limit: int = 40) -> str:
    """The progress display's "solving FILE": the name escaped (terminal_text.one_line) and
    not read as rich markup (a file named "[bold]x.toml" is shown as named), a long one by its
    last `limit` characters (the work beside it stays on the line)."""
    from rich.markup import escape

    from linkcli.io.terminal_text import one_line
    name = one_line(name)
    if len(name) > limit:
        name = "..." + name[-(limit - 3):]
    return f"solving {escape(name)}"


class _Evaluations:
    """The evaluations a serial solve spends (search.budget.watch), and the work of its
    analysis (linkcli.progress.watch: the tolerance study's sample-targets ...), shown in the
    progress display at most every `every` seconds; `reset()` for the next file."""

    def __init__(self, prog, task, every: float = 0.1) -> None:
        import time
        self.prog, self.task, self.every, self.clock = prog, task, every, time.monotonic
        self.count, self.shown, self.what = 0, 0.0, ""

    def __call__(self, n: int) -> None:
        self.count += n
        now = self.clock()
        if now - self.shown >= self.every:
            self.shown = now
            self.prog.update(self.task, work=f"{self.count:,} evaluations")

    def work(self, what: str, done: int, total: int | None) -> None:
        """Shown at most every `every` seconds, and at once when a new kind of work begins
        (a phase shorter than a refresh is still seen)."""
        now = self.clock()
        new = what != self.what
        if new or now - self.shown >= self.every:
            self.shown, self.what = now, what
            of = f" of {total:,}" if total else ""
            self.prog.update(self.task, work=f"{done:,}{of} {what}", refresh=new)

    def reset(self) -> None:
        from linkcli import progress
        progress.reset()
        self.count, self.shown, self.what = 0, 0.0, ""
        self.prog.update(self.task, work="")


_ctrl_c_seen = [False]  # set by _interruptible's handler; read by _stop_if_interrupted
_term_seen = [False]  # the same for SIGTERM
TERMINATED_EXIT = 143  # 128 + SIGTERM, as a shell reports a command the signal ended


class Terminated(BaseException):
    """SIGTERM to the command (`kill PID`, a job scheduler's time limit): raised by the
    handler _interruptible installs, so that the executors clean up on the way out (--jobs
    ends its workers, --cluster cancels its tasks) before "terminated" and exit 143. A
    BaseException, as KeyboardInterrupt is: no `except Exception` of a solver swallows it."""


def _on_ctrl_c(signum, frame) -> None:
    """SIGINT handler: remember the Ctrl-C, then raise KeyboardInterrupt as Python's own
    handler does. The raise can be lost (Python only prints an exception raised inside a
    garbage-collector callback, such as the one Dask installs); the flag is not."""
    _ctrl_c_seen[0] = True
    raise KeyboardInterrupt


def _on_term(signum, frame) -> None:
    """SIGTERM handler: remember it, then raise Terminated (as _on_ctrl_c does)."""
    _term_seen[0] = True
    raise Terminated


def _quiet_lost_ctrl_c(previous):
    """A sys.unraisablehook that takes a KeyboardInterrupt (or Terminated) Python could not
    raise (it landed in a garbage-collector callback) as the recorded signal, instead of
    printing "Exception ignored in ..." with a traceback; anything else goes to `previous`."""
    def hook(unraisable) -> None:
        if isinstance(unraisable.exc_value, KeyboardInterrupt):
            _ctrl_c_seen[0] = True
            return
        if isinstance(unraisable.exc_value, Terminated):
            _term_seen[0] = True
            return
        previous(unraisable)
    return hook


def _stop_if_interrupted() -> None:
    """Raise KeyboardInterrupt (or Terminated) if a Ctrl-C (or SIGTERM) came whose exception
    was swallowed on the way."""
    if _term_seen[0]:
        raise Terminated
    if _ctrl_c_seen[0]:
        raise KeyboardInterrupt


@contextlib.contextmanager
def _interruptible():
    """Ctrl-C in a command: "interrupted" on stderr and exit 130 (typer would exit 130
    silently); SIGTERM: "terminated" and exit 143 (Python would die at once, leaving
    --jobs workers computing); also when the exception was swallowed where it landed
    (checked after each file and at the end; not printed as an ignored exception either).
    The executors clean up on the way out (--jobs ends its workers, --cluster cancels its
    tasks)."""
    import signal
    import threading
    _ctrl_c_seen[0] = _term_seen[0] = False
    main = threading.current_thread() is threading.main_thread()
    # only where Ctrl-C raises KeyboardInterrupt already: a process started with SIGINT
    # ignored (`linkcli ... &` in a script, nohup) keeps ignoring it; SIGTERM likewise only
    # where it has its default action
    own = main and signal.getsignal(signal.SIGINT) is signal.default_int_handler
    own_term = main and signal.getsignal(signal.SIGTERM) == signal.SIG_DFL
    previous = signal.signal(signal.SIGINT, _on_ctrl_c) if own else None
    previous_term = signal.signal(signal.SIGTERM, _on_term) if own_term else None
    unraisable = sys.unraisablehook
    sys.unraisablehook = _quiet_lost_ctrl_c(unraisable)
    try:
        yield
        _stop_if_interrupted()
    except KeyboardInterrupt:
        _err("interrupted")
        raise typer.Exit(130) from None
    except Terminated:
        _err("terminated")
        raise typer.Exit(TERMINATED_EXIT) from None
    finally:
        sys.unraisablehook = unraisable
        if own:
            signal.signal(signal.SIGINT, previous)
        if own_term:
            signal.signal(signal.SIGTERM, previous_term)


def _solve_command(files: list[str], request, fmt: Format, out: Path | None, precision: int,
                   jobs: int, plot: Path | None, table: str | None = None,
                   cluster: str | None = None, exports: tuple = (None, None),
                   front_dir: Path | None = None) -> int:
    """synth and analyze: run the pipeline over the files (`request`: mode, seed, debug,
    timing) with the executor the options ask for (serial, --jobs, --cluster), print or
    write the reports, draw them; the worst exit code. An error of the executor itself
    (a --cluster that cannot be reached, or lost mid-run) ends the command with its line."""
    from linkcli.errors import LinkcliError
    from linkcli.pipeline import executor
    names = [str(f) for f in files]
    debug = request.debug
    try:
        execute = executor(jobs, names, debug, cluster)
    except LinkcliError as exc:
        return _fail(exc, debug)
    request = _spread_fronts(request, execute, jobs, cluster)
    if table is not None and fmt is not Format.csv:
        _err(f"--table: expected --format csv with it (the row table to write), found --format {fmt.value}")
        return 2
    if fmt is Format.csv and out is None and len(names) > 1:
        _err(f"--format csv: expected --out DIR with several files (one CSV file per table), "
             f"found {len(names)} files")
        return 2
    if out is not None and not _prepare_out(out):
        return 2
    if (out is not None and fmt is not Format.csv
            and _overwrites_input([out / f"{stem}.{EXT[fmt.value]}" for stem in _stems(names)], names)):
        return 2
    if front_dir is not None and not _prepare_out(front_dir, "--front-dir"):
        return 2
    if plot is not None and _plot_problem(plot, names):
        return 2
    if any(exports) and _exports_problem(exports, names):  # --animate, --dxf
        return 2
    worst = 0
    counts: dict = {0: 0, 1: 0, 2: 0}
    reports: list[dict] = []
    indices: list[int] = []  # each report's file's index in `names`
    results = []
    printed = 0  # reports shown so far
    prog = _progress(len(names))
    task = None
    counter = None
    if prog is not None:
        from linkcli.pipeline import serial
        from linkcli.search import budget
        prog.start()
        task = prog.add_task(_solving(names[0]), total=len(names), work="")
        counter = _Evaluations(prog, task)
        if execute is serial:  # solves in this process count here (a forked --jobs worker must not
            from linkcli import progress  # touch the display: its lock may have been held at the fork)
            budget.watch = counter
            progress.watch = counter.work
    try:
        with contextlib.closing(execute(names, request)) as outcomes:  # Ctrl-C: closed at once
            for index, (name, outcome) in enumerate(zip(names, outcomes)):
                _stop_if_interrupted()
                code, errors = outcome.exit_code, outcome.errors
                report = outcome.result.report if outcome.result is not None else None
                if outcome.result is not None and front_dir is not None:
                    worst = max(worst, _write_front(outcome.result, name, names, front_dir, precision))
                if outcome.result is not None and (plot is not None or any(exports)):
                    results.append(outcome.result)  # kept for the drawings only: a report may hold 100,000 rows
                if prog is not None:
                    prog.stop()  # the transient bar clears; output prints cleanly below
                for line in errors:
                    _err(line)
                worst = max(worst, code)
                kind = "error" if code == 1 and outcome.result is None else code  # no answer: a crash
                counts[kind] = counts.get(kind, 0) + 1
                if report is None and fmt is Format.json:
                    # keep one object per file, in argument order, for scripts
                    reports.append({"file": name, "status": "bad-input" if code == 2 else "error",
                                    "message": "; ".join(errors)})
                    indices.append(index)
                elif report is not None:
                    printed += 1
                    if fmt in (Format.json, Format.toml) or out is not None:
                        reports.append(report)  # written at the end
                        indices.append(index)  # its file's place among the arguments (its --out name)
                    if fmt is Format.csv and out is None:
                        worst = max(worst, _print_csv(report, table, precision))
                    if fmt is Format.table and out is None:
                        from linkcli.report import print_reports
                        print_reports([report], precision)
                        if printed < len(names):
                            sys.stdout.write("\n")
                        sys.stdout.flush()
                if prog is not None:
                    done = int(prog.tasks[0].completed) + 1
                    nxt = names[done] if done < len(names) else ""
                    prog.update(task, advance=1, description=_solving(nxt) if nxt else "done")
                    counter.reset()
                    prog.start()
    except LinkcliError as exc:  # the executor failed (--cluster): no file is to blame
        return max(worst, _fail(exc, debug))
    finally:
        if prog is not None:
            from linkcli import progress
            from linkcli.search import budget
            budget.watch = progress.watch = None
            prog.stop()
    if out is not None:
        worst = max(worst, _write_out([(i, r) for i, r in zip(indices, reports) if "type" in r], out, fmt, precision,
                                      table, names))
    elif fmt is Format.json:  # a bad file has its slot object, alone or in a batch
        from linkcli.io.export import write_json
        write_json(reports if len(names) > 1 else reports[0], precision, sys.stdout)
    elif fmt is Format.toml and reports:
        from linkcli.io.export import to_toml_many
        sys.stdout.write(to_toml_many(reports, precision))
    if plot is not None and results:
        worst = max(worst, _plot(results, len(names), plot, debug, precision))
    if any(exports) and results:
        from linkcli import exports as export_files
        with _watched("writing " + ("the animation" if exports[0] is not None else "the drawing")
                      + ("s" if len(results) > 1 else "")):
            worst = max(worst, export_files.write(results, len(names), *exports, debug))
    if len(names) > 1:
        _err(f"{len(names)} files: {counts[0]} solved, {counts[1]} infeasible or not converged, "
             f"{counts[2]} bad input" + (f", {counts['error']} failed (internal error)" if counts.get("error") else ""))
    return worst


def _fail(exc, debug: bool) -> int:
    """Print an error that ends the command (one line each) and return its exit code;
    --debug lets it through with its traceback."""
    if debug:
        raise exc
    for line in exc.lines():
        _err(line)
    return exc.exit_code


def _plot_problem(plot: Path, names: list[str]) -> bool:
    from linkcli.plot import plot_path_problem
    line = plot_path_problem(plot, names)
    if line:
        _err(line)
    return bool(line)


def _exports_problem(exports: tuple, names: list[str]) -> bool:
    from linkcli.exports import problems
    lines = problems(*exports, names)
    for line in lines:
        _err(line)
    return bool(lines)


def _prepare_out(out: Path, option: str = "--out") -> bool:
    """--out (--front-dir) must be a folder that exists or can be made, and that takes a
    file (a probe file is made and removed: permissions, a read-only file system); checked
    before any solve."""
    from linkcli.io.output_guard import refuses_files
    if out.exists() and not out.is_dir():
        _err(f"{out}: expected a folder for {option}, found a file")
        return False
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        _err(f"{out}: expected a folder for {option} that can be created, found {exc.strerror or exc}")
        return False
    why = refuses_files(out)
    if why:
        _err(f"{out}: expected a folder for {option} that can be written, found {why}")
        return False
    return True


def _spread_fronts(request, execute, jobs: int, cluster: str | None):
    """The request with where a front's levels go (linkcli.pareto.spread): a cluster's workers
    with --cluster; with --jobs N, N processes when the files themselves are not spread (one
    file: the jobs are the front's, never N processes per file)."""
    import os

    from linkcli.pipeline import serial
    if cluster is not None:
        return request._replace(front=("cluster",))
    if jobs > 1 and execute is serial and not request.debug:
        return request._replace(front=("jobs", min(jobs, os.cpu_count() or 1)))
    return request


def _write_front(result, name: str, names: list[str], folder: Path, precision: int) -> int:
    """--front-dir: the front's designs of one file as result files (linkcli.pareto.files)."""
    from linkcli.io.export import result_stems
    from linkcli.pareto.files import write_front
    stem = result_stems(names)[names.index(name)]
    try:
        write_front(result, folder, stem, precision)
    except OSError as exc:
        _err(f"{folder}: expected a folder for --front-dir that can be written, found {exc.strerror or exc}")
        return 2
    return 0


def _csv_tables(report: dict, table: str | None) -> tuple[dict, str | None]:
    """The row tables --format csv writes for one report (all, or the one --table names),
    or an error line."""
    from linkcli.io.csv_tables import row_tables
    tables = row_tables(report)
    if table is None:
        return tables, None
    if table not in tables:
        known = ", ".join(tables) or "none (ask for a section with rows, e.g. kinematics or positions)"
        return {}, f"{report['file']}: --table: expected a row table of this report, one of: {known}; found {table}"
    return {table: tables[table]}, None


def _print_csv(report: dict, table: str | None, precision: int) -> int:
    """One problem's one row table as CSV on stdout (the only one, or --table NAME)."""
    from linkcli.io.csv_tables import write_csv
    tables, problem = _csv_tables(report, table)
    if problem is None and len(tables) != 1:
        known = ", ".join(tables) or "none (ask for a section with rows, e.g. kinematics or positions)"
        problem = (f"{report['file']}: --format csv: expected one row table, or --table NAME or --out DIR; "
                   f"found {len(tables)}: {known}")
    if problem:
        _err(problem)
        return 2
    write_csv(next(iter(tables.values())), precision, sys.stdout)
    return 0


def _stems(names: list[str]) -> list[str]:
    from linkcli.io.export import result_stems
    return result_stems(names)


def _overwrites_input(targets: list[Path], names: list[str]) -> bool:
    """Whether a result file would replace one of the input files (--out DIR the inputs' own
    folder with --format toml: a problem file overwritten by its result, the drawing lost):
    one line, nothing written."""
    def key(path) -> str:
        try:
            return os.path.realpath(path)
        except (OSError, ValueError):
            return str(path)
    inputs = {key(n): n for n in names}
    for target in targets:
        if key(target) in inputs:
            _err(f"{target}: expected a result file name that is not one of the input files, found the "
                 f"problem file {inputs[key(target)]} (--out names its folder: write the results to another "
                 "folder, or use another --format)")
            return True
    return False


def _write_out(reports: list[tuple[int, dict]], out: Path, fmt: Format, precision: int, table: str | None,
               names: list[str]) -> int:
    """Each report (its file's index in `names`, the report) as DIR/<stem>.<ext>, the stems of
    every input in argument order (result_stems: a bad file keeps its stem, so the others' names
    do not depend on it), one CSV file per row table; nothing written when a target would
    replace an input file."""
    from linkcli.io.export import to_toml, write_json
    from linkcli.io.whole_file import whole_text_file
    from linkcli.report import render_text
    every = _stems(names)
    stems = [every[i] for i, _ in reports]
    csv: list[dict] = []
    if fmt is Format.csv:  # one file per row table: <stem>.<table>.csv
        for (_, rep), stem in zip(reports, stems):
            tables, problem = _csv_tables(rep, table)
            if problem:
                _err(problem)
                return 2
            csv.append(tables)
        targets = [out / f"{stem}.{name}.csv" for stem, tables in zip(stems, csv) for name in tables]
    else:
        targets = [out / f"{stem}.{EXT[fmt.value]}" for stem in stems]
    if _overwrites_input(targets, names):
        return 2
    for k, ((_, rep), stem) in enumerate(zip(reports, stems)):
        if fmt is Format.csv:
            from linkcli.io.csv_tables import write_csv
            for name, rows in csv[k].items():
                target = out / f"{stem}.{name}.csv"
                try:
                    with whole_text_file(target, newline="") as handle:
                        write_csv(rows, precision, handle)
                except OSError as exc:
                    _err(f"{target}: expected a writable result file, found {exc.strerror or exc}")
                    return 2
            continue
        target = out / f"{stem}.{EXT[fmt.value]}"
        try:
            with whole_text_file(target) as handle:  # a failed write leaves no partial file
                if fmt is Format.json:
                    write_json(rep, precision, handle)
                else:
                    handle.write(to_toml(rep, precision) if fmt is Format.toml else render_text([rep], precision))
        except OSError as exc:
            _err(f"{target}: expected a writable result file, found {exc.strerror or exc}")
            return 2
    return 0


def _plot(results, files: int, plot: Path, debug: bool, precision: int = 6) -> int:
    try:
        from linkcli import plot as plotting
    except ImportError:
        _err(f"{plot}: expected the plot extra (pip install \"linkcli[plot]\"), found no plotting module")
        return 2
    return plotting.plot_command(results, files, plot, debug, precision)


PATH_WANTED = {"out": "a folder name", "plot": "a .png or .svg file name (a folder with several files)",
               "animate": "a .gif, .mp4 or .svg file name (a folder with several files)",
               "dxf": "a .dxf file name (a folder with several files)"}


def _paths(**given: str | None) -> list[Path | None]:
    """The path options as Paths (None where not given); an empty one is one line and exit 2
    (pathlib reads "" as ".", the current folder: `--out ""` wrote there, and the other
    options' errors named "."). Plain strings on the command line for that reason, as FILE."""
    out = []
    for name, value in given.items():
        if value == "":
            _err(f"--{name}: expected {PATH_WANTED[name]}, found an empty argument")
            raise typer.Exit(2)
        out.append(None if value is None else Path(value))
    return out


# metavars are written for people: FILE..., N, DIR (not click's {files}... or <int range>)
# FILE arguments are plain strings: click's Path would refuse an unreadable file for the
# whole batch before anything runs, and pathlib would rewrite the names ("" -> ".",
# "./a//b.toml" -> "a/b.toml"); each file is read, and refused in its slot, by io.safe_read
FILES = typer.Argument(..., help="Problem files (TOML).", metavar="FILE...")
FORMAT = typer.Option(Format.table, "--format", "-f", metavar="table|json|toml|csv",
                      help="Output format (csv: the row tables, see --table).")
TABLE = typer.Option(None, "--table", metavar="NAME",
                     help="With --format csv: the row table to write (e.g. kinematics, positions, forces.rows).")
OUT = typer.Option(None, "--out", metavar="DIR", help="Write one result file per problem into this folder.")
SEED = typer.Option(None, "--seed", metavar="N", help="Override the files' [solver] seed (0 .. 4294967295).",
                    min=0, max=2**32 - 1)
PRECISION = typer.Option(6, "--precision", metavar="N", help="Significant digits in the output (1 .. 17).",
                         min=1, max=17)
JOBS = typer.Option(1, "--jobs", "-j", metavar="N",
                    help="Solve files in N processes (output keeps argument order).", min=1)
PLOT = typer.Option(None, "--plot", metavar="FILE",
                    help="Draw the result to FILE.png|FILE.svg (a folder with several files).")
ANIMATE = typer.Option(None, "--animate", metavar="FILE",
                       help="Animate the linkage's motion to FILE.gif|FILE.mp4|FILE.svg (a folder with several files).")
DXF = typer.Option(None, "--dxf", metavar="FILE",
                   help="Write the design for CAD to FILE.dxf (a folder with several files).")
DEBUG = typer.Option(False, "--debug", help="Show Python tracebacks.")
TIMING = typer.Option(False, "--timing", help="Add the solver's wall-clock seconds to the report.")
FRONT_DIR = typer.Option(None, "--front-dir", metavar="DIR",
                         help="Write each design of a Pareto front as a result file into this folder.")
CLUSTER = typer.Option(None, "--cluster", metavar="ADDRESS",
                       help="Run on the Dask scheduler at tcp://HOST:PORT, or local:N for N local "
                            "worker processes (pip install \"linkcli[cluster]\"; not with --jobs).")


@app.command(cls=PlainUsage)
def synth(files: list[str] = FILES, format: Format = FORMAT, out: str | None = OUT,
          seed: int | None = SEED, precision: int = PRECISION, jobs: int = JOBS,
          plot: str | None = PLOT, debug: bool = DEBUG, timing: bool = TIMING,
          table: str | None = TABLE, cluster: str | None = CLUSTER,
          animate: str | None = ANIMATE, dxf: str | None = DXF,
          front_dir: Path | None = FRONT_DIR) -> None:
    """Solve each problem file and print its report."""
    from linkcli.pipeline import Request
    out, plot, animate, dxf = _paths(out=out, plot=plot, animate=animate, dxf=dxf)
    request = Request(mode="synth", seed=seed, debug=debug, timing=timing,
                      plot=plot is not None or animate is not None or dxf is not None or front_dir is not None)
    with _interruptible():
        code = _solve_command(files, request, format, out, precision, jobs, plot, table, cluster, (animate, dxf),
                              front_dir)
    raise typer.Exit(code)


@app.command(cls=PlainUsage)
def analyze(files: list[str] = FILES, format: Format = FORMAT, out: str | None = OUT,
            precision: int = PRECISION, jobs: int = JOBS, plot: str | None = PLOT,
            debug: bool = DEBUG, table: str | None = TABLE,
            animate: str | None = ANIMATE, dxf: str | None = DXF) -> None:
    """Analyse given linkages: `type = "linkage"` files or results of `synth --format toml`."""
    from linkcli.pipeline import Request
    out, plot, animate, dxf = _paths(out=out, plot=plot, animate=animate, dxf=dxf)
    request = Request(mode="analyze", debug=debug,
                      plot=plot is not None or animate is not None or dxf is not None)
    with _interruptible():
        code = _solve_command(files, request, format, out, precision, jobs, plot, table, None, (animate, dxf))
    raise typer.Exit(code)


@app.command(cls=PlainUsage)
def check(files: list[str] = FILES, debug: bool = DEBUG) -> None:
    """Validate problem files without solving (exit 2 on any error)."""
    from linkcli.io.terminal_text import line as terminal_line
    from linkcli.pipeline import Request, serial
    worst = 0
    for f, outcome in zip(files, serial([str(f) for f in files], Request(mode="check", debug=debug))):
        for line in outcome.errors:
            _err(line)
        if outcome.exit_code == 0:  # the verdict is output (escaped as an error line is); errors stay on stderr
            sys.stdout.write(terminal_line(f"{f}: ok"))
        worst = max(worst, outcome.exit_code)
    raise typer.Exit(worst)


@app.command(cls=PlainUsage)
def bench(files: list[str] = typer.Argument(None, metavar="[FILE...]",
                                             help="Problem files (default: the bench set shipped with linkcli, "
                                                  "a copy of problems/bench/)."),
          format: Format = typer.Option(Format.table, "--format", "-f", metavar="table|json|toml|csv",
                                        help="Output format (csv: one row per run)."),
          seeds: int = typer.Option(3, "--seeds", metavar="N", min=1, max=MAX_SEEDS,
                                    help=f"Seeds per setting (1 .. {MAX_SEEDS}: the seeds 0 .. N-1)."),
          precision: int = typer.Option(4, "--precision", metavar="N",
                                        help="Significant digits in the output (1 .. 17).", min=1, max=17),
          summary: bool = typer.Option(False, "--summary",
                                       help="Only the reliability over the seeds, one row per problem "
                                            "and method (any format); the table view shows it after "
                                            "every run."),
          debug: bool = DEBUG, cluster: str | None = CLUSTER) -> None:
    """Time each solver setting against its error on a set of problems, and how reliably
    its seeds reach the best known."""
    from linkcli import bench as benchmod
    with _interruptible():
        code = benchmod.command([str(f) for f in files or []], format.value, seeds, precision,
                                debug, cluster, summary_only=summary)
    raise typer.Exit(code)


@app.command(cls=PlainUsage)
def new(type_name: str = typer.Argument(..., metavar="TYPE",
                                        help="The problem type (e.g. linkage, path-generation), or a mechanism "
                                             "with a template of its own (five-bar, drawn)."),
        file: str | None = typer.Argument(None, metavar="[FILE]",
                                              help="Write the template here (never over an existing file); "
                                                   "without FILE, print it.")) -> None:
    """Write a commented template problem file of TYPE (to FILE, or to stdout)."""
    from linkcli.io.terminal_text import shown
    from linkcli.templates import nearest_name, template_names, template_text
    names = template_names()
    if type_name not in names:
        hint = nearest_name(type_name)
        extra = f' (did you mean "{hint}"?)' if hint else ""
        _err(f"TYPE: expected a problem type or a mechanism with a template{extra}, one of: {', '.join(names)}; "
             f'found "{shown(type_name, 60)}"')
        raise typer.Exit(2)
    text = template_text(type_name)
    if file is None:
        sys.stdout.write(text)
        raise typer.Exit(0)
    if file == "":
        _err('"": expected a new file name, found an empty argument')
        raise typer.Exit(2)
    try:
        with open(file, "x", encoding="utf-8") as handle:  # "x": refuses an existing file
            handle.write(text)
    except FileExistsError:
        what = "an existing folder" if Path(file).is_dir() else "an existing file (not overwritten)"
        _err(f"{file}: expected a new file name, found {what}")
        raise typer.Exit(2)
    except IsADirectoryError:
        _err(f"{file}: expected a new file name, found an existing folder")
        raise typer.Exit(2)
    except OSError as exc:
        _err(f"{file}: expected a writable new file, found {exc.strerror or exc}")
        raise typer.Exit(2)
    raise typer.Exit(0)


atlas_app = typer.Typer(add_completion=False, no_args_is_help=True, rich_markup_mode=None,
                        pretty_exceptions_enable=False,
                        help="The coupler-curve atlas that free-timing path searches start from.")
app.add_typer(atlas_app, name="atlas")


@atlas_app.command("build", cls=PlainUsage)
def atlas_build(out: str | None = typer.Option(None, "--out", metavar="PATH",
                                                   help="Write the atlas here (default: the user's cache, "
                                                        "where searches look for it)."),
                size: int = typer.Option(100_000, "--size", metavar="N", help="Four-bars in the atlas."),
                seed: int = typer.Option(0, "--seed", metavar="N", help="Seed of the draws.", min=0, max=2**32 - 1)) -> None:
    """Build the coupler-curve atlas (deterministic: the same bytes for the same size and
    seed on every machine)."""
    from linkcli.atlas.command import build_command
    with _interruptible():
        code = build_command(out, size, seed)
    raise typer.Exit(code)


def main() -> None:
    """Console-script entry point. Standard output is guarded (io.output_guard): a reader
    that closes the pipe ends the command quietly with exit 141, an output that refuses the
    text (a full device, a closed stdout) is one line and exit 2. A closed stderr (`2>&-`)
    becomes /dev/null first, so that nothing which writes there (the progress display,
    rich, a warning) can change the result."""
    from linkcli.io.output_guard import Guarded, OutputLost, exit_code, sink_for_closed_stderr
    sink_for_closed_stderr()
    sys.stdout = Guarded(sys.stdout)
    try:
        try:
            app(prog_name="linkcli")
        except SystemExit as done:
            code = done.code
        sys.stdout.flush()  # what the buffer held fails here, inside the guard
    except KeyboardInterrupt:
        _err("interrupted")
        code = 130
    except Terminated:
        _err("terminated")
        code = TERMINATED_EXIT
    except OutputLost as lost:
        code = exit_code(lost, _err)
    sys.exit(code)


if __name__ == "__main__":
    main()
