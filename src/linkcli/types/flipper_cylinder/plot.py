"""flipper-cylinder: the platform turning about its hinge B = (0, 0), drawn to scale in
its start and end positions (the triangle hinge B -> rod pivot A -> centre of mass G,
turned by the platform angle: X(t) = R(t - start) X_start), the cylinder from its base
pivot C to A in both, beside the cylinder force (push and pull), its moment arm about B
and the cylinder length over the sweep, from the report's `cylinder.forces` table, with
the peak force marked.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.plots.common import LINK_COLORS, drawn, frame_drawing, no_linkage, num, panels
from linkcli.units import Units

NEEDS = ("cylinder",)
PLATFORM = "#1f77b4"
CYLINDER = "#444444"
ROD = "#d62728"


def rotate(point, angle: float):
    """R(angle) p: counter-clockwise about the hinge B = (0, 0)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * point[0] - s * point[1], s * point[0] + c * point[1]])


def force_table(cyl: dict) -> dict[str, np.ndarray]:
    """Columns of the densest force table in the section (`forces_full` when present)."""
    rows = cyl.get("forces_full") or cyl.get("forces") or []
    cols = {}
    for key in ("angle", "force", "arm", "length"):
        cols[key] = np.array([r.get(key, np.nan) if r.get(key) is not None else np.nan for r in rows], dtype=float)
    return cols


def force_scale(peak: float) -> tuple[float, str]:
    """Newtons shown as kN from 10 kN up (forces are in newtons)."""
    return (1e-3, "kN") if abs(peak) >= 1e4 else (1.0, "N")


def _sweep(problem, table, u: Units) -> tuple[float, float]:
    """(start, end) platform angles in rad: the problem's [motion], else the table's ends."""
    for lo, hi in ((getattr(problem, "start", None), getattr(problem, "end", None)),):
        if lo is not None and hi is not None:
            sign = -1.0 if getattr(problem, "clockwise", False) else 1.0  # solved mirrored in x
            return sign * float(lo), sign * float(hi)
    ang = table["angle"]
    return (float(u.angles_to_rad(ang[0])), float(u.angles_to_rad(ang[-1]))) if len(ang) else (0.0, 0.0)


def centre_of_mass(problem):
    g = getattr(problem, "center_of_mass", None)
    sign = -1.0 if getattr(problem, "clockwise", False) else 1.0  # solved mirrored in x
    return None if g is None else np.array([sign * float(g[0]), float(g[1])])


def draw_platform(ax, cyl: dict, problem, start: float, end: float, lu: str) -> None:
    from matplotlib.patches import Polygon
    a0 = np.array(cyl["rod_pivot"], dtype=float)
    c = np.array(cyl["base_pivot"], dtype=float)
    g0 = centre_of_mass(problem)
    min_len = cyl.get("min_length")
    for when, turn, solid in (("start", 0.0, True), ("end", end - start, False)):
        a = rotate(a0, turn)
        pts = [np.zeros(2), a] + ([rotate(g0, turn)] if g0 is not None else [])
        ax.add_patch(Polygon(pts, closed=True, facecolor=PLATFORM, alpha=0.22 if solid else 0.08,
                             edgecolor=PLATFORM, lw=2.0 if solid else 1.4, ls="-" if solid else "--",
                             label=f"platform at {when}", zorder=2))
        # cylinder: barrel from C as long as the shortest C-A (fully closed there), rod to A
        length = float(np.hypot(*(a - c)))
        unit = (a - c) / length if length > 0 else np.zeros(2)
        barrel = c + unit * min(float(min_len) if min_len else 0.6 * length, length)
        ax.plot([c[0], barrel[0]], [c[1], barrel[1]], color=CYLINDER, lw=7.0 if solid else 5.0,
                alpha=0.9 if solid else 0.35, solid_capstyle="butt", zorder=3,
                label="cylinder barrel" if solid else None)
        ax.plot([barrel[0], a[0]], [barrel[1], a[1]], color=ROD, lw=2.4 if solid else 1.6,
                alpha=1.0 if solid else 0.45, zorder=3, label="rod" if solid else None)
        ax.scatter([a[0]], [a[1]], s=40, facecolor="white", edgecolor="black", zorder=5)
        ax.annotate(f"A ({when})", (float(a[0]), float(a[1])), xytext=(7, 5), textcoords="offset points",
                    fontsize=10, fontweight="bold" if solid else "normal")
        if g0 is not None:
            gpt = rotate(g0, turn)
            ax.scatter([gpt[0]], [gpt[1]], marker="o", s=60, facecolor="black" if solid else "white",
                       edgecolor="black", zorder=5)
            ax.annotate(f"G ({when})", (float(gpt[0]), float(gpt[1])), xytext=(7, -12), textcoords="offset points",
                        fontsize=10, fontweight="bold" if solid else "normal")
    # the path of A over the sweep
    t = np.linspace(0.0, end - start, 181)
    ct, st = np.cos(t), np.sin(t)
    ax.plot(ct * a0[0] - st * a0[1], st * a0[0] + ct * a0[1], color="#888888", lw=0.9, ls=(0, (1, 2.5)),
            label="path of A", zorder=1)
    size = max(float(np.hypot(*a0)), float(np.hypot(*c)), 1.0)
    s = 0.05 * size
    for name, (x, y) in (("B (hinge)", (0.0, 0.0)), ("C", (float(c[0]), float(c[1])))):
        ax.add_patch(Polygon([(x, y), (x - 0.6 * s, y - s), (x + 0.6 * s, y - s)], closed=True,
                             facecolor="white", edgecolor=LINK_COLORS["ground"], hatch="///", zorder=1))
        ax.scatter([x], [y], s=70, color="black", zorder=5)
        ax.annotate(name, (x, y), xytext=(7, 6), textcoords="offset points", fontsize=10, fontweight="bold")
    ax.legend(loc="best", framealpha=0.85)


