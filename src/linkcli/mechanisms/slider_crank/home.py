"""The offset slider-crank behind the mechanism protocol (mechanisms.protocol): its sections,
loads, made parts and drawing, from the closed forms of `kinematics`.

Frame (docs/format.md, the slider-crank): crank pivot A0 at the origin, A = a e^{i phi}, the
slider pin B = (s, e) on the guide y = e parallel to x, P = A + (px + i py) e^{i theta}.
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.protocol import Guide, LoadRows, Mechanism, Skeleton, Study
from linkcli.mechanisms.slider_crank import kinematics as sc
from linkcli.mechanisms.slider_crank import sections


class SliderCrankMechanism(Mechanism):
    name = "slider-crank"
    NO_ASSEMBLY = "the slider-crank cannot assemble at any crank angle"
    DEAD_POINT = "the rod normal to the guide"

    def size(self) -> float:
        return sections.size(self.linkage)

    def lengths_section(self, units) -> dict:
        return sections.linkage_section(self.linkage, units)

    def class_section(self, units) -> dict:
        return sections.grashof_section(self.linkage)

    def linkage_notes(self, want: set, units) -> list[str]:
        """The change-point warning, with the class section."""
        if "grashof" not in want or sections.grashof_section(self.linkage)["class"] != "change-point":
            return []
        return ["change-point slider-crank: input + |offset| = coupler (within 1e-9), the rod "
                f"stands normal to the guide once a turn, where it can switch branch; the {self.linkage.branch} "
                "branch reported changes form there"]

    def study(self, near=None) -> Study | None:
        return sections.study_arc(self.linkage, near)

    def transmission_section(self, study, span, units, notes) -> dict:
        return sections.transmission_section(self.linkage, study, units, notes)

    def motion_section(self, study, units) -> dict:
        return sections.motion_section(self.linkage, study, units)

    def kinematics_rows(self, study, speed, steps, units) -> list[dict]:
        return sections.kinematics_rows(self.linkage, study, speed, steps, units)

    def load_rows(self, phi, speed, case, metres) -> LoadRows:
        """Pins A0 (ground -> crank), A (crank -> rod), B (rod -> slider) and the guide's
        normal force on the slider, at crank angles phi, constant crank speed."""
        from linkcli.mechanisms.newton_euler import in_metres
        from linkcli.mechanisms.slider_crank.loads import slider_crank_loads
        return slider_crank_loads(self._state(phi, speed, metres), case.loads, in_metres(case.masses, metres))

    def member_forces(self, phi, speed, case, metres, rows):
        """Links input (A0, A) and coupler (A, B); the drive's torque acts on the crank at
        A0, the coupler force at P. Pins A0, A, B (the guide is no pin; the slider no link)."""
        from linkcli.mechanisms.newton_euler import in_metres
        from linkcli.mechanisms.slider_crank.loads import slider_crank_members
        return slider_crank_members(self._state(phi, speed, metres), case.loads,
                                    in_metres(case.masses, metres), rows)

    def _state(self, phi, speed, metres):
        """The loads' kinematic state (mechanisms.slider_crank.loads.SliderCrankState), metres."""
        from linkcli.mechanisms.slider_crank.loads import SliderCrankState
        sl = self.linkage
        a, b, e = sl.abe
        p = sc.pose(a, b, e, phi, sl.branch)
        _, w3 = sc.velocities(a, b, p, speed)
        _, a3 = sc.accelerations(a, b, p, speed)
        point = None if sl.coupler_point is None else tuple(v * metres for v in sl.coupler_point)
        return SliderCrankState.from_angles(
            input_length=a * metres, coupler_length=b * metres, phi=phi, theta=p.theta,
            omega_input=speed, omega_coupler=w3, alpha_input=0.0, alpha_coupler=a3, coupler_point=point)

    def body_graph(self, case, metres):
        """Bodies input, coupler and the slider block; pins A0, A, B and the guide
        (mechanisms.slider_crank.dynamics)."""
        from linkcli.mechanisms.slider_crank.dynamics import body_graph
        return body_graph(self.linkage, case, metres)

    def coefficients(self, q, metres):
        from linkcli.mechanisms.slider_crank.dynamics import coefficients
        return coefficients(self.linkage, q, metres)

    def tolerance_model(self, problem, solution):
        from linkcli.mechanisms.slider_crank.tolerance import model
        return model(problem, solution)

    def skeleton(self, phi) -> Skeleton:
        """A0 on the ground; A, B (and P) moving; links input A0-A, coupler A-B(-P); B slides
        on the guide y = offset (angle 0)."""
        sl = self.linkage
        a, b, e = sl.abe
        p = sc.pose(a, b, e, phi, sl.branch)
        ok = np.asarray(p.valid)
        n = p.slider.shape
        joints = {"A0": np.zeros(n + (2,)),
                  "A": np.stack([a * np.cos(p.phi), a * np.sin(p.phi)], axis=-1),
                  "B": np.stack([np.where(ok, p.slider, np.nan), np.where(ok, e, np.nan)], axis=-1)}
        coupler = ("A", "B")
        if sl.coupler_point is not None:
            px, py = sc.coupler_point(a, p, *sl.coupler_point)
            joints["P"] = np.stack([np.where(ok, px, np.nan), np.where(ok, py, np.nan)], axis=-1)
            coupler = ("A", "B", "P")
        return Skeleton(joints=joints, links={"input": ("A0", "A"), "coupler": coupler},
                        ground=("A0",), valid=ok, guides=(Guide((0.0, float(e)), 0.0, "B"),),
                        sliders=("B",), traced=("P",) if "P" in joints else ())


HOME = SliderCrankMechanism
