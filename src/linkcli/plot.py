"""`--plot PATH` on synth and analyze: draw each solved problem to PNG or SVG.

matplotlib is an optional extra (`pip install "linkcli[plot]"`) imported only here, inside
the functions, when a plot is asked for; the drawing of each problem type lives in
`linkcli.types.<type>.plot` and draws the `linkcli.pipeline.Result` it is handed (it never
loads or solves). One file: PATH is the picture (.png or .svg). Several files:
PATH is a folder (created) holding `<stem>.png` per problem. Output is deterministic:
fixed metadata and a fixed SVG hash salt give identical bytes from run to run.
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

from linkcli.errors import LinkcliError, PlotError

FORMATS = (".png", ".svg")
FOLDER_FORMAT = ".png"


def _err(line: str) -> None:
    from linkcli.io.terminal_text import write_error
    write_error(line)


def plot_command(results: list, files: int, plot_path, debug: bool, digits: int = 6) -> int:
    """Draw every Result; return the exit code (0, or 2 for a bad PATH or no matplotlib,
    1 for a plot that failed to draw). `files`: how many files the command was given
    (one: PATH is the picture; several: PATH is a folder); `digits`: --precision, for the
    numbers of the titles."""
    plot_path = Path(plot_path)
    try:
        targets = output_paths([result.report for result in results], files, plot_path)
        require_matplotlib(plot_path)
    except PlotError as exc:
        _err(str(exc))
        return exc.exit_code
    return write_each(results, targets, lambda result, target: write(result, target, digits), debug,
                      "plotting")


WRITTEN = {"plotting": "plot", "animating": "animation", "drawing": "DXF drawing"}


def write_each(results: list, targets: list[Path], write_one, debug: bool, doing: str) -> int:
    """`write_one(result, target)` for each Result, and a line on stderr saying where each
    went (`FILE: plot written to PATH`: the report on stdout does not say it); the worst
    exit code: 2 for a PlotError (bad input: its line), a LinkcliError's own, 1 for a bug
    (one line; --debug raises)."""
    worst = 0
    for result, target in zip(results, targets):
        try:
            write_one(result, target)
            _err(f"{result.report.get('file') or 'linkcli'}: {WRITTEN.get(doing, 'file')} written to {target}")
        except PlotError as exc:
            _err(str(exc))
            worst = max(worst, exc.exit_code)
        except LinkcliError as exc:
            if debug:
                raise
            for line in exc.lines():
                _err(line)
            worst = max(worst, exc.exit_code)
        except Exception as exc:  # a bug: one line, not a traceback
            if debug:
                raise
            _err(f"{target}: internal error while {doing} {result.report.get('file')}: "
                 f"{type(exc).__name__}: {exc} (run with --debug for the traceback)")
            worst = max(worst, 1)
    return worst


def output_paths(reports: list[dict], files: int, plot_path: Path, formats: tuple[str, ...] = FORMATS,
                 folder_format: str = FOLDER_FORMAT, what: str = "plots") -> list[Path]:
    """One file: PATH itself, which must end in one of `formats` (.png or .svg). Several
    files: PATH is a folder (created) and each picture is `<stem>.png` (`folder_format`;
    `<stem>_2.png` for a repeated stem). `what` names the pictures in the error line."""
    names = " or ".join([", ".join(formats[:-1]), formats[-1]] if len(formats) > 1 else formats)
    if files <= 1:
        suffix = plot_path.suffix.lower()
        if suffix not in formats:
            found = f'"{plot_path.suffix}"' if plot_path.suffix else "no extension"
            raise PlotError(f"{plot_path}: expected a {names} file name, found {found}")
        if plot_path.is_dir():
            raise PlotError(f"{plot_path}: expected a {names} file name, found a folder")
        return [plot_path]
    if plot_path.suffix.lower() in formats or (plot_path.exists() and not plot_path.is_dir()):
        found = "a file" if plot_path.exists() and not plot_path.is_dir() else f'a "{plot_path.suffix}" file name'
        raise PlotError(f"{plot_path}: expected a folder for the {what} of {files} files "
                        f"(each written as <problem>{folder_format}), found {found}")
    from linkcli.io.export import result_stems
    stems = result_stems([report.get("file") or "plot" for report in reports])
    return [plot_path / f"{stem}{folder_format}" for stem in stems]


def require_matplotlib(plot_path: Path) -> None:
    """Import matplotlib with the Agg backend, or say how to install it (exit 2)."""
    try:
        import matplotlib
    except ImportError:
        raise PlotError(f'{plot_path}: expected matplotlib for --plot (pip install "linkcli[plot]"), '
                        "found it not installed") from None
    matplotlib.use("Agg")


def figure(result):
    """A matplotlib Figure of one pipeline Result (no pyplot: nothing global is touched)."""
    import matplotlib
    from matplotlib.figure import Figure

    from linkcli.plots.common import FIGSIZE, STYLE, drawn
    from linkcli.registry import problem_type
    report = drawn(result)
    with matplotlib.rc_context(STYLE):
        panels = []  # any type's result with a forces (strength) section: panels under its figure
        if "forces" in report and report["forces"].get("rows"):
            from linkcli.plots import forces
            panels.append(forces)
        if "strength" in report and report["strength"].get("rows"):
            from linkcli.plots import strength
            panels.append(strength)
        if "history" in report or "balance" in report:  # [dynamics]
            from linkcli.plots.dynamics import panels as dynamics_panels
            panels.extend(dynamics_panels(report))
        if panels:
            heights = [FIGSIZE[1]] + [panel.HEIGHT for panel in panels]
            fig = Figure(figsize=(FIGSIZE[0], sum(heights)), layout="constrained")
            top, *below = fig.subfigures(len(heights), 1, height_ratios=heights)
            problem_type(report["type"]).module("plot").draw(top, result)
            for panel, sub in zip(panels, below):
                panel.draw(sub, result)
            return fig
        fig = Figure(figsize=FIGSIZE, layout="constrained")
        problem_type(report["type"]).module("plot").draw(fig, result)
    return fig


def render(result, fmt: str, digits: int = 6) -> bytes:
    """The picture of one Result as PNG or SVG bytes, identical from run to run; numbers
    in its title to `digits` significant digits. A glyph the font lacks (a title in a
    script DejaVu Sans does not cover) is drawn as a box without matplotlib's warning."""
    import warnings

    import matplotlib

    from linkcli import __version__
    from linkcli.io.terminal_text import one_line
    from linkcli.plots.common import DPI, STYLE, TITLE_DIGITS
    report = result.report
    title = one_line(str(report.get("title") or report.get("file") or "linkcli plot"))
    buf = io.BytesIO()
    token = TITLE_DIGITS.set(digits)
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message="Glyph .* missing from", category=UserWarning)
            fig = figure(result)
            with matplotlib.rc_context(STYLE):
                if fmt == "svg":
                    fig.savefig(buf, format="svg",
                                metadata={"Date": None, "Creator": f"linkcli {__version__}", "Title": title})
                else:
                    fig.savefig(buf, format="png", dpi=DPI,
                                metadata={"Software": f"linkcli {__version__}", "Title": title})
    finally:
        TITLE_DIGITS.reset(token)
    return buf.getvalue()


