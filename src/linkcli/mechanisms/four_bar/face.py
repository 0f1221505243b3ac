"""The four-bar's synthesis face (mechanisms.synthesis): it designs every design type with
closed forms of its own -- Freudenstein's equations (precision positions, the starts of
function generation), the coupler curve's timing hypotheses and linear fits with projected
Levenberg-Marquardt (path generation), Burmester theory and its least squares (motion
generation). They were written in the type packages (types/<type>/) and stay there: the
face names them."""

from __future__ import annotations

from linkcli.mechanisms.synthesis import Face


class FourBarFace(Face):
    mechanism = "four-bar"
    strategies = {
        "precision-position": ("linkcli.types.precision_position.schema:parse_positions",
                               "linkcli.types.precision_position.solve:solve_four_bar"),
        "function-generation": ("linkcli.types.function_generation.schema:parse_four_bar",
                                "linkcli.types.function_generation.solve:solve_four_bar"),
        "path-generation": ("linkcli.types.path_generation.schema:parse_four_bar",
                            "linkcli.types.path_generation.solve:solve_four_bar"),
        "motion-generation": ("linkcli.types.motion_generation.schema:parse_four_bar",
                              "linkcli.types.motion_generation.solve:solve_four_bar"),
    }
    figures = {
        "precision-position": "linkcli.mechanisms.four_bar.angle_plot:draw",
        "function-generation": "linkcli.mechanisms.four_bar.angle_plot:draw",
        "path-generation": "linkcli.types.path_generation.plot:draw_four_bar",
        "motion-generation": "linkcli.types.motion_generation.plot:draw_four_bar",
    }


FACE = FourBarFace()
