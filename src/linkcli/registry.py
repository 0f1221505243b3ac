"""The problem types: a type is one package under `linkcli.types` plus one line here.

Each package `linkcli.types.<package>` declares its vocabulary in `__init__.py` as
`TYPE = ProblemType(...)` (light: no numpy) and holds `schema.py` (file -> frozen
problem), `solve.py` (problem -> Solution), `sections.py` (its own report sections) and
`plot.py` (draws a Result). The modules are imported only when asked for, so `check`
never imports numpy and a closed-form type never imports scipy.
"""

from __future__ import annotations

import importlib
from typing import NamedTuple

PACKAGES = {  # the `type` key of a problem file -> its package under linkcli.types
    "precision-position": "precision_position",
    "function-generation": "function_generation",
    "path-generation": "path_generation",
    "flipper-cylinder": "flipper_cylinder",
    "linkage": "linkage",
    "motion-generation": "motion_generation",
    "quick-return": "quick_return",
}
NAMES = tuple(PACKAGES)


class ProblemType(NamedTuple):
    """What the reader and `linkcli bench` need to know of a type before solving it."""

    package: str
    methods: tuple[str, ...]  # [solver] method values, "auto" first
    default_sections: tuple[str, ...]  # reported when [report] sections is absent
    sections: tuple[str, ...]  # every section the type can report
    tolerance: bool  # reads a [tolerance] table
    bench_settings: tuple[tuple[str, int | None], ...] = ()  # (method, budget); () -> each method
    atlas: bool = False  # reads [solver] atlas (linkcli.atlas: free-timing path starts)

    def module(self, name: str):
        """`schema`, `solve`, `sections` or `plot` of this type, imported on demand."""
        return importlib.import_module(f"linkcli.types.{self.package}.{name}")


def problem_type(name: str) -> ProblemType:
    """The type of a `type` key (KeyError for an unknown one)."""
    return importlib.import_module(f"linkcli.types.{PACKAGES[name]}").TYPE
