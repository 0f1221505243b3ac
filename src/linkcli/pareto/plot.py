"""The front's drawing (`--plot` of a report with a `front` section): two objectives, the
front as a curve with the knee marked; three, the three pairwise panels, the knee marked in
each. Draws on the (sub)figure it is handed; never imports matplotlib itself."""

from __future__ import annotations

HEIGHT = 3.4  # inches of the front's panel under the design's drawing
PAIRS = ((0, 1), (0, 2), (1, 2))


def label(front: dict, name: str) -> str:
    unit = front.get("units", {}).get(name)
    return f"{name} ({unit})" if unit and unit != "1" else name


def draw(fig, result) -> None:
    """The front of result.report["front"] on `fig`."""
    front = result.report["front"]
    names = front["objectives"]
    rows = [[row["objectives"][n] for n in names] for row in front["rows"]]
    knee = front["knee"]["index"]
    pairs = PAIRS[:1] if len(names) == 2 else PAIRS
    axes = fig.subplots(1, len(pairs), squeeze=False)[0]
    for ax, (i, j) in zip(axes, pairs):
        xs, ys = [r[i] for r in rows], [r[j] for r in rows]
        if len(names) == 2:
            ax.plot(xs, ys, "-o", color="C0", markersize=4, label="front")
        else:
            ax.plot(xs, ys, "o", color="C0", markersize=4, label="front")
        ax.plot([xs[knee]], [ys[knee]], "*", color="C3", markersize=14, label=f"knee (row {knee})")
        ax.set_xlabel(label(front, names[i]))
        ax.set_ylabel(label(front, names[j]))
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize="small")
    fig.suptitle(f"Pareto front: {len(rows)} designs, hypervolume {front['hypervolume']:.6g}", fontsize="medium")
