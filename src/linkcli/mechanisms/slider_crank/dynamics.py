"""The offset slider-crank for linkcli.analysis.dynamics: its bodies, pins and guide (BodyGraph) and
its kinematic coefficients from the closed forms of `kinematics`.

Coefficients: at unit crank speed and no crank acceleration, `velocities` gives (s', theta3')
and `accelerations` (s'', theta3''), the velocity ratios with respect to the crank angle and
their derivatives (Uicker, Pennock & Shigley, ch. 16). Frame: A0 at the origin, the guide
along +x at y = offset; A = a e(phi), B = (s, e).
"""

from __future__ import annotations

import numpy as np

from linkcli.mechanisms.protocol import BodyGraph, Coefficients
from linkcli.mechanisms.slider_crank import kinematics as sc

PINS = (("A0", "A0", "ground", "input"), ("A", "A", "input", "coupler"),
        ("B", "B", "coupler", "slider"))
GUIDES = (("guide", "B", "ground", "slider", (1.0, 0.0)),)


def body_graph(sl, case, metres: float) -> BodyGraph:
    """Bodies crank `input` (frame A0 -> A), rod `coupler` (A -> B) and the `slider` block (a
    point mass at B); pins and the guide's normal force as the loads report them
    (slider_crank.loads); `output_force` on the slider along +x, `coupler_force` at P."""
    from linkcli.mechanisms.newton_euler import in_metres
    from linkcli.model import LinkMass
    a, b, _ = sl.abe
    masses = in_metres(case.masses, metres)
    points = {"A0": ("input", (0.0, 0.0)), "A": ("input", (a * metres, 0.0)), "B": ("slider", (0.0, 0.0))}
    if sl.coupler_point is not None:
        points["P"] = ("coupler", (sl.coupler_point[0] * metres, sl.coupler_point[1] * metres))
    loads = case.loads
    forces = ((("P", tuple(loads.coupler_force)),) if any(loads.coupler_force) else ()) + \
        ((("B", (float(loads.output_force), 0.0)),) if loads.output_force else ())
    named = {"input": masses.input, "coupler": masses.coupler,
             "slider": None if masses.output is None else LinkMass(masses.output.mass)}
    return BodyGraph(bodies=("input", "coupler", "slider"), blocks=("slider",),
                     masses={k: v for k, v in named.items() if v is not None}, points=points,
                     pins=PINS, guides=GUIDES, drive="input", forces=forces,
                     gravity=tuple(loads.gravity))


def coefficients(sl, phi, metres: float) -> Coefficients:
    """Origins and angles of crank, rod and slider with their derivatives with respect to phi
    (module docstring); lock = |cos theta3| (0 where the rod stands normal to the guide)."""
    a, b, e = sl.abe
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    p = sc.pose(a, b, e, phi, sl.branch)
    ds, h3 = sc.velocities(a, b, p, 1.0)
    dds, dh3 = sc.accelerations(a, b, p, 1.0)
    n = len(phi)
    zero2, zero, one = np.zeros((n, 2)), np.zeros(n), np.ones(n)
    e2 = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    n2 = np.stack([-e2[:, 1], e2[:, 0]], axis=-1)
    am = a * metres
    slider = np.stack([p.slider * metres, np.full(n, e * metres)], axis=-1)
    valid = np.asarray(p.valid) & np.isfinite(ds) & np.isfinite(dds)
    return Coefficients(
        q=phi,
        origin={"input": (zero2, zero2, zero2), "coupler": (am * e2, am * n2, -am * e2),
                "slider": (slider, np.stack([ds * metres, zero], axis=-1),
                           np.stack([dds * metres, zero], axis=-1))},
        angle={"input": (phi, one, zero), "coupler": (p.theta, h3, dh3), "slider": (zero, zero, zero)},
        valid=valid, lock=np.where(np.asarray(p.valid), np.abs(p.run) / b, 0.0))
