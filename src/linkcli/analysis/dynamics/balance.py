"""Balancing: the shaking force and moment a linkage puts on its frame over a cycle, and the
counterweights that cancel the shaking force, side by side with the linkage as given.

At a constant drive speed w (the motion study's: [motion] input_speed, a drawn linkage's [drive]
speed) the frame carries the reaction of every body's inertia (Norton,
Design of Machinery, ch. 12; Berkof & Lowen 1969):

    F_shaking = -sum m a_G,     M_shaking = -sum (I alpha + (G - O) x m a_G)     (about O)

with O the origin of the driven body's frame (a ground pivot: the four-bar's A0) and the
accelerations from the kinematic coefficients, a_G = G'' w^2, alpha = theta'' w^2 (gravity and
the [loads] are static loads the frame carries anyway: not part of the shaking). Counterweights
come from the home's rule (a four-bar: Berkof-Lowen, on input and output); each is a point mass
at its radius (the link's length unless [dynamics] counterweights names one) and angle in the
link's frame, added to the link's mass, centre and inertia. The input torque and pin forces of
both linkages are the inverse dynamics at the same rows and speed with the file's [loads]
(dynamics.body_forces, q'' = 0), so the cost of balancing reads off side by side.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from linkcli.analysis.dynamics import bodies, body_forces
from linkcli.noise import first_max, snap


def section(system, problem, meta, notes: list) -> dict:
    from linkcli.analysis.motion_study import motion_study
    units = meta.units
    dyn = meta.dynamics
    mech, graph, metres = system.mech, system.graph, system.metres
    speed, steps = motion_study(problem, units)
    speed = mech.study_speed(speed)
    study = mech.study(None if dyn.start is None else dyn.start[0])
    phi, shown = study.rows(steps)
    inputs = study.printed(shown, units)
    coef = mech.coefficients(phi, metres)
    out = {"speed": float(units.from_rad(speed)), "rows": steps,
           "unbalanced": _summary(graph, coef, speed, inputs)}
    cases = {"unbalanced": graph}
    if dyn.counterweights:
        rule = mech.counterweights(graph, metres)
        radii = dict(dyn.counterweight_radii)
        added, weights = {}, {}
        for body, (mass_radius, angle, length) in rule.items():
            radius = radii[body] * metres if body in radii else length
            weights[body] = (mass_radius, angle, radius)
            added[body] = _with_point_mass(graph.masses.get(body), mass_radius / radius,
                                           (radius * math.cos(angle), radius * math.sin(angle)))
        balanced = replace(graph, masses={**graph.masses, **added})
        cases["balanced"] = balanced
        out["counterweights"] = {body: {"mass_radius": mr / metres, "angle": float(units.from_rad(angle)),
                                        "radius": radius / metres, "mass": mr / radius}
                                 for body, (mr, angle, radius) in weights.items()}
        out["balanced"] = _summary(balanced, coef, speed, inputs)
    out["cycle"] = _rows(cases, coef, speed, inputs)
    return out


def _with_point_mass(mass, extra: float, at):
    """A link's mass with a point mass `extra` kg at `at` (m, its frame) added: the combined
    mass, centre and inertia about the new centre (parallel axes)."""
    from linkcli.model import LinkMass
    m0 = 0.0 if mass is None else mass.mass
    c0 = np.zeros(2) if mass is None else np.asarray(mass.center, dtype=float)
    i0 = 0.0 if mass is None else mass.inertia
    at = np.asarray(at, dtype=float)
    total = m0 + extra
    centre = (m0 * c0 + extra * at) / total
    inertia = i0 + m0 * float(np.sum((c0 - centre) ** 2)) + extra * float(np.sum((at - centre) ** 2))
    return LinkMass(total, (float(centre[0]), float(centre[1])), inertia)


def shaking(graph, coef, speed: float):
    """(F (n, 2) N, M (n,) N m): the shaking force and moment (module docstring)."""
    force, moment = bodies.momentum_rates(graph, coef, speed)
    return -force, -moment


def _inverse(graph, coef, speed):
    n = len(coef.q)
    loads = body_forces.Loads(
        [(graph.points[name][0], bodies.point(graph, coef, name)[0], np.asarray(f, dtype=float))
         for name, f in graph.forces],
        [(body, np.full(n, torque)) for body, torque in graph.couples])
    return body_forces.solve(graph, coef, np.full(n, speed), loads, acceleration=np.zeros(n))


def _peak(values, inputs, scale) -> dict:
    v = np.asarray(snap(np.asarray(values, dtype=float), scale), dtype=float)
    finite = np.isfinite(v)
    if not finite.any():
        return {"max": None, "at_input": None, "rms": None}
    k = int(first_max(np.where(finite, np.abs(v), -np.inf)))
    return {"max": float(v[k]), "at_input": float(inputs[k]),
            "rms": float(snap(math.sqrt(float(np.mean(v[finite] ** 2))), scale))}


def _summary(graph, coef, speed, inputs) -> dict:
    force, moment = shaking(graph, coef, speed)
    size = np.hypot(force[:, 0], force[:, 1])
    solved = _inverse(graph, coef, speed)
    f_scale = max(float(np.max(size)), _mass_scale(graph, coef, speed))
    m_scale = max(float(np.max(np.abs(moment))), f_scale * _length(coef))
    torque = solved.drive
    t_scale = max(float(np.nanmax(np.abs(torque), initial=0.0)), m_scale)
    pins = {}
    for name, v in {**solved.pins, **solved.guides}.items():
        mag = np.hypot(v[:, 0], v[:, 1])
        pins[name] = float(snap(float(np.nanmax(mag, initial=0.0)), f_scale))
    return {"shaking_force": _peak(size, inputs, f_scale), "shaking_moment": _peak(moment, inputs, m_scale),
            "input_torque": _peak(torque, inputs, t_scale), "pins": pins}


def _mass_scale(graph, coef, speed) -> float:
    """The scale of the inertia forces: sum m |G''| w^2 over the bodies (each alone)."""
    total = 0.0
    for body in graph.bodies:
        mass = graph.masses.get(body)
        if mass is not None:
            _, _, ddg = bodies.centre(graph, coef, body)
            total += mass.mass * float(np.max(np.hypot(ddg[:, 0], ddg[:, 1]))) * speed * speed
    return total


def _length(coef) -> float:
    origins = np.concatenate([v[0] for v in coef.origin.values()])
    return max(float(np.max(np.ptp(origins, axis=0))), 1e-300)


def _rows(cases: dict, coef, speed, inputs) -> list[dict]:
    per = {}
    for name, graph in cases.items():
        force, moment = shaking(graph, coef, speed)
        scale = _mass_scale(cases["unbalanced"], coef, speed)
        per[name] = (snap(force, scale), snap(np.hypot(force[:, 0], force[:, 1]), scale),
                     snap(moment, scale * _length(coef)))
    rows = []
    for k, x in enumerate(np.asarray(inputs, dtype=float).tolist()):
        row = {"input": x}
        for name, (force, size, moment) in per.items():
            row[name] = {"shaking_force": {"x": float(force[k, 0]), "y": float(force[k, 1]),
                                           "magnitude": float(size[k])},
                         "shaking_moment": float(moment[k])}
        rows.append(row)
    return rows