def write(result, target: Path, digits: int = 6) -> None:
    """Render and write one plot; a path that cannot be written is bad input (exit 2)."""
    write_bytes(target, render(result, target.suffix.lower().lstrip(".") or "png", digits))


def write_bytes(target: Path, data: bytes) -> None:
    """Write a picture, an animation or a drawing (its folder created); a path that cannot
    be written is bad input. The bytes go to a temporary file beside the target, renamed
    over it once complete: a write that fails (a full disk, a quota) leaves no partial file
    behind, and an existing file is replaced whole or not at all."""
    import os
    import tempfile
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=target.parent)
    except OSError as exc:
        raise PlotError(f"{target}: expected a file name that can be written, "
                        f"found {exc.strerror or type(exc).__name__}") from None
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        os.chmod(temporary, 0o666 & ~_umask())
        os.replace(temporary, target)
    except OSError as exc:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise PlotError(f"{target}: expected a file name that can be written, "
                        f"found {exc.strerror or type(exc).__name__}") from None


def _umask() -> int:
    """The process's umask (read by setting it and setting it back): a file made through
    mkstemp (mode 0600) gets the mode a plain open would have given it."""
    import os
    mask = os.umask(0)
    os.umask(mask)
    return mask


def plot_path_problem(plot: Path, names: list[str], **rules) -> str | None:
    """`--plot PATH` checked before any solve (as `--out` is: a long batch must not fail at
    its very end on a name it could have refused at once): the same rules as the plot itself
    (`output_paths`), and the folder that will hold the picture must be creatable: its nearest
    existing ancestor must be a folder (`afile/x.png` is refused) that takes a file (a probe
    file is made there and removed; nothing else is created). The error line for a --plot
    PATH that cannot work, or None. `rules`: another
    option's formats, folder_format and what (plot.output_paths), and `noun` (the line's
    "a plot path")."""
    noun = rules.pop("noun", "a plot path")
    try:
        output_paths([], len(names), plot, **rules)
    except PlotError as exc:
        return str(exc)
    folder = plot.parent if len(names) <= 1 else plot
    probe = folder
    while not probe.exists() and probe != probe.parent:
        probe = probe.parent
    if probe.exists() and not probe.is_dir():
        return f"{plot}: expected {noun} inside a folder, found {probe} is a file"
    if probe.is_dir():  # the folder that will hold the picture (or be made in) must take a file
        from linkcli.io.output_guard import refuses_files
        why = refuses_files(probe)
        if why:
            return f"{plot}: expected {noun} in a folder that can be written, found {probe}: {why}"
    return None
