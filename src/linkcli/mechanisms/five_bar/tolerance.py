"""The five-bar's made parts for the tolerance Monte Carlo (analysis.tolerance drives it, with
its per-row statistics): P's position error at every row of [motion], and the error a phase
change adds.

Lengths. Each of ground, input, input2, coupler, coupler2 is made as l + dl (the ground
moves B0 along the ground line; the frame stays at A0). Keys as in [linkage].

Pin clearance, effective-link model (Lee & Gilmore 1991; Ting, Zhu & Watkins 2000, "The
effects of joint clearance on position and orientation deviation of linkages and
manipulators", Mech. Mach. Theory 35): at each of the five revolute joints A0, A, P, B, B0
the journal lies anywhere within the radial clearance r of its bearing's centre, drawn per
sample, joint and row (the load, and with it the contact, changes between rows). With the
offsets e_A0 .. e_B0 the drives still turn their cranks to the nominal angles:

    A' = e_A0 + a1' e^{i phi1} + e_A,   B' = (d', 0) + e_B0 + a2' e^{i phi2} + e_B + e_P,
    P  = meet(A', B', b1', b2', branch)

(P is the centre of the pin the left distal link carries; the right one's bearing sits e_P
from it). A sample fails at a row where it cannot assemble, everywhere when a length comes
out <= 0.

Phase changes, the held drive's play (linkcli's model, after the clearance-discontinuity
analyses of five-bars by Altuzarra, Aginaga, Hernandez & Zabalza, "Workspace analysis of
positioning discontinuities due to clearances in parallel manipulators", Mech. Mach. Theory
46, 2011: where the contact mode changes, P jumps). A drive held still by a phase rests in
its lock, which has an angular play +- `lock_play`: when the lock takes over from the
drive at the phase's first row, the held crank settles anywhere within the play, at
phi_held + delta (delta uniform on [-lock_play, lock_play], drawn once per phase and
sample: held still, it stays there over the phase); when the drive takes over again after
the phase's last row, it takes the play up and the crank returns to its commanded angle.
Over the phase's rows P's error includes delta's effect; the error a phase change adds is
the jump of P when the play appears (at the phase's first row, unless that is row 0) or
is taken up (at its last row, unless that is the last row): |P(delta) - P(0)| of the same
made linkage at that row. The draws are analysis.tolerance.unit_draws's: the lock play of
phase j is the play column j at the phase's first row.

Sensitivity: per link, the largest |dP/dl| over the rows (length per length), closed form
(kinematics.length_partials); None where a row is on a type II singularity.
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.five_bar import kinematics as kin
from linkcli.mechanisms.five_bar.model import DRIVES
from linkcli.mechanisms.five_bar.schema import TOLERANCED
from linkcli.mechanisms.five_bar.track import Track, size

PINS = ("A0", "A", "P", "B", "B0")
NO_ALLOWED_ERROR = ("no allowed_error given: a sample fails only when it cannot be made (a length "
                    "<= 0) or assembled at a row")


class Model:
    """The five-bar's made parts (analysis.tolerance.Model) over the rows it reaches."""

    columns = inverse = TOLERANCED
    pins = len(PINS)
    pin_names = PINS  # as [joints] names them, in the order of the offsets (fits: clearance = "fits")
    play_names = ()  # the locks' plays are angular, not fitted
    kind = "length"
    per_row = True
    measure = "largest distance of P from its nominal position over the rows"
    no_allowed_error = NO_ALLOWED_ERROR
    no_assembly = "the five-bar reaches none of its rows"

    def __init__(self, track: Track, units=None) -> None:
        self.track, self.units = track, units
        fb = track.fb
        self.rows = np.flatnonzero(track.valid)  # the row numbers studied
        self.inputs = self.rows.astype(float)
        self.scale = size(fb)
        self.cap = min(fb.lengths)
        self.known = {k: getattr(fb, k) for k in TOLERANCED}
        self.plays = len(fb.motion.phases)
        p = track.pose
        k = self.rows
        self.phi1, self.phi2 = p.phi1[k], p.phi2[k]
        self.px, self.py = p.px[k], p.py[k]
        self.locks = []  # per phase: (column of its play, drive index, studied rows in it, its first)
        self.events = []  # (label dict, phase index, position among the studied rows)
        position = {int(r): i for i, r in enumerate(k.tolist())}
        last = track.rows - 1
        for j, ph in enumerate(fb.motion.phases):
            inside = np.flatnonzero((k >= ph.first) & (k <= ph.last))
            if not inside.size:
                continue
            self.locks.append((j, DRIVES.index(ph.locked), inside, int(inside[0])))
            for at, row, edge in (("start", ph.first, ph.first > 0), ("end", ph.last, ph.last < last)):
                if edge and row in position:
                    self.events.append(({"rows": [ph.first, ph.last], "locked": ph.locked, "at": at, "row": row},
                                        len(self.locks) - 1, position[row]))

    def column_scale(self, lengths: dict) -> np.ndarray:
        """Each length's tolerance from [tolerance] lengths (keyed by link)."""
        return np.array([float(lengths.get(k, 0.0)) for k in self.columns])

    def given(self, tol) -> dict:
        play = tol.lock_play if self.units is None else float(self.units.from_rad(tol.lock_play))
        return {"lock_play": play} if self.plays else {}

    def play_size(self, tol) -> float:
        return tol.lock_play if self.plays else 0.0

    # ---------------------------------------------------------------- made parts

    def _made(self, dl, pins, cols=slice(None), drives=None):
        """P (x, y) and `ok` of made linkages at the studied rows `cols`, (n, M') arrays;
        `drives` (phi1, phi2) overrides the drive angles."""
        fb = self.track.fb
        d, a1, a2, b1, b2 = (v + dl[:, i:i + 1] for i, v in enumerate(fb.lengths))
        made = np.all(np.concatenate([d, a1, a2, b1, b2], axis=1) > 0.0, axis=1)[:, None]
        d, a1, a2, b1, b2 = (np.where(made, x, 1.0) for x in (d, a1, a2, b1, b2))
        phi1, phi2 = (self.phi1[cols], self.phi2[cols]) if drives is None else drives
        ax, ay, bx, by = kin.cranks(d, a1, a2, phi1, phi2)
        if pins is not None:
            e = pins[:, cols]
            ax = ax + e[..., 0, 0] + e[..., 1, 0]
            ay = ay + e[..., 0, 1] + e[..., 1, 1]
            bx = bx + e[..., 4, 0] + e[..., 3, 0] + e[..., 2, 0]
            by = by + e[..., 4, 1] + e[..., 3, 1] + e[..., 2, 1]
        px, py, ok = kin.meet(ax, ay, bx, by, b1, b2, self.track.side)
        return px, py, ok & made

    def _drives(self, plays, n: int):
        """Drive angles (n, M) with each phase's lock play on its rows (None without plays)."""
        if plays is None or not self.locks:
            return None
        phi = [np.broadcast_to(self.phi1, (n, len(self.rows))).copy(),
               np.broadcast_to(self.phi2, (n, len(self.rows))).copy()]
        for j, drive, inside, first in self.locks:
            phi[drive][:, inside] += plays[:, first, j][:, None]
        return tuple(phi)

    def row_errors(self, dl, pins, plays):
        """(dev (n, M), ok (n, M), events {index: (n,) added error}) at the studied rows."""
        n = len(dl)
        drives = self._drives(plays, n)
        px, py, ok = self._made(dl, pins, drives=drives)
        dev = np.hypot(px - self.px, py - self.py)
        events = {}
        if drives is not None:
            for i, (_, lock, col) in enumerate(self.events):
                qx, qy, _ = self._made(dl, pins, cols=slice(col, col + 1))
                events[i] = np.where(ok[:, col], np.hypot(px[:, col] - qx[:, 0], py[:, col] - qy[:, 0]), np.inf)
        return np.where(ok, dev, np.inf), ok, events

    def errors(self, dl, pins, plays):
        dev, ok, _ = self.row_errors(dl, pins, plays)
        all_ok = np.all(ok, axis=1)
        return np.where(all_ok, dev.max(axis=1, initial=0.0), np.inf), all_ok

    def event_labels(self) -> list[dict]:
        return [label for label, _, _ in self.events]

    def sensitivity(self) -> dict:
        p = self.track.pose
        k = self.rows
        part = kin.length_partials(kin.Pose(*(getattr(p, f)[k] for f in
                                              ("phi1", "phi2", "ax", "ay", "bx", "by", "px", "py", "valid")),
                                            p.lengths))
        out = {}
        for name in TOLERANCED:
            mag = np.hypot(*part[name])
            out[name] = float(mag.max()) if mag.size and np.all(np.isfinite(mag)) else None
        return out
