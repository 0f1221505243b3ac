"""The picture of this type: the linkage at its positions and the output angle against
the input (shared with the other angle-function type, linkcli.plots.angle_function); a
slider-crank's through linkcli.plots.slider_crank (slider travel with the targets)."""

from linkcli.plots import angle_function
from linkcli.plots.angle_function import NEEDS


def draw(fig, report: dict, problem=None) -> None:
    from linkcli.plots import slider_crank
    if slider_crank.is_slider_crank(report):
        return slider_crank.draw(fig, report, problem)
    return angle_function.draw(fig, report, problem)


__all__ = ["NEEDS", "draw"]
