"""What an animation and a CAD drawing show of one solved problem (a pipeline Result),
whatever its mechanism: its Skeleton (mechanisms.protocol) at the frames of the motion,
along the whole motion (the paths), at the precision positions (ghosts), and the targets
of the report's `positions`.

The drive is the linkage's input over `Mechanism.study` (its full turn, or the arc it
rocks over), or, for a result without a linkage, the problem type's own
`types/<type>/animation.py` (`drive(result)`: the flipper's platform and cylinder).

Frames, one per kinematics step (`[motion] steps`, 360 without it) and at most MAX_FRAMES:
a full turn takes the rows of `Study.rows(n)`, n = min(steps, MAX_FRAMES); a rocking drive
goes out over `Study.rows(m)`, m = min(steps, MAX_FRAMES / 2 + 1), and back without
repeating its ends (2 m - 2 frames), so that every animation loops without a jump.

Targets, by the shape of the report's `positions` rows: [x, y] targets are points (path
generation), [x, y, angle] targets are poses (motion generation), and a number (an
output angle or a slider position at a given input) makes the row a precision position:
the linkage is ghosted at its input (MAX_GHOSTS of them at most, evenly chosen).
"""

from __future__ import annotations

import importlib.util
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.protocol import Skeleton, Study

MAX_FRAMES = 120
PATH_ROWS = 720  # rows of the drawn paths over the drive's range
MAX_GHOSTS = 6
INPUT = "input angle \u03c6"


class NothingToDraw(Exception):
    """A result with no linkage to move (the reason is the message)."""


@dataclass(frozen=True)
class Drive:
    """What moves: `skeleton(values)` at drive values (rad) over `study`'s range; `name`
    (how the frame's value is labelled); `steps` (the kinematics steps); `ghosts`: drive
    values drawn ghosted; `reference`: the drive value a CAD drawing shows (None: the
    first target's input, else the start of a full turn or the middle of a rocking arc);
    `origin`: the drive value the report's positions' inputs count from."""

    skeleton: Callable[[np.ndarray], Skeleton]
    study: Study
    name: str = INPUT
    steps: int = 360
    ghosts: tuple[float, ...] = ()
    reference: float | None = None
    origin: float = 0.0  # the drive value the report's positions inputs count from (the home's input_origin)


@dataclass(frozen=True)
class Scene:
    """One result ready to draw (lengths in the file's unit, angles in rad):
    frames/values/shown: the Skeleton at the frames, their drive values and those values as
    printed (file's angle unit); paths: PATH_ROWS rows over the range; ghosts: at the
    ghosted values (None without); reference: one row, the position a CAD drawing shows;
    points (k, 2) and poses (k, 3) the targets."""

    report: dict
    units: object
    drive: Drive
    values: np.ndarray
    shown: np.ndarray
    frames: Skeleton
    paths: Skeleton
    ghosts: Skeleton | None
    reference: Skeleton
    points: np.ndarray
    poses: np.ndarray

    @property
    def full_turn(self) -> bool:
        return self.drive.study.full_turn

    @property
    def size(self) -> float:
        """The drawing's length scale: the largest extent of the joints over the motion."""
        return self.paths.size()


def frame_values(study: Study, steps: int, cap: int = MAX_FRAMES) -> tuple[np.ndarray, np.ndarray]:
    """(values rad, shown rad) of the frames (module docstring)."""
    if study.full_turn:
        return study.rows(max(1, min(steps, cap)))
    m = max(2, min(steps, cap // 2 + 1))
    phi, shown = study.rows(m)
    back = slice(m - 2, 0, -1)
    return np.concatenate([phi, phi[back]]), np.concatenate([shown, shown[back]])


def target_rows(rows, units) -> tuple[np.ndarray, np.ndarray, list[float], list[float]]:
    """(points (k, 2), poses (k, 3) angle rad, inputs of the precision positions (rad),
    inputs of every row (rad)) from a report's positions rows."""
    points, poses, ghosts, inputs = [], [], [], []
    for row in rows or []:
        target = row.get("target")
        phi = row.get("input")
        if phi is not None:
            inputs.append(float(units.angles_to_rad(float(phi))))
        if isinstance(target, (list, tuple)) and len(target) == 2:
            points.append([float(target[0]), float(target[1])])
        elif isinstance(target, (list, tuple)) and len(target) == 3:
            poses.append([float(target[0]), float(target[1]), float(units.angles_to_rad(float(target[2])))])
        elif phi is not None:
            ghosts.append(inputs[-1])
    return (np.array(points, dtype=float).reshape(-1, 2), np.array(poses, dtype=float).reshape(-1, 3),
            ghosts, inputs)


def evenly(values: list[float], most: int = MAX_GHOSTS) -> list[float]:
    """All values, or `most` of them evenly spread (first and last kept)."""
    if len(values) <= most:
        return list(values)
    return [values[int(i)] for i in np.round(np.linspace(0, len(values) - 1, most))]


def linkage_drive(result) -> Drive:
    """The solved linkage's input over its motion study (the arc holding the targets when
    it rocks in several)."""
    from linkcli import mechanisms
    from linkcli.analysis.motion_study import motion_study
    mech = mechanisms.of(result.solution.linkage)
    span = result.solution.working_span
    study = mech.study(span[0] if span else None)
    if study is None:
        raise NothingToDraw(mech.NO_ASSEMBLY)
    _, steps = motion_study(result.problem, result.problem.meta.units)
    return Drive(mech.skeleton, study, INPUT, int(steps), origin=mech.input_origin())


def type_drive(result) -> Drive:
    """The problem type's own drive (`types/<type>/animation.py`), for a result without a
    linkage."""
    from linkcli.registry import PACKAGES
    kind = result.report.get("type")
    name = f"linkcli.types.{PACKAGES[kind]}.animation" if kind in PACKAGES else None
    if name is None or importlib.util.find_spec(name) is None:
        status = result.report.get("message") or result.report.get("status", "")
        raise NothingToDraw(f"no linkage in the result ({status})" if status else "no linkage in the result")
    return importlib.import_module(name).drive(result)


def scene_of(result, cap: int = MAX_FRAMES) -> Scene:
    """The Scene of a pipeline Result; NothingToDraw when it has nothing that moves."""
    from linkcli.plots.common import drawn
    drive = linkage_drive(result) if result.solution.linkage is not None else type_drive(result)
    report = drawn(result)
    units = result.problem.meta.units
    points, poses, ghosts, inputs = target_rows(report.get("positions"), units)
    values, shown = frame_values(drive.study, drive.steps, cap)
    with np.errstate(all="ignore"):
        frames = drive.skeleton(values)
        if not bool(np.any(frames.valid)):
            raise NothingToDraw("the linkage does not assemble over its motion")
        paths = drive.skeleton(drive.study.rows(PATH_ROWS)[0])
        ghost_values = list(drive.ghosts) + [drive.origin + g for g in evenly(ghosts)]
        ghost_sk = drive.skeleton(np.array(ghost_values)) if ghost_values else None
        reference = drive.reference
        if reference is None:
            reference = (drive.origin + inputs[0] if inputs
                         else values[0] if drive.study.full_turn else 0.5 * sum(drive.study.arc))
        ref = drive.skeleton(np.array([float(reference)]))
    if not bool(ref.valid[0]):  # a target the linkage misses: the first frame instead
        ref = drive.skeleton(values[:1])
    return Scene(report=report, units=units, drive=drive, values=values, shown=units.from_rad(shown),
                 frames=frames, paths=paths, ghosts=ghost_sk, reference=ref, points=points, poses=poses)
