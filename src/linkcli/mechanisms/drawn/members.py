"""The loads on every link of a drawn linkage and the shear through every pin (protocol.
MemberForces, for the strength section), from the pin forces of its Newton-Euler solve
(drawn.loads; the same equations, so every link's loads are in equilibrium, d'Alembert).

Every link's loads, forces ON it in N at points in m, global frame:
- its joints' forces, in its [links] order, named by the joint: the pin's force on it
  (drawn.loads.link_forces: the owner B_0 carries minus the others'); at a slider joint whose
  guide it carries, the guide's reaction -N perp(u) on it; 0 at a joint no other body shares
  (a point of the link);
- "drive": a turning drive's torque as a couple at the link's ground pivot; a sliding drive's
  reaction -F u at the slider joint on the link that carries the guide (a cylinder);
- "torque": a [loads] torque, as a couple at the link's ground pivot (its shaft), else at its
  first joint; "force": a [loads] force at a joint (on the first link of [links] carrying it,
  as drawn.loads applies it; a slider joint's force acts on the block, no link);
- "inertia": its mass's weight and d'Alembert inertia at its centre, m (g - a_G) and
  -I_G alpha (newton_euler.inertia_loads, in the link's frame: origin at its first joint, x
  towards the second as drawn).

Links: every link with its joints in [links] order; a binary link is a bar from its first
joint to its second, a link of three or more joints a plate, and a binary link that carries a
slider's guide no bar (the block runs along it; `not_bars`): strength checks bars only.

Pins: every joint joining two bodies or more (the ground, links, a slider's block; a slider's
guide is no pin). Two bodies: the force the pin's owner B_0 exerts on B_1 (the forces
section's "J"). Three or more: the pin passes through a stack of bodies whose order the
drawing does not say, so its shear is taken as the largest force it transmits to any one
body (the owner's included), row by row: F = max_i |F_i|, the force of that body. With three
bodies the two shear planes carry the two outer bodies' forces and the middle one's is their
sum, so F is at least the shear of either plane whatever the stacking; with four or more an
inner plane can carry more (docs/drawn.md).
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.drawn.loads import link_forces, pin_bodies
from linkcli.mechanisms.drawn.model import TURN
from linkcli.mechanisms.drawn.structure import GROUND
from linkcli.mechanisms.newton_euler import in_metres, inertia_loads, link_load
from linkcli.mechanisms.protocol import MemberForces

GUIDE = "carries a slider's guide (the block runs along it, no bar between two pins)"


def drawn_members(home, st, case, metres: float, rows) -> MemberForces:
    """MemberForces of a drawn linkage at the state `st` (the rows of `rows`, drawn_loads of
    the same state), lengths times `metres` in metres (module docstring)."""
    d = home.linkage
    kin = home.solved.kin
    loads, masses = case.loads, in_metres(case.masses, metres)
    pos = {j: st.pos[j] * metres for j in st.pos}
    bodies = pin_bodies(d)
    on = link_forces(d, rows)
    extra = {k.name: [] for k in d.links}
    for drive in d.drives:
        effort = rows.efforts[drive.name]
        if drive.kind == TURN:
            extra[drive.name].append(link_load("drive", pos[_pivot(d, drive.name)], couple=effort))
            continue
        _, u, body = kin.guide_line(st, drive.name)
        if body != GROUND:
            extra[body].append(link_load("drive", pos[drive.name], -effort[:, None] * u))
    for link, torque in loads.torques:
        extra[link].append(link_load("torque", pos[_pivot(d, link) or d.link(link).joints[0]],
                                     couple=torque))
    for joint, force in loads.forces:
        if d.joint(joint).slider is None:
            target = next(b for b in bodies[joint] if b != GROUND)
            extra[target].append(link_load("force", pos[joint], force))
    links, member_loads, not_bars = {}, {}, {}
    for k in d.links:
        joints = []
        for j in k.joints:
            force = on.get((j, k.name))
            if d.joint(j).guide == k.name:
                force = -rows.pins[f"{j}/guide"]
                if len(k.joints) == 2:
                    not_bars[k.name] = GUIDE
            joints.append(link_load(j, pos[j], force))
        c, s = np.cos(st.theta[k.name]), np.sin(st.theta[k.name])
        origin = st.origin[k.name] * metres
        weight = inertia_loads(masses.of(k.name), origin, origin + np.stack([c, s], axis=-1),
                               st.origin_a[k.name] * metres, st.omega[k.name], st.alpha[k.name],
                               loads.gravity)
        links[k.name] = k.joints
        member_loads[k.name] = (*joints, *extra[k.name], *weight)
    return MemberForces(links=links, loads=member_loads, pins=_pins(bodies, on), not_bars=not_bars)


def _pivot(drawing, link: str) -> str | None:
    """The link's ground joint (a link has at most one), else None."""
    return next((j for j in drawing.link(link).joints if drawing.joint(j).ground), None)


def _pins(bodies: dict, on: dict) -> dict[str, np.ndarray]:
    """Joint -> (n, 2) N: the shear force of each pin joining two bodies or more (module
    docstring): two bodies, the owner's force on the other; more, at each row the force of
    largest magnitude on any one body (ties: the first in the bodies' order)."""
    out = {}
    for joint, joined in bodies.items():
        if len(joined) < 2:
            continue
        if len(joined) == 2:
            out[joint] = on[(joint, joined[1])]
            continue
        forces = np.stack([on[(joint, b)] for b in joined], axis=1)  # (n, k, 2)
        size = np.hypot(forces[..., 0], forces[..., 1])
        pick = np.argmax(np.where(np.isnan(size), -np.inf, size), axis=1)
        out[joint] = np.take_along_axis(forces, pick[:, None, None], axis=1)[:, 0]
    return out
