"""The five-bar over the rows of its [motion]: forward or inverse kinematics of every row at
once, the drives' speeds per row, the metamorphic phases' four-bars, and what keeps a row
from being reached (the defects that make a report exit 1).

Forward (`inputs`): P = meet(A, B, coupler, coupler2, branch) at every row; a row where the
distal links cannot reach each other (|A B| outside [|b1 - b2|, b1 + b2]) cannot assemble.
The branch is kept at every row (the side of A -> B that P lies on), and each chain's
working mode is read off per row (it changes where a chain passes stretched or folded: a
type I singularity, which two driven cranks pass through).

Inverse (`path`): each chain's elbow from P in its working mode (kinematics.inverse). A row
is out of the workspace when a chain cannot reach P (|P - pivot| outside [|a - b|, a + b]).
The assembly mode is the side of A -> B that P lies on at the first row (or `branch` when
given, which the path must then keep); a row on the other side means the distal links
passed in line between it and the row before (a type II singularity crossed: the drives
alone cannot carry P over it). The path between two rows is taken as the straight segment:
a segment that dips into a chain's folded limit (the disc |P - pivot| < |a - b|, convex, so
the ends alone do not show it) leaves the workspace between the rows.

Phases (a drive held over rows first..last): the mechanism is the four-bar left with the
driven crank's pivot and the held elbow as its ground pivots (input = the driven crank,
coupler = its distal link, output = the held chain's distal link, ground = from the driven
crank's pivot to the held elbow); P is that four-bar's output pin, so over the phase P
runs on the circle of radius `output` about the held elbow: a path row of a phase farther
than PHASE_RTOL x size from that circle is a defect.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from linkcli.angles import wrap
from linkcli.mechanisms.five_bar import kinematics as kin
from linkcli.mechanisms.five_bar.model import DRIVES, FiveBar, Phase
from linkcli.mechanisms.four_bar import kinematics as four
from linkcli.textnum import num

PHASE_RTOL = 1e-6  # a path row of a phase this far (relative to the size) off the phase's circle
MAX_LISTED = 6  # rows named in a sentence; more are counted


def listed(rows) -> str:
    """Rows as a sentence: runs of consecutive rows as first..last, at most MAX_LISTED runs."""
    rows = [int(r) for r in rows]
    runs: list[list[int]] = []
    for r in rows:
        if runs and r == runs[-1][1] + 1:
            runs[-1][1] = r
        else:
            runs.append([r, r])
    text = [f"{a}" if a == b else f"{a}..{b}" for a, b in runs[:MAX_LISTED]]
    more = f" and {len(runs) - MAX_LISTED} more runs" if len(runs) > MAX_LISTED else ""
    return ("row " if len(rows) == 1 else "rows ") + ", ".join(text) + more


@dataclass
class PhaseBar:
    """The four-bar of one phase, in its own frame (origin at the driven crank's pivot, x
    toward the held elbow): lengths a (input), b (coupler), c (output), d (ground), its
    branch, its input angles over the phase's rows (rad), where its frame sits in the
    five-bar's local frame (origin, angle beta), the held drive's angle and the largest
    distance of P from its circle over the phase's rows."""

    phase: Phase
    a: float
    b: float
    c: float
    d: float
    branch: str
    phi: np.ndarray
    origin: tuple[float, float]
    beta: float
    held: float
    deviation: float

    def to_local(self, x, y):
        """A point of the four-bar's frame in the five-bar's local frame."""
        cb, sb = math.cos(self.beta), math.sin(self.beta)
        return self.origin[0] + cb * x - sb * y, self.origin[1] + sb * x + cb * y