def draw(fig, result) -> None:
    report, problem = drawn(result), result.problem
    u, ax_geo, (ax_f, ax_arm, ax_len) = panels(fig, result, 3, [1.0, 1.2])
    au, lu = u.angle, u.length
    cyl = report.get("cylinder")
    if not cyl or "rod_pivot" not in cyl or "base_pivot" not in cyl:
        no_linkage(ax_geo, "no cylinder in the report")
        for ax in (ax_f, ax_arm, ax_len):
            ax.set_axis_off()
        return
    table = force_table(cyl)
    start, end = _sweep(problem, table, u)
    draw_platform(ax_geo, cyl, problem, start, end, lu)
    frame_drawing(ax_geo, lu, f"Platform and cylinder to scale, start {num(float(u.from_rad(start)))} {au} "
                              f"and end {num(float(u.from_rad(end)))} {au}")

    ang, force = table["angle"], table["force"]
    peak = cyl.get("peak_force")
    peak = float(peak) if peak is not None else (float(np.nanmax(np.abs(force))) if len(force) else 0.0)
    k, fu = force_scale(peak)
    if len(ang):
        ax_f.axhline(0.0, color="#444444", lw=0.8)
        ax_f.plot(ang, force * k, color=CYLINDER, lw=1.9, label="cylinder force")
        ax_f.fill_between(ang, 0.0, force * k, where=force >= 0, color="#1f77b4", alpha=0.18, lw=0,
                          label="push (rod in compression)")
        ax_f.fill_between(ang, 0.0, force * k, where=force < 0, color="#d62728", alpha=0.18, lw=0,
                          label="pull (rod in tension)")
    at = cyl.get("peak_angle")
    kind = cyl.get("peak_kind", "push")
    if at is not None:
        signed = peak if kind == "push" else -peak
        ax_f.scatter([at], [signed * k], s=60, color="black", zorder=5)
        right = len(ang) and float(at) > 0.5 * (float(np.nanmin(ang)) + float(np.nanmax(ang)))
        ax_f.annotate(f"peak {num(peak * k)} {fu} ({kind}) at {num(float(at))} {au}", (float(at), signed * k),
                      xytext=(-8 if right else 8, -14 if signed > 0 else 8), textcoords="offset points",
                      ha="right" if right else "left", fontsize=9.5)
    ax_f.set_ylabel(f"force ({fu})")
    ax_f.set_title("Cylinder force over the sweep (static balance)")
    ax_f.legend(loc="best", framealpha=0.85)

    ax_arm.plot(ang, table["arm"], color="#2ca02c", lw=1.9, label="moment arm about B")
    ax_arm.set_ylabel(f"moment arm ({lu})")
    ax_arm.legend(loc="best", framealpha=0.85)

    ax_len.plot(ang, table["length"], color="#9467bd", lw=1.9, label="cylinder length C-A")
    for key, style in (("min_length", ":"), ("max_length", "--")):
        if cyl.get(key) is not None:
            ax_len.axhline(float(cyl[key]), color="#777777", lw=1.0, ls=style,
                           label=f"{key.replace('_', ' ')} {num(float(cyl[key]))} {lu}")
    if cyl.get("stroke") is not None:
        ax_len.set_title(f"stroke {num(float(cyl['stroke']))} {lu}", fontsize=10, loc="right")
    ax_len.set_ylabel(f"length ({lu})")
    ax_len.set_xlabel(f"platform angle ({au})")
    ax_len.legend(loc="best", framealpha=0.85)
    for ax in (ax_f, ax_arm):
        ax.tick_params(labelbottom=False)
    if len(ang):
        ax_len.set_xlim(float(np.nanmin(ang)), float(np.nanmax(ang)))
