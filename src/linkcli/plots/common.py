"""What every plot shares: the style, the report's units, any mechanism drawn to scale from
its skeleton (mechanisms.protocol.Skeleton), and the figure header. A mechanism's own
drawings live in its home (`mechanisms/<name>/plot.py`, the four-bar's `drawing.py`).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.units import Units

# rcParams for every figure (applied with rc_context, never globally): text stays text
# in SVG, ids are salted with a constant, so two runs write identical bytes.
STYLE = {
    "svg.fonttype": "none",
    "svg.hashsalt": "linkcli",
    "font.family": "DejaVu Sans",
    "font.size": 10.5,
    "axes.titlesize": 11.5,
    "axes.labelsize": 10.5,
    "legend.fontsize": 9.5,
    "figure.titlesize": 14,
    "figure.titleweight": "bold",
    "axes.grid": True,
    "grid.alpha": 0.35,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.solid_capstyle": "round",
}
FIGSIZE = (13.0, 7.0)  # inches
DPI = 100  # PNG pixels per inch: 1300 x 700, read at 100 % zoom

LINK_COLORS = {"input": "#1f77b4", "coupler": "#d62728", "output": "#2ca02c", "ground": "#555555"}
# links of other names (a drawn linkage's), in the order the skeleton lists them
MORE_COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
               "#7f7f7f", "#9467bd")
TARGET_COLOR = "#111111"
CURVE_COLOR = "#9467bd"
BAND_COLOR = "#2ca02c"
SLIDER_COLOR = "#ff7f0e"
# a skeleton's marks (draw_skeleton, and the animations that move them): line widths in
# points, marker areas in points^2, the slider block's width as a share of the drawing
LINK_WIDTH = 3.2
GHOST_WIDTH = 1.6
GHOST_ALPHA = 0.28
PLATE_ALPHA = 0.18
JOINT_SIZE = 42
GHOST_JOINT_SIZE = 22
PIVOT_SIZE = 70
SLIDER_SHARE = 0.12
SLIDER_ALPHA = 0.7


def num(v: float, digits: int = 4) -> str:
    """A number for a label: `digits` significant digits, plain (no exponent) from 1e-3
    to 1e6, no trailing zeros."""
    v = float(v)
    if v == 0.0 or not math.isfinite(v):
        return f"{v:g}"
    mag = math.floor(math.log10(abs(v)))
    if not -3 <= mag < 6:
        return f"{v:.{digits}g}"
    text = f"{v:.{max(digits - 1 - mag, 0)}f}"
    return text.rstrip("0").rstrip(".") if "." in text else text


def robust_ylim(ax, *series, spread: float = 4.0) -> bool:
    """Keep an axis readable when a few values shoot off (a toggle, where a constant input
    speed asks for an infinite output speed): if the largest |value| exceeds `spread`
    times the 95th percentile, zoom on the 5..95 % range. Returns whether it zoomed."""
    v = np.concatenate([np.asarray(x, dtype=float).ravel() for x in series])
    v = v[np.isfinite(v)]
    if v.size == 0:
        return False
    q = float(np.percentile(np.abs(v), 95))
    if q == 0.0 or float(np.max(np.abs(v))) <= spread * q:
        return False
    lo, hi = (float(x) for x in np.percentile(v, [5, 95]))
    pad = 0.3 * max(hi - lo, q)
    ax.set_ylim(lo - pad, hi + pad)
    return True


def ground_mark(ax, x, y, s, color):
    """A hatched ground triangle under a fixed pivot (size s in length units)."""
    from matplotlib.patches import Polygon
    tri = [(x, y), (x - 0.6 * s, y - s), (x + 0.6 * s, y - s)]
    ax.add_patch(Polygon(tri, closed=True, facecolor="white", edgecolor=color, hatch="///",
                         lw=1.0, zorder=1))


def body_frames(ax, poses, arm, **style) -> None:
    """Body frames at poses (n, 3) (angles rad): an L, the x axis `arm` long and a y axis
    half as long."""
    for x, y, t in poses:
        c, s = np.cos(t), np.sin(t)
        ax.plot([x + 0.5 * arm * -s, x, x + arm * c], [y + 0.5 * arm * c, y, y + arm * s], **style)


def frame_drawing(ax, length_unit: str, title: str) -> None:
    """Equal axes (to scale), labelled in the length unit, with a little margin."""
    from matplotlib.ticker import MaxNLocator
    ax.set_aspect("equal", adjustable="datalim")
    ax.xaxis.set_major_locator(MaxNLocator(nbins=7))
    ax.yaxis.set_major_locator(MaxNLocator(nbins=9))
    ax.margins(0.08)
    ax.set_xlabel(f"x ({length_unit})")
    ax.set_ylabel(f"y ({length_unit})")
    ax.set_title(title)


def drawn(result) -> dict:
    """The report a plot draws from: the Result's `drawing` (the report with the sections
    a plot needs) or its report."""
    return result.drawing if result.drawing is not None else result.report


def header(fig, report: dict) -> None:
    """Figure title: the problem's title (or file), its type and status."""
    title = report.get("title") or report.get("file") or "linkage"
    status = report.get("status", "ok")
    line2 = f"{report.get('type', '')}, status {status}"
    if report.get("file") and report.get("title"):
        line2 += f"  ({report['file']})"
    text = f"{title}\n{line2}"
    if status != "ok" and report.get("message"):
        text += f"\n{report['message']}"
    fig.suptitle(text, fontsize=13)


