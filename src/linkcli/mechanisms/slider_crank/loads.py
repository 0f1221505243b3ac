"""Loads on an offset slider-crank: one (n, 8, 8) Newton-Euler system per row, solved at once.

Crank 3 + rod 3 + slider 2 equations, unknowns [A0x, A0y, Ax, Ay, Bx, By, N, T_in]
(mechanisms.newton_euler; Norton, Design of Machinery, ch. 11). Every force acts on the link
named second: A0 ground -> crank, A crank -> rod, B rod -> slider; `guide` the guide's normal
force on the slider (along +y; frictionless, the guide along x); T_in the drive's torque on
the crank, counter-clockwise positive.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.newton_euler import (
    NO_MASS,
    SINGULAR_TOLERANCE,
    fill_input_and_coupler,
    finite_max,
    in_frame,
    mechanical_advantage,
    points,
    scales,
    solve,
    unit_angle,
)
from linkcli.mechanisms.protocol import LoadRows
from linkcli.model import Loads, Masses


@dataclass(frozen=True)
class SliderCrankState:
    """Kinematic state of a slider-crank, one row per position (n rows), SI, global frame.

    A0 crank pivot, A crank pin, B slider pin ((n, 2); A0 may be (2,)), P optional coupler
    point on the rod. The guide is along +x. The slider's acceleration is that of B as a
    point of the rod (its x component: the guide carries the rest).
    """

    A0: np.ndarray
    A: np.ndarray
    B: np.ndarray
    omega_input: np.ndarray
    omega_coupler: np.ndarray
    alpha_input: np.ndarray
    alpha_coupler: np.ndarray
    P: np.ndarray | None = None

    def __post_init__(self) -> None:
        n = len(points(self.A))
        for name in ("A0", "A", "B") + (("P",) if self.P is not None else ()):
            object.__setattr__(self, name, points(getattr(self, name), n))
        for name in ("omega_input", "omega_coupler", "alpha_input", "alpha_coupler"):
            object.__setattr__(self, name, np.broadcast_to(
                np.asarray(getattr(self, name), dtype=float), (n,)))

    @property
    def rows(self) -> int:
        return len(self.A)

    @classmethod
    def from_angles(cls, *, input_length, coupler_length, phi, theta, omega_input,
                    omega_coupler, alpha_input=0.0, alpha_coupler=0.0, coupler_point=None):
        """State from the file format's slider-crank frame: A0 at the origin, A = a e(phi),
        B = A + b e(theta) (on the axis y = offset), lengths in metres, angles in radians."""
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        a = input_length * unit_angle(phi)
        b = a + coupler_length * unit_angle(theta)
        p = None if coupler_point is None else in_frame(a, b, coupler_point)
        return cls(np.zeros(2), a, b, omega_input, omega_coupler, alpha_input,
                   alpha_coupler, p)



def slider_crank_loads(state: SliderCrankState, loads: Loads = Loads(),
                       masses: Masses = Masses()) -> LoadRows:
    """Input torque, pin forces and guide force of a slider-crank (one (n, 8, 8) solve).

    Slider rows 6-7 (frictionless guide along x, slider mass m4 = masses.output.mass):
    Bx + F_out = m4 (a_slider - gx); By + N = -m4 gy. Singular where the rod is
    perpendicular to the guide (|cos theta3| <= SINGULAR_TOLERANCE).
    """
    n = state.rows
    matrix = np.zeros((n, 8, 8))
    rhs = np.zeros((n, 8))
    if loads.output_torque != 0:
        raise ValueError("a slider-crank takes output_force (along the guide), not output_torque")
    with np.errstate(all="ignore"):
        acc_b, force_terms, inertia_terms, length = fill_input_and_coupler(
            matrix, rhs, state, loads, masses, 7)
        gravity = np.asarray(loads.gravity, dtype=float)
        m4 = (masses.output or NO_MASS).mass
        matrix[:, 6, 4] = 1.0                # rod on slider, x
        matrix[:, 7, 5] = 1.0                # rod on slider, y
        matrix[:, 7, 6] = 1.0                # guide's normal force
        rhs[:, 6] = m4 * (acc_b[:, 0] - gravity[0]) - loads.output_force
        rhs[:, 7] = -m4 * gravity[1]
        rod = state.B - state.A
        singular = ~(np.abs(rod[:, 0]) / np.linalg.norm(rod, axis=1) > SINGULAR_TOLERANCE)
        solution = solve(matrix, rhs, singular)
        force_terms += [abs(loads.output_force), m4 * np.abs(gravity).sum(),
                        m4 * finite_max(acc_b[:, 0])]
        force_scale, torque_scale = scales(force_terms, inertia_terms, 0.0, length)
        guide = np.stack([np.where(singular, np.nan, 0.0), solution[:, 6]], axis=1)
        pins = {"A0": solution[:, 0:2], "A": solution[:, 2:4], "B": solution[:, 4:6],
                "guide": guide}
        return LoadRows(solution[:, 7], pins, singular, mechanical_advantage(state, state.B[:, 0] - state.A[:, 0]),
                        force_scale, torque_scale, ("A0", "A", "B", "guide"))



def slider_crank_members(state: SliderCrankState, loads: Loads, masses: Masses, rows: LoadRows):
    """The loads on crank and rod (protocol.MemberForces) from the pin forces of `rows`
    (slider_crank_loads of the same state): input A0 -> A with the drive's torque at A0;
    coupler A -> B with the coupler force at P; each with its mass's weight and inertia
    (newton_euler.input_and_coupler_members). The slider only translates (no link to size)
    and the guide is no pin."""
    from linkcli.mechanisms.newton_euler import input_and_coupler_members
    from linkcli.mechanisms.protocol import MemberForces
    input_link, coupler = input_and_coupler_members(state, loads, masses, rows)
    return MemberForces(links={"input": ("A0", "A"), "coupler": ("A", "B")},
                        loads={"input": input_link, "coupler": coupler},
                        pins={name: rows.pins[name] for name in ("A0", "A", "B")})
