"""Pin and guide friction in the integrator's right-hand side.

The friction couples depend on the pin forces, and the pin forces on everything that loads the
linkage: the inertia terms (q'^2 and the acceleration), gravity and the constant loads, each
element's force, the drive's torque, and the friction itself (dynamics.body_forces). The
equations being linear, the forces are the combination of fixed responses: the pin and guide
forces per unit of each load (body_forces.responses, the drive's acceleration eliminated),
tabulated over the drive's range at the nodes of the equation's own table (dynamics.tables) with
the pins' relative rotation and the guides' sliding rate coefficients. At each evaluation the
couples are found by fixed-point iteration on that small linear map (FRICTION_RTOL, at most
body_forces.FRICTION_ITERATIONS passes), and their generalized force is

    Q_friction = sum_pins tau_j (theta_acted' - theta_exerting') + sum_guides f_g v_g'

(tau_j = -mu r_j |F_j| sign~(rel. rotation), f_g = -mu |N_g| sign~(sliding): virtual work).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.dynamics import bodies, body_forces
from linkcli.dynamics.tables import SplineTable, nodes

FRICTION_RTOL = 1e-13


def unit_loads(system, coef) -> list:
    """[gravity's companions: the constant [loads] forces] + one Loads per element for a unit
    force of it (a tension at its ends, or a restoring torque), at the rows of `coef`."""
    graph = system.graph
    constant = body_forces.Loads(
        [(graph.points[name][0], bodies.point(graph, coef, name)[0], np.asarray(f, dtype=float))
         for name, f in graph.forces], [])
    out = [constant]
    n = len(coef.q)
    for element, k in zip(system.elements, system.coordinate_of):
        c = system.coordinates[k]
        if c.kind == "distance":
            p1 = bodies.end_point(graph, coef, c.first, system.metres)[0]
            p2 = bodies.end_point(graph, coef, c.second, system.metres)[0]
            d = p2 - p1
            u = d / np.hypot(d[:, 0], d[:, 1])[:, None]
            out.append(body_forces.Loads([(_body(graph, c.first), p1, u), (_body(graph, c.second), p2, -u)], []))
        else:
            couples = [(c.second or bodies.GROUND, -np.ones(n))]
            if c.first is not None:
                couples.append((c.first, np.ones(n)))
            out.append(body_forces.Loads([], couples))
    return out


def _body(graph, end) -> str:
    return graph.points[end.point][0] if end.point is not None else bodies.GROUND


class FrictionModel:
    """Q_friction(q, q', element forces, drive torque) for the integrator (module docstring)."""

    def __init__(self, system) -> None:
        from linkcli.dynamics.history import friction_of
        self.friction = friction_of(system)
        graph = system.graph
        q = nodes(system.lo, system.hi, system.nodes)
        coef = system.mech.coefficients(q, system.metres)
        x, assembly = body_forces.responses(graph, coef, unit_loads(system, coef))
        pin_rate, guide_rate = assembly.rates_at_pins(1.0)
        self.rows, self.columns = x.shape[1], x.shape[2]
        self.pins = [name for name, *_ in graph.pins]
        self.guides = [name for name, *_ in graph.guides]
        self.cols = [assembly.layout.pin_col[p] for p in self.pins]
        self.guide_cols = [assembly.layout.guide_col[g] for g in self.guides]
        rates = np.stack([pin_rate[p] for p in self.pins] + [guide_rate[g] for g in self.guides], axis=1) \
            if self.pins or self.guides else np.zeros((len(q), 0))
        values = np.concatenate([x.reshape(len(q), -1), rates], axis=1)
        self.table = SplineTable(system.lo, system.hi, values, system.full_turn)
        self.loads = 2 + len(system.elements) + 1
        self.radii = np.array([self.friction.radii[p] for p in self.pins])

    def __call__(self, q: float, w: float, forces: list, torque: float) -> float:
        f = self.friction
        i, t = self.table._place(q)
        c = self.table.coef[i]
        v = ((c[0] * t + c[1]) * t + c[2]) * t + c[3]
        size = self.rows * self.columns
        response = v[:size].reshape(self.rows, self.columns)
        rates = v[size:]
        pins, guides = len(self.pins), len(self.guides)
        loads = np.array([w * w, 1.0] + list(forces) + [torque])
        base = response[:, :self.loads] @ loads
        per_unit = response[:, self.loads:]
        x = base
        pin_sign = rates[:pins] * w / np.sqrt((rates[:pins] * w) ** 2 + f.eps ** 2)
        guide_sign = rates[pins:] * w / np.sqrt((rates[pins:] * w) ** 2 + f.eps_v ** 2)
        scale = float(np.max(np.abs(base))) if base.size else 0.0
        amounts = np.zeros(pins + guides)
        for _ in range(body_forces.FRICTION_ITERATIONS):
            sizes = np.concatenate([np.hypot(x[self.cols], x[[k + 1 for k in self.cols]]),
                                    np.abs(x[self.guide_cols])])
            new = -f.mu * sizes * np.concatenate([self.radii * pin_sign, guide_sign])
            change = float(np.max(np.abs(new - amounts))) if new.size else 0.0
            amounts = new
            x = base + per_unit @ amounts
            scale = max(scale, float(np.max(np.abs(x))))
            if change <= FRICTION_RTOL * max(scale, 1e-300) * max(float(np.max(self.radii, initial=0.0)), 1.0):
                break
        return float(amounts @ rates) if amounts.size else 0.0


def attach(system) -> None:
    """Give the system its friction model (the integrator reads `system.friction_rhs`)."""
    system.friction_rhs = FrictionModel(system) if system.dyn.friction else None