def panels(fig, result, right: int, width_ratios, height_ratios=None):
    """The figure header, one tall axes on the left (the drawing to scale) and `right`
    stacked axes on the right sharing their x axis -> (the problem's Units, left axes,
    right axes)."""
    header(fig, drawn(result))
    gs = fig.add_gridspec(right, 2, width_ratios=width_ratios, height_ratios=height_ratios)
    left = fig.add_subplot(gs[:, 0])
    first = fig.add_subplot(gs[0, 1])
    return result.problem.meta.units, left, [first] + [fig.add_subplot(gs[i, 1], sharex=first) for i in range(1, right)]


def no_linkage(ax, text: str) -> None:
    """An axes that says why there is nothing to draw."""
    ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, wrap=True)
    ax.set_axis_off()


def angle_ticks(ax, units: Units, axis: str = "x") -> None:
    """Ticks every 45 deg on a degree axis that spans at least 180 deg."""
    if units.angle != "deg":
        return
    from matplotlib.ticker import MultipleLocator
    lo, hi = (ax.get_xlim() if axis == "x" else ax.get_ylim())
    if abs(hi - lo) >= 180:
        (ax.xaxis if axis == "x" else ax.yaxis).set_major_locator(MultipleLocator(45 if abs(hi - lo) <= 400 else 90))


def link_color(name: str, index: int) -> str:
    """A link's colour: the four-bar's names keep theirs, others cycle through MORE_COLORS."""
    return LINK_COLORS.get(name, MORE_COLORS[index % len(MORE_COLORS)])


def joint_places(sk, k: int) -> dict[str, tuple[float, float]]:
    """Row k of a Skeleton: joint name -> (x, y)."""
    return {name: tuple(float(v) for v in np.asarray(xy)[k]) for name, xy in sk.joints.items()}


def guide_ends(sk, guide, margin: float = 0.15) -> np.ndarray:
    """(2, 2) ends of a slider guide drawn over the travel of its joint in the Skeleton's
    rows, `margin` x the drawing's size beyond it at each end."""
    track = np.asarray(sk.joints[guide.joint], dtype=float).reshape(-1, 2)
    track = track[np.all(np.isfinite(track), axis=1)]
    u = np.array([math.cos(guide.angle), math.sin(guide.angle)])
    s = (track - np.asarray(guide.point)) @ u if len(track) else np.zeros(1)
    pad = margin * sk.size()
    return np.asarray(guide.point) + np.outer([float(s.min()) - pad, float(s.max()) + pad], u)


