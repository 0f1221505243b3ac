"""The five-bar behind the mechanism protocol (mechanisms.protocol): its sections, made parts
and drawing, from the closed forms of `kinematics` over the rows of its [motion] (`track`).

The five-bar has two drives and no single drive angle: its study is its rows. `study()`
gives a `RowStudy` whose `rows(steps)` are the row numbers 0 .. M-1 whatever `steps`
(shown as the left drive's angle), and `skeleton(k)` draws rows k; the kinematics section
has one row per row of [motion]. Frames (model.py): local A0 = (0, 0), B0 = (ground, 0),
A = input e^{i phi1}, B = B0 + input2 e^{i phi2}, P where the distal links meet; global:
A0 at `ground_pivot`, the ground line at `ground_angle`.

The numbers' conventions, for a five-bar given another way (a drawing with two drives) to
print the same: joints A0, B0 (ground), A, B, P; links input A0-A, input2 B0-B, coupler A-P,
coupler2 B-P; drives input and input2. Drive angles are the cranks' directions from the
ground line A0 -> B0, counter-clockwise, shown wrapped to (-180, 180]; P, its velocity (at
the rows' drive speeds, 0 for a held drive) and acceleration are global; the Jacobian's
columns are per unit of the file's angle unit; the transmission angles are the triangles'
unoriented angles in [0, 180] (at P between P->A and P->B, at A between A->A0 and A->P, at B
between B->B0 and B->P); the condition number is that of dP/d(phi1, phi2) with the angles
in radians (the unit does not change it).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from linkcli.angles import wrap
from linkcli.mechanisms.five_bar import sections
from linkcli.mechanisms.five_bar import track as tracking
from linkcli.mechanisms.protocol import LoadRows, Mechanism, Skeleton, Study
from linkcli.noise import snap


@dataclass(frozen=True)
class RowStudy(Study):
    """A study whose drive parameter is the row number (the five-bar's two drives move
    together along its rows); `detail` is the Track."""

    def rows(self, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """(row numbers 0 .. M-1, the left drive's angle at each, wrapped), whatever `steps`."""
        track = self.detail
        return np.arange(track.rows, dtype=float), snap(wrap(track.pose.phi1), 1.0)


class FiveBarMechanism(Mechanism):
    name = "five-bar"
    NO_ASSEMBLY = "the five-bar reaches none of its rows"
    DEAD_POINT = "the distal links in line"

    def __init__(self, linkage) -> None:
        super().__init__(linkage)
        self._track = None
        self._at = None

    def track(self):
        """The rows of [motion] solved once (track.solve); None without a motion."""
        if self._track is None and self.linkage.motion is not None:
            self._track = tracking.solve(self.linkage)
        return self._track

    def size(self) -> float:
        return tracking.size(self.linkage)

    def lengths_section(self, units) -> dict:
        return sections.linkage_section(self.linkage, self.track(), units)

    def class_section(self, units) -> dict:
        return sections.class_section(self.linkage, self.track())

    def study(self, near=None) -> Study | None:
        """The rows of [motion]; its `shortfall` names the rows not reached (exit 1); None
        without a motion or when no row is reached."""
        track = self.track()
        if track is None or not track.valid.any():
            return None
        phi = np.unwrap(track.pose.phi1[track.valid])
        return RowStudy(False, (float(phi.min()), float(phi.max())), track, "; ".join(track.defects) or None)

    def transmission_section(self, study, span, units, notes) -> dict:
        return sections.transmission_section(study.detail, units, notes)

    def motion_section(self, study, units) -> dict:
        return sections.motion_section(study.detail, units)

    def study_keys(self, speed, steps, units) -> dict:
        """The five-bar's own [motion] (its rows, the drives' rates, its phases), not a
        single drive's speed and steps."""
        track = self.track()
        return {} if track is None else sections.motion_echo(track, units)

    def kinematics_rows(self, study, speed, steps, units) -> list[dict]:
        """One row per row of [motion], at its own input_speeds (not `speed`, `steps`)."""
        return sections.kinematics_rows(study.detail, units)

    def load_rows(self, phi, speed, case, metres) -> LoadRows:
        """Both drives' torques (input_torque; input2's beside it) and the pins A0 (ground ->
        input), A (input -> coupler), P (coupler -> coupler2), B (input2 -> coupler2), B0
        (ground -> input2) at rows `phi` (row numbers), each row at its own drive speeds and
        accelerations (five_bar.loads); `speed` is not used."""
        from linkcli.mechanisms.five_bar.loads import five_bar_loads
        k = np.asarray(phi, dtype=int)
        return five_bar_loads(self._state(k, metres), case, metres, wrap(self.track().pose.phi2[k]))

    def member_forces(self, phi, speed, case, metres, rows):
        """Links input (A0, A), input2 (B0, B), coupler (A, P), coupler2 (B, P); the drives'
        torques at A0 and B0, the coupler force at P (five_bar.loads)."""
        from linkcli.mechanisms.five_bar.loads import five_bar_members
        return five_bar_members(self._state(np.asarray(phi, dtype=int), metres), case, metres, rows)

    def _state(self, k, metres):
        """The loads' state (five_bar.loads.FiveBarState) at rows k: their drive angles, speeds
        and accelerations."""
        from linkcli.mechanisms.five_bar.loads import state
        track = self.track()
        p = track.pose
        q = np.stack([p.phi1[k], p.phi2[k]], axis=-1)
        w = np.stack([track.w1[k], track.w2[k]], axis=-1)
        al = np.stack([track.al1[k], track.al2[k]], axis=-1)
        st = state(self.linkage_for_rows(), q, w, al, metres)
        valid = st.valid & track.valid[k]
        return type(st)(st.joints, st.omega, st.alpha, st.origin_a, st.lock, valid)

    def linkage_for_rows(self):
        """The linkage with the branch its rows run on (a path's first row decides it)."""
        track = self.track()
        if track is None:
            return replace(self.linkage, branch=self.linkage.branch or "left")
        return replace(self.linkage, branch="left" if track.side > 0 else "right")

    def body_graph(self, case, metres):
        """Bodies input, input2, coupler, coupler2; pins A0, A, P, B, B0; drives input and
        input2 (mechanisms.five_bar.dynamics)."""
        from linkcli.mechanisms.five_bar.dynamics import body_graph
        return body_graph(self.linkage, case, metres)

    def coefficients(self, q, metres):
        """At rows q (n, 2) of (phi1, phi2) (five_bar.coefficients)."""
        from linkcli.mechanisms.five_bar.coefficients import coefficients
        return coefficients(self.linkage_for_rows(), q, metres)

    def coefficients_at(self, q, metres):
        from linkcli.mechanisms.five_bar.coefficients import coefficients_at
        if self._at is None:
            self._at = self.linkage_for_rows()
        return coefficients_at(self._at, q, metres)

    def tolerance_model(self, problem, solution):
        from linkcli.mechanisms.five_bar.tolerance import Model
        return Model(self.track(), problem.meta.units)

    def skeleton(self, phi) -> Skeleton:
        """At rows `phi` (row numbers, protocol: the five-bar's drive parameter): A0, B0 on
        the ground; A, B, P moving; links input A0-A, input2 B0-B, coupler A-P, coupler2
        B-P; P's path is traced."""
        track = self.track()
        k = np.asarray(phi, dtype=int)
        p = track.pose
        ok = track.valid[k]

        def place(x, y, moving=True):
            gx, gy = track.to_global(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
            gx, gy = np.broadcast_arrays(gx, gy)
            if moving:
                gx, gy = np.where(ok, gx, np.nan), np.where(ok, gy, np.nan)
            return np.stack([gx, gy], axis=-1)

        zero = np.zeros(k.shape)
        joints = {"A0": place(zero, zero, False), "B0": place(zero + self.linkage.ground, zero, False),
                  "A": place(p.ax[k], p.ay[k]), "B": place(p.bx[k], p.by[k]), "P": place(p.px[k], p.py[k])}
        links = {"input": ("A0", "A"), "coupler": ("A", "P"), "coupler2": ("B", "P"), "input2": ("B0", "B")}
        return Skeleton(joints=joints, links=links, ground=("A0", "B0"), valid=np.asarray(ok), traced=("P",))


HOME = FiveBarMechanism
