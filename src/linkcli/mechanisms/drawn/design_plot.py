"""A drawn design's figure (path, motion or function generation with mechanism = "drawn"):
the designed linkage to scale where the drive reaches the first target, with the path of the
target joint (or of the followed link's frame origin) over the drive's range, the targets
numbered and what the design achieves (path: points; motion: body frames, targets black,
achieved red dashes); beside it each target's error, and the drive value that reaches it
(path, motion) or the followed link's angle against the drive angle with the law asked for
(function)."""

from __future__ import annotations

import numpy as np

from linkcli.plots.common import (CURVE_COLOR, TARGET_COLOR, body_frames, draw_skeleton, drawn, frame_drawing,
                                  num, panels)

SAMPLES = 720
BODY = 0.12  # a body marker's arm, as a share of the drawing's size


def draw(fig, result) -> None:
    from linkcli import mechanisms
    report, problem = drawn(result), result.problem
    u, ax, (ax_top, ax_bottom) = panels(fig, result, 2, [1.45, 1.0])
    lu, au = u.length, u.angle
    home = mechanisms.of(result.solution.linkage)
    sv = home.solved
    pos = result.solution.positions
    kind = problem.kind
    rows = report.get("positions") or []
    q = np.asarray(pos.input if pos is not None else [u.to_rad(r["input"]) for r in rows], dtype=float)
    study = home.study()
    x, _ = study.rows(SAMPLES)
    st = sv.kin.run(sv.q_of(x, study.full_turn), rates=False)
    link = home.linkage.link(problem.link) if problem.link else None  # motion: the frame's origin;
    traced = problem.joint if kind == "path" else link.joints[0 if kind == "motion" else 1]  # function: its other end
    path = np.where(st.valid[:, None], st.pos[traced], np.nan)
    if study.full_turn:
        path = np.vstack([path, path[:1]])
    ax.plot(path[:, 0], path[:, 1], color=CURVE_COLOR, lw=1.6, zorder=2, label=f"path of {traced}")
    first = sv.start + (q[0] if len(q) else 0.0)
    sk = home.skeleton(np.array([first]))
    draw_skeleton(ax, sk, 0)
    idx = np.arange(1, len(rows) + 1)
    if kind == "path":
        target = np.array([r["target"] for r in rows], dtype=float).reshape(-1, 2)
        achieved = np.array([r["achieved"] for r in rows], dtype=float).reshape(-1, 2)
        ax.plot(target[:, 0], target[:, 1], "o", mfc="none", mec=TARGET_COLOR, ms=8, zorder=6,
                label=f"targets ({len(target)})")
        ax.plot(achieved[:, 0], achieved[:, 1], "x", color="#d62728", ms=6, zorder=7, label="achieved")
        _numbered(ax, target)
        err = np.array([r["error"] for r in rows], dtype=float)
        _bars(ax_top, idx, err, f"error ({lu})", f"Error at each target (max {num(float(err.max()), 3)} {lu})")
        _timing(ax_bottom, idx, rows, au)
    elif kind == "motion":
        target = np.array([r["target"] for r in rows], dtype=float).reshape(-1, 3)
        achieved = np.array([r["achieved"] for r in rows], dtype=float).reshape(-1, 3)
        target[:, 2], achieved[:, 2] = u.angles_to_rad(target[:, 2]), u.angles_to_rad(achieved[:, 2])
        arm = BODY * home.size()
        body_frames(ax, target, arm, color=TARGET_COLOR, lw=2.2, zorder=6)
        ax.plot([], [], color=TARGET_COLOR, lw=2.2, label=f"target poses ({len(target)})")
        body_frames(ax, achieved, arm, color="#d62728", lw=1.4, ls=(0, (3, 2)), zorder=7)
        ax.plot([], [], color="#d62728", lw=1.4, ls=(0, (3, 2)), label=f"achieved poses of {problem.link}")
        _numbered(ax, target[:, :2])
        err = np.array([r["position_error"] for r in rows], dtype=float)
        _bars(ax_top, idx, err, f"position error ({lu})",
              f"Position error at each pose (max {num(float(err.max()), 3)} {lu})")
        ang = np.array([r["angle_error"] for r in rows], dtype=float)
        _bars(ax_bottom, idx, ang, f"angle error ({au})", f"Angle error (max {num(float(np.abs(ang).max()), 3)} {au})")
        ax_bottom.set_xlabel("pose")
    else:
        phi = u.from_rad(q)
        target = np.array([r["target"] for r in rows], dtype=float)
        achieved = np.array([r["achieved"] for r in rows], dtype=float)
        ax_top.plot(phi, target, "o", mfc="none", mec=TARGET_COLOR, ms=7, label="law asked for")
        ax_top.plot(phi, achieved, "-", color="#d62728", lw=1.6, label=f"{problem.link} achieved")
        ax_top.set_ylabel(f"{problem.link} from its drawn angle ({au})")
        ax_top.set_title(f"Output angle against the drive angle")
        ax_top.legend(loc="best", framealpha=0.85, fontsize=8)
        ax_top.tick_params(labelbottom=False)
        err = np.array([r["error"] for r in rows], dtype=float)
        ax_bottom.plot(phi, err, "o-", color="#d62728", lw=1.2, ms=4)
        ax_bottom.axhline(0.0, color="#444444", lw=0.8)
        ax_bottom.set_ylabel(f"error ({au})")
        ax_bottom.set_xlabel(f"drive angle from the drawn position ({au})")
        ax_bottom.set_title(f"Error at each point (max {num(float(np.abs(err).max()), 3)} {au})")
    ax.legend(loc="best", framealpha=0.85, fontsize=8.5)
    frame_drawing(ax, lu, "Designed linkage at the first target, with its path")


def _numbered(ax, points) -> None:
    step = max(1, len(points) // 12)
    for k in range(0, len(points), step):
        ax.annotate(str(k + 1), (points[k, 0], points[k, 1]), xytext=(-12, 5), textcoords="offset points",
                    fontsize=9, color=TARGET_COLOR, zorder=8)


def _bars(axis, idx, values, label: str, title: str) -> None:
    if len(values) and not np.any(values):
        axis.text(0.5, 0.5, "exact: 0 at every target", ha="center", va="center", transform=axis.transAxes)
        axis.set_yticks([])
    elif len(values):
        axis.bar(idx, values, color="#d62728", alpha=0.8, width=0.6)
        axis.axhline(0.0, color="#444444", lw=0.8)
    axis.set_ylabel(label)
    axis.set_title(title)
    axis.set_xlim(0.4, len(idx) + 0.6)


def _timing(axis, idx, rows, au: str) -> None:
    """The drive value that reaches each target (from the drawn position)."""
    drive = np.array([r["input"] for r in rows], dtype=float)
    axis.plot(idx, drive, "o-", color="#1f77b4", lw=1.2, ms=5)
    axis.set_ylabel(f"drive angle ({au})")
    axis.set_xlabel("target")
    axis.set_title("Timing: the drive angle from the drawn position at each target")
    axis.set_xlim(0.4, len(idx) + 0.6)
