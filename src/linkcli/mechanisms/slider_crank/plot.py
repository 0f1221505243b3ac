"""A slider-crank result (linkage analysis or precision positions): the mechanism to scale
with its guide at its worst transmission angle (the coupler curve when there is a coupler
point, the target positions when there are any) beside its motion over the crank's range:
slider travel s(phi), slider velocity and acceleration at the file's input speed, and the
transmission angle against its recommended lower limit. Everything is drawn from the
report handed in (linkage lengths, motion study, positions), through the closed forms of
`kinematics`; nothing is loaded or solved here.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.columns import TRANSMISSION_BAND
from linkcli.mechanisms.slider_crank import kinematics as sc
from linkcli.plots.common import (
    BAND_COLOR,
    CURVE_COLOR,
    LINK_COLORS,
    TARGET_COLOR,
    angle_ticks,
    drawn,
    frame_drawing,
    no_linkage,
    num,
    panels,
    robust_ylim,
)
from linkcli.units import Units

SAMPLES = 720


def study_grid(a, b, e, near=None, n: int = SAMPLES):
    """Crank angles of the study (rad): 0..360 deg for a turning crank, else the centres of
    n equal cells of the arc (its ends are limit positions); None if it never assembles."""
    arcs = sc.input_arcs(a, b, e)
    if arcs is None:
        return np.linspace(0.0, 2 * math.pi, n + 1)
    if not arcs:
        return None
    lo, hi = sc.choose_arc(arcs, near)
    return lo + (np.arange(n) + 0.5) * (sc.arc_sweep(lo, hi) / n)


def _block(ax, s, e, w, h, alpha=1.0):
    from matplotlib.patches import Rectangle
    ax.add_patch(Rectangle((s - w / 2, e - h / 2), w, h, facecolor="#dddddd", edgecolor="black",
                           alpha=alpha, zorder=2))


def draw_mechanism(ax, a, b, e, branch, phi_show, grid, u: Units, coupler_point=None, ghosts=()):
    """Crank circle, the guide (dashed, at y = e, over the slider's travel), the crank and rod
    at phi_show (ghosts faint), the slider block, and the coupler curve of P."""
    from matplotlib.lines import Line2D
    p = sc.pose(a, b, e, grid, branch)
    s = p.slider[np.isfinite(p.slider)]
    s_lo, s_hi = float(s.min()), float(s.max())
    ax.plot(a * np.cos(grid), a * np.sin(grid), color="#888888", lw=0.9, ls=(0, (1, 2.5)), zorder=0)
    pad = 0.15 * b
    ax.plot([min(s_lo - pad, -a), s_hi + pad], [e, e], color=LINK_COLORS["ground"], lw=1.4, ls=(0, (6, 3)))
    ax.plot([s_lo, s_hi], [e, e], color="#ff7f0e", lw=5, alpha=0.35, solid_capstyle="butt", zorder=1)
    if coupler_point is not None:
        x, y = sc.coupler_point(a, p, *coupler_point)
        ax.plot(x, y, color=CURVE_COLOR, lw=1.8, zorder=1)
    for phi, ghost in [(g, True) for g in ghosts] + [(phi_show, False)]:
        q = sc.pose(a, b, e, np.array([phi]), branch)
        if not bool(q.valid[0]):
            continue
        xa, ya = a * math.cos(phi), a * math.sin(phi)
        sb = float(q.slider[0])
        alpha, lw = (0.3, 1.8) if ghost else (1.0, 3.2)
        ax.plot([0, xa], [0, ya], color=LINK_COLORS["input"], lw=lw, alpha=alpha, zorder=3)
        ax.plot([xa, sb], [ya, e], color=LINK_COLORS["coupler"], lw=lw, alpha=alpha, zorder=3)
        _block(ax, sb, e, 0.14 * b, 0.08 * b, alpha)
        ax.scatter([xa, sb], [ya, e], s=40, zorder=4, facecolor="white", edgecolor="black", alpha=alpha)
        if coupler_point is not None and not ghost:
            px, py = sc.coupler_point(a, q, *coupler_point)
            ax.plot([xa, float(px[0]), sb], [ya, float(py[0]), e], color=LINK_COLORS["coupler"], lw=1.2,
                    alpha=0.5, zorder=3)
            ax.scatter([px], [py], s=40, marker="D", color=CURVE_COLOR, zorder=5)
    ax.scatter([0], [0], s=70, zorder=4, color="black")
    ax.annotate("A0", (0, 0), xytext=(7, 6), textcoords="offset points", fontweight="bold")
    lu = u.length
    handles = [Line2D([], [], color=LINK_COLORS["input"], lw=3, label=f"crank a = {num(a)} {lu}"),
               Line2D([], [], color=LINK_COLORS["coupler"], lw=3, label=f"rod b = {num(b)} {lu}"),
               Line2D([], [], color=LINK_COLORS["ground"], lw=1.4, ls=(0, (6, 3)),
                      label=f"guide at offset e = {num(e)} {lu}"),
               Line2D([], [], color="#ff7f0e", lw=5, alpha=0.35, label=f"slider travel {num(s_hi - s_lo)} {lu}")]
    if coupler_point is not None:
        handles.append(Line2D([], [], color=CURVE_COLOR, lw=1.8, label="coupler curve of P"))
    ax.legend(handles=handles, loc="best", framealpha=0.85)


def draw(fig, result) -> None:
    report = drawn(result)
    u, ax_link, (ax_s, ax_v, ax_a, ax_mu) = panels(fig, result, 4, [1.0, 1.25])
    au, lu = u.angle, u.length
    lk = report["linkage"]
    a, b, e = float(lk["input"]), float(lk["coupler"]), float(lk["offset"])
    branch = lk.get("branch", "open")
    cp = tuple(lk["coupler_point"]) if "coupler_point" in lk else None
    positions = report.get("positions") or []
    targets = np.array([float(u.angles_to_rad(r["input"])) for r in positions]) if positions else np.zeros(0)
    grid = study_grid(a, b, e, near=float(targets[0]) if len(targets) else None)
    if grid is None:
        no_linkage(ax_link, "the slider-crank cannot assemble at any crank angle")
        for ax in (ax_s, ax_v, ax_a, ax_mu):
            ax.set_axis_off()
        return
    p = sc.pose(a, b, e, grid, branch)
    speed = report.get("motion", {}).get("input_speed")
    w2 = float(u.angles_to_rad(speed)) if speed else float(u.angles_to_rad(1.0))
    vs, _ = sc.velocities(a, b, p, w2)
    acc, _ = sc.accelerations(a, b, p, w2)
    x = u.from_rad(grid)
    mu = u.from_rad(p.mu)
    worst = int(np.nanargmin(np.where(p.valid, p.mu, np.nan)))
    show = float(targets[0]) if len(targets) else float(grid[worst])
    draw_mechanism(ax_link, a, b, e, branch, show, grid, u, cp, ghosts=tuple(targets[1:]))
    what = ("first target position" if len(targets)
            else f"worst transmission angle, \u03bc = {num(float(mu[worst]))} {au}")
    frame_drawing(ax_link, lu, f"Slider-crank to scale at crank angle {num(float(u.from_rad(sc.wrap(show))))} {au}\n({what})")

    ax_s.plot(x, np.where(p.valid, p.slider, np.nan), color="#ff7f0e", lw=1.8, label="slider position s")
    if positions:
        ax_s.scatter([r["input"] for r in positions], [r["target"] for r in positions], marker="x", s=60,
                     color=TARGET_COLOR, zorder=4, label="target positions")
    ax_s.set_ylabel(f"s ({lu})")
    ax_s.set_title(f"Motion at a constant crank speed of {num(float(u.from_rad(w2)))} {au}/s")
    ax_s.legend(loc="best", framealpha=0.85)
    fin = lambda v: np.where(np.isfinite(v), v, np.nan)  # noqa: E731
    ax_v.plot(x, fin(vs), color=LINK_COLORS["coupler"], lw=1.8, label="slider velocity")
    ax_v.set_ylabel(f"v ({lu}/s)")
    ax_a.plot(x, fin(acc), color=LINK_COLORS["output"], lw=1.8, label="slider acceleration")
    ax_a.set_ylabel(f"a ({lu}/s\u00b2)")
    for ax, v in ((ax_v, vs), (ax_a, acc)):
        ax.axhline(0.0, color="#777777", lw=0.8)
        ax.legend(loc="upper right", framealpha=0.85)
        if robust_ylim(ax, v):
            ax.text(0.01, 0.03, "clipped: values grow without bound near the limit positions",
                    transform=ax.transAxes, fontsize=9, color="#555555")
    lo = TRANSMISSION_BAND[0] if au == "deg" else math.radians(TRANSMISSION_BAND[0])
    ax_mu.axhspan(lo, float(u.from_rad(math.pi / 2)), color=BAND_COLOR, alpha=0.12, lw=0,
                  label=f"recommended \u2265 {num(lo)} {au}")
    ax_mu.plot(x, mu, color="#1f77b4", lw=1.8, label="transmission angle \u03bc")
    ax_mu.scatter([x[worst]], [mu[worst]], color="black", zorder=4, s=28)
    ax_mu.set_ylim(0.0, 1.15 * float(u.from_rad(math.pi / 2)))
    ax_mu.set_ylabel(f"\u03bc ({au})")
    ax_mu.set_xlabel(f"crank angle \u03c6 ({au})")
    ax_mu.legend(loc="lower right", framealpha=0.85)
    for ax in (ax_s, ax_v, ax_a):
        ax.tick_params(labelbottom=False)
    for ax in (ax_s, ax_v, ax_a, ax_mu):
        ax.axvline(float(x[worst]), color="#777777", lw=0.9, ls=":")  # the worst transmission angle
    ax_mu.set_xlim(float(x[0]), float(x[-1]))
    angle_ticks(ax_mu, u)
