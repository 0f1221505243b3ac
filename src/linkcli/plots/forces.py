"""The forces section drawn under any type's figure: the input torque and the magnitude of
every pin force over the motion study's rows (`forces.rows` of the report; nothing is solved
here). Rows left null (dead points) leave a gap in the curves."""

from __future__ import annotations

import numpy as np

from linkcli.plots.common import angle_ticks, drawn, num

HEIGHT = 3.4  # inches added to the figure for the forces panels
PIN_COLORS = {"A0": "#1f77b4", "A": "#d62728", "B": "#2ca02c", "B0": "#9467bd", "guide": "#8c564b",
              "P": "#ff7f0e"}


def _column(rows, get) -> np.ndarray:
    return np.array([np.nan if get(r) is None else get(r) for r in rows], dtype=float)


def draw(fig, result) -> None:
    """Two axes side by side: input torque (N m) and pin force magnitudes (N) against the input."""
    forces = drawn(result)["forces"]
    rows = forces["rows"]
    u = result.problem.meta.units
    x = _column(rows, lambda r: r["input"])
    ax_t, ax_f = fig.subplots(1, 2, sharex=True)
    torque = _column(rows, lambda r: r["input_torque"])
    ax_t.plot(x, torque, color="#111111", lw=1.8, label="input torque")
    others = [k for k in forces if k.endswith("_torque") and k != "input_torque"]
    for key, color in zip(others, ("#d62728", "#2ca02c", "#9467bd")):  # a linkage's other drives
        ax_t.plot(x, _column(rows, lambda r, k=key: r[k]), color=color, lw=1.6, label=key.replace("_", " "))
    if others:
        ax_t.legend(loc="upper right", framealpha=0.85)
    ax_t.axhline(0.0, color="#777777", lw=0.8)
    peak = forces["input_torque"]
    if peak.get("peak") is not None:
        ax_t.scatter([peak["at_input"]], [peak["peak"]], color="black", zorder=4, s=28)
        right = peak["at_input"] > 0.5 * (float(np.nanmin(x)) + float(np.nanmax(x)))
        ax_t.annotate(f"peak {num(peak['peak'])} N m", (peak["at_input"], peak["peak"]),
                      xytext=(-6 if right else 6, 6), textcoords="offset points", fontsize=9.5,
                      ha="right" if right else "left")
    ax_t.set_ylabel("input torque (N m)" if not others else "drive torques (N m)")
    if others:
        ax_t.set_title("Torques the drives supply")
    else:
        ax_t.set_title(f"Torque the drive supplies (rms {num(peak['rms'])} N m)"
                       if peak.get("rms") is not None else "Torque the drive supplies")
    for name in forces["pins"]:
        size = _column(rows, lambda r, n=name: r["pins"][n]["magnitude"])
        ax_f.plot(x, size, color=PIN_COLORS.get(name, None), lw=1.6, label=name)
    ax_f.set_ylabel("pin force magnitude (N)")
    ax_f.set_title("Pin forces over the cycle")
    ax_f.legend(loc="upper right", framealpha=0.85, ncols=len(forces["pins"]))
    for ax in (ax_t, ax_f):
        ax.set_xlabel(f"input angle \u03c6 ({u.angle})")
        if np.isfinite(x).any():
            ax.set_xlim(float(np.nanmin(x)), float(np.nanmax(x)))
        angle_ticks(ax, u)
