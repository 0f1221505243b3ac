"""The dynamics sections drawn under any type's figure (docs/dynamics.md): a run's history (the
drive's angle and speed, the drive's torque and the elements' forces, the pin forces, all over
time, with the events marked), and the balance (the shaking force's path on the frame and the
shaking moment over the cycle, as given and balanced). Nothing is solved here: the report's
`history`, `events` and `balance` are drawn."""

from __future__ import annotations

import numpy as np

from linkcli.plots.common import drawn, num

HEIGHT = 3.6  # inches added to the figure for each panel
PIN_COLORS = {"A0": "#1f77b4", "A": "#d62728", "B": "#2ca02c", "B0": "#9467bd", "guide": "#8c564b", "P": "#ff7f0e"}
EVENT_COLORS = {"stop": "#111111", "dead-point": "#d62728", "reversal": "#7f7f7f", "mark": "#2ca02c"}


def _column(rows, get) -> np.ndarray:
    return np.array([np.nan if get(r) is None else get(r) for r in rows], dtype=float)


class History:
    """The history panel: three axes side by side."""

    HEIGHT = HEIGHT

    @staticmethod
    def draw(fig, result) -> None:
        report = drawn(result)
        rows = report["history"]
        au = result.problem.meta.units.angle
        t = _column(rows, lambda r: r["time"])
        ax_a, ax_t, ax_f = fig.subplots(1, 3, sharex=True)
        drives = list(rows[0]["drives"]) if "drives" in rows[0] else [None]  # several drives: each
        ax_s = ax_a.twinx()
        for drive, style in zip(drives, ("-", "--", ":")):
            def pick(r, key, d=drive):
                return r[key] if d is None else r["drives"][d][{"drive_torque": "torque"}.get(key, key)]
            tag = "" if drive is None else f" {drive}"
            ax_a.plot(t, _column(rows, lambda r: pick(r, "angle")), color="#1f77b4", lw=1.8, ls=style, label=f"angle{tag}")
            ax_s.plot(t, _column(rows, lambda r: pick(r, "speed")), color="#ff7f0e", lw=1.4, ls=style, label=f"speed{tag}")
            ax_t.plot(t, _column(rows, lambda r: pick(r, "drive_torque")), color="#111111", lw=1.8, ls=style,
                      label="drive" if drive is None else drive)
        ax_a.set_ylabel(f"drive angle ({au})", color="#1f77b4")
        ax_s.set_ylabel(f"speed ({au}/s)", color="#ff7f0e")
        ax_s.grid(False)
        if drive is not None:
            ax_a.legend(loc="best", framealpha=0.85)
        sim = report.get("simulation", {})
        title = "Drive angle and speed" if drive is None else "Drive angles and speeds"
        if sim.get("stop_time") is not None and drive is None:
            title += f" (stop at {num(sim['stop_time'])} s, {num(sim['stop_speed'])} {au}/s)"
        elif sim.get("stop_time") is not None:
            title += f" ({sim.get('stop_drive')} stops at {num(sim['stop_time'])} s)"
        ax_a.set_title(title)
        for name in rows[0].get("elements", {}):
            ax_t.plot(t, _column(rows, lambda r, n=name: r["elements"][n]), lw=1.4, label=name)
        ax_t.axhline(0.0, color="#777777", lw=0.8)
        ax_t.set_ylabel("torque (N m) / force (N)")
        ax_t.set_title("Drive torque and element forces")
        ax_t.legend(loc="best", framealpha=0.85)
        for name in rows[0].get("pins", {}):
            ax_f.plot(t, _column(rows, lambda r, n=name: r["pins"][n]["magnitude"]),
                      color=PIN_COLORS.get(name), lw=1.5, label=name)
        ax_f.set_ylabel("pin force magnitude (N)")
        ax_f.set_title("Pin forces")
        ax_f.legend(loc="best", framealpha=0.85, ncols=2)
        for ax in (ax_a, ax_t, ax_f):
            ax.set_xlabel("time (s)")
            for event in report.get("events", [])[:20]:
                ax.axvline(event["time"], color=EVENT_COLORS.get(event["event"], "#777777"), lw=0.8, ls="--")
            if np.isfinite(t).any() and t[-1] > t[0]:
                ax.set_xlim(float(t[0]), float(t[-1]))


class Balance:
    """The balance panel: the shaking force's path (x against y) and the shaking moment over
    the cycle, as given and balanced."""

    HEIGHT = HEIGHT

    @staticmethod
    def draw(fig, result) -> None:
        report = drawn(result)
        rows = report["balance"]["cycle"]
        au = result.problem.meta.units.angle
        x = _column(rows, lambda r: r["input"])
        ax_f, ax_m = fig.subplots(1, 2)
        styles = {"unbalanced": ("#d62728", "as given"), "balanced": ("#2ca02c", "balanced")}
        for case, (color, label) in styles.items():
            if case not in rows[0]:
                continue
            fx = _column(rows, lambda r, c=case: r[c]["shaking_force"]["x"])
            fy = _column(rows, lambda r, c=case: r[c]["shaking_force"]["y"])
            ax_f.plot(np.append(fx, fx[:1]), np.append(fy, fy[:1]), color=color, lw=1.8, label=label,
                      marker="o" if case == "balanced" else None, ms=3)
            ax_m.plot(x, _column(rows, lambda r, c=case: r[c]["shaking_moment"]), color=color, lw=1.8, label=label)
        ax_f.set_aspect("equal", adjustable="datalim")
        ax_f.set_xlabel("shaking force x (N)")
        ax_f.set_ylabel("shaking force y (N)")
        ax_f.set_title("Shaking force on the frame over a cycle")
        ax_f.legend(loc="best", framealpha=0.85)
        ax_m.axhline(0.0, color="#777777", lw=0.8)
        ax_m.set_xlabel(f"input angle ({au})")
        ax_m.set_ylabel("shaking moment (N m)")
        ax_m.set_title("Shaking moment about the drive's pivot")
        ax_m.legend(loc="best", framealpha=0.85)


def panels(report: dict) -> list:
    """The panels a report's dynamics sections draw."""
    out = []
    if report.get("history"):
        out.append(History)
    if report.get("balance", {}).get("cycle"):
        out.append(Balance)
    return out
