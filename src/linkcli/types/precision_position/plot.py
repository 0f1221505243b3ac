"""The picture of this type: the linkage at its positions and the output angle against
the input (shared with the other angle-function type, linkcli.plots.angle_function); a
slider-crank's through linkcli.plots.slider_crank (slider travel with the targets)."""

from linkcli.plots import angle_function
from linkcli.plots.angle_function import NEEDS


def draw(fig, result) -> None:
    from linkcli.plots import slider_crank
    from linkcli.plots.common import drawn
    if slider_crank.is_slider_crank(drawn(result)):
        return slider_crank.draw(fig, result)
    return angle_function.draw(fig, result)


__all__ = ["NEEDS", "draw"]
