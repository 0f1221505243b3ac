"""The catalogue of six-bar topologies for synthesis on drawn linkages (docs/six_bars.md):
the five inversions of the Watt and Stephenson chains (enumerated by drawn.chains), their
drives and targets, named, and starting drawings of each (drawn.starts), the four-bar beside
them as the baseline.

A `Choice` is one topology to search: an inversion, the link that drives it (turning about
its ground pivot) and the target link (the tracer's, the guided body's, or the function's
output). Links are named by role: "crank" (the drive), "output" (a function's target), the
other links pinned to the ground "rocker", "rocker2", the links pinned to the crank but not to
the ground "coupler", "coupler2", the rest "link", "link2". Ground pivots are O1 (the crank's),
O2, O3; moving pins A, B, C, ... in the order the links are named; the tracer P (on the target
link, after its pins); a body's frame P (origin), Q (on its x axis), first on the target link.
Names depend only on the topology, the drive and the target: the same on every call.

Pure Python down to `starting_drawings` (which imports numpy).
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass
from functools import lru_cache

from linkcli.mechanisms.drawn.chains import FREE, TIMED, Inversion, inversions
from linkcli.mechanisms.drawn.topology import ANY_SIX_BAR, SIX_BARS, topologies

BASELINE = "four-bar"
TASKS = ("path", "motion", "function")
TIMINGS = (TIMED, FREE)  # "prescribed", "any"


@dataclass(frozen=True)
class Choice:
    """One topology to search. `topology`: an inversion's name (or "four-bar"); `task`:
    "path", "motion" or "function"; `drive`, `target`: link names in its drawings;
    `timing`: "any" (goes beyond the four-bar with free timing too) or "prescribed" (a
    four-bar's curve or poses with the six-bar's timing; every function); `crank`: "binary"
    or "ternary" (the driven link: a bar, or a plate on three pins); `plan`: "four-bar",
    "four-bar and dyad" or "triad" (how the drive determines the rest: a four-bar loop, then
    a dyad; or one Assur group of four links); `inversion`, `drive_link`, `target_link`: the
    chain's graph and its links."""

    topology: str
    task: str
    drive: str
    target: str
    timing: str
    crank: str
    plan: str
    inversion: Inversion
    drive_link: int
    target_link: int

    @property
    def label(self) -> str:
        """Unique in the catalogue: "stephenson-iii, binary crank (triad), tracer P on link"."""
        what = {"path": f"tracer P on {self.target}", "motion": f"body {self.target}",
                "function": "output link"}[self.task]
        return f"{self.topology}, {self.crank} crank ({self.plan}), {what}"


def _inversion(name: str) -> Inversion:
    pool = inversions(4) if name == BASELINE else inversions(6)
    return next(inv for inv in pool if inv.name == name)


def topology_names(value: str) -> tuple[str, ...]:
    """The inversions a `topology` value stands for ("any six-bar": all five)."""
    if value in SIX_BARS + (ANY_SIX_BAR, BASELINE):
        return topologies(value)
    raise ValueError(f"a topology of {', '.join(SIX_BARS + (ANY_SIX_BAR, BASELINE))}, not {value!r}")


def choices(topology: str, task: str, timing: str = TIMED) -> tuple[Choice, ...]:
    """Every choice of drive and target of `topology` (an inversion's name, "any six-bar",
    or "four-bar") for `task`, in catalogue order; with timing = "any" (free timing of a path
    or a motion) only those that go beyond the four-bar without prescribed timing (a
    function is timed by nature: its timing is not a filter)."""
    if task not in TASKS:
        raise ValueError(f"a task of {', '.join(TASKS)}, not {task!r}")
    if timing not in TIMINGS:
        raise ValueError(f"a timing of {', '.join(TIMINGS)}, not {timing!r}")
    out = []
    for name in topology_names(topology):
        inv = _inversion(name)
        for drive in inv.drives():
            plan = ("four-bar" if inv.chain.links == 4 else
                    "four-bar and dyad" if inv.loop_with(drive) is not None else "triad")
            for target, how in inv.targets(drive, task):
                if timing == FREE and how != FREE and task != "function":
                    continue
                names = link_names(inv, drive, target, task)
                crank = "ternary" if inv.chain.degree(drive) == 3 else "binary"
                out.append(Choice(name, task, names[drive], names[target], how, crank, plan, inv, drive, target))
    return tuple(out)


def timing_of(task: str, timing: str) -> str:
    """The catalogue's timing for a task and a problem's timing: FREE ("any") for a
    free-timing path or motion (only the choices whose curves or motions go beyond a
    four-bar's), else TIMED."""
    return FREE if task != "function" and timing == "free" else TIMED


def empty_reason(topology: str, task: str, timing: str = TIMED) -> str | None:
    """Why `topology` offers no choice for this task and timing (a sentence for an error
    line), or None when it offers some."""
    if choices(topology, task, timing):
        return None
    if task == "function":
        return (f"{topology} has no output link that a four-bar loop with the ground and the crank "
                "does not move alone (its function is a four-bar's)")
    if timing == FREE and choices(topology, task, TIMED):
        return (f"with free timing, every {'curve' if task == 'path' else 'motion'} of {topology} is "
                "a four-bar's (prescribed timing makes it a six-bar's)")
    return f"every {'curve' if task == 'path' else 'motion'} of {topology} is a four-bar's"


# ---------------------------------------------------------------- names

