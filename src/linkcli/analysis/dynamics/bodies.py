"""Points, centres of mass, the generalized inertia and the potential of a linkage's bodies, from
its kinematic coefficients (mechanisms.protocol.Coefficients), vectorized over rows. SI.

A point l of a body (frame origin x, angle theta, both functions of the drive value q):

    p = x + R(theta) l,   p' = x' + theta' perp(R l),   p'' = x'' + theta'' perp(R l) - theta'^2 R l

The generalized inertia of a one-drive linkage (Lagrange; Uicker, Pennock & Shigley, Theory of
Machines and Mechanisms, ch. 16; Paul, Kinematics and Dynamics of Planar Machinery, ch. 13):

    M(q) = sum_b m_b |G_b'|^2 + I_b theta_b'^2,    M'(q) = 2 sum_b m_b G_b' . G_b'' + I_b theta_b' theta_b''

so that the kinetic energy is M q'^2 / 2. The potential of gravity and of the constant [loads]
forces: V(q) = -sum_b m_b g . G_b - sum F . P, V' likewise with the first derivatives.
"""

from __future__ import annotations

import numpy as np

GROUND = "ground"


def perp(v: np.ndarray) -> np.ndarray:
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1]


def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def rotated(local, angle) -> np.ndarray:
    """R(theta) l for rows of angles and one local point (2,)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([local[0] * c - local[1] * s, local[0] * s + local[1] * c], axis=-1)


def body_point(coef, body: str, local):
    """(p, p', p'') of the point `local` (2,) of `body` over the rows (module docstring); of a
    linkage of k drives, the partials: p (n, 2), p_j (n, 2, k), p_ij (n, 2, k, k)."""
    n = len(coef.q)
    local = np.asarray(local, dtype=float)
    if body == GROUND:
        p = np.broadcast_to(local, (n, 2)).copy()
        k = coef.drives
        if k == 1:
            zero = np.zeros((n, 2))
            return p, zero, zero.copy()
        return p, np.zeros((n, 2, k)), np.zeros((n, 2, k, k))
    x, dx, ddx = coef.origin[body]
    theta, dtheta, ddtheta = coef.angle[body]
    rl = rotated(local, theta)
    prl = perp(rl)
    if np.ndim(dtheta) == 1:
        return (x + rl, dx + dtheta[:, None] * prl,
                ddx + ddtheta[:, None] * prl - (dtheta ** 2)[:, None] * rl)
    # k drives: p_j = x_j + theta_j perp(R l), p_ij = x_ij + theta_ij perp(R l) - theta_i theta_j R l
    both = dtheta[:, :, None] * dtheta[:, None, :]
    return (x + rl, dx + dtheta[:, None, :] * prl[:, :, None],
            ddx + ddtheta[:, None] * prl[:, :, None, None] - both[:, None] * rl[:, :, None, None])


def point(graph, coef, name: str):
    """(p, p', p'') of a named point of the graph."""
    body, local = graph.points[name]
    return body_point(coef, body, local)


def end_point(graph, coef, end, metres: float):
    """(p, p', p'') of an element's end: a named point, or a ground anchor (length unit)."""
    if end.point is not None:
        return point(graph, coef, end.point)
    return body_point(coef, GROUND, (end.at[0] * metres, end.at[1] * metres))


def centre(graph, coef, body: str):
    """(G, G', G'') of a body's centre of mass (its frame's origin for a massless body)."""
    mass = graph.masses.get(body)
    return body_point(coef, body, (0.0, 0.0) if mass is None else mass.center)


def angle(coef, body: str):
    """(theta, theta', theta'') of a body; the ground's is 0."""
    if body == GROUND:
        n, k = len(coef.q), coef.drives
        if k == 1:
            zero = np.zeros(n)
            return zero, zero, zero
        return np.zeros(n), np.zeros((n, k)), np.zeros((n, k, k))
    return coef.angle[body]


def inertia(graph, coef, flywheel: float = 0.0):
    """(M, M') over the rows (module docstring); `flywheel` kg m^2 turns with the drive's body."""
    n = len(coef.q)
    m_total, dm_total = np.zeros(n), np.zeros(n)
    for body in graph.bodies:
        mass = graph.masses.get(body)
        if mass is None:
            continue
        _, dg, ddg = centre(graph, coef, body)
        _, dth, ddth = coef.angle[body]
        m_total += mass.mass * dot(dg, dg)
        dm_total += 2.0 * mass.mass * dot(dg, ddg)
        if mass.inertia and body not in graph.blocks:
            m_total += mass.inertia * dth * dth
            dm_total += 2.0 * mass.inertia * dth * ddth
    if flywheel:
        _, dth, ddth = coef.angle[graph.drive]
        m_total += flywheel * dth * dth
        dm_total += 2.0 * flywheel * dth * ddth
    return m_total, dm_total


def potential(graph, coef):
    """(V, V') of gravity on the masses and of the constant [loads] forces (J, J per unit q)."""
    n = len(coef.q)
    g = np.asarray(graph.gravity, dtype=float)
    v, dv = np.zeros(n), np.zeros(n)
    for body in graph.bodies:
        mass = graph.masses.get(body)
        if mass is None or not mass.mass:
            continue
        p, dp, _ = centre(graph, coef, body)
        v -= mass.mass * (p @ g)
        dv -= mass.mass * (dp @ g)
    for name, force in graph.forces:
        p, dp, _ = point(graph, coef, name)
        f = np.asarray(force, dtype=float)
        v -= p @ f
        dv -= dp @ f
    return v, dv


def momentum_rates(graph, coef, speed: float):
    """(sum m a_G (n, 2), sum (I alpha + (G - O) x m a_G) (n,)) at a constant drive `speed`:
    the inertia forces the frame balances (balance: the shaking force and moment are their
    negatives), moments about O, the drive body's frame origin."""
    n = len(coef.q)
    force, moment = np.zeros((n, 2)), np.zeros(n)
    origin = coef.origin[graph.drive][0]
    w2 = speed * speed
    for body in graph.bodies:
        mass = graph.masses.get(body)
        if mass is None:
            continue
        g, _, ddg = centre(graph, coef, body)
        acc = ddg * w2
        force += mass.mass * acc
        moment += mass.mass * cross(g - origin, acc)
        if mass.inertia and body not in graph.blocks:
            moment += mass.inertia * coef.angle[body][2] * w2
    return force, moment
