"""The strength section drawn under any type's figure: each checked pin's shear stress and
each checked link's largest fibre stress over the motion study's rows (`strength.rows` of the
report; nothing is computed here), the weakest part drawn bold with its peak marked and its
safety factor in the title. Rows left null (dead points) leave a gap."""

from __future__ import annotations

import numpy as np

from linkcli.plots.common import LINK_COLORS, angle_ticks, drawn, num
from linkcli.plots.forces import PIN_COLORS

HEIGHT = 3.4  # inches added to the figure for the strength panels


def _column(rows, group: str, name: str) -> np.ndarray:
    return np.array([np.nan if r[group][name] is None else r[group][name] for r in rows], dtype=float)


def draw(fig, result) -> None:
    """Two axes side by side: pin shear (MPa) and link fibre stress (MPa) against the input."""
    strength = drawn(result)["strength"]
    rows = strength["rows"]
    u = result.problem.meta.units
    x = np.array([r["input"] for r in rows], dtype=float)
    critical = strength.get("critical") or {}
    ax_p, ax_l = fig.subplots(1, 2, sharex=True)
    panels = ((ax_p, "pins", "pin", PIN_COLORS, "pin shear stress (MPa)", "Pin shear over the cycle"),
              (ax_l, "links", "link", LINK_COLORS, "largest fibre stress (MPa)",
               "Link stress over the cycle"))
    for ax, group, kind, colors, label, title in panels:
        names = [p[kind] for p in strength[group]]
        for name in names:
            weakest = critical.get("kind") == kind and critical.get("name") == name
            y = _column(rows, group, name)
            ax.plot(x, y, color=colors.get(name), lw=2.6 if weakest else 1.4,
                    label=f"{name} (n = {num(critical['factor'], 3)})" if weakest else name)
            if weakest and np.isfinite(y).any():
                k = int(np.nanargmax(y))
                ax.scatter([x[k]], [y[k]], color="black", zorder=4, s=28)
        ax.set_ylabel(label)
        ax.set_title(title if names else f"{title}: no part sized")
        if names:
            ax.legend(loc="upper right", framealpha=0.85, ncols=len(names))
        ax.set_xlabel(f"input angle \u03c6 ({u.angle})")
        if np.isfinite(x).any():
            ax.set_xlim(float(np.nanmin(x)), float(np.nanmax(x)))
        angle_ticks(ax, u)
    if critical:
        fig.suptitle(f"Weakest part: {critical['part']}, {critical['mode']} safety factor "
                     f"{num(critical['factor'], 3)}", fontsize=11.5, fontweight="normal")
