"""A four-bar's linkage analysis: the four-bar to scale at its worst transmission angle (with the
coupler curve when there is a coupler point) beside its motion study over the input's
range: angular velocity and acceleration of coupler and output at the file's constant
input speed (closed forms of kinematics.velocities / accelerations, Norton ch. 6-7),
and the transmission angle against its recommended band (40..140 deg).
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.columns import TRANSMISSION_BAND
from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.four_bar.drawing import Geometry, draw_linkage, joint_paths, link_legend
from linkcli.plots.common import (
    BAND_COLOR,
    CURVE_COLOR,
    LINK_COLORS,
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


def study_grid(mot: kin.Motion, n: int = SAMPLES) -> np.ndarray:
    """Input angles of the study: 0..360 deg for a full turn; for a rocking input the
    centres of n equal cells of its arc (the ends are toggles, where a constant input
    speed asks for an infinite output speed)."""
    if mot.input_full_turn:
        return np.linspace(0.0, kin.TWO_PI, n + 1)
    lo, hi = mot.input_arc
    return lo + (np.arange(n) + 0.5) * ((hi - lo) / n)


def input_speed(problem, units: Units) -> float:
    """rad/s: the problem's [motion] input_speed, else 1 angle unit per second (as analyse)."""
    speed = getattr(problem, "input_speed", None)
    return float(speed) if speed else float(units.angles_to_rad(1.0))


def finite(x):
    x = np.asarray(x, dtype=float)
    return np.where(np.isfinite(x), x, np.nan)


def draw(fig, result) -> None:
    report, problem = drawn(result), result.problem
    u, ax_link, (ax_w, ax_a, ax_mu) = panels(fig, result, 3, [1.0, 1.25])
    au, lu = u.angle, u.length
    if "linkage" not in report:
        no_linkage(ax_link, "no linkage in the report")
        for ax in (ax_w, ax_a, ax_mu):
            ax.set_axis_off()
        return
    geo = Geometry.of(result)
    mot = geo.motion()
    if not mot.assembles:
        no_linkage(ax_link, "the linkage cannot assemble at any input angle")
        for ax in (ax_w, ax_a, ax_mu):
            ax.set_axis_off()
        return
    phi = study_grid(mot)
    p = geo.pose(phi)
    w2 = input_speed(problem, u)
    w3, w4 = kin.velocities(geo.a, geo.b, geo.c, p, w2)
    a3, a4 = kin.accelerations(geo.a, geo.b, geo.c, p, w2)
    x = u.from_rad(phi)
    mu = u.from_rad(p.mu)

    # Left: the linkage at its worst transmission angle (farthest from 90 deg).
    worst = int(np.argmax(np.abs(p.mu - np.pi / 2)))
    joint_paths(ax_link, geo, phi)
    if geo.coupler_point is not None:
        cx, cy = geo.joints(phi)["P"]
        ax_link.plot(cx, cy, color=CURVE_COLOR, lw=1.8, zorder=1, label="coupler curve of P")
    draw_linkage(ax_link, geo, float(phi[worst]))
    link_legend(ax_link, geo, lu)
    frame_drawing(ax_link, lu, f"Linkage to scale at input {num(float(x[worst]))} {au}\n"
                               f"(worst transmission angle, \u03bc = {num(float(mu[worst]))} {au})")

    speed = f"{num(float(u.from_rad(w2)))} {au}/s"
    ax_w.plot(x, finite(u.from_rad(w3)), color=LINK_COLORS["coupler"], lw=1.8, label="coupler \u03c9\u2083")
    ax_w.plot(x, finite(u.from_rad(w4)), color=LINK_COLORS["output"], lw=1.8, label="output \u03c9\u2084")
    ax_w.set_ylabel(f"angular velocity ({au}/s)")
    ax_w.set_title(f"Motion study at a constant input speed of {speed}")
    ax_w.legend(loc="upper right", framealpha=0.85, ncols=2)

    ax_a.plot(x, finite(u.from_rad(a3)), color=LINK_COLORS["coupler"], lw=1.8, label="coupler \u03b1\u2083")
    ax_a.plot(x, finite(u.from_rad(a4)), color=LINK_COLORS["output"], lw=1.8, label="output \u03b1\u2084")
    for ax, series in ((ax_w, (w3, w4)), (ax_a, (a3, a4))):
        if robust_ylim(ax, *(u.from_rad(v) for v in series)):
            ax.text(0.01, 0.03, "clipped: values grow without bound near the toggles", transform=ax.transAxes,
                    fontsize=9, color="#555555")
    ax_a.set_ylabel(f"angular accel. ({au}/s\u00b2)")
    ax_a.legend(loc="upper right", framealpha=0.85, ncols=2)

    lo, hi = (float(u.from_rad(np.radians(v))) for v in TRANSMISSION_BAND)
    ax_mu.axhspan(lo, hi, color=BAND_COLOR, alpha=0.12, lw=0,
                  label=f"recommended {num(lo)}..{num(hi)} {au}")
    ax_mu.plot(x, mu, color="#1f77b4", lw=1.8, label="transmission angle \u03bc")
    k_min, k_max = int(np.argmin(mu)), int(np.argmax(mu))
    for k, word in ((k_min, "min"), (k_max, "max")):
        ax_mu.scatter([x[k]], [mu[k]], color="black", zorder=4, s=28)
        right = float(x[k]) > 0.5 * (float(x[0]) + float(x[-1]))
        ax_mu.annotate(f"{word} {num(float(mu[k]))} {au}", (float(x[k]), float(mu[k])),
                       xytext=(-6 if right else 6, 7), textcoords="offset points", fontsize=9.5,
                       ha="right" if right else "left")
    ax_mu.set_ylabel(f"\u03bc ({au})")
    ax_mu.set_xlabel(f"input angle \u03c6 ({au})")
    ax_mu.legend(loc="best", framealpha=0.85)
    top = max(float(mu.max()), hi)
    ax_mu.set_ylim(min(0.0, float(mu.min())), 1.22 * top)
    for ax in (ax_w, ax_a, ax_mu):
        ax.axvline(float(x[worst]), color="#777777", lw=0.9, ls=":")
    for ax in (ax_w, ax_a):
        ax.tick_params(labelbottom=False)
    ax_mu.set_xlim(float(x[0]), float(x[-1]))
    angle_ticks(ax_mu, u)
