"""The five-bar's synthesis face (mechanisms.synthesis): path generation, the lengths and
pivot under which the path lies in one pair of working modes with the best worst
conditioning or transmission along it (mechanisms.five_bar.synthesis scores a population;
types/path_generation/five_bar_design_solve.py searches it)."""

from __future__ import annotations

from linkcli.mechanisms.synthesis import Face


class FiveBarFace(Face):
    mechanism = "five-bar"
    strategies = {
        "path-generation": ("linkcli.types.path_generation.five_bar_design:parse",
                            "linkcli.types.path_generation.five_bar_design_solve:solve"),
    }


FACE = FiveBarFace()
