"""A drawn linkage for linkcli.analysis.dynamics: its bodies, pins and guides (BodyGraph, as its loads
name them: drawn.loads) and its kinematic coefficients.

Coefficients: the drawing's plan run at unit speed of its one drive (solver.Kinematics; every
op already gives first and second rates of each body, which at unit speed and no drive
acceleration are the velocity ratios with respect to the drive value and their derivatives).
One turning drive only: a sliding drive (a linear actuator) or several drives have no
dynamics here (body_graph gives None). Slider blocks are point masses at their joints, named
by their joint (as [masses] names them).
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache

import numpy as np

from linkcli.mechanisms.drawn.model import TURN
from linkcli.mechanisms.protocol import BodyGraph, Coefficients

GROUND_NAME = "ground"


def supported(drawing) -> bool:
    """One turning drive: a one-degree-of-freedom linkage driven by a link's angle."""
    return len(drawing.drives) == 1 and drawing.drives[0].kind == TURN


def body_graph(home, case, metres: float) -> BodyGraph | None:
    from linkcli.mechanisms.drawn.loads import SLIDER, pin_bodies, pin_names
    from linkcli.mechanisms.drawn.structure import GROUND
    from linkcli.model import LinkMass
    d = home.linkage
    if not supported(d):
        return None
    geo = home.solved.kin.geometry
    sliders = [j.name for j in d.joints if j.slider is not None]
    bodies_at = pin_bodies(d)

    def body(name, joint):
        if name == SLIDER:
            return joint
        return GROUND_NAME if name == GROUND else name

    points = {}
    for joint in d.joints:
        if joint.slider is not None:
            points[joint.name] = (joint.name, (0.0, 0.0))
            continue
        on = next((b for b in bodies_at[joint.name] if b != GROUND), None)
        if on is None:
            points[joint.name] = (GROUND_NAME, tuple(float(v) * metres for v in joint.at))
        else:
            points[joint.name] = (on, tuple(float(v) * metres for v in geo.local[(on, joint.name)]))
    pins = []
    for name, joint, acted in pin_names(d):
        if acted == "guide":
            continue
        owner = bodies_at[joint][0]
        pins.append((name, joint, body(owner, joint), body(acted, joint)))
    guides = []
    for j in sliders:
        gbody, _, beta = geo.guides[j]
        guides.append((f"{j}/guide", j, body(gbody, j), j, (float(np.cos(beta)), float(np.sin(beta)))))
    masses = {}
    for link in d.links:
        m = case.masses.of(link.name)
        if m is not None:
            masses[link.name] = LinkMass(m.mass, (m.center[0] * metres, m.center[1] * metres), m.inertia)
    for j in sliders:
        m = case.masses.of(j)
        if m is not None:
            masses[j] = LinkMass(m.mass)
    loads = case.loads
    return BodyGraph(bodies=tuple(k.name for k in d.links) + tuple(sliders), blocks=tuple(sliders),
                     masses=masses, points=points, pins=tuple(pins), guides=tuple(guides),
                     drive=d.drives[0].name, forces=tuple((j, tuple(f)) for j, f in loads.forces),
                     couples=tuple(loads.torques), gravity=tuple(loads.gravity))


@lru_cache(maxsize=16)
def unit_kinematics(drawing):
    """The drawing's plan with its drive at unit speed (the groups' tracks shared)."""
    from linkcli.mechanisms.drawn.solved import solved
    from linkcli.mechanisms.drawn.solver import Kinematics
    sv = solved(drawing)
    unit = replace(drawing, drives=(replace(drawing.drives[0], speed=1.0),))
    return Kinematics(unit, sv.structure, sv.kin.geometry, tracks=sv.kin.tracks)


def coefficients(home, x, metres: float) -> Coefficients:
    """Every link's frame origin and angle with their derivatives with respect to the drive
    value x (the drive link's angle, global, as the study's rows); slider blocks at their
    joints; lock: the smallest |sin mu| over the closures."""
    from linkcli.mechanisms.drawn.motion import closure_vectors, transmission
    d = home.linkage
    sv = home.solved
    x = np.atleast_1d(np.asarray(x, dtype=float))
    kin = unit_kinematics(d)
    st = kin.run(sv.q_of(x, sv.reach.full_turn))
    n = len(x)
    zero = np.zeros(n)
    origin, angle = {}, {}
    for link in d.links:
        k = link.name
        origin[k] = (st.origin[k] * metres, st.origin_v[k] * metres, st.origin_a[k] * metres)
        angle[k] = (st.theta[k], st.omega[k], st.alpha[k])
    for j in d.joints:
        if j.slider is not None:
            origin[j.name] = (st.pos[j.name] * metres, st.vel[j.name] * metres, st.acc[j.name] * metres)
            angle[j.name] = (zero, zero, zero)
    lock = np.ones(n)
    with np.errstate(all="ignore"):
        for c in sv.structure.closures():
            a, _, _, b, _, _ = closure_vectors(kin, st, c)
            mu, _, _ = transmission(c.kind, a, None, None, b, None, None)
            lock = np.minimum(lock, np.abs(np.sin(mu)))
    valid = st.valid & np.isfinite(lock)
    return Coefficients(q=x, origin=origin, angle=angle, valid=valid, lock=np.where(valid, lock, 0.0))
