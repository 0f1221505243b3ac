"""Mechanism homes: one package per mechanism, `mechanisms/<package>/`, holding everything
specific to it (kinematics, its [linkage] keys, report sections, loads, made parts, drawing)
behind one protocol (`protocol.Mechanism`). Shared code calls `of(linkage)` and the protocol;
it never asks which mechanism it holds. A new mechanism is one package and one line here.

Light (no numpy): `check` reads the names and the schemas through it.
"""

from __future__ import annotations

import importlib

PACKAGES = {  # the `[linkage] mechanism` value -> its package under linkcli.mechanisms
    "four-bar": "four_bar",
    "slider-crank": "slider_crank",
    "five-bar": "five_bar",
    "drawn": "drawn",
}
NAMES = tuple(PACKAGES)
DEFAULT = "four-bar"  # a [linkage] without `mechanism`


def module(name: str, part: str):
    """`part` (schema, home, kinematics, ...) of the mechanism `name`, imported on demand."""
    return importlib.import_module(f"linkcli.mechanisms.{PACKAGES[name]}.{part}")


def of(linkage):
    """The protocol.Mechanism of a linkage (a model dataclass naming its `mechanism`)."""
    return module(linkage.mechanism, "home").HOME(linkage)


def layout_of(class_section: dict):
    """The `layout` module of the mechanism whose class section has these keys (a report
    holds sections, not linkages: its tables are laid out from what they hold)."""
    keys = tuple(class_section)
    for name in NAMES:
        layout = module(name, "layout")
        if keys == layout.CLASS_KEYS:
            return layout
    return None
