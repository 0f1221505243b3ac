"""One drawing module per problem type, each exposing `NEEDS` (the report sections it
draws from), `PROBLEM` (whether it also reads the problem file: input speed, platform
load) and `draw(fig, report, problem)`.

Every module imports matplotlib only through the `Figure` it is handed, so importing
this package never imports matplotlib; `linkcli.plot` does that, on demand.
"""

from __future__ import annotations

import importlib

MODULES = {
    "precision-position": "function",
    "function-generation": "function",
    "path-generation": "path",
    "flipper-cylinder": "flipper",
    "linkage": "linkage",
}


def module_for(kind: str):
    """The drawing module of a problem type (KeyError for an unknown type)."""
    return importlib.import_module(f"linkcli.plots.{MODULES[kind]}")
