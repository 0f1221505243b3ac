"""`--plot PATH` checked before any solve (as `--out` is): a long batch must not fail at
its very end on a name it could have refused at once.

The same rules as the plot itself (plot.output_paths: one file -> PATH.png|PATH.svg, several
-> a folder), and the folder that will hold the picture must be creatable: its nearest
existing ancestor must be a folder (`afile/x.png` is refused). Nothing is created here.
"""

from __future__ import annotations

from pathlib import Path


def plot_path_problem(plot: Path, names: list[str], **rules) -> str | None:
    """The error line for a --plot PATH that cannot work, or None. `rules`: another
    option's formats, folder_format and what (plot.output_paths), and `noun` (the line's
    "a plot path")."""
    from linkcli.plot import PlotError, output_paths
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
    return None
