"""quick-return: the linkage to scale at its two dead centres (crank and coupler collinear:
the rocker's extremes or the slider's ends), beside the family curve (worst transmission
angle against the free parameter, the chosen member marked, the window shaded) and the
transmission angle over the chosen member's full turn."""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.four_bar.drawing import Geometry, draw_linkage, joint_paths, link_legend
from linkcli.mechanisms.slider_crank import kinematics as sc
from linkcli.plots.common import BAND_COLOR, LINK_COLORS, angle_ticks, drawn, frame_drawing, header, no_linkage, num
from linkcli.units import Units

from . import family

NEEDS = ("linkage", "family", "design")
CURVE_ROWS = 400


def draw(fig, result) -> None:
    report, problem = drawn(result), result.problem
    header(fig, report)
    gs = fig.add_gridspec(2, 2, width_ratios=[1.0, 1.15])
    ax_link, ax_fam, ax_mu = fig.add_subplot(gs[:, 0]), fig.add_subplot(gs[0, 1]), fig.add_subplot(gs[1, 1])
    u = problem.meta.units
    if "linkage" not in report:
        for ax in (ax_link, ax_fam, ax_mu):
            no_linkage(ax, "no linkage in the report")
        return
    slider = report["linkage"].get("mechanism") == "slider-crank"
    phi = np.linspace(0.0, kin.TWO_PI, 721)
    if slider:
        mu = draw_slider(ax_link, report, u, phi)
    else:
        mu = draw_crank_rocker(ax_link, result, u, phi)
    draw_family(ax_fam, report, problem, u)
    window = getattr(problem, "transmission", None)
    if window is not None:
        lo, hi = (float(u.from_rad(w)) for w in window)
        ax_mu.axhspan(lo, hi, color=BAND_COLOR, alpha=0.12, lw=0, label=f"window {num(lo)}..{num(hi)} {u.angle}")
    x = u.from_rad(phi)
    ax_mu.plot(x, u.from_rad(mu), color="#1f77b4", lw=1.8, label="transmission angle \u03bc")
    ax_mu.set_xlim(float(x[0]), float(x[-1]))
    ax_mu.set_ylim(0.0, float(u.from_rad(math.pi / 2 if slider else math.pi)))
    ax_mu.set_xlabel(f"input angle \u03c6 ({u.angle})")
    ax_mu.set_ylabel(f"\u03bc ({u.angle})")
    ax_mu.set_title("Transmission angle of the chosen member over the full turn")
    ax_mu.legend(loc="best", framealpha=0.85)
    angle_ticks(ax_mu, u)


def draw_crank_rocker(ax, result, u: Units, phi) -> np.ndarray:
    """The four-bar at the extended dead centre (solid) and the folded one (faint); returns
    mu over phi."""
    report = drawn(result)
    geo = Geometry.of(result)
    mot = geo.motion()
    joint_paths(ax, geo, phi)
    ext, fold = mot.toggle_inputs
    draw_linkage(ax, geo, fold, ghost=True)
    draw_linkage(ax, geo, ext)
    link_legend(ax, geo, u.length)
    swing = report.get("design", {}).get("swing", u.from_rad(mot.output_swing))
    frame_drawing(ax, u.length, f"Dead centres: extended (solid) at input {num(float(u.from_rad(kin.wrap(ext))))} "
                                f"{u.angle}, folded (faint) at {num(float(u.from_rad(kin.wrap(fold))))} {u.angle}\n"
                                f"rocker swing {num(float(swing))} {u.angle} between them")
    return geo.pose(phi).mu


