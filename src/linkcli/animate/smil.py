"""The animation as one self-contained SVG that plays by itself in a browser: SMIL
animations, no script, no external file.

The still parts are matplotlib's SVG of the Movie (the moving parts hidden), written at
72 dpi so that one SVG user unit is one point and the figure's display coordinates are
the SVG's (y turned down). Over them a group of moving elements, each at frame 0 and
animated through every frame (FRAME_MS a frame, looping): links as <polyline>/<polygon>
(`points` animated), joint rings, slider blocks and joint names moved by a translate
<animateTransform>, interpolated linearly between frames. The frame's drive value is one
matplotlib text a frame, shown only during its frame (discrete `visibility`); so are the
moving parts where the linkage does not assemble. Coordinates are written to 0.01 pt.
"""

from __future__ import annotations

import io
from xml.sax.saxutils import escape

import numpy as np

from linkcli.animate.figure import Movie
from linkcli.animate.raster import FRAME_MS

SVG_DPI = 72  # matplotlib writes SVG in points: at 72 dpi, display pixels are SVG units
GROUP = "linkcli-motion"


def _xy(v) -> str:
    return f"{v:.2f}"


def _points(rows: np.ndarray) -> str:
    """(m, 2) SVG coordinates as `x,y x,y`."""
    return " ".join(f"{_xy(x)},{_xy(y)}" for x, y in rows)


def _rgba(color) -> tuple[str, float]:
    from matplotlib.colors import to_hex, to_rgba
    rgba = to_rgba(color)
    return to_hex(rgba, keep_alpha=False), round(float(rgba[3]), 4)


def _paint(kind: str, color, width: float | None = None) -> str:
    hexa, alpha = _rgba(color)
    out = f'{kind}="{hexa}"' + (f' {kind}-opacity="{alpha:g}"' if alpha < 1 else "")
    if width is not None:
        out += f' stroke-width="{width:g}"'
    return out


class Timeline:
    """The timing shared by every animation: n frames, FRAME_MS each, looping; a closed
    list of values (the first repeated at the end) so that the last frame runs back into
    the first."""

    def __init__(self, frames: int) -> None:
        self.frames = frames
        self.dur = f"{frames * FRAME_MS / 1000:g}s"

    def animate(self, attribute: str, values: list[str]) -> str:
        return (f'<animate attributeName="{attribute}" dur="{self.dur}" repeatCount="indefinite" '
                f'values="{";".join(values + values[:1])}"/>')

    def move(self, xy: np.ndarray) -> str:
        values = [f"{_xy(x)} {_xy(y)}" for x, y in xy]
        return (f'<animateTransform attributeName="transform" type="translate" dur="{self.dur}" '
                f'repeatCount="indefinite" values="{";".join(values + values[:1])}"/>')

    def shown(self, on: np.ndarray) -> str:
        """visibility over the frames (on: (n,) bool), switched where it changes (discrete)."""
        on = np.asarray(on, dtype=bool)
        changes = [0] + [k for k in range(1, self.frames) if on[k] != on[k - 1]]
        keys = ";".join(f"{k / self.frames:.6g}" for k in changes)
        values = ";".join("visible" if on[k] else "hidden" for k in changes)
        return (f'<animate attributeName="visibility" dur="{self.dur}" repeatCount="indefinite" '
                f'calcMode="discrete" keyTimes="{keys}" values="{values}"/>')


def to_svg_units(mv: Movie, points: np.ndarray) -> np.ndarray:
    """Data points (..., 2) to SVG user units: display coordinates at 72 dpi, y down."""
    flat = np.asarray(points, dtype=float).reshape(-1, 2)
    xy = mv.axes.transData.transform(flat)
    xy[:, 1] = mv.figure.bbox.height - xy[:, 1]
    return xy.reshape(np.shape(points))


