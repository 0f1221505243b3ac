"""precision-position and function-generation: the linkage at its first target (the
other targets ghosted) beside the output angle it achieves over the whole motion,
psi(phi) from the loop closure (kinematics.pose), with the targets marked and the
error (achieved - target) at the targets below.
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.four_bar.drawing import Geometry, draw_linkage, input_grid, joint_paths, link_legend, on_grid
from linkcli.plots.common import CURVE_COLOR, TARGET_COLOR, angle_ticks, drawn, frame_drawing, no_linkage, num, panels

NEEDS = ("linkage", "positions")
GHOST_ALL = 6  # up to this many targets every one is ghosted; beyond, only the last
MARK_ALL = 12  # up to this many targets each is marked, with its achieved value; beyond, a law line
ERROR_FLOOR_DEG = 1e-3  # the error axis spans at least +- this much


def output_curve(geo: Geometry, phi_targets: np.ndarray):
    """(grid, psi, valid): the achieved output angle over the whole motion, unwrapped
    and shifted by whole turns so that it passes near the first target."""
    mot = geo.motion(near=float(phi_targets[0]) if len(phi_targets) else None)
    if not mot.assembles:
        return None
    centre = float(np.mean(phi_targets)) if len(phi_targets) else None
    grid = input_grid(mot, centre=centre)
    p = geo.pose(grid)
    return grid, np.unwrap(p.psi), p.valid, mot


def align(values: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Angles moved by whole turns to lie nearest the reference angles (rad)."""
    return values + kin.TWO_PI * np.round((reference - values) / kin.TWO_PI)


def draw(fig, result) -> None:
    report = drawn(result)
    u, ax_link, (ax_psi, ax_err) = panels(fig, result, 2, [1.0, 1.25], [1.6, 1.0])
    au, lu = u.angle, u.length

    geo = Geometry.of(result)
    rows = report.get("positions") or []
    phi_t = u.angles_to_rad(np.array([r["input"] for r in rows], dtype=float))
    psi_t = u.angles_to_rad(np.array([r["target"] for r in rows], dtype=float))
    err = np.array([r["error"] for r in rows], dtype=float)
    curve = output_curve(geo, phi_t)
    if curve is None:
        no_linkage(ax_link, "the linkage cannot assemble at any input angle")
        no_linkage(ax_psi, "no output curve")
        ax_err.set_axis_off()
        return
    grid, psi, valid, mot = curve

    # Left: the linkage to scale at the first target, the other targets ghosted.
    joint_paths(ax_link, geo, grid)
    ghosts = range(1, len(phi_t)) if len(phi_t) <= GHOST_ALL else [len(phi_t) - 1]
    for k in ghosts:
        draw_linkage(ax_link, geo, float(phi_t[k]), ghost=True, labels=False)
    shown = float(phi_t[0]) if len(phi_t) else float(grid[0])
    draw_linkage(ax_link, geo, shown)
    link_legend(ax_link, geo, lu, loc="upper left")
    at = f"input {num(float(u.from_rad(shown)))} {au}"
    where = f"target 1 ({at})" if len(phi_t) else at
    extra = "; others ghosted" if len(phi_t) > 1 else ""
    frame_drawing(ax_link, lu, f"Linkage to scale at {where}{extra}")

    # Right, top: achieved psi over the whole motion, targets marked.
    x_t = on_grid(grid, phi_t)  # a rocking input's arc also lies within one turn of grid[0]
    at_t = np.interp(x_t, grid, psi)
    shift = float(kin.wrap(at_t[0] if len(at_t) else psi[0])) - float(at_t[0] if len(at_t) else psi[0])
    psi, at_t = psi + shift, at_t + shift
    y_t = align(psi_t, at_t)
    ax_psi.plot(u.from_rad(grid), np.where(valid, u.from_rad(psi), np.nan), color=CURVE_COLOR, lw=2.0,
                label="achieved output angle")
    if len(x_t):
        lo, hi = float(u.from_rad(x_t.min())), float(u.from_rad(x_t.max()))
        if hi > lo:
            ax_psi.axvspan(lo, hi, color="#f0c040", alpha=0.18, lw=0, label="working range (targets)")
        many = len(x_t) > MARK_ALL
        if many:  # a law sampled at many points: a dashed line with small marks
            ax_psi.plot(u.from_rad(x_t), u.from_rad(y_t), color=TARGET_COLOR, lw=1.2, ls="--", zorder=3,
                        marker="x", ms=4, label=f"target law ({len(x_t)} points)")
        else:
            ax_psi.scatter(u.from_rad(x_t), u.from_rad(y_t), marker="x", s=70, color=TARGET_COLOR, zorder=4,
                           linewidths=2.0, label=f"targets ({len(x_t)})")
            ax_psi.scatter(u.from_rad(x_t), u.from_rad(at_t), marker="o", s=26, facecolor="white",
                           edgecolor=CURVE_COLOR, zorder=5, label="achieved at the targets")
    ax_psi.set_ylabel(f"output angle \u03c8 ({au})")
    ax_psi.set_title("Output angle over the whole motion" + (" (input turns fully)" if mot.input_full_turn
                                                              else " (input rocks between its limits)"))
    ax_psi.legend(loc="best", framealpha=0.85)
    ax_psi.tick_params(labelbottom=False)

    # Right, bottom: the error at the targets.
    if len(x_t):
        ax_err.axhline(0.0, color="#444444", lw=0.8)
        ax_err.plot(u.from_rad(x_t), err, color="#d62728", marker="o", ms=3 if len(x_t) > MARK_ALL else 5, lw=1.4)
        worst = float(np.max(np.abs(err)))
        rms = float(np.sqrt(np.mean(err * err)))
        ax_err.set_title(f"Output-angle error: max |error| {num(worst, 3)} {au}, rms {num(rms, 3)} {au}")
        # never zoom below ERROR_FLOOR_DEG: round-off of an exact fit stays on the zero line
        span = max(1.2 * worst, float(u.from_rad(np.radians(ERROR_FLOOR_DEG))))
        ax_err.set_ylim(-span, span)
    ax_err.set_xlabel(f"input angle \u03c6 ({au})")
    ax_err.set_ylabel(f"error, achieved \u2212 target ({au})")
    if not len(x_t):
        ax_err.set_title("Output-angle error")
    ax_psi.set_xlim(float(u.from_rad(grid[0])), float(u.from_rad(grid[-1])))
    angle_ticks(ax_err, u)
