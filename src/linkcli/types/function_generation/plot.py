"""The picture of this type: the linkage at its positions and the output angle against
the input (shared with the other angle-function type, linkcli.mechanisms.four_bar.angle_plot)."""

from linkcli.mechanisms.four_bar.angle_plot import NEEDS, draw

__all__ = ["NEEDS", "draw"]
