"""A run's history at its output times, every quantity computed exactly (the homes' coefficients,
not the tables) for all output points at once: positions, speeds and works from the dense
output; the acceleration, the drive's torque, every element's force and every pin's force from
the Newton-Euler equations of all rows in one batched solve (dynamics.body_forces); the
energies. No Python loop over output points.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkcli.analysis.dynamics import bodies, body_forces


@dataclass
class State:
    """The exact state at rows (internal q, speed w): everything the report and the balance
    need. forces: element name -> (n,) its force on its coordinate (N, or N m); coords: per
    coordinate (g followed continuously, g'); generalized: Q without friction (n,);
    acceleration (n,); torque: the drive's (n,); solved: body_forces.BodyForces; energies
    kinetic, potential (gravity and constant loads, relative to `reference` rows' value when
    given), spring (n,)."""

    q: np.ndarray
    w: np.ndarray
    exact: object
    coords: list
    forces: dict
    torque: np.ndarray
    acceleration: np.ndarray
    solved: object
    kinetic: np.ndarray
    potential: np.ndarray
    spring: np.ndarray


def friction_of(system):
    """The body_forces.Friction of the file's [dynamics] friction, or None."""
    dyn = system.dyn
    if not dyn.friction:
        return None
    diameters = dict(dyn.pin_diameters)
    radii = {name: 0.5 * diameters[joint] * system.metres for name, joint, *_ in system.graph.pins}
    size = system.mech.size() * system.metres
    return body_forces.Friction(dyn.friction, radii, dyn.friction_speed, dyn.friction_speed * size)


def state(system, q, w, *, acceleration=None) -> State:
    """The exact state at internal drive values q turning at w (forward: the drive's torque
    from its law; with `acceleration` given, inverse: the torque that gives it)."""
    q = np.atleast_1d(np.asarray(q, dtype=float))
    w = np.broadcast_to(np.asarray(w, dtype=float), q.shape)
    e = system.exact(q)
    coords = []
    for k, c in enumerate(system.coordinates):
        g, dg = e.coords[k]
        if c.kind == "angle":
            g = system.angle(k, q, g)
        coords.append((g, dg))
    graph, coef = system.graph, e.coef
    per_element, forces, loads, spring, couple_energy = element_loads(
        system, coef, coords, [dg * w for _, dg in coords])
    generalized = -e.d_potential
    for element, k, force in zip(system.elements, system.coordinate_of, per_element):
        generalized = generalized - force * coords[k][1]
    potential = e.potential.copy()
    for energy in couple_energy:
        potential = potential + energy
    friction = friction_of(system)
    if acceleration is None:
        torque = system.drive(w)
        solved = body_forces.solve(graph, coef, w, loads, torque=torque, friction=friction)
        qdd = (generalized + torque - 0.5 * e.d_inertia * w * w) / e.inertia
        if friction is not None:
            qdd = solved.drive
    else:
        qdd = np.broadcast_to(np.asarray(acceleration, dtype=float), q.shape)
        solved = body_forces.solve(graph, coef, w, loads, acceleration=qdd, friction=friction)
        torque = solved.drive
    kinetic = 0.5 * e.inertia * w * w
    return State(q, w, e, coords, forces, torque, qdd, solved, kinetic, potential, spring)


def element_loads(system, coef, coords, rates):
    """Every element's force at the rows (from its coordinate (g, ...) in `coords` and its rate
    in `rates`, per coordinate), as loads on the bodies, with the constant [loads] forces:
    (forces per element in order, {name: force} of the springs and dampers, body_forces.Loads,
    the springs' stored energy (n,), the constant couples' potentials [(n,), ...])."""
    graph = system.graph
    per_element, forces, point_forces, couples = [], {}, [], []
    n = len(coef.q)
    spring, couple_energy = np.zeros(n), []
    for element, k in zip(system.elements, system.coordinate_of):
        g = coords[k][0]
        force = element.force(g, rates[k])
        per_element.append(force)
        if element.role == "couple":
            couple_energy.append(element.energy(g))
        else:
            forces[element.name] = force
            spring = spring + element.energy(g)
        c = system.coordinates[k]
        if c.kind == "distance":
            (p1, _, _), (p2, _, _) = (bodies.end_point(graph, coef, end, system.metres)
                                      for end in (c.first, c.second))
            d = p2 - p1
            u = d / np.hypot(d[:, 0], d[:, 1])[:, None]
            point_forces.append((_body_of(graph, c.first), p1, force[:, None] * u))
            point_forces.append((_body_of(graph, c.second), p2, -force[:, None] * u))
        else:
            couples.append((c.second or bodies.GROUND, -force))
            if c.first is not None:
                couples.append((c.first, force))
    for name, force in graph.forces:
        body, _ = graph.points[name]
        point_forces.append((body, bodies.point(graph, coef, name)[0], np.asarray(force, dtype=float)))
    return per_element, forces, body_forces.Loads(point_forces, couples), spring, couple_energy


def _body_of(graph, end) -> str:
    return graph.points[end.point][0] if end.point is not None else bodies.GROUND


def at_times(system, run, steps: int):
    """(times, states y (5, n), State) at `steps` times evenly spaced over the run."""
    times = np.linspace(0.0, run.t_end, steps)
    y = run.solution.sol(times)
    return times, y, state(system, y[0], y[1])