def link_names(inv: Inversion, drive: int, target: int, task: str) -> dict[int, str]:
    """Link -> name (module docstring); the ground is absent."""
    chain, g = inv.chain, inv.ground
    pivoted = [v for v in chain.neighbours(g) if v not in (drive, target if task == "function" else -1)]
    floating = inv.floating()
    near = [v for v in floating if chain.adjacent(v, drive)]
    far = [v for v in floating if v not in near]
    names = {drive: "crank"}
    if task == "function":
        names[target] = "output"
    for stem, group in (("rocker", pivoted), ("coupler", near), ("link", far)):
        for i, v in enumerate(group):
            names[v] = stem if i == 0 else f"{stem}{i + 1}"
    return names


def _order(names: dict[int, str]) -> list[int]:
    rank = {"crank": 0, "coupler": 1, "rocker": 2, "link": 3, "output": 4}
    return sorted(names, key=lambda v: (rank[names[v].rstrip("0123456789")], names[v]))


def joint_names(inv: Inversion, names: dict[int, str]) -> dict[tuple[int, int], str]:
    """Pin (pair of links) -> name: ground pivots O1 (the crank's), O2, ... and moving pins
    A, B, ... in the order of the links' names."""
    g = inv.ground
    out: dict[tuple[int, int], str] = {}
    pivots = moving = 0
    for v in _order(names):
        for w in sorted(inv.chain.neighbours(v), key=lambda w: (w != g, _order(names).index(w) if w != g else 0)):
            edge = (min(v, w), max(v, w))
            if edge in out:
                continue
            if w == g:
                pivots += 1
                out[edge] = f"O{pivots}"
            else:
                out[edge] = chr(ord("A") + moving)
                moving += 1
    return out


# ---------------------------------------------------------------- drawings

def starting_drawings(choice: Choice, box, seed: int = 0, count: int = 3):
    """`count` starting drawings of a choice (tuple of drawn.model.Drawn): each assembles,
    its crank turns fully with every closure away from its dead points (drawn.starts), the
    tracer's path (a body's origin; for a function the whole linkage) fitted into `box` =
    (x_lo, y_lo, x_hi, y_hi). The same seed gives the same drawings; drawing k comes from
    its own stream (seed, k, the choice's label), so the first ones do not depend on count."""
    import numpy as np

    from linkcli.mechanisms.drawn import starts
    if count < 1:
        raise ValueError(f"a count of at least 1, not {count}")
    out = []
    tag = zlib.crc32(choice.label.encode("utf-8"))
    keep = closure_pins(choice)
    for k in range(count):
        rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence([int(seed) & (2**63 - 1), k, tag])))
        at = starts.sketch(choice.inversion, choice.drive_link, choice.target_link, choice.task, rng, keep)
        out.append(_drawing(choice, starts.fit(at, choice.task, box, rng)))
    return tuple(out)


@lru_cache(maxsize=64)
def closure_pins(choice: Choice) -> tuple:
    """(first, joint, second) pins (pairs of links) of every closure linkcli measures on this
    choice's drawings (structure.Closure: a dyad's two links, a group's links along their lines
    to their next listed joints). The plan does not depend on the places: found once, on the
    drawing with every joint on a parabola (no three in line)."""
    from linkcli.mechanisms.drawn.structure import analyse
    inv = choice.inversion
    pins = joint_names(inv, link_names(inv, choice.drive_link, choice.target_link, choice.task))
    keys = sorted(pins) + ["P", "Q"]
    layout = {key: (float(k), float(k * k)) for k, key in enumerate(keys)}
    structure = analyse(_drawing(choice, {k: v for k, v in layout.items() if k in pins or _carries(choice, k)}))
    edge = {name: key for key, name in pins.items()}
    return tuple((edge[c.first], edge[c.joint], edge[c.second]) for c in structure.closures()
                 if c.kind == "pin" and {c.first, c.joint, c.second} <= edge.keys())


def _carries(choice: Choice, point: str) -> bool:
    """Whether the choice's drawings have the point P or Q."""
    return choice.task == "motion" or (choice.task == "path" and point == "P")


def _drawing(choice: Choice, places: dict):
    """The drawn.model.Drawn of a choice from the places of its pins (pairs of links) and of
    P, Q."""
    from linkcli.mechanisms.drawn.model import TURN, Drawn, DrawnJoint, DrawnLink, Drive
    inv = choice.inversion
    names = link_names(inv, choice.drive_link, choice.target_link, choice.task)
    pins = joint_names(inv, names)
    g = inv.ground
    joints = [DrawnJoint(name, places[edge], ground=g in edge)
              for edge, name in sorted(pins.items(), key=lambda item: (item[1][0] != "O", item[1]))]
    extra = [p for p in ("P", "Q") if p in places]
    joints += [DrawnJoint(p, places[p]) for p in extra]
    links = []
    for v in _order(names):
        carried = sorted((pins[(min(v, w), max(v, w))] for w in inv.chain.neighbours(v)),
                         key=lambda n: (n[0] != "O", n))
        if v == choice.target_link and extra:
            carried = (extra + carried) if choice.task == "motion" else (carried + extra)
        links.append(DrawnLink(names[v], tuple(carried)))
    return Drawn(joints=tuple(joints), links=tuple(links), drives=(Drive("crank", TURN, 1.0),),
                 points=("P",) if extra else (),
                 output=choice.target if choice.task == "function" else None)


def to_tables(drawing) -> dict:
    """The [joints], [links] and [drive] tables of a drawing (a TOML document's dict)."""
    joints = {}
    for j in drawing.joints:
        entry = {"at": [j.at[0], j.at[1]]}
        if j.ground:
            entry["ground"] = True
        joints[j.name] = entry
    return {"joints": joints, "links": {k.name: list(k.joints) for k in drawing.links},
            "drive": {d.name: {} for d in drawing.drives}}
