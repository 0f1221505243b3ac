"""motion-generation: in the global frame, on equal axes, the body drawn at each pose (an
L-shaped frame marker: its origin and x axis; targets in black, achieved in red dashes),
the coupler curve of the body origin over the input's whole motion, the linkage to scale
at the first pose; for four poses the centre-point curve (ground pivots) and the
circle-point curve (moving pivots at pose 1) of burmester.centre_point_curve. Beside it
each pose's position error and angle error.
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.four_bar.drawing import Geometry, draw_linkage, input_grid, joint_paths, link_legend
from linkcli.plots.common import CURVE_COLOR, TARGET_COLOR, body_frames, drawn, frame_drawing, num, panels

NEEDS = ("linkage", "positions")
BODY = 0.12  # the body marker's arm, as a share of the longest link (or of the poses' spread)


def _frame(ax, points) -> None:
    """Autoscale the axes on `points` alone (the poses, the linkage and its joints'
    paths), with frame_drawing's margin and equal aspect; what lies beyond (the far
    branches of the centre-point and circle-point curves, which run to infinity) is
    clipped rather than shrinking the drawing to a dot."""
    points = points[np.all(np.isfinite(points), -1)]
    if len(points) == 0:
        return
    ax.ignore_existing_data_limits = True
    ax.update_datalim(points)
    ax.autoscale_view()


def draw(fig, result) -> None:
    """The design's figure, by its mechanism's synthesis face: the four-bar's below."""
    from linkcli.mechanisms import synthesis
    return synthesis.draw("motion-generation", fig, result)


def draw_four_bar(fig, result) -> None:
    report, problem = drawn(result), result.problem
    u, ax, (ax_pos, ax_ang) = panels(fig, result, 2, [1.45, 1.0])
    lu, au = u.length, u.angle
    rows = report.get("positions") or []
    target = np.array([r["target"] for r in rows], float).reshape(-1, 3)
    achieved = np.array([r["achieved"] for r in rows], float).reshape(-1, 3)
    target[:, 2], achieved[:, 2] = u.angles_to_rad(target[:, 2]), u.angles_to_rad(achieved[:, 2])
    if not rows and problem is not None:  # no linkage (the title says why): the poses asked for
        target = np.array(problem.poses, float).reshape(-1, 3)  # length unit, rad
    origins = target[:, :2]
    scale = float(np.sqrt(np.mean(np.sum((origins - origins.mean(0)) ** 2, 1)))) if len(target) else 1.0
    size = max(float(max(report["linkage"][k] for k in ("ground", "input", "coupler", "output")))
               if "linkage" in report else 0.0, 2 * scale)
    arm = BODY * (size if size > 0 else 1.0)
    phi = u.angles_to_rad(np.array([r["input"] for r in rows], dtype=float))
    reach = arm * np.array([[-1.0, -1.0], [1.0, 1.0]])  # a body marker about its origin
    framed = [(target[:, None, :2] + reach).reshape(-1, 2), achieved[:, :2]]  # what the axes must show
    if "linkage" in report:
        geo = Geometry.of(result)
        mot = geo.motion(near=float(phi[0]) if len(phi) else None)
        if mot.assembles:
            grid = input_grid(mot)
            j = geo.joints(grid)
            ok = j["pose"].valid
            joint_paths(ax, geo, grid)
            cx, cy = j["P"]
            ax.plot(np.where(ok, cx, np.nan), np.where(ok, cy, np.nan), color=CURVE_COLOR, lw=1.8, zorder=2,
                    label="coupler curve (body origin)")
            framed += [np.column_stack([np.asarray(j[k][0])[ok], np.asarray(j[k][1])[ok]]) for k in ("A", "B", "P")]
            framed += [np.atleast_2d(np.column_stack(j[k])) for k in ("A0", "B0")]
            draw_linkage(ax, geo, float(phi[0]) if len(phi) else float(grid[0]))
        link_legend(ax, geo, lu)
    if problem is not None and len(problem.poses) == 4:
        from linkcli.types.motion_generation.burmester import centre_point_curve
        from linkcli.types.motion_generation.no_candidates import rotating_pair
        poses = np.array(problem.poses, float)
        pair = rotating_pair(poses)
        first = list(pair or (0, 1)) + [k for k in range(4) if k not in (pair or (0, 1))]  # as solve.py
        with np.errstate(all="ignore"):
            curve = centre_point_curve(poses[first], samples=361, max_distance=4.0)
        for data, color, name in ((curve.ground, "#8c564b", "centre-point curve"),
                                  (curve.circle, "#17becf", f"circle-point curve (pose {first[0] + 1})")):
            for branch in range(2):
                ax.plot(data[:, branch, 0], data[:, branch, 1], ".", ms=1.6, color=color,
                        label=name if branch == 0 else None, zorder=1)
        ax.plot(curve.poles[:, 0], curve.poles[:, 1], "D", ms=4, color="#8c564b", zorder=2, label="poles")
    if len(target):
        body_frames(ax, target, arm, color=TARGET_COLOR, lw=2.2, zorder=6)
        ax.plot([], [], color=TARGET_COLOR, lw=2.2, label=f"target poses ({len(target)})")
        if len(rows):
            body_frames(ax, achieved, arm, color="#d62728", lw=1.4, ls=(0, (3, 2)), zorder=7)
            ax.plot([], [], color="#d62728", lw=1.4, ls=(0, (3, 2)), label="achieved poses")
        for k in range(len(target)):
            ax.annotate(str(k + 1), (target[k, 0], target[k, 1]), xytext=(-12, 5), textcoords="offset points",
                        fontsize=9.5, color=TARGET_COLOR, zorder=8)
        ax.legend(loc="best", framealpha=0.85, fontsize=8.5)
    frame_drawing(ax, lu, "Body at each pose, coupler curve, linkage at pose 1")
    _frame(ax, np.concatenate([f.reshape(-1, 2) for f in framed]))
    idx = np.arange(1, len(rows) + 1)
    pos = np.array([r["position_error"] for r in rows], float)
    ang = np.array([r["angle_error"] for r in rows], float)
    for axis, err in ((ax_pos, pos), (ax_ang, ang)):
        if len(rows) and not np.any(err):
            axis.text(0.5, 0.5, "exact: 0 at every pose", ha="center", va="center", transform=axis.transAxes)
            axis.set_yticks([])
    if len(rows):
        ax_pos.bar(idx, pos, color="#d62728", alpha=0.8, width=0.6)
        ax_pos.set_ylim(0.0, max(float(pos.max()), 1e-12) * 1.25)
        ax_ang.bar(idx, ang, color="#1f77b4", alpha=0.8, width=0.6)
        top = max(float(np.abs(ang).max()), 1e-12) * 1.25
        ax_ang.set_ylim(-top, top)
        ax_ang.axhline(0.0, color="#444444", lw=0.8)
    ax_pos.set_ylabel(f"position error ({lu})")
    ax_pos.set_title(f"Error at each pose (max {num(float(pos.max()), 3) if len(pos) else '-'} {lu})")
    ax_pos.tick_params(labelbottom=False)
    ax_ang.set_ylabel(f"angle error ({au})")
    ax_ang.set_xlabel("pose")
    ax_ang.set_title(f"Angle error (max {num(float(np.abs(ang).max()), 3) if len(ang) else '-'} {au})")
    if len(rows):
        from matplotlib.ticker import MaxNLocator
        ax_ang.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax_ang.set_xlim(0.4, len(rows) + 0.6)