def draw_slider(ax, report: dict, u: Units, phi) -> np.ndarray:
    """Crank circle, slider line, and the slider-crank at its two dead centres (extended
    solid, folded faint); returns mu over phi."""
    from matplotlib.lines import Line2D
    lk = report["linkage"]
    a, b, e = float(lk["input"]), float(lk["coupler"]), float(lk["offset"])
    dc = {k: float(v) for k, v in sc.dead_centres(a, b, e, "open").items()}
    s_lo, s_hi = sorted((dc["folded_slider"], dc["extended_slider"]))
    ax.plot(a * np.cos(phi), a * np.sin(phi), color="#888888", lw=0.9, ls=(0, (1, 2.5)), zorder=0)
    pad = 0.25 * (s_hi - s_lo)
    ax.plot([min(s_lo - pad, -a), s_hi + pad], [e, e], color=LINK_COLORS["ground"], lw=1.4, ls=(0, (6, 3)))
    for name, ghost in (("folded", True), ("extended", False)):
        ang, s = dc[f"{name}_input"], dc[f"{name}_slider"]
        xa, ya = a * math.cos(ang), a * math.sin(ang)
        alpha, lw = (0.3, 1.8) if ghost else (1.0, 3.2)
        ax.plot([0, xa], [0, ya], color=LINK_COLORS["input"], lw=lw, alpha=alpha, zorder=3)
        ax.plot([xa, s], [ya, e], color=LINK_COLORS["coupler"], lw=lw, alpha=alpha, zorder=3)
        w, h = 0.12 * b, 0.07 * b
        ax.add_patch(_block(s, e, w, h, alpha))
        ax.scatter([xa, s], [ya, e], s=40, zorder=4, facecolor="white", edgecolor="black", alpha=alpha)
    ax.scatter([0], [0], s=70, zorder=4, color="black")
    ax.annotate("A0", (0, 0), xytext=(7, 6), textcoords="offset points", fontweight="bold")
    handles = [Line2D([], [], color=LINK_COLORS["input"], lw=3, label=f"crank a = {num(a)} {u.length}"),
               Line2D([], [], color=LINK_COLORS["coupler"], lw=3, label=f"rod b = {num(b)} {u.length}"),
               Line2D([], [], color=LINK_COLORS["ground"], lw=1.4, ls=(0, (6, 3)),
                      label=f"slider line, offset e = {num(e)} {u.length}")]
    ax.legend(handles=handles, loc="best", framealpha=0.85)
    frame_drawing(ax, u.length, f"Dead centres: extended (solid) and folded (faint)\n"
                                f"stroke {num(s_hi - s_lo)} {u.length} between them")
    return sc.pose(a, b, e, phi, "open").mu


def _block(s, e, w, h, alpha):
    from matplotlib.patches import Rectangle
    return Rectangle((s - w / 2, e - h / 2), w, h, facecolor="#dddddd", edgecolor="black",
                     alpha=alpha, zorder=2)


def draw_family(ax, report: dict, problem, u: Units) -> None:
    """Worst transmission angle across the family: a dense curve from the problem (the
    report's rows when there is no problem), the report's rows as dots, the chosen member."""
    rows = report.get("family") or []
    design = report.get("design", {})
    curve = _dense(problem)
    if curve is not None:
        x, y = curve
        ax.plot(x, u.from_rad(y), color="#9467bd", lw=1.8, label="worst transmission angle of each member")
    if rows:
        ax.scatter([r["parameter"] for r in rows if not r["chosen"]],
                   [r["worst_transmission"] for r in rows if not r["chosen"]],
                   s=14, color="#555555", zorder=3, label="rows of the family table")
    if "parameter" in design:
        px, py = design["parameter"], design["worst_transmission"]
        ax.scatter([px], [py], s=80, marker="*", color="#d62728", zorder=4,
                   label=f"chosen: parameter {num(px)}, {num(py)} {u.angle}")
    window = getattr(problem, "transmission", None)
    if window is not None:
        lo = float(u.from_rad(window[0]))  # the worst angle is min(mu, 180 - mu): only lo bounds it alone
        ax.axhline(lo, color=BAND_COLOR, lw=1.0, ls="--", label=f"window lower limit {num(lo)} {u.angle}")
    ax.set_ylim(bottom=0.0)
    ax.set_xlabel("free parameter (see docs/quick_return.md)")
    ax.set_ylabel(f"worst \u03bc ({u.angle})")
    ax.set_title("The family: worst transmission angle over the full turn")
    ax.legend(loc="best", framealpha=0.85, fontsize=8.5)


def _dense(problem):
    """(parameter, worst transmission in rad) of CURVE_ROWS members, or None."""
    if getattr(problem, "mechanism", None) == "crank-rocker":
        t = family.crank_rocker_family(problem.time_ratio, problem.swing, problem.scale,
                                       rows=CURVE_ROWS, bounds=problem.bounds)
    elif getattr(problem, "mechanism", None) == "slider-crank":
        bounds = problem.bounds if problem.offset is None else {}
        t = family.slider_crank_family(problem.time_ratio, problem.stroke, rows=CURVE_ROWS, bounds=bounds)
    else:
        return None
    x = np.asarray(t["parameter"], dtype=float)
    y = np.asarray(t["worst_transmission"], dtype=float)
    gaps = np.flatnonzero((x[1:] > 0) != (x[:-1] > 0))  # two pieces of the family: no line across
    if gaps.size:
        x, y = np.insert(x, gaps + 1, np.nan), np.insert(y, gaps + 1, np.nan)
    return x, y