def _element(part, xy: np.ndarray, time: Timeline, scale: float) -> str:
    """One moving part as SVG (xy: (n, m, 2) SVG units; `scale`: SVG units per length
    unit, the same on both equal axes)."""
    a = part.artist
    if part.kind == "bar":
        return (f'<polyline points="{_points(xy[0])}" fill="none" {_paint("stroke", a.get_color(), a.get_linewidth())} '
                f'stroke-linecap="round" stroke-linejoin="round">'
                + time.animate("points", [_points(f) for f in xy]) + "</polyline>")
    if part.kind == "plate":
        return (f'<polygon points="{_points(xy[0])}" {_paint("fill", a.get_facecolor())} '
                f'{_paint("stroke", a.get_edgecolor(), a.get_linewidth())} stroke-linejoin="round">'
                + time.animate("points", [_points(f) for f in xy]) + "</polygon>")
    centre = xy[:, 0, :]
    at = f'transform="translate({_xy(centre[0, 0])} {_xy(centre[0, 1])})"'
    if part.kind == "block":
        w, h = a.get_width() * scale, a.get_height() * scale
        return (f'<rect x="{_xy(-w / 2)}" y="{_xy(-h / 2)}" width="{_xy(w)}" height="{_xy(h)}" {at} '
                f'{_paint("fill", a.get_facecolor())} {_paint("stroke", a.get_edgecolor(), a.get_linewidth())}>'
                + time.move(centre) + "</rect>")
    if part.kind == "ring":
        radius = float(np.sqrt(a.get_sizes()[0])) / 2  # a marker of area s pt^2
        return (f'<circle r="{radius:.3f}" {at} {_paint("fill", a.get_facecolor()[0])} '
                f'{_paint("stroke", a.get_edgecolor()[0], float(a.get_linewidths()[0]))}>'
                + time.move(centre) + "</circle>")
    if part.kind == "label":
        dx, dy = (float(v) for v in a.xyann)  # offset points: SVG units at 72 dpi
        weight = "font-weight: 700; " if a.get_fontweight() in ("bold", 700) else ""
        return (f'<text x="{_xy(dx)}" y="{_xy(-dy)}" {at} style="{weight}font-size: {a.get_fontsize():g}px; '
                f"font-family: 'DejaVu Sans'; text-anchor: start\">{escape(a.get_text())}"
                + time.move(centre) + "</text>")
    raise ValueError(part.kind)


def svg(mv: Movie) -> bytes:
    """The SMIL SVG of a Movie drawn at SVG_DPI (module docstring)."""
    import matplotlib

    from linkcli import __version__
    from linkcli.plots.common import STYLE
    time = Timeline(mv.frames)
    text = next(p for p in mv.parts if p.kind == "text")
    moving = [p for p in mv.parts if p.kind != "text"]
    for part in mv.parts:
        part.artist.set_visible(False)
    label = text.artist
    copies = []
    for k, words in enumerate(text.texts):  # one text a frame, drawn by matplotlib in its style
        copy = mv.axes.text(*label.get_position(), words, transform=label.get_transform(), ha=label.get_ha(),
                            va=label.get_va(), fontsize=label.get_fontsize(), color=label.get_color(),
                            zorder=label.get_zorder(), gid=f"{GROUP}-frame-{k}")
        copies.append(copy)
    title = str(mv.figure.get_suptitle() or "linkcli animation").splitlines()[0]
    buf = io.BytesIO()
    with matplotlib.rc_context(STYLE):
        mv.figure.savefig(buf, format="svg", dpi=SVG_DPI,
                          metadata={"Date": None, "Creator": f"linkcli {__version__}", "Title": title})
    page = buf.getvalue().decode("utf-8")
    for copy in copies:
        copy.remove()
    for k in range(mv.frames):
        opening = f'<g id="{GROUP}-frame-{k}">'
        on = np.arange(mv.frames) == k
        page = page.replace(opening, f'<g id="{GROUP}-frame-{k}" visibility="{"visible" if k == 0 else "hidden"}">'
                            + time.shown(on), 1)
    scale = float(np.diff(to_svg_units(mv, np.array([[0.0, 0.0], [1.0, 0.0]]))[:, 0])[0])
    body = [_element(p, to_svg_units(mv, p.points), time, scale) for p in moving]
    valid = np.asarray(mv.valid, dtype=bool)
    hide = "" if valid.all() else time.shown(valid)
    group = f'<g id="{GROUP}">{hide}\n' + "\n".join(body) + "\n</g>\n"
    end = page.rindex("</svg>")
    return (page[:end] + group + page[end:]).encode("utf-8")
