"""A drawn linkage's analysis figure: the linkage to scale as drawn (plots.common.draw_skeleton)
with the paths of the asked points over the drive's range and a few ghost positions, beside
its motion study over the leading drive: every link's angular velocity, and every closure's
transmission angle against the recommended band (40..140 deg). A design (path, motion or
function generation) draws its targets instead (design_plot)."""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.columns import TRANSMISSION_BAND
from linkcli.plots.common import (BAND_COLOR, CURVE_COLOR, angle_ticks, draw_skeleton, drawn, frame_drawing,
                                  link_color, num, panels, robust_ylim)

SAMPLES = 720
GHOSTS = 4


def draw(fig, result) -> None:
    from linkcli import mechanisms
    if getattr(result.problem, "kind", None) is not None and result.solution.linkage.designed:
        from linkcli.mechanisms.drawn.design_plot import draw as draw_design
        return draw_design(fig, result)  # a design: its targets
    from linkcli.mechanisms.drawn.motion import closure_vectors, transmission
    drawn(result)
    u, ax_link, (ax_w, ax_mu) = panels(fig, result, 2, [1.0, 1.25])
    au, lu = u.angle, u.length
    home = mechanisms.of(result.solution.linkage)
    sv = home.solved
    study = home.study()
    x, shown = study.rows(SAMPLES)
    st = sv.kin.run(sv.q_of(x, study.full_turn), rates=True)
    at = np.asarray(study.printed(shown, u), dtype=float)
    order = np.argsort(at, kind="stable")
    sk = home.skeleton(np.array([sv.start]))
    ghosts = home.skeleton(x[np.linspace(0, len(x) - 1, GHOSTS + 2, dtype=int)[1:-1]])
    for k in range(GHOSTS):
        draw_skeleton(ax_link, ghosts, k, ghost=True)
    for name in sk.traced:
        path = np.where(st.valid[:, None], st.pos[name], np.nan)
        if study.full_turn:
            path = np.vstack([path, path[:1]])
        ax_link.plot(path[:, 0], path[:, 1], color=CURVE_COLOR, lw=1.6, zorder=2)
    draw_skeleton(ax_link, sk, 0)
    frame_drawing(ax_link, lu, f"As drawn, with the paths of {', '.join(sk.traced) or 'no point'}"
                  if sk.traced else "As drawn ([motion] points = [...] traces paths)")
    for index, link in enumerate(home.linkage.links):
        w = u.from_rad(np.where(st.valid, st.omega[link.name], np.nan))
        ax_w.plot(at[order], w[order], color=link_color(link.name, index), lw=1.6, label=link.name)
    ax_w.axhline(0.0, color="#777777", lw=0.8)
    ax_w.set_ylabel(f"\u03c9 ({au}/s)")
    speeds = ", ".join(f"{d.name} {num(float(u.from_rad(d.speed)) if d.kind == 'turn' else d.speed)}"
                       f" {au if d.kind == 'turn' else lu}/s" for d in home.linkage.drives)
    ax_w.set_title(f"Angular velocities at constant drive speeds ({speeds})")
    ax_w.legend(loc="upper right", framealpha=0.85, fontsize=8)
    robust_ylim(ax_w, *[np.asarray(line.get_ydata(), dtype=float) for line in ax_w.get_lines()[1:]])
    lo, hi = TRANSMISSION_BAND
    if au != "deg":
        lo, hi = math.radians(lo), math.radians(hi)
    ax_mu.axhspan(lo, hi, color=BAND_COLOR, alpha=0.12, lw=0, label=f"recommended {num(lo)}..{num(hi)} {au}")
    for index, c in enumerate(sv.structure.closures()):
        a, _, _, b, _, _ = closure_vectors(sv.kin, st, c)
        mu = u.from_rad(np.where(st.valid, transmission(c.kind, a, None, None, b, None, None)[0], np.nan))
        ax_mu.plot(at[order], mu[order], lw=1.6, color=link_color(c.joint, index + 3), label=f"\u03bc at {c.joint}")
    ax_mu.set_ylim(0.0, float(u.from_rad(math.pi)))
    ax_mu.set_ylabel(f"\u03bc ({au})")
    ax_mu.set_xlabel(f"drive {home.linkage.drives[0].name} ({study.unit(u)})")
    ax_mu.legend(loc="lower right", framealpha=0.85, fontsize=8)
    ax_w.tick_params(labelbottom=False)
    ax_mu.set_xlim(float(np.nanmin(at)), float(np.nanmax(at)))
    if sv.turning:
        angle_ticks(ax_mu, u)
