"""The synthesis face of a mechanism home: how the design types (path-, motion-, function
generation, precision positions) design a mechanism without asking which one it is.

Every home has `mechanisms/<package>/face.py` holding `FACE`, a `Face`: the problem types it
designs (`designs`), and for each of them where its reader, its strategy and its figure are.
A type's schema calls `read(kind, root, meta)`, its solve module `solve(kind, problem)` and
its plot module `draw(kind, fig, result)`; each goes through the face of the mechanism the
file names (`[linkage] mechanism`, default four-bar).
A home with closed forms of its own (the four-bar's Freudenstein, Burmester and projected
Levenberg-Marquardt pipelines, the slider-crank's linear fit, the five-bar's maximin design)
names them as its strategies: they stay the same numbers. A home designed by the shared
search (linkcli.synthesis: starts, batched Levenberg-Marquardt, the KKT settle, found-twice
confirmation) hands it a `Population` -- its design variables and bounds, the geometry and
kinematics of a whole population of designs at once (designs x drive values), its
constraint residuals and the starts it knows.

Pure Python at import (`check` reads files through it without numpy).
"""

from __future__ import annotations

import importlib
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar

from linkcli.mechanisms import DEFAULT, NAMES, module

DESIGN_TYPES = ("precision-position", "function-generation", "path-generation", "motion-generation")


class Face:
    """A home's synthesis face. `strategies`: problem type -> ("module:reader",
    "module:solver"), each imported when first called: reader(root, meta) -> the frozen
    problem (None after recording its errors), solver(problem) -> Solution."""

    mechanism: ClassVar[str]
    strategies: ClassVar[dict[str, tuple[str, str]]] = {}
    figures: ClassVar[dict[str, str]] = {}  # type -> "module:function" drawing its design (--plot);
    # a type not here: the home's own figure (mechanisms/<package>/plot.py `draw`)

    @property
    def designs(self) -> tuple[str, ...]:
        return tuple(kind for kind in DESIGN_TYPES if kind in self.strategies)

    def read(self, kind: str, root, meta):
        return _named(self.strategies[kind][0])(root, meta)

    def solve(self, kind: str, problem):
        return _named(self.strategies[kind][1])(problem)

    def draw(self, kind: str, fig, result) -> None:
        if kind in self.figures:
            return _named(self.figures[kind])(fig, result)
        return module(self.mechanism, "plot").draw(fig, result)


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
    from linkcli.mechanisms.schema import mechanism_of
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


def draw(kind: str, fig, result) -> None:
    """The figure of a design (--plot), by the face of the mechanism it designed (its linkage's;
    without one, the problem's)."""
    linkage = result.solution.linkage if result.solution is not None else None
    name = linkage.mechanism if linkage is not None else getattr(result.problem, "mechanism", DEFAULT)
    return face(name).draw(kind, fig, result)


# ---------------------------------------------------------------- the shared search's side

@dataclass
class Motion:
    """What a population's kinematics gives at drive values q (N designs x S values): points
    (N, S, P, 2) of the traced joints (`Population.traced`); angles (N, S, L) and frame
    origins (N, S, L, 2) of the followed links (`Population.followed`); valid (N, S): every
    closure closes there on its drawn side; margins (N, S, C): each closure's distance from
    locking (length unit, < 0 where it cannot close); transmission (N, S, C): each closure's
    transmission angle (rad)."""

    points: Any
    angles: Any
    origins: Any
    valid: Any
    margins: Any
    transmission: Any


class Population(ABC):
    """The designs of one home for one problem, vectorized over designs (numpy): a design is
    a row x (nx,) of `names` within [lo, hi]; drive values are offsets q from the design's
    drawn position (rad, 0 = as drawn). `traced` are the points whose paths and `followed`
    the links whose frames a kinematics call reports; `closures` name the closures."""

    names: tuple[str, ...]
    lo: Any
    hi: Any
    traced: tuple[str, ...] = ()
    followed: tuple[str, ...] = ()
    closures: tuple[str, ...] = ()
    held: tuple[str, ...] = ()  # what was given a box but moves nothing measured: held where drawn
    evaluation_cost: float = 1.0  # an evaluation's cost over a closed-form plan's: the default budget's divisor

    @abstractmethod
    def geometry(self, x):
        """The home's geometry record of N designs (N, nx): what their drawings are."""

    @abstractmethod
    def kinematics(self, x, q) -> Motion:
        """The population's motion at drive values q (N, S) (each design its own row)."""

    def constraints(self, motion: Motion, window=None):
        """(g, kinds): constraint residuals g (N, S, M) at the drive values of `motion`
        (g <= 0 feasible) and the kind of each of the M columns: ("assembly", closure) --
        -margin, length unit: assembly on the drawn side, and over a travel no dead point;
        ("transmission", closure) -- window[0] - mu and mu - window[1], rad."""
        import numpy as np
        cols = [-motion.margins]
        kinds = [("assembly", c) for c in self.closures]
        if window is not None:
            cols += [window[0] - motion.transmission, motion.transmission - window[1]]
            kinds += [("transmission", c) for c in self.closures] * 2
        return np.concatenate(cols, axis=-1), tuple(kinds)

    def phase_variable(self) -> int | None:
        """The home variable to hold where a design's drawing may be its configuration at any
        drive value (the timing shifted back: a flat direction of every objective), or None."""
        return None

    def placement_free(self) -> bool:
        """Whether the whole design may be moved, turned and scaled (the shared starts then
        fit its placement to the targets in closed form: z -> g + u z on the home's variables,
        taken as pairs (x, y))."""
        return False

    @abstractmethod
    def starts(self, rng, count: int):
        """(count, nx) designs the home knows to be good places to start (the drawing, and
        what it draws from it)."""

    @abstractmethod
    def size(self, x):
        """(N,) each design's length scale."""

    def round_off_scales(self, x):
        """(N, nx) the scale of each variable of N designs, below NOISE_FLOOR of which it is
        round-off (noise.snap): every variable a length or a coordinate, `size`."""
        import numpy as np
        x = np.atleast_2d(np.asarray(x, dtype=float))
        return np.repeat(np.asarray(self.size(x), dtype=float)[:, None], x.shape[1], axis=1)

    @abstractmethod
    def linkage(self, x):
        """The model linkage of one design x (nx,): what the report and `analyze` read."""
