"""The four-bar behind the mechanism protocol (mechanisms.protocol): its sections, loads,
made parts and drawing, from the closed forms of `kinematics`.

Frames (the conventions of docs/format.md): local A0 = (0, 0), B0 = (d, 0), A = a e^{i phi},
B = B0 + c e^{i psi}, P = A + (px + i py) e^{i theta}; the global frame puts A0 at
`ground_pivot` and turns the ground line by `ground_angle`.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.four_bar import sections
from linkcli.mechanisms.protocol import LoadRows, Mechanism, Skeleton, Study


class FourBarMechanism(Mechanism):
    name = "four-bar"
    NO_ASSEMBLY = "the linkage cannot assemble at any input angle"
    DEAD_POINT = "coupler and output in line"

    def size(self) -> float:
        return max(self.linkage.abcd)

    def lengths_section(self, units) -> dict:
        return sections.linkage_section(self.linkage, units)

    def class_section(self, units) -> dict:
        return kin.grashof(*self.linkage.abcd)

    def linkage_notes(self, want: set, units) -> list[str]:
        """The change-point warning, with any section that depends on the class or motion."""
        if not want & {"grashof", "transmission", "motion", "kinematics"}:
            return []
        flat = sections.change_point_inputs(*self.linkage.abcd)
        return [sections.change_point_note(flat, self.linkage, units)] if flat else []

    def study(self, near=None) -> Study | None:
        fb = self.linkage
        mot = kin.motion(*fb.abcd, fb.branch, near=near)
        return Study(mot.input_full_turn, mot.input_arc, mot) if mot.assembles else None

    def transmission_section(self, study, span, units, notes) -> dict:
        return sections.transmission_section(self.linkage, study.detail, span, units, notes)

    def motion_section(self, study, units) -> dict:
        return sections.motion_section(study.detail, units)

    def kinematics_rows(self, study, speed, steps, units) -> list[dict]:
        return sections.kinematics_rows(self.linkage, study, speed, steps, units)

    def load_rows(self, phi, speed, case, metres) -> LoadRows:
        """Pins A0 (ground -> input), A (input -> coupler), B (coupler -> output), B0
        (ground -> output) at input angles phi (local frame), constant input speed."""
        from linkcli.mechanisms.four_bar.loads import four_bar_loads
        from linkcli.mechanisms.newton_euler import in_metres
        return four_bar_loads(self._state(phi, speed, metres), case.loads, in_metres(case.masses, metres))

    def member_forces(self, phi, speed, case, metres, rows):
        """Links input (A0, A), coupler (A, B), output (B0, B); the drive's torque acts on the
        input at A0, `output_torque` on the output at B0, the coupler force at P."""
        from linkcli.mechanisms.four_bar.loads import four_bar_members
        from linkcli.mechanisms.newton_euler import in_metres
        return four_bar_members(self._state(phi, speed, metres), case.loads,
                                in_metres(case.masses, metres), rows)

    def _state(self, phi, speed, metres):
        """The loads' kinematic state (mechanisms.four_bar.loads.FourBarState) in metres."""
        from linkcli.mechanisms.four_bar.loads import FourBarState
        fb = self.linkage
        a, b, c, d = fb.abcd
        p = kin.pose(a, b, c, d, phi, fb.branch)
        w3, w4 = kin.velocities(a, b, c, p, speed)
        a3, a4 = kin.accelerations(a, b, c, p, speed)
        point = None if fb.coupler_point is None else tuple(v * metres for v in fb.coupler_point)
        return FourBarState.from_angles(
            ground_length=d * metres, input_length=a * metres, coupler_length=b * metres,
            output_length=c * metres, phi=phi, psi=p.psi, omega_input=speed, omega_coupler=w3,
            omega_output=w4, alpha_input=0.0, alpha_coupler=a3, alpha_output=a4, coupler_point=point,
            ground_pivot=tuple(v * metres for v in fb.ground_pivot), ground_angle=fb.ground_angle)

    def body_graph(self, case, metres):
        """Bodies input, coupler, output; pins A0, A, B, B0 (mechanisms.four_bar.dynamics)."""
        from linkcli.mechanisms.four_bar.dynamics import body_graph
        return body_graph(self.linkage, case, metres)

    def coefficients(self, q, metres):
        from linkcli.mechanisms.four_bar.dynamics import coefficients
        return coefficients(self.linkage, q, metres)

    def counterweights(self, graph, metres):
        """Berkof-Lowen: on the input and the output (mechanisms.four_bar.dynamics)."""
        from linkcli.mechanisms.four_bar.dynamics import counterweights
        return counterweights(self.linkage, graph, metres)

    def tolerance_model(self, problem, solution):
        from linkcli.mechanisms.four_bar.tolerance import Model, targets
        return Model(self.linkage, targets(problem, solution))

    def skeleton(self, phi) -> Skeleton:
        """A0, B0 on the ground; A, B (and P) moving; links input A0-A, coupler A-B(-P),
        output B0-B; the coupler point's path is traced."""
        fb = self.linkage
        joints, ok = _joints(*fb.abcd, kin.branch_sign(fb.branch), math.cos(fb.ground_angle),
                             math.sin(fb.ground_angle), *fb.ground_pivot, phi, fb.coupler_point)
        coupler = ("A", "B", "P") if "P" in joints else ("A", "B")
        return Skeleton(joints=joints, links={"input": ("A0", "A"), "coupler": coupler, "output": ("B0", "B")},
                        ground=("A0", "B0"), valid=np.asarray(ok), traced=("P",) if "P" in joints else ())

    @classmethod
    def joint_paths(cls, linkages, phi) -> dict[str, np.ndarray]:
        """`skeleton(phi[k]).joints` of every linkage k at once (protocol.Mechanism.joint_paths):
        the same closed forms, elementwise over (linkages, angles), so the same numbers."""
        linkages = list(linkages)
        points = {fb.coupler_point is None for fb in linkages}
        if len(points) != 1:  # some with a coupler point, some without: different joints
            return super().joint_paths(linkages, phi)
        phi = np.asarray(phi, dtype=float)
        col = np.array([[*fb.abcd, kin.branch_sign(fb.branch), math.cos(fb.ground_angle),
                         math.sin(fb.ground_angle), *fb.ground_pivot] for fb in linkages], dtype=float)
        point = None
        if points == {False}:
            pxy = np.array([fb.coupler_point for fb in linkages], dtype=float)
            point = (pxy[:, 0:1], pxy[:, 1:2])
        return _joints(*(col[:, k:k + 1] for k in range(9)), phi, point)[0]


def _joints(a, b, c, d, sign, cg, sg, gx, gy, phi, point):
    """(joints, valid): A0, B0, A, B (and P at `point`, in the coupler's frame) by the closed
    forms of kinematics.pose, placed by the ground's turn (cg, sg) and pivot (gx, gy); the
    lengths scalars (one linkage) or columns (linkages x angles); B and P NaN where the loop
    does not close."""
    p = kin.pose(a, b, c, d, phi, sign)

    def place(x, y):
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        return np.stack([gx + cg * x - sg * y, gy + sg * x + cg * y], axis=-1)

    n = p.psi.shape
    ok = p.valid
    joints = {"A0": place(np.zeros(n), np.zeros(n)), "B0": place(np.broadcast_to(d, n), np.zeros(n)),
              "A": place(a * np.cos(p.phi), a * np.sin(p.phi)),
              "B": place(np.where(ok, d + c * np.cos(p.psi), np.nan), np.where(ok, c * np.sin(p.psi), np.nan))}
    if point is not None:
        px, py = p.coupler_point(a, *point)
        joints["P"] = place(np.where(ok, px, np.nan), np.where(ok, py, np.nan))
    return joints, ok


HOME = FourBarMechanism
