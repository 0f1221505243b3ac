"""The equation of motion of a linkage of several drives (dynamics.several) over rows, in numpy:
every body's inertia terms, every element's coordinate, the drives' accelerations and torques
and every pin's force (dynamics.body_forces) at the history's output times, all rows at once --
no Python loop over rows. The integrator's right-hand side evaluates the same equation at one
state in Python floats (several.Several.rhs_function); tests hold the two equal.

    M_ij = sum_b m_b G_b,i . G_b,j + I_b theta_b,i theta_b,j        (+ flywheel_j on drive j)
    h_i  = sum_b m_b G_b,i . (sum_jl G_b,jl q_j' q_l') + I_b theta_b,i (sum_jl theta_b,jl q_j' q_l')
    V    = -sum_b m_b g . G_b - sum F . P,   dV/dq_i likewise with G_b,i and P_i
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.analysis.dynamics import bodies, body_forces

TWO_PI = 2.0 * math.pi


@dataclass
class State:
    """The exact state at rows (q, w (n, k); the followed angles (n, m)): coords per coordinate
    (g followed, g_j (n, k)); forces: element name -> (n,); inertia M (n, k, k); h (n, k);
    generalized Q without friction (n, k); torque (n, k) the drives'; acceleration (n, k);
    solved: body_forces.BodyForces; kinetic, potential (gravity, constant loads and couples),
    spring (n,); damper_power, friction_power (n,): the power each does on the linkage; lock,
    valid (n,)."""

    q: np.ndarray
    w: np.ndarray
    coef: object
    coords: list
    forces: dict
    inertia: np.ndarray
    h: np.ndarray
    generalized: np.ndarray
    torque: np.ndarray
    acceleration: np.ndarray
    solved: object
    kinetic: np.ndarray
    potential: np.ndarray
    spring: np.ndarray
    damper_power: np.ndarray
    friction_power: np.ndarray
    lock: np.ndarray
    valid: np.ndarray


def inertia_terms(system, coef, w):
    """(M (n, k, k), h (n, k), V (n,), dV/dq (n, k)) over the rows (module docstring)."""
    graph = system.graph
    n, k = len(coef.q), system.k
    m, h = np.zeros((n, k, k)), np.zeros((n, k))
    v, dv = np.zeros(n), np.zeros((n, k))
    g = np.asarray(graph.gravity, dtype=float)
    ww = w[:, :, None] * w[:, None, :]
    for body, mass in system.massive:
        p, d1, d2 = bodies.centre(graph, coef, body)
        acc = np.sum(d2 * ww[:, None], axis=(2, 3))  # (n, 2)
        m += mass.mass * np.einsum("nai,naj->nij", d1, d1)
        h += mass.mass * np.einsum("nai,na->ni", d1, acc)
        v -= mass.mass * (p @ g)
        dv -= mass.mass * np.einsum("nai,a->ni", d1, g)
        if mass.inertia and body not in graph.blocks:
            _, dth, ddth = coef.angle[body]
            m += mass.inertia * dth[:, :, None] * dth[:, None, :]
            h += mass.inertia * dth * np.sum(ddth * ww, axis=(1, 2))[:, None]
    for j, (_, body) in enumerate(graph.driven):
        if system.flywheels[j]:
            _, dth, ddth = coef.angle[body]
            m += system.flywheels[j] * dth[:, :, None] * dth[:, None, :]
            h += system.flywheels[j] * dth * np.sum(ddth * ww, axis=(1, 2))[:, None]
    for name, force in graph.forces:
        p, d1, _ = bodies.point(graph, coef, name)
        f = np.asarray(force, dtype=float)
        v -= p @ f
        dv -= np.einsum("nai,a->ni", d1, f)
    return m, h, v, dv


def coordinate_rows(system, coef, c):
    """(g, g_j (n, k)) of a coordinate over the rows: a distance, or an angle (the home's)."""
    if c.kind == "distance":
        p1, d1, _ = bodies.end_point(system.graph, coef, c.first, system.metres)
        p2, d2, _ = bodies.end_point(system.graph, coef, c.second, system.metres)
        d = p2 - p1
        length = np.hypot(d[:, 0], d[:, 1])
        with np.errstate(all="ignore"):
            rate = np.einsum("na,nai->ni", d, d2 - d1) / length[:, None]
        return length, rate
    t2, r2, _ = bodies.angle(coef, c.second or bodies.GROUND)
    t1, r1, _ = bodies.angle(coef, c.first or bodies.GROUND)
    return t2 - t1, r2 - r1


def state(system, q, w, tracked, lean: bool = False) -> State:
    """The exact state at rows q, w (n, k), `tracked` (n, m) the followed angle coordinates
    (module docstring): the drives' torques from their laws, the accelerations from the
    equation of motion (with friction: from the Newton-Euler equations, which hold it), the
    pin forces by body_forces. `lean` (the integrator's friction, one row): without the
    inertia matrix and the energies (their fields zero)."""
    from linkcli.analysis.dynamics.history import element_loads
    q = np.atleast_2d(np.asarray(q, dtype=float))
    w = np.atleast_2d(np.asarray(w, dtype=float))
    tracked = np.asarray(tracked, dtype=float).reshape(len(q), -1)
    coef = system.mech.coefficients(q, system.metres)
    if lean and system.friction is not None:
        n, k = len(q), system.k
        m, h, v, dv = np.zeros((n, k, k)), np.zeros((n, k)), np.zeros(n), np.zeros((n, k))
    else:
        m, h, v, dv = inertia_terms(system, coef, w)
    coords = []
    for k, c in enumerate(system.coordinates):
        g, dg = coordinate_rows(system, coef, c)
        if c.kind == "angle":
            near = tracked[:, system.angles.index(k)]
            g = g + TWO_PI * np.round((near - g) / TWO_PI)
        coords.append((g, dg))
    rates = [np.sum(dg * w, axis=1) for _, dg in coords]
    per_element, forces, loads, spring, couple_energy = element_loads(system, coef, coords, rates)
    generalized = -dv
    damper_power = np.zeros(len(q))
    for element, k, force in zip(system.elements, system.coordinate_of, per_element):
        generalized = generalized - force[:, None] * coords[k][1]
        if element.role == "damper":
            damper_power = damper_power - force * rates[k]
    torque = np.stack([law(w[:, j]) for j, law in enumerate(system.laws)], axis=1)
    valid = coef.valid & (coef.lock > 0)
    locked, free = list(system.locked), list(system.free)
    solved = body_forces.solve(system.graph, coef, w, loads, torque=torque, friction=system.friction,
                               held=system.locked)
    if system.friction is not None:
        qdd = solved.drive.copy()
        torque = torque.copy()
        torque[:, locked] = qdd[:, locked]  # a locked drive's unknown is its holding torque
        qdd[:, locked] = 0.0
        power = np.zeros(len(q))
        for name, _, exerting, acted in system.graph.pins:  # the couple times the relative rotation
            rate = bodies.angle(coef, acted)[1] - bodies.angle(coef, exerting)[1]
            power = power + solved.pin_friction[name] * np.sum(rate * w, axis=1)
    else:
        qdd = np.zeros((len(q), system.k))
        reduced = m[:, free][:, :, free]
        with np.errstate(all="ignore"):
            qdd[:, free] = np.linalg.solve(np.where(valid[:, None, None], reduced, np.eye(len(free))),
                                           (generalized + torque - h)[:, free, None])[..., 0]
            if locked:  # the torque that holds a locked drive: its row of the equation
                torque = torque.copy()
                torque[:, locked] = (np.einsum("nij,nj->ni", m, qdd) + h - generalized)[:, locked]
        qdd = np.where(valid[:, None], qdd, np.nan)
        power = np.zeros(len(q))
    kinetic = 0.5 * np.einsum("ni,nij,nj->n", w, m, w)
    for energy in couple_energy:
        v = v + energy
    return State(q, w, coef, coords, forces, m, h, generalized, torque, qdd, solved, kinetic,
                 v, spring, damper_power, power, coef.lock, valid)