def draw_ground(ax, sk, k: int = 0, *, labels: bool = True) -> None:
    """The fixed parts of a Skeleton (row k for the pivots' places): guides dashed over the
    travel of their joints in the rows given, hatched marks and black discs at the ground
    pivots, their names unless `labels` is False."""
    size = sk.size()
    at = joint_places(sk, k)
    for guide in sk.guides:
        ends = guide_ends(sk, guide)
        ax.plot(ends[:, 0], ends[:, 1], color=LINK_COLORS["ground"], lw=1.2, ls=(0, (6, 3)), zorder=1)
    for name in sk.ground:
        ground_mark(ax, *at[name], 0.06 * size, LINK_COLORS["ground"])
    fixed = [at[name] for name in sk.ground]
    ax.scatter([p[0] for p in fixed], [p[1] for p in fixed], s=PIVOT_SIZE, zorder=4, facecolor="black", edgecolor="black")
    if labels:
        for name in sk.ground:
            joint_label(ax, name, at[name])


def plate(pts, color: str, alpha: float = 1.0, lw: float = LINK_WIDTH):
    """A link carrying three or more joints: a translucent polygon (PLATE_ALPHA) edged in
    its colour, 0.6 lw wide; `alpha` fades both (a ghost)."""
    from matplotlib.colors import to_rgba
    from matplotlib.patches import Polygon
    return Polygon(pts, closed=True, zorder=2, facecolor=to_rgba(color, PLATE_ALPHA * alpha),
                   edgecolor=to_rgba(color, alpha), lw=lw * 0.6)


def slider_block(xy, size: float, alpha: float = 1.0):
    """A slider's block centred on xy: SLIDER_SHARE x `size` wide, two thirds as tall."""
    from matplotlib.patches import Rectangle
    w = SLIDER_SHARE * size
    return Rectangle((xy[0] - w / 2, xy[1] - w / 3), w, 2 * w / 3, facecolor=SLIDER_COLOR, edgecolor="black",
                     alpha=SLIDER_ALPHA * alpha, lw=1.0, zorder=3)


def joint_label(ax, name: str, xy):
    """A joint's name beside it (bold, 7 pt right and 6 pt up)."""
    return ax.annotate(name, xy, xytext=(7, 6), textcoords="offset points", fontsize=10, fontweight="bold", zorder=5)


def draw_skeleton(ax, sk, k: int, *, ghost: bool = False, labels: bool = True) -> None:
    """Row k of a mechanism's Skeleton to scale: guides (dashed), ground pivots (hatched),
    each link as a bar (two joints) or a translucent plate (three or more), slider blocks,
    joints as rings; names beside the joints unless `labels` is False."""
    if not bool(np.asarray(sk.valid)[k]):
        return
    alpha = GHOST_ALPHA if ghost else 1.0
    lw = GHOST_WIDTH if ghost else LINK_WIDTH
    size = sk.size()
    at = joint_places(sk, k)
    if not ghost:
        draw_ground(ax, sk, k, labels=labels)
    for index, (name, joints) in enumerate(sk.links.items()):
        color = link_color(name, index)
        pts = [at[j] for j in joints]
        if len(pts) > 2:
            ax.add_patch(plate(pts, color, alpha, lw))
        else:
            ax.plot([p[0] for p in pts], [p[1] for p in pts], color=color, lw=lw, alpha=alpha, zorder=3)
    for name in sk.sliders:
        ax.add_patch(slider_block(at[name], size, alpha))
    moving = [p for name, p in at.items() if name not in sk.ground]
    ax.scatter([p[0] for p in moving], [p[1] for p in moving], s=GHOST_JOINT_SIZE if ghost else JOINT_SIZE, zorder=4,
               facecolor="white", edgecolor="black", linewidths=1.0, alpha=alpha)
    if labels and not ghost:
        for name, xy in at.items():
            if name not in sk.ground:
                joint_label(ax, name, xy)