@dataclass
class Track:
    """The five-bar at every row of its motion, local frame: `pose` (kinematics.Pose over
    the rows), `valid` rows, `side` (the branch: +1 left, -1 right), the drives' speeds and
    accelerations per row (rad/s, rad/s^2; 0 for a held drive on its phase's rows), the
    phases' four-bars and the defects (sentences; none: every row is reached)."""

    fb: FiveBar
    pose: kin.Pose
    valid: np.ndarray
    side: float
    w1: np.ndarray
    w2: np.ndarray
    al1: np.ndarray
    al2: np.ndarray
    phases: list[PhaseBar] = field(default_factory=list)
    defects: list[str] = field(default_factory=list)

    @property
    def rows(self) -> int:
        return len(self.valid)

    def to_global(self, x, y):
        """A point of the local frame in the global frame: X = G + R(ground_angle) x."""
        fb = self.fb
        c, s = math.cos(fb.ground_angle), math.sin(fb.ground_angle)
        return fb.ground_pivot[0] + c * x - s * y, fb.ground_pivot[1] + s * x + c * y

    def turned(self, x, y):
        """A vector of the local frame in the global frame: R(ground_angle) x."""
        c, s = math.cos(self.fb.ground_angle), math.sin(self.fb.ground_angle)
        return c * x - s * y, s * x + c * y


def size(fb: FiveBar) -> float:
    """The five-bar's scale: its longest link."""
    return max(fb.lengths)


def to_local(fb: FiveBar, points) -> tuple[np.ndarray, np.ndarray]:
    """Global points (n, 2) in the local frame: x = R(-ground_angle) (X - G)."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    c, s = math.cos(fb.ground_angle), math.sin(fb.ground_angle)
    x, y = p[:, 0] - fb.ground_pivot[0], p[:, 1] - fb.ground_pivot[1]
    return c * x + s * y, -s * x + c * y


def solve(fb: FiveBar) -> Track:
    """Every row of fb.motion (module docstring)."""
    mo = fb.motion
    n = mo.rows
    if mo.inputs is not None:
        phi = np.asarray(mo.inputs, dtype=float).reshape(n, 2)
        side = 1.0 if fb.branch == "left" else -1.0
        pose = kin.forward(fb.lengths, phi[:, 0], phi[:, 1], side)
        valid = np.asarray(pose.valid, dtype=bool)
        defects = []
        if not valid.all():
            defects.append(f"{listed(np.flatnonzero(~valid))} cannot assemble (the distal links "
                           "cannot reach each other: |A B| outside [|coupler - coupler2|, coupler + coupler2])")
    else:
        pose, valid, side, defects = _inverse(fb)
    w1, w2, al1, al2 = _rates(fb, n)
    track = Track(fb, pose, valid, side, w1, w2, al1, al2, defects=defects)
    track.phases = [phase_bar(track, ph) for ph in mo.phases]
    for bar in track.phases:
        if bar is not None and bar.deviation > PHASE_RTOL * size(fb):
            ph = bar.phase
            track.defects.append(
                f"over the phase of rows {ph.first}..{ph.last} ({ph.locked} held) the path leaves the "
                f"circle P runs on about the held elbow by up to {num(bar.deviation)}: it is not the "
                "coupler curve of the phase's four-bar")
    return track


def _inverse(fb: FiveBar):
    """(pose, valid, side, defects) of a path (module docstring)."""
    mo = fb.motion
    d, a1, a2, b1, b2 = fb.lengths
    px, py = to_local(fb, mo.path)
    m1, m2 = (1.0 if m == "+" else -1.0 for m in mo.modes)
    pose, reach1, reach2 = kin.inverse(fb.lengths, px, py, m1, m2)
    valid = np.asarray(reach1 & reach2, dtype=bool)
    defects = []
    for name, reach, (ox, a, b) in (("left", reach1, (0.0, a1, b1)), ("right", reach2, (d, a2, b2))):
        if reach.all():
            continue
        r = np.hypot(px - ox, py)
        far = ~reach & (r > 0.5 * (a + b + abs(a - b)))
        near = ~reach & ~far
        if far.any():
            defects.append(f"the path leaves the workspace at {listed(np.flatnonzero(far))}: beyond the reach "
                           f"of the {name} chain (|P - pivot| > input + coupler; type I, stretched)")
        if near.any():
            defects.append(f"the path leaves the workspace at {listed(np.flatnonzero(near))}: inside the folded "
                           f"limit of the {name} chain (|P - pivot| < |input - coupler|; type I, folded)")
    sides = np.where(valid, pose.side(), 0.0)
    first = int(np.argmax(valid)) if valid.any() else 0
    side = float(sides[first]) if sides[first] != 0 else 1.0
    if fb.branch is not None:
        given = 1.0 if fb.branch == "left" else -1.0
        if valid.any() and sides[first] not in (0.0, given):
            defects.append(f"the path with modes {mo.modes[0]}{mo.modes[1]} puts P on the {_side(-given)} of "
                           f"A -> B at row {first}, not on the {fb.branch} (branch)")
        side = given
    flip = np.flatnonzero(valid & (sides != side))
    if flip.size:
        defects.append(f"the distal links pass in line (type II singularity) before {listed(flip)}: P "
                       f"leaves the {_side(side)} of A -> B there")
    for name, (ox, a, b) in (("left", (0.0, a1, b1)), ("right", (d, a2, b2))):
        dips = _dips(px - ox, py, abs(a - b))
        if dips.size:
            defects.append(f"the path between rows leaves the workspace inside the folded limit of the {name} "
                           f"chain (type I) before {listed(dips + 1)}")
    return pose, valid, side, defects


def _side(s: float) -> str:
    return "left" if s > 0 else "right"


def _dips(x, y, radius: float) -> np.ndarray:
    """Indices k whose segment from point k to k + 1 passes strictly inside the circle of
    `radius` about the origin while both its ends lie on or outside it."""
    if radius <= 0.0 or len(x) < 2:
        return np.zeros(0, dtype=int)
    x0, y0, dx, dy = x[:-1], y[:-1], np.diff(x), np.diff(y)
    length2 = dx * dx + dy * dy
    t = np.clip(-(x0 * dx + y0 * dy) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    closest = np.hypot(x0 + t * dx, y0 + t * dy)
    ends = (np.hypot(x0, y0) >= radius) & (np.hypot(x[1:], y[1:]) >= radius)
    return np.flatnonzero(ends & (closest < radius * (1.0 - 1e-9)))


def _rates(fb: FiveBar, n: int):
    """Per row (w1, w2, al1, al2): the drives' speeds and accelerations, 0 for a held drive
    on its phase's rows."""
    mo = fb.motion
    out = [np.full(n, mo.speeds[0]), np.full(n, mo.speeds[1]),
           np.full(n, mo.accelerations[0]), np.full(n, mo.accelerations[1])]
    for ph in mo.phases:
        k = DRIVES.index(ph.locked)
        out[k][ph.first:ph.last + 1] = 0.0
        out[k + 2][ph.first:ph.last + 1] = 0.0
    return tuple(out)


