"""The animation's figure, in the still plots' style (plots.common): the header, one axes
with the drawing to scale (equal axes, labelled in the length unit), the still parts drawn
once -- ground pivots and guides, the dotted paths of the moving joints, the traced paths
(the coupler curve), the targets (points numbered, poses as body frames), the precision
positions ghosted, a legend of the links with their lengths -- and the moving parts as
`Part`s: each one artist and its data points at every frame, which the GIF/MP4 writer
moves frame by frame and the SVG writer turns into SMIL animations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from linkcli.animate.scene import Scene

FIGSIZE = (9.6, 6.4)  # inches: 960 x 640 pixels at DPI
DPI = 100
LABEL_ALL = 12  # up to this many point targets each is numbered; beyond, every k-th
BODY = 0.12  # a pose's body frame arm, as a share of the drawing's size
DASH = "\u2013"


@dataclass
class Part:
    """One moving artist: `kind` bar (Line2D), plate (Polygon), block (Rectangle centred on
    its point), ring (a one-point scatter), label (Annotation at its point) or text (a Text
    whose string changes: `texts`); `points` (n, m, 2) its data points at each frame."""

    kind: str
    artist: object
    points: np.ndarray | None = None
    texts: list[str] = field(default_factory=list)


@dataclass
class Movie:
    """A Scene drawn: the Figure, its axes, the moving parts, `valid` (n,) the frames where
    the linkage assembles (elsewhere the moving parts are hidden)."""

    figure: object
    axes: object
    parts: list[Part]
    valid: np.ndarray

    @property
    def frames(self) -> int:
        return len(self.valid)

    def pose(self, k: int) -> None:
        """Move every part to frame k."""
        show = bool(self.valid[k])
        for part in self.parts:
            part.artist.set_visible(show or part.kind == "text")
            if part.kind == "text":
                part.artist.set_text(part.texts[k])
            elif not show:
                continue
            elif part.kind == "bar":
                part.artist.set_data(part.points[k, :, 0], part.points[k, :, 1])
            elif part.kind == "plate":
                part.artist.set_xy(part.points[k])
            elif part.kind == "block":
                w, h = part.artist.get_width(), part.artist.get_height()
                part.artist.set_xy((part.points[k, 0, 0] - w / 2, part.points[k, 0, 1] - h / 2))
            elif part.kind == "ring":
                part.artist.set_offsets(part.points[k])
            elif part.kind == "label":
                part.artist.xy = tuple(part.points[k, 0])


def frame_label(scene: Scene, k: int) -> str:
    """The frame's drive value: `input angle φ = 123.5 deg` (4 significant digits)."""
    from linkcli.plots.common import num
    return f"{scene.drive.name} = {num(float(scene.shown[k]))} {scene.units.angle}"


def title(scene: Scene) -> str:
    """The drawing's title: the motion and its frames."""
    from linkcli.plots.common import num
    n = len(scene.values)
    if scene.full_turn:
        step = scene.units.from_rad(2 * math.pi / n)
        return f"A full turn in {n} frames, one every {num(float(step))} {scene.units.angle}"
    lo, hi = (num(float(scene.units.from_rad(v))) for v in scene.drive.study.arc)
    return f"From {lo} to {hi} {scene.units.angle} and back in {n} frames"


def movie(scene: Scene, dpi: float = DPI) -> Movie:
    """The figure of a Scene with every moving part at frame 0 (animated artists: a plain
    draw leaves them out, the writers draw them)."""
    import matplotlib
    from matplotlib.figure import Figure

    from linkcli.plots.common import STYLE, frame_drawing, header
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=FIGSIZE, dpi=dpi, layout="constrained")
        header(fig, scene.report)
        ax = fig.add_subplot()
        handles = _still(ax, scene)
        parts = _moving(ax, scene)
        frame_drawing(ax, scene.units.length, title(scene))
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, framealpha=0.85, fontsize=9)
    for part in parts:
        part.artist.set_animated(True)
    with matplotlib.rc_context(STYLE):
        fig.draw_without_rendering()  # the layout, once: then frozen, so that the still parts
    fig.set_layout_engine("none")  # and every frame share one data -> display map
    same_scale(ax)
    out = Movie(fig, ax, parts, np.asarray(scene.frames.valid, dtype=bool))
    out.pose(0)
    return out


def same_scale(ax) -> None:
    """Widen one axis's limits about their middle so that a length unit spans exactly as
    many pixels along x as along y (matplotlib's equal aspect tolerates 0.5 %)."""
    box = ax.get_window_extent()
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    sx, sy = box.width / (x1 - x0), box.height / (y1 - y0)
    s = min(sx, sy)
    if sx > s:
        half = 0.5 * box.width / s
        ax.set_xlim(0.5 * (x0 + x1) - half, 0.5 * (x0 + x1) + half)
    elif sy > s:
        half = 0.5 * box.height / s
        ax.set_ylim(0.5 * (y0 + y1) - half, 0.5 * (y0 + y1) + half)


