"""Loads on a four-bar: one (n, 9, 9) Newton-Euler system per row, solved at once.

Three links x three equations, unknowns [A0x, A0y, Ax, Ay, Bx, By, B0x, B0y, T_in]
(mechanisms.newton_euler; Norton, Design of Machinery, ch. 11). Every force acts on the link
named second: A0 ground -> input, A input -> coupler, B coupler -> output, B0 ground ->
output; T_in the drive's torque on the input, counter-clockwise positive.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.newton_euler import (
    SINGULAR_TOLERANCE,
    add_force,
    body,
    cross,
    fill_input_and_coupler,
    finite_max,
    in_frame,
    max_norm,
    mechanical_advantage,
    point_acceleration,
    points,
    scales,
    solve,
    unit_angle,
)
from linkcli.mechanisms.protocol import LoadRows
from linkcli.model import Loads, Masses


@dataclass(frozen=True)
class FourBarState:
    """Kinematic state of a four-bar, one row per position (n rows), SI, global frame.

    A0, A, B, B0, P: (n, 2) points (A0, B0 may be (2,), P may be None: no coupler point);
    omega_*: angular velocities (rad/s), alpha_*: angular accelerations (rad/s^2), (n,), CCW +.
    The ground pivots are fixed.
    """

    A0: np.ndarray
    A: np.ndarray
    B: np.ndarray
    B0: np.ndarray
    omega_input: np.ndarray
    omega_coupler: np.ndarray
    omega_output: np.ndarray
    alpha_input: np.ndarray
    alpha_coupler: np.ndarray
    alpha_output: np.ndarray
    P: np.ndarray | None = None

    def __post_init__(self) -> None:
        n = len(points(self.A))
        for name in ("A0", "A", "B", "B0") + (("P",) if self.P is not None else ()):
            object.__setattr__(self, name, points(getattr(self, name), n))
        for name in ("omega_input", "omega_coupler", "omega_output",
                     "alpha_input", "alpha_coupler", "alpha_output"):
            object.__setattr__(self, name, np.broadcast_to(
                np.asarray(getattr(self, name), dtype=float), (n,)))

    @property
    def rows(self) -> int:
        return len(self.A)

    @classmethod
    def from_angles(cls, *, ground_length, input_length, coupler_length, output_length,
                    phi, psi, omega_input, omega_coupler, omega_output,
                    alpha_input=0.0, alpha_coupler=0.0, alpha_output=0.0,
                    coupler_point=None, ground_pivot=(0.0, 0.0), ground_angle=0.0):
        """State from the conventions of docs/format.md's angles (local frame, radians) and lengths in metres.

        A0 = ground_pivot, B0 = A0 + d e(gamma), A = A0 + a e(gamma + phi),
        B = B0 + c e(gamma + psi); P from `coupler_point` (m) in the coupler frame
        (the coupler's direction follows from A and B).
        """
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        a0 = np.asarray(ground_pivot, dtype=float)
        b0 = a0 + ground_length * unit_angle(ground_angle)
        a = a0 + input_length * unit_angle(ground_angle + phi)
        b = b0 + output_length * unit_angle(ground_angle + np.asarray(psi, dtype=float))
        p = None if coupler_point is None else in_frame(a, b, coupler_point)
        return cls(a0, a, b, b0, omega_input, omega_coupler, omega_output,
                   alpha_input, alpha_coupler, alpha_output, p)




def four_bar_loads(state: FourBarState, loads: Loads = Loads(),
                   masses: Masses = Masses()) -> LoadRows:
    """Input torque and pin forces of a four-bar at every row (one (n, 9, 9) solve).

    Output link rows 6-8: B + B0 = m4 (a_G4 - g); (B - G4) x B + (B0 - G4) x B0 + T_out
    = I4 alpha4. Singular where coupler and output are collinear (|sin| <= SINGULAR_TOLERANCE).
    """
    n = state.rows
    matrix = np.zeros((n, 9, 9))
    rhs = np.zeros((n, 9))
    with np.errstate(all="ignore"):
        _, force_terms, inertia_terms, length = fill_input_and_coupler(
            matrix, rhs, state, loads, masses, 8)
        gravity = np.asarray(loads.gravity, dtype=float)
        m4, i4, g4 = body(masses.output, state.B0, state.B)
        acc_g4 = point_acceleration(np.zeros((n, 1)), g4 - state.B0,
                                     state.omega_output, state.alpha_output)
        for k in range(2):
            matrix[:, 6 + k, 4 + k] = 1.0    # coupler on output = B
            matrix[:, 6 + k, 6 + k] = 1.0    # ground on output = B0
            rhs[:, 6 + k] = m4 * (acc_g4[:, k] - gravity[k])
        add_force(matrix, 8, 4, state.B - g4)
        add_force(matrix, 8, 6, state.B0 - g4)
        rhs[:, 8] = i4 * state.alpha_output - loads.output_torque
        coupler, output = state.B - state.A, state.B - state.B0
        sine = cross(coupler, output) / (np.linalg.norm(coupler, axis=1)
                                          * np.linalg.norm(output, axis=1))
        singular = ~(np.abs(sine) > SINGULAR_TOLERANCE)
        solution = solve(matrix, rhs, singular)
        force_terms += [m4 * np.abs(gravity).sum(), m4 * max_norm(acc_g4)]
        inertia_terms.append(i4 * finite_max(state.alpha_output))
        length = max(length, max_norm(output))
        force_scale, torque_scale = scales(force_terms, inertia_terms,
                                            loads.output_torque, length)
        pins = {name: solution[:, 2 * k:2 * k + 2]
                for k, name in enumerate(("A0", "A", "B", "B0"))}
        return LoadRows(solution[:, 8], pins, singular, mechanical_advantage(state, cross(state.B - state.B0, state.B - state.A)),
                        force_scale, torque_scale, ("A0", "A", "B", "B0"))



def four_bar_members(state: FourBarState, loads: Loads, masses: Masses, rows: LoadRows):
    """The loads on each link (protocol.MemberForces) from the pin forces of `rows`
    (four_bar_loads of the same state): input A0 -> A with the drive's torque at A0; coupler
    A -> B with the coupler force at P; output B0 -> B with `output_torque` at B0; each with
    its mass's weight and inertia (newton_euler.inertia_loads). The same equations as
    four_bar_loads, so each link is in equilibrium."""
    from linkcli.mechanisms.newton_euler import inertia_loads, input_and_coupler_members, link_load
    from linkcli.mechanisms.protocol import MemberForces
    pins = rows.pins
    input_link, coupler = input_and_coupler_members(state, loads, masses, rows)
    output = (link_load("B0", state.B0, pins["B0"]), link_load("B", state.B, pins["B"]),
              *((link_load("output_torque", state.B0, couple=loads.output_torque),)
                if loads.output_torque else ()),
              *inertia_loads(masses.output, state.B0, state.B, 0.0, state.omega_output,
                             state.alpha_output, loads.gravity))
    return MemberForces(links={"input": ("A0", "A"), "coupler": ("A", "B"), "output": ("B0", "B")},
                        loads={"input": input_link, "coupler": coupler, "output": output},
                        pins={name: pins[name] for name in ("A0", "A", "B", "B0")})
