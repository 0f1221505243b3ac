"""Mechanism homes: one package per mechanism, `mechanisms/<package>/`, holding everything
specific to it (kinematics, its [linkage] keys, report sections, loads, made parts, drawing)
behind one protocol: `protocol.Mechanism` (a linkage's numbers) and `schema.Schema` (its tables). Shared code calls `of(linkage)` and the protocol;
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


def schema_of(name: str):
    """The `mechanisms.schema.Schema` of the mechanism `name` (its vocabulary and readers)."""
    return module(name, "schema").SCHEMA


def of_class_section(class_section: dict):
    """The Schema of the mechanism whose class section has these keys, None for none (a
    report holds sections, not linkages: its tables are laid out from what they hold)."""
    keys = tuple(class_section)
    return next((schema_of(name) for name in NAMES if schema_of(name).class_keys == keys), None)
