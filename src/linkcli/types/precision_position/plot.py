"""The picture of this type, by the mechanism's synthesis face: the four-bar at its positions
and the output angle against the input (mechanisms.four_bar.angle_plot, shared with function
generation); a slider-crank draws itself (its home's plot: slider travel with the targets)."""

from linkcli.mechanisms.four_bar.angle_plot import NEEDS


def draw(fig, result) -> None:
    """The design's figure, by its mechanism's synthesis face (the four-bar's: angle_plot)."""
    from linkcli.mechanisms import synthesis
    return synthesis.draw("precision-position", fig, result)


__all__ = ["NEEDS", "draw"]
