"""`--animate PATH` and `--dxf PATH` on synth and analyze: checked before any solve (as
`--plot` is: the name, its folder, the library it needs), written after.

One file: PATH is the file (`.gif`, `.mp4` or `.svg` for --animate, `.dxf` for --dxf).
Several: PATH is a folder holding `<problem>.gif` or `<problem>.dxf` for each solved
problem. A result with nothing that moves (a linkage that never assembles, a flipper
without a design) is bad input for these options (exit 2, one line naming the file);
the report itself has printed. Light module: the writers import their libraries.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

ANIMATE = {"formats": (".gif", ".mp4", ".svg"), "folder_format": ".gif", "what": "animations",
           "noun": "an animation path"}
DXF = {"formats": (".dxf",), "folder_format": ".dxf", "what": "drawings", "noun": "a DXF path"}
NEEDS = {  # format -> (module, pip name, extra) it needs
    ".gif": (("matplotlib", "matplotlib", "plot"),),
    ".svg": (("matplotlib", "matplotlib", "plot"),),
    ".mp4": (("matplotlib", "matplotlib", "video"), ("imageio_ffmpeg", "imageio-ffmpeg", "video")),
    ".dxf": (("ezdxf", "ezdxf", "cad"),),
}


def installed(module: str) -> bool:
    """Whether `module` can be imported (without importing it)."""
    if module in sys.modules:
        return sys.modules[module] is not None
    return importlib.util.find_spec(module) is not None


def library_problem(path: Path, fmt: str, option: str) -> str | None:
    """The line for a library the format needs and does not have, or None."""
    for module, name, extra in NEEDS[fmt]:
        if not installed(module):
            return (f'{path}: expected {name} for {option} {fmt[1:].upper()} (pip install "linkcli[{extra}]"), '
                    "found it not installed")
    if fmt == ".mp4":
        import imageio_ffmpeg  # light: finds the binary its wheel ships
        try:
            imageio_ffmpeg.get_ffmpeg_exe()
        except RuntimeError as exc:
            return f"{path}: expected the ffmpeg binary of imageio-ffmpeg for {option} MP4, found {exc}"
    return None


def problems(animate: Path | None, dxf: Path | None, names: list[str]) -> list[str]:
    """Error lines for --animate and --dxf paths that cannot work (before solving)."""
    from linkcli.plot import plot_path_problem
    lines = []
    for path, rules, option in ((animate, ANIMATE, "--animate"), (dxf, DXF, "--dxf")):
        if path is None:
            continue
        line = plot_path_problem(path, names, **rules)
        if line is None:
            fmt = path.suffix.lower() if len(names) <= 1 else rules["folder_format"]
            line = library_problem(path, fmt, option)
        if line:
            lines.append(line)
    return lines


def write(results: list, files: int, animate: Path | None, dxf: Path | None, debug: bool) -> int:
    """Write the animations and drawings of the solved Results; the worst exit code."""
    from linkcli.plot import PlotError, output_paths, write_each
    worst = 0
    reports = [result.report for result in results]
    for path, rules, write_one, doing in ((animate, ANIMATE, write_animation, "animating"),
                                          (dxf, DXF, write_dxf, "drawing")):
        if path is None:
            continue
        try:
            targets = output_paths(reports, files, Path(path), rules["formats"], rules["folder_format"], rules["what"])
        except PlotError as exc:
            from linkcli.io.terminal_text import write_error
            write_error(str(exc))
            worst = max(worst, exc.exit_code)
            continue
        worst = max(worst, write_each(results, targets, write_one, debug, doing))
    return worst


def scene(result, target: Path, verb: str):
    """The Scene of a Result, or a PlotError naming the file when nothing moves."""
    from linkcli.animate.scene import NothingToDraw, scene_of
    from linkcli.plot import PlotError
    try:
        return scene_of(result)
    except NothingToDraw as exc:
        raise PlotError(f"{target}: expected a result with a linkage to {verb}, "
                        f"found {result.report.get('file')}: {exc}") from None


def write_animation(result, target: Path) -> None:
    from linkcli.animate.render import render
    from linkcli.plot import write_bytes
    write_bytes(target, render(scene(result, target, "animate"), target.suffix.lower()))


def write_dxf(result, target: Path) -> None:
    from linkcli.cad.dxf import render
    from linkcli.plot import write_bytes
    meta = result.problem.meta
    diameters = {j.name: j.diameter for j in meta.joints if j.diameter}
    widths = {name: section.plane_width for name, section in meta.link_sections.items()}
    write_bytes(target, render(scene(result, target, "draw"), widths=widths, diameters=diameters))
