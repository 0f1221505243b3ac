"""The slider-crank's synthesis face (mechanisms.synthesis): precision positions, exact for
three (crank angle, slider position) pairs through the linear equation of SPEC, least
squares on the true slider error beyond (types/precision_position/slider_synthesis.py)."""

from __future__ import annotations

from linkcli.mechanisms.synthesis import Face


class SliderCrankFace(Face):
    mechanism = "slider-crank"
    strategies = {
        "precision-position": ("linkcli.types.precision_position.schema:parse_positions",
                               "linkcli.types.precision_position.slider:solve"),
    }


FACE = SliderCrankFace()