def _still(ax, scene: Scene) -> list:
    """Everything that does not move; returns the legend's handles: the links (a bar with
    its length, or "varies" for a cylinder), then what was drawn."""
    from matplotlib.lines import Line2D

    from linkcli.plots.common import CURVE_COLOR, TARGET_COLOR, body_frames, draw_ground, draw_skeleton, link_color, num
    paths, lu = scene.paths, scene.units.length
    closed = scene.full_turn
    draw_ground(ax, paths, 0)
    for name, xy in paths.joints.items():
        if name in paths.ground:
            continue
        x, y = _closed(xy, closed)
        if name in paths.traced:
            ax.plot(x, y, color=CURVE_COLOR, lw=2.0, zorder=2, label=f"path of {name}")
        else:
            ax.plot(x, y, color="#888888", lw=0.9, ls=(0, (1, 2.5)), zorder=0)
    if scene.ghosts is not None:
        for k in range(len(scene.ghosts.valid)):
            draw_skeleton(ax, scene.ghosts, k, ghost=True, labels=False)
        ax.plot([], [], color="#777777", lw=1.6, alpha=0.5, label=f"positions ghosted ({len(scene.ghosts.valid)})")
    if len(scene.points):
        pts = scene.points
        ax.scatter(pts[:, 0], pts[:, 1], marker="x", s=60, color=TARGET_COLOR, linewidths=2.0, zorder=6,
                   label=f"target points ({len(pts)})")
        step = 1 if len(pts) <= LABEL_ALL else int(np.ceil(len(pts) / LABEL_ALL))
        for k in range(0, len(pts), step):
            ax.annotate(str(k + 1), tuple(pts[k]), xytext=(-12, 5), textcoords="offset points", fontsize=9.5,
                        color=TARGET_COLOR, zorder=7)
    if len(scene.poses):
        body_frames(ax, scene.poses, BODY * scene.size, color=TARGET_COLOR, lw=2.2, zorder=6)
        ax.plot([], [], color=TARGET_COLOR, lw=2.2, label=f"target poses ({len(scene.poses)})")
        for k, (x, y, _) in enumerate(scene.poses):
            ax.annotate(str(k + 1), (x, y), xytext=(-12, 5), textcoords="offset points", fontsize=9.5,
                        color=TARGET_COLOR, zorder=7)
    first = int(np.argmax(scene.frames.valid))
    handles = []
    for index, (name, joints) in enumerate(scene.frames.links.items()):
        color = link_color(name, index)
        text = f"{name} {DASH.join(joints)}"
        if len(joints) == 2:
            p, q = (np.asarray(scene.frames.joints[j][first], dtype=float) for j in joints)
            text += f" = {num(float(np.hypot(*(q - p))))} {lu}" if _rigid(scene.paths, joints) else " (varies)"
        handles.append(Line2D([], [], color=color, lw=3, label=text))
    own, _ = ax.get_legend_handles_labels()
    return handles + own


def _rigid(paths, joints) -> bool:
    """Whether the distance between two joints stays the same over the motion (a bar, not
    a cylinder) to 1e-9 of the drawing's size."""
    p, q = (np.asarray(paths.joints[j], dtype=float) for j in joints)
    d = np.hypot(*(q - p).T)
    d = d[np.isfinite(d)]
    return bool(len(d)) and float(d.max() - d.min()) <= 1e-9 * paths.size()


def _closed(xy, closed: bool):
    """x, y of a path, the first row repeated at the end of a full turn (a closed curve)."""
    xy = np.asarray(xy, dtype=float)
    if closed and len(xy):
        xy = np.concatenate([xy, xy[:1]])
    return xy[:, 0], xy[:, 1]


def _moving(ax, scene: Scene) -> list[Part]:
    """The moving parts at frame 0, in drawing order: links, slider blocks, joint rings,
    joint names, the frame's drive value."""
    from linkcli.plots.common import JOINT_SIZE, LINK_WIDTH, joint_label, link_color, plate, slider_block
    sk = scene.frames
    pts = {name: np.nan_to_num(np.asarray(xy, dtype=float)) for name, xy in sk.joints.items()}
    parts: list[Part] = []
    for index, (name, joints) in enumerate(sk.links.items()):
        color = link_color(name, index)
        data = np.stack([pts[j] for j in joints], axis=1)  # (n, m, 2)
        if len(joints) > 2:
            artist = plate(data[0], color)
            ax.add_patch(artist)
            parts.append(Part("plate", artist, data))
        else:
            (artist,) = ax.plot(data[0, :, 0], data[0, :, 1], color=color, lw=LINK_WIDTH, zorder=3)
            parts.append(Part("bar", artist, data))
    size = scene.size
    for name in sk.sliders:
        artist = slider_block(pts[name][0], size)
        ax.add_patch(artist)
        parts.append(Part("block", artist, pts[name][:, None, :]))
    moving = [name for name in sk.joints if name not in sk.ground]
    for name in moving:
        artist = ax.scatter(pts[name][:1, 0], pts[name][:1, 1], s=JOINT_SIZE, zorder=4, facecolor="white",
                            edgecolor="black", linewidths=1.0)
        parts.append(Part("ring", artist, pts[name][:, None, :]))
    for name in moving:
        parts.append(Part("label", joint_label(ax, name, tuple(pts[name][0])), pts[name][:, None, :]))
    texts = [frame_label(scene, k) for k in range(len(scene.values))]
    artist = ax.text(0.015, 0.985, texts[0], transform=ax.transAxes, ha="left", va="top", fontsize=11,
                     color="#111111", zorder=8)
    parts.append(Part("text", artist, texts=texts))
    return parts