def phase_bar(track: Track, ph: Phase) -> PhaseBar | None:
    """The four-bar of a phase (module docstring), None when its first row is not reached."""
    p = track.pose
    d, a1, a2, b1, b2 = track.fb.lengths
    rows = slice(ph.first, ph.last + 1)
    k = ph.first
    if not track.valid[k]:
        return None
    if ph.locked == "input2":  # A0 drives; B is held
        ox, oy, ex, ey = 0.0, 0.0, float(p.bx[k]), float(p.by[k])
        a, b, c, drive, held = a1, b1, b2, p.phi1[rows], float(p.phi2[k])
    else:  # B0 drives; A is held
        ox, oy, ex, ey = d, 0.0, float(p.ax[k]), float(p.ay[k])
        a, b, c, drive, held = a2, b2, b1, p.phi2[rows], float(p.phi1[k])
    beta = math.atan2(ey - oy, ex - ox)
    ground = math.hypot(ex - ox, ey - oy)
    phi = np.asarray(drive, dtype=float) - beta
    ok = track.valid[rows]
    dev = np.abs(np.hypot(p.px[rows] - ex, p.py[rows] - ey) - c)
    deviation = float(dev[ok].max()) if ok.any() else 0.0
    # its branch: the one whose output angle puts its output pin where P is at the first row
    psi = math.atan2(float(p.py[k]) - ey, float(p.px[k]) - ex) - beta
    branch = min(("open", "crossed"), key=lambda br: abs(float(wrap(
        four.pose(a, b, c, ground, phi[0], br).psi - psi))))
    return PhaseBar(ph, a, b, c, ground, branch, phi, (ox, oy), beta, held, deviation)
