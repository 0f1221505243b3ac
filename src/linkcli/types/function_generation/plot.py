"""The picture of this type: the four-bar at its positions and the output angle against
the input (shared with the other angle-function type, linkcli.plots.angle_function); another
mechanism's design draws itself (its home's plot: a drawn design's targets)."""

from linkcli.plots import angle_function
from linkcli.plots.angle_function import NEEDS


def draw(fig, result) -> None:
    from linkcli import mechanisms
    linkage = result.solution.linkage
    if linkage is not None and linkage.mechanism != "four-bar":
        return mechanisms.module(linkage.mechanism, "plot").draw(fig, result)
    return angle_function.draw(fig, result)


__all__ = ["NEEDS", "draw"]
