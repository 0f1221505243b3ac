"""The picture of this type: the four-bar at its positions and the output angle against
the input (shared with the other angle-function type, linkcli.mechanisms.four_bar.angle_plot); a
slider-crank draws itself (its home's plot: slider travel with the targets)."""

from linkcli.mechanisms.four_bar import angle_plot
from linkcli.mechanisms.four_bar.angle_plot import NEEDS


def draw(fig, result) -> None:
    from linkcli import mechanisms
    linkage = result.solution.linkage
    if linkage is not None and linkage.mechanism != "four-bar":
        return mechanisms.module(linkage.mechanism, "plot").draw(fig, result)
    return angle_plot.draw(fig, result)


__all__ = ["NEEDS", "draw"]
