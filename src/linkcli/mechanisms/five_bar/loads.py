"""Loads on a five-bar: both drives' torques and every pin's force at the rows of its motion,
one (n, 12, 12) Newton-Euler system per row, solved at once (mechanisms.newton_euler; Norton,
Design of Machinery, ch. 11, written for the five-bar's four moving links and two drives).

Four links x three equations = 12 equations per row, in 12 unknowns
[A0x, A0y, Ax, Ay, Px, Py, Bx, By, B0x, B0y, T1, T2]. Every pin force acts on the link named
second (the drawn convention for the links in the order input, input2, coupler, coupler2):

    A0  ground on input          A  input on coupler        P  coupler on coupler2
    B   input2 on coupler2       B0 ground on input2

T1 and T2 are the drives' torques on the cranks input and input2 (counter-clockwise
positive; the ground takes the reactions). Loads ([loads]): gravity on every mass,
`coupler_force` at P (on the coupler, the left distal link: the link [links] lists first at P
in the drawn convention), `torques` by link (a couple on it, counter-clockwise positive).

    input     A0 - A + m g = m a_G;   (A0 - G) x A0 - (A - G) x A + T1 + T = I alpha
    input2    B0 - B + m g = m a_G;   (B0 - G) x B0 - (B - G) x B + T2 + T = I alpha
    coupler   A - P + F + m g = m a_G; (A - G) x A - (P - G) x P + (P - G) x F + T = I alpha
    coupler2  B + P + m g = m a_G;    (B - G) x B + (P - G) x P + T = I alpha

The motion is the [motion] rows': drive angles (phi1, phi2), speeds and accelerations per row
(a held drive still on its phase's rows); each link's angular velocity and acceleration and its
frame origin's acceleration come from the kinematic coefficients (five_bar.coefficients):
omega = sum_j theta_j w_j, alpha = sum_j theta_j al_j + sum_ij theta_ij w_i w_j. Singular rows:
the distal links in line (type II, |sin mu_P| <= SINGULAR_TOLERANCE: the drives cannot hold P,
forces unbounded) or not assembled: NaN. A chain stretched or folded (type I) is no dead point
here: both cranks are driven. The five-bar has no one mechanical advantage (two inputs):
none is reported.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.newton_euler import (
    SINGULAR_TOLERANCE,
    add_force,
    body,
    finite_max,
    link_load,
    max_norm,
    point_acceleration,
    scales,
    solve,
)
from linkcli.mechanisms.protocol import LoadRows, MemberForces

PINS = ("A0", "A", "P", "B", "B0")
LINKS = {"input": ("A0", "A"), "input2": ("B0", "B"), "coupler": ("A", "P"), "coupler2": ("B", "P")}


@dataclass(frozen=True)
class FiveBarState:
    """The five-bar at n rows, SI, global frame: joints A0, A, P, B, B0 (n, 2) m; per link
    `omega`, `alpha` (n,) rad/s, rad/s^2 and the acceleration of its frame origin `origin_a`
    (n, 2) m/s^2 (the cranks' origins are fixed); `lock` (n,) |sin mu_P|, `valid` (n,)."""

    joints: dict
    omega: dict
    alpha: dict
    origin_a: dict
    lock: np.ndarray
    valid: np.ndarray

    @property
    def rows(self) -> int:
        return len(self.lock)


def state(fb, q, w, al, metres: float) -> FiveBarState:
    """The state at drive angles q (n, 2) rad (local), speeds w (n, 2) rad/s and accelerations
    al (n, 2) rad/s^2, lengths times `metres` (module docstring)."""
    from linkcli.mechanisms.five_bar.coefficients import coefficients
    coef = coefficients(fb, q, metres)
    w = np.asarray(w, dtype=float).reshape(-1, 2)
    al = np.asarray(al, dtype=float).reshape(-1, 2)
    with np.errstate(all="ignore"):
        omega, alpha, origin_a = {}, {}, {}
        for name in LINKS:
            _, dth, ddth = coef.angle[name]
            omega[name] = np.einsum("nj,nj->n", dth, w)
            alpha[name] = np.einsum("nj,nj->n", dth, al) + np.einsum("ni,nij,nj->n", w, ddth, w)
            _, dx, ddx = coef.origin[name]
            origin_a[name] = np.einsum("ncj,nj->nc", dx, al) + np.einsum("ni,ncij,nj->nc", w, ddx, w)
        theta3 = coef.angle["coupler"][0]
        a = coef.origin["coupler"][0]
        p = a + fb.coupler * metres * np.stack([np.cos(theta3), np.sin(theta3)], axis=-1)
        joints = {"A0": coef.origin["input"][0], "A": a, "P": p, "B": coef.origin["coupler2"][0],
                  "B0": coef.origin["input2"][0]}
    return FiveBarState(joints, omega, alpha, origin_a, coef.lock, coef.valid)


def five_bar_loads(st: FiveBarState, case, metres: float, shown2) -> LoadRows:
    """Both drives' torques and the five pin forces at every row of the state (one (n, 12, 12)
    solve; module docstring). `shown2`: the right drive's angle per row as printed (rad,
    wrapped), reported beside its torque."""
    from linkcli.mechanisms.newton_euler import in_metres
    n = st.rows
    loads = case.loads
    masses = in_metres(case.masses, metres)
    gravity = np.asarray(loads.gravity, dtype=float)
    torques = dict(loads.torques)
    force = np.asarray(loads.coupler_force, dtype=float)
    j = st.joints
    matrix = np.zeros((n, 12, 12))
    rhs = np.zeros((n, 12))
    col = {"A0": 0, "A": 2, "P": 4, "B": 6, "B0": 8}
    # link -> (first equation row, its joints' forces as (pin, sign), the drive's column)
    plan = {"input": (0, (("A0", 1.0), ("A", -1.0)), 10), "input2": (3, (("B0", 1.0), ("B", -1.0)), 11),
            "coupler": (6, (("A", 1.0), ("P", -1.0)), None), "coupler2": (9, (("B", 1.0), ("P", 1.0)), None)}
    force_terms, inertia_terms = [float(np.abs(force).sum())], []
    with np.errstate(all="ignore"):
        for name, (row, pins, drive) in plan.items():
            origin, towards = LINKS[name]
            m, inertia, g = body(masses.of(name), j[origin], j[towards])
            acc = point_acceleration(st.origin_a[name], g - j[origin], st.omega[name], st.alpha[name])
            for k in range(2):
                for pin, sign in pins:
                    matrix[:, row + k, col[pin] + k] = sign
                rhs[:, row + k] = m * (acc[:, k] - gravity[k])
            for pin, sign in pins:
                add_force(matrix, row + 2, col[pin], j[pin] - g, sign)
            if drive is not None:
                matrix[:, row + 2, drive] = 1.0
            rhs[:, row + 2] = inertia * st.alpha[name] - torques.get(name, 0.0)
            if name == "coupler" and np.any(force):
                rhs[:, row:row + 2] -= force
                lever = j["P"] - g
                rhs[:, row + 2] -= lever[:, 0] * force[1] - lever[:, 1] * force[0]
            force_terms += [m * float(np.abs(gravity).sum()), m * max_norm(acc)]
            inertia_terms.append(inertia * finite_max(st.alpha[name]))
        singular = ~st.valid | ~(st.lock > SINGULAR_TOLERANCE)
        solution = solve(matrix, rhs, singular)
        length = max(max_norm(j[b] - j[a]) for a, b in LINKS.values())
        force_scale, torque_scale = scales(force_terms, inertia_terms,
                                           sum(abs(t) for t in torques.values()), length)
    pins = {name: solution[:, col[name]:col[name] + 2] for name in PINS}
    return LoadRows(solution[:, 10], pins, singular, None, force_scale, torque_scale, PINS,
                    other_drives={"input2": (np.asarray(shown2, dtype=float), solution[:, 11])})


def five_bar_members(st: FiveBarState, case, metres: float, rows: LoadRows) -> MemberForces:
    """The loads on each link (protocol.MemberForces) from the pin forces of `rows`
    (five_bar_loads of the same state): input A0 -> A with T1 at A0, input2 B0 -> B with T2 at
    B0, coupler A -> P with the coupler force at P, coupler2 B -> P; `torques` at each link's
    frame origin; each with its mass's weight and inertia (newton_euler.inertia_loads). The
    same equations as five_bar_loads, so each link is in equilibrium."""
    from linkcli.mechanisms.newton_euler import in_metres, inertia_loads
    loads, masses = case.loads, in_metres(case.masses, metres)
    j, pins = st.joints, rows.pins
    torques = dict(loads.torques)
    on = {"input": (("A0", pins["A0"]), ("A", -pins["A"])), "input2": (("B0", pins["B0"]), ("B", -pins["B"])),
          "coupler": (("A", pins["A"]), ("P", -pins["P"])), "coupler2": (("B", pins["B"]), ("P", pins["P"]))}
    drives = {"input": rows.input_torque, "input2": rows.other_drives["input2"][1]}
    out = {}
    for name, (origin, towards) in LINKS.items():
        items = [link_load(pin, j[pin], force) for pin, force in on[name]]
        if name in drives:
            items.append(link_load("drive", j[origin], couple=drives[name]))
        if name == "coupler" and any(loads.coupler_force):
            items.append(link_load("coupler_force", j["P"], loads.coupler_force))
        if torques.get(name):
            items.append(link_load("torque", j[origin], couple=torques[name]))
        items += inertia_loads(masses.of(name), j[origin], j[towards], st.origin_a[name], st.omega[name],
                               st.alpha[name], loads.gravity)
        out[name] = tuple(items)
    return MemberForces(links=dict(LINKS), loads=out, pins={name: pins[name] for name in PINS})
