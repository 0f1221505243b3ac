"""A five-bar's study (`--plot`): on the left, to scale in the global frame, the workspace of
its working modes (where both chains reach P: the two annuli's overlap, shaded), the
singularity curves (type I: the four circles where a chain is stretched or folded, the
workspace's boundary; type II: where the distal links are in line with the chains in the
chosen modes, kinematics.type_two_curve), the path of P over the rows and the linkage at a
few rows (plots.common.draw_skeleton of the home's Skeleton); on the right, per row, the
Jacobian's condition number and the transmission angles at P and the elbows. The modes
drawn: the path's `modes`, or those of the first row reached for given inputs.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli import mechanisms
from linkcli.mechanisms.columns import TRANSMISSION_BAND
from linkcli.mechanisms.five_bar import kinematics as kin
from linkcli.plots.common import BAND_COLOR, CURVE_COLOR, draw_skeleton, frame_drawing, no_linkage, num, panels

SHOWN = 4  # rows drawn (the first reached, then evenly spread)
GRID = 240  # cells per side of the workspace's shading
SWEEP = 1441  # drive angles of the type II curve


def shown_rows(valid: np.ndarray) -> list[int]:
    """Up to SHOWN rows reached, evenly spread from the first to the last."""
    rows = np.flatnonzero(valid)
    if rows.size <= SHOWN:
        return rows.tolist()
    return rows[np.round(np.linspace(0, rows.size - 1, SHOWN)).astype(int)].tolist()


def draw(fig, result) -> None:
    u, ax, (ax_k, ax_mu) = panels(fig, result, 2, [1.35, 1.0])
    lu = u.length
    mech = mechanisms.of(result.solution.linkage)
    track = mech.track()
    if track is None or not track.valid.any():
        no_linkage(ax, "the five-bar reaches none of its rows")
        for a in (ax_k, ax_mu):
            a.set_axis_off()
        return
    fb, p, ok = track.fb, track.pose, track.valid
    modes = _modes(fb, p, ok)
    _workspace(ax, track, modes)
    x, y = track.to_global(p.px, p.py)
    ax.plot(np.where(ok, x, np.nan), np.where(ok, y, np.nan), color=CURVE_COLOR, lw=2.2, marker="o", ms=3,
            zorder=5, label=f"path of P ({track.rows} rows)")
    rows = shown_rows(ok)
    sk = mech.skeleton(np.asarray(rows))
    for i in range(len(rows)):
        draw_skeleton(ax, sk, i, ghost=i > 0, labels=i == 0)
    ax.legend(loc="best", framealpha=0.85, fontsize=8.5)
    frame_drawing(ax, lu, f"Workspace of modes {modes[0]}{modes[1]}, singularities, path;\n"
                          f"linkage at row {rows[0]} (ghosts: rows {', '.join(map(str, rows[1:])) or '-'})")
    _rows_panels(ax_k, ax_mu, track, u)


def _modes(fb, p, ok) -> tuple[str, str]:
    if fb.motion.path is not None:
        return fb.motion.modes
    m1, m2 = p.modes()
    k = int(np.argmax(ok))
    return ("+" if m1[k] >= 0 else "-"), ("+" if m2[k] >= 0 else "-")


def _workspace(ax, track, modes) -> None:
    """The annuli's overlap (shaded), the type I circles and the type II curve, global frame."""
    fb = track.fb
    d, a1, a2, b1, b2 = fb.lengths
    reach = max(a1 + b1, a2 + b2)
    lo_x, hi_x, lo_y, hi_y = -reach, d + reach, -reach, reach
    gx, gy = np.meshgrid(np.linspace(lo_x, hi_x, GRID), np.linspace(lo_y, hi_y, GRID))
    r1, r2 = np.hypot(gx, gy), np.hypot(gx - d, gy)
    inside = ((r1 >= abs(a1 - b1)) & (r1 <= a1 + b1) & (r2 >= abs(a2 - b2)) & (r2 <= a2 + b2)).astype(float)
    wx, wy = track.to_global(gx, gy)
    ax.contourf(wx, wy, inside, levels=[0.5, 1.5], colors=["#2ca02c"], alpha=0.10, zorder=0)
    t = np.linspace(0.0, 2.0 * math.pi, 721)
    first = True
    for cx, a, b in ((0.0, a1, b1), (d, a2, b2)):
        for r in (a + b, abs(a - b)):
            if r <= 0.0:
                continue
            cx_, cy_ = track.to_global(cx + r * np.cos(t), r * np.sin(t))
            ax.plot(cx_, cy_, color="#1f77b4", lw=1.0, ls=(0, (5, 3)), zorder=1,
                    label="type I: a chain stretched or folded" if first else None)
            first = False
    m1, m2 = (1.0 if m == "+" else -1.0 for m in modes)
    xs, ys = kin.type_two_curve(fb.lengths, np.linspace(-math.pi, math.pi, SWEEP), m1, m2)
    first = True
    for cx, cy in zip(xs, ys):
        qx, qy = track.to_global(cx, cy)
        ax.plot(qx, qy, color="#d62728", lw=1.3, zorder=2,
                label="type II: distal links in line" if first else None)
        first = False
    ax.plot([], [], color="#2ca02c", alpha=0.35, lw=6, label="workspace (both chains reach P)")


def _rows_panels(ax_k, ax_mu, track, u) -> None:
    """Condition number (log scale over a wide range) and transmission angles per row."""
    p, ok = track.pose, track.valid
    rows = np.arange(track.rows)
    kappa = np.where(ok, kin.condition(p), np.nan)
    kappa = np.where(np.isfinite(kappa), kappa, np.nan)
    worst = np.nanmax(kappa) if np.isfinite(kappa).any() else float("nan")
    ax_k.plot(rows, kappa, color="#9467bd", marker="o", ms=3, lw=1.6)
    if worst > 10.0 * np.nanmin(kappa):  # a wide range (near a singularity): log scale
        ax_k.set_yscale("log")
    ax_k.set_ylabel("condition number of J")
    ax_k.set_title(f"Condition number per row (worst {num(float(worst))}; 1 is isotropic)")
    ax_k.tick_params(labelbottom=False)
    for ph in track.fb.motion.phases:
        for a in (ax_k, ax_mu):
            a.axvspan(ph.first - 0.5, ph.last + 0.5, color="#ff7f0e", alpha=0.10, lw=0)
    mu_p, mu_a, mu_b = (np.where(ok, u.from_rad(m), np.nan) for m in p.transmissions())
    lo, hi = (float(u.from_rad(math.radians(v))) for v in TRANSMISSION_BAND)
    ax_mu.axhspan(lo, hi, color=BAND_COLOR, alpha=0.12, lw=0, label=f"recommended {num(lo)}..{num(hi)} {u.angle}")
    ax_mu.plot(rows, mu_p, color="#d62728", marker="o", ms=3, lw=1.6, label="\u03bc at P (distal links)")
    ax_mu.plot(rows, mu_a, color="#1f77b4", lw=1.2, ls="--", label="\u03bc at A (left elbow)")
    ax_mu.plot(rows, mu_b, color="#2ca02c", lw=1.2, ls="--", label="\u03bc at B (right elbow)")
    ax_mu.set_ylim(0.0, float(u.from_rad(math.pi)) * 1.05)
    ax_mu.set_ylabel(f"transmission angle ({u.angle})")
    ax_mu.set_xlabel("row" + ("  (shaded: a drive held)" if track.fb.motion.phases else ""))
    ax_mu.legend(loc="best", framealpha=0.85, fontsize=8.5)
    if track.rows > 1:
        ax_mu.set_xlim(-0.5, track.rows - 0.5)
