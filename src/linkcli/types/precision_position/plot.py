"""The picture of this type: the linkage at its positions and the output angle against
the input (shared with the other angle-function type, linkcli.plots.angle_function)."""

from linkcli.plots.angle_function import NEEDS, draw

__all__ = ["NEEDS", "draw"]
