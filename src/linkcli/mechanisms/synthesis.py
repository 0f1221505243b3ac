"""The synthesis face of a mechanism home: how the design types (path-, motion-, function
generation, precision positions) design a mechanism without asking which one it is.

Every home has `mechanisms/<package>/face.py` holding `FACE`, a `Face`: the problem types it
designs (`designs`), and for each of them where its reader and its strategy are. A type's
schema calls `read(kind, root, meta)` and its solve module `solve(kind, problem)`; both go
through the face of the mechanism the file names (`[linkage] mechanism`, default four-bar).
A home with closed forms of its own (the four-bar's Freudenstein, Burmester and projected
Levenberg-Marquardt pipelines, the slider-crank's linear fit, the five-bar's maximin design)
names them as its strategies: they stay the same numbers.

Pure Python at import (`check` reads files through it without numpy).
"""

from __future__ import annotations

import importlib
from typing import ClassVar

from linkcli.mechanisms import DEFAULT, NAMES, module

DESIGN_TYPES = ("precision-position", "function-generation", "path-generation", "motion-generation")


class Face:
    """A home's synthesis face. `strategies`: problem type -> ("module:reader",
    "module:solver"), each imported when first called: reader(root, meta) -> the frozen
    problem (None after recording its errors), solver(problem) -> Solution."""

    mechanism: ClassVar[str]
    strategies: ClassVar[dict[str, tuple[str, str]]] = {}

    @property
    def designs(self) -> tuple[str, ...]:
        return tuple(kind for kind in DESIGN_TYPES if kind in self.strategies)

    def read(self, kind: str, root, meta):
        return _named(self.strategies[kind][0])(root, meta)

    def solve(self, kind: str, problem):
        return _named(self.strategies[kind][1])(problem)


def _named(where: str):
    path, name = where.split(":")
    return getattr(importlib.import_module(path), name)


def face(name: str) -> Face:
    """The synthesis face of the mechanism `name`."""
    return module(name, "face").FACE


def designers(kind: str) -> tuple[str, ...]:
    """The mechanisms whose homes design problems of type `kind`, in mechanisms.NAMES order."""
    return tuple(name for name in NAMES if kind in face(name).designs)


def read(kind: str, root, meta):
    """The frozen problem of a design file of type `kind`: read by the face of the mechanism
    its [linkage] names. A mechanism whose home does not design this type is one located
    line naming those that do (and nothing more: its other keys belong to no reader)."""
    from linkcli.io.loads import mechanism_of
    name = mechanism_of(root)
    if kind in face(name).designs:
        link = root.data.get("linkage")
        if isinstance(link, dict) and "mechanism" in link:
            root.reader.mark(("linkage",), "mechanism")  # read here: a reader need not know it
        return face(name).read(kind, root, meta)
    t = root.table("linkage")
    t.allow(*t.keys())
    t.string("mechanism", DEFAULT, choices=designers(kind))  # the line: one of those that do
    for table in root.keys():
        if table not in ("type", "title"):
            root.allow(table)
    return None


def solve(kind: str, problem):
    """The Solution of a design problem, by the strategy of its mechanism's face."""
    return face(problem.mechanism).solve(kind, problem)
