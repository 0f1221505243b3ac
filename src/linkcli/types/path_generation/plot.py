"""path-generation: in the global frame, on equal axes, the full coupler curve of P
over the input's whole motion (kinematics.pose, placed by ground_pivot and ground_angle),
the target points numbered, the points achieved and the error of each, with the
linkage to scale at the first target; beside it each point's error and the input angle
that reaches it (the timing).
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.four_bar.drawing import Geometry, draw_linkage, input_grid, joint_paths, link_legend
from linkcli.plots.common import CURVE_COLOR, TARGET_COLOR, drawn, frame_drawing, num, panels

NEEDS = ("linkage", "positions")
LABEL_ALL = 12  # up to this many targets each one is numbered; beyond, every k-th


def draw(fig, result) -> None:
    """The design's figure, by its mechanism's synthesis face: the four-bar's below."""
    from linkcli.mechanisms import synthesis
    return synthesis.draw("path-generation", fig, result)


def draw_four_bar(fig, result) -> None:
    report = drawn(result)
    u, ax, (ax_err, ax_in) = panels(fig, result, 2, [1.45, 1.0])
    au, lu = u.angle, u.length
    rows = report.get("positions") or []
    target = np.array([r["target"] for r in rows], dtype=float).reshape(-1, 2)
    achieved = np.array([r["achieved"] for r in rows], dtype=float).reshape(-1, 2)
    err = np.array([r["error"] for r in rows], dtype=float)
    phi_t = u.angles_to_rad(np.array([r["input"] for r in rows], dtype=float))
    idx = np.arange(1, len(rows) + 1)

    if "linkage" in report and report["linkage"].get("coupler_point") is not None:
        geo = Geometry.of(result)
        mot = geo.motion(near=float(phi_t[0]) if len(phi_t) else None)
    else:
        geo, mot = None, {}
    if geo is not None and mot.assembles:
        grid = input_grid(mot)
        j = geo.joints(grid)
        ok = j["pose"].valid
        joint_paths(ax, geo, grid)
        cx, cy = j["P"]
        ax.plot(np.where(ok, cx, np.nan), np.where(ok, cy, np.nan), color=CURVE_COLOR, lw=2.0, zorder=2,
                label="coupler curve" + ("" if mot.input_full_turn else " (input rocks)"))
        draw_linkage(ax, geo, float(phi_t[0]) if len(phi_t) else float(grid[0]))
        title = "Coupler curve and targets, linkage to scale at target 1"
    else:
        title = "Targets (no linkage to draw)"
    if len(rows):
        from matplotlib.collections import LineCollection
        ax.add_collection(LineCollection(np.stack([target, achieved], axis=1), colors="#d62728", linewidths=1.2,
                                         zorder=5))  # error vectors: target -> achieved
        ax.scatter(target[:, 0], target[:, 1], marker="x", s=60, color=TARGET_COLOR, linewidths=2.0, zorder=6,
                   label=f"target points ({len(rows)})")
        ax.scatter(achieved[:, 0], achieved[:, 1], marker="o", s=24, facecolor="white", edgecolor="#d62728",
                   zorder=6, label="achieved (red: error)")
        step = 1 if len(rows) <= LABEL_ALL else int(np.ceil(len(rows) / LABEL_ALL))
        for k in range(0, len(rows), step):
            ax.annotate(str(k + 1), (target[k, 0], target[k, 1]), xytext=(-12, 5), textcoords="offset points",
                        fontsize=9.5, color=TARGET_COLOR, zorder=7)
    if geo is not None:
        link_legend(ax, geo, lu)
    elif len(rows):
        ax.legend(loc="best", framealpha=0.85)
    frame_drawing(ax, lu, title)

    if len(rows):
        bars = ax_err.bar(idx, err, color="#d62728", alpha=0.8, width=0.6)
        if len(rows) <= LABEL_ALL:
            ax_err.bar_label(bars, labels=[num(float(e), 3) for e in err], fontsize=8.5, padding=2)
        rms = float(np.sqrt(np.mean(err * err)))
        ax_err.axhline(rms, color="#444444", lw=1.0, ls="--", label=f"rms {num(rms, 3)} {lu}")
        ax_err.set_ylim(0.0, max(float(err.max()), 1e-12) * 1.25)
        ax_err.legend(loc="upper right", framealpha=0.85)
        ax_in.plot(idx, u.from_rad(np.unwrap(phi_t)), color="#1f77b4", marker="o", ms=5, lw=1.2)
    ax_err.set_ylabel(f"distance to target ({lu})")
    ax_err.set_title(f"Error at each target point (max {num(float(err.max()), 3) if len(err) else '-'} {lu})")
    ax_err.tick_params(labelbottom=False)
    ax_in.set_ylabel(f"input angle \u03c6 ({au})")
    ax_in.set_xlabel("target point")
    ax_in.set_title("Timing: input angle at each target")
    if len(rows):
        from matplotlib.ticker import MaxNLocator
        ax_in.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax_in.set_xlim(0.4, len(rows) + 0.6)
    if geo is not None and not mot.assembles:
        ax.text(0.5, 0.95, "the linkage cannot assemble at any input angle", transform=ax.transAxes,
                ha="center", va="top", color="#b00000")
