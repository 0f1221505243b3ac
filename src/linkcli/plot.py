"""`--plot PATH` on synth and analyze: draw each solved problem to PNG or SVG.

matplotlib is an optional extra (`pip install "linkcli[plot]"`) imported only here, inside
the functions, when a plot is asked for; the drawing for each problem type lives in
`linkcli.plots.<module>`. One file: PATH is the picture (.png or .svg). Several files:
PATH is a folder (created) holding `<stem>.png` per problem. Output is deterministic:
fixed metadata and a fixed SVG hash salt give identical bytes from run to run.
"""

from __future__ import annotations

import io
import sys
from dataclasses import replace
from pathlib import Path

FORMATS = (".png", ".svg")
FOLDER_FORMAT = ".png"


class PlotError(Exception):
    """A plot request that cannot be met: one stderr line, an exit code."""

    def __init__(self, line: str, exit_code: int = 2) -> None:
        super().__init__(line)
        self.exit_code = exit_code


def _err(line: str) -> None:
    sys.stderr.write(line.rstrip("\n") + "\n")


def plot_command(reports: list[dict], names: list[str], plot_path, mode: str, seed, debug: bool) -> int:
    """Draw every report; return the exit code (0, or 2 for a bad PATH or no matplotlib,
    1 for a plot that failed to draw)."""
    plot_path = Path(plot_path)
    try:
        targets = output_paths(reports, names, plot_path)
        require_matplotlib(plot_path)
    except PlotError as exc:
        _err(str(exc))
        return exc.exit_code
    worst = 0
    for report, target in zip(reports, targets):
        try:
            report = complete(report, mode, seed)
            write(report, target, load_problem(report, mode))
        except PlotError as exc:
            _err(str(exc))
            worst = max(worst, exc.exit_code)
        except Exception as exc:  # a bug: one line, not a traceback
            from linkcli.errors import LinkcliError
            if debug:
                raise
            if isinstance(exc, LinkcliError):
                for line in (exc.lines() if hasattr(exc, "lines") else [str(exc)]):
                    _err(line)
                worst = max(worst, getattr(exc, "exit_code", 1))
                continue
            _err(f"{target}: internal error while plotting {report.get('file')}: "
                 f"{type(exc).__name__}: {exc} (run with --debug for the traceback)")
            worst = max(worst, 1)
    return worst


def output_paths(reports: list[dict], names: list[str], plot_path: Path) -> list[Path]:
    """One file: PATH itself, which must end in .png or .svg. Several files: PATH is a
    folder (created) and each plot is `<stem>.png` (`<stem>_2.png` for a repeated stem)."""
    if len(names) <= 1:
        suffix = plot_path.suffix.lower()
        if suffix not in FORMATS:
            found = f'"{plot_path.suffix}"' if plot_path.suffix else "no extension"
            raise PlotError(f"{plot_path}: expected a .png or .svg file name, found {found}")
        if plot_path.is_dir():
            raise PlotError(f"{plot_path}: expected a .png or .svg file name, found a folder")
        return [plot_path]
    if plot_path.suffix.lower() in FORMATS or (plot_path.exists() and not plot_path.is_dir()):
        what = "a file" if plot_path.exists() and not plot_path.is_dir() else f'a "{plot_path.suffix}" file name'
        raise PlotError(f"{plot_path}: expected a folder for the plots of {len(names)} files "
                        f"(each written as <problem>{FOLDER_FORMAT}), found {what}")
    from linkcli.export import result_stems
    stems = result_stems([report.get("file") or "plot" for report in reports])
    return [plot_path / f"{stem}{FOLDER_FORMAT}" for stem in stems]


def require_matplotlib(plot_path: Path) -> None:
    """Import matplotlib with the Agg backend, or say how to install it (exit 2)."""
    try:
        import matplotlib
    except ImportError:
        raise PlotError(f'{plot_path}: expected matplotlib for --plot (pip install "linkcli[plot]"), '
                        "found it not installed") from None
    matplotlib.use("Agg")


def complete(report: dict, mode: str, seed) -> dict:
    """The report itself when it holds the sections its plot draws from; otherwise the
    problem is loaded and solved again (deterministic: same file and seed) with those
    sections asked for. That happens only when `[report] sections` left them out."""
    from linkcli.plots import module_for
    needs = module_for(report["type"]).NEEDS
    if all(k in report for k in needs) or not report.get("file"):
        return report
    from linkcli import analyse
    from linkcli.problemfile.common import ALL_SECTIONS
    from linkcli.solvers import solve
    problem = _load(report["file"], mode)
    meta = problem.meta
    if _sections_for(needs) <= set(meta.sections):
        return report  # asked for, yet absent: the solution has none (the plot says so)
    wanted = tuple(s for s in ALL_SECTIONS if s in set(meta.sections) | _sections_for(needs))
    solver = meta.solver if seed is None else replace(meta.solver, seed=seed)
    problem = replace(problem, meta=replace(meta, sections=wanted, solver=solver, tolerance=None))
    return analyse.build(problem, solve(problem))


def _sections_for(needs) -> set[str]:
    """Report keys -> the `[report] sections` names that produce them."""
    return {"lengths" if k == "linkage" else k for k in needs}


def load_problem(report: dict, mode: str):
    """The problem file, for the plots that need data the report does not carry
    (a linkage's input speed, a flipper's load); None otherwise."""
    from linkcli.plots import module_for
    if not module_for(report["type"]).PROBLEM or not report.get("file"):
        return None
    return _load(report["file"], mode)


def _load(path: str, mode: str):
    from linkcli.problemfile import load, load_for_analysis
    return load_for_analysis(path) if mode == "analyze" else load(path)


def figure(report: dict, problem=None):
    """A matplotlib Figure of one report (no pyplot: nothing global is touched)."""
    import matplotlib
    from matplotlib.figure import Figure

    from linkcli.plots import module_for
    from linkcli.plots.common import FIGSIZE, STYLE
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=FIGSIZE, layout="constrained")
        module_for(report["type"]).draw(fig, report, problem)
    return fig


def render(report: dict, fmt: str, problem=None) -> bytes:
    """The picture of one report as PNG or SVG bytes, identical from run to run."""
    import matplotlib

    from linkcli import __version__
    from linkcli.plots.common import DPI, STYLE
    fig = figure(report, problem)
    title = str(report.get("title") or report.get("file") or "linkcli plot")
    buf = io.BytesIO()
    with matplotlib.rc_context(STYLE):
        if fmt == "svg":
            fig.savefig(buf, format="svg",
                        metadata={"Date": None, "Creator": f"linkcli {__version__}", "Title": title})
        else:
            fig.savefig(buf, format="png", dpi=DPI, metadata={"Software": f"linkcli {__version__}", "Title": title})
    return buf.getvalue()


def write(report: dict, target: Path, problem=None) -> None:
    """Render and write one plot; a path that cannot be written is bad input (exit 2)."""
    data = render(report, target.suffix.lower().lstrip(".") or "png", problem)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(data)
    except OSError as exc:
        raise PlotError(f"{target}: expected a file name that can be written, "
                        f"found {exc.strerror or type(exc).__name__}") from None
