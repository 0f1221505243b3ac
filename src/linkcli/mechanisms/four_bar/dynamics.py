"""The four-bar for linkcli.analysis.dynamics: its bodies and pins (BodyGraph), its kinematic
coefficients from the closed forms of `kinematics`, and the Berkof-Lowen counterweights.

Coefficients (Uicker, Pennock & Shigley, ch. 16: the velocity ratios of the links with
respect to the input angle): at unit input speed and no input acceleration the closed forms
give theta3' = w3, theta4' = w4 and theta3'' = alpha3, theta4'' = alpha4. Global frame:
A0 = ground_pivot, every link angle turned by ground_angle gamma; A = A0 + a e(gamma + phi),
A' = a perp(e), A'' = -a e.
"""

from __future__ import annotations

import cmath
import math

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.protocol import BodyGraph, Coefficients

PINS = (("A0", "A0", "ground", "input"), ("A", "A", "input", "coupler"),
        ("B", "B", "coupler", "output"), ("B0", "B0", "ground", "output"))


def body_graph(fb, case, metres: float) -> BodyGraph:
    """Bodies input (frame A0 -> A), coupler (A -> B), output (B0 -> B); pins as the loads
    report them (four_bar.loads); `coupler_force` at P, `output_torque` on the output."""
    from linkcli.mechanisms.newton_euler import in_metres
    a, b, c, _ = fb.abcd
    masses = in_metres(case.masses, metres)
    points = {"A0": ("input", (0.0, 0.0)), "A": ("input", (a * metres, 0.0)),
              "B": ("coupler", (b * metres, 0.0)), "B0": ("output", (0.0, 0.0))}
    if fb.coupler_point is not None:
        points["P"] = ("coupler", (fb.coupler_point[0] * metres, fb.coupler_point[1] * metres))
    loads = case.loads
    forces = (("P", tuple(loads.coupler_force)),) if any(loads.coupler_force) else ()
    couples = (("output", float(loads.output_torque)),) if loads.output_torque else ()
    named = {"input": masses.input, "coupler": masses.coupler, "output": masses.output}
    return BodyGraph(bodies=("input", "coupler", "output"), blocks=(),
                     masses={k: v for k, v in named.items() if v is not None}, points=points,
                     pins=PINS, guides=(), drive="input", forces=forces, couples=couples,
                     gravity=tuple(loads.gravity))


def coefficients(fb, phi, metres: float) -> Coefficients:
    """Origins and angles of input, coupler and output, with their first and second
    derivatives with respect to phi (module docstring); lock = |sin(psi - theta)|, the
    transmission angle's sine at B."""
    a, b, c, d = fb.abcd
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    p = kin.pose(a, b, c, d, phi, fb.branch)
    h3, h4 = kin.velocities(a, b, c, p, 1.0)
    dh3, dh4 = kin.accelerations(a, b, c, p, 1.0)
    gamma = fb.ground_angle
    cg, sg = math.cos(gamma), math.sin(gamma)
    a0 = np.broadcast_to(np.array(fb.ground_pivot, dtype=float) * metres, (len(phi), 2))
    b0 = a0 + d * metres * np.array([cg, sg])
    zero2, zero, one = np.zeros((len(phi), 2)), np.zeros(len(phi)), np.ones(len(phi))
    t2 = gamma + phi
    e2 = np.stack([np.cos(t2), np.sin(t2)], axis=-1)
    n2 = np.stack([-e2[:, 1], e2[:, 0]], axis=-1)
    am = a * metres
    lock = np.abs(np.sin(p.psi - p.theta))
    valid = np.asarray(p.valid) & np.isfinite(h3) & np.isfinite(dh3)
    return Coefficients(
        q=phi,
        origin={"input": (a0, zero2, zero2), "coupler": (a0 + am * e2, am * n2, -am * e2),
                "output": (b0, zero2, zero2)},
        angle={"input": (t2, one, zero), "coupler": (gamma + p.theta, h3, dh3),
               "output": (gamma + p.psi, h4, dh4)},
        valid=valid, lock=np.where(np.asarray(p.valid), lock, 0.0))


def counterweights(fb, graph: BodyGraph, metres: float) -> dict:
    """Berkof-Lowen full force balance of a four-bar by counterweights on input and output
    (Berkof & Lowen, "A new method for completely force balancing simple linkages", ASME J.
    Eng. Ind. 91 (1969) 21-26; Norton, Design of Machinery, ch. 12). With each link's mass
    moment m c (c its centre as a complex number in its own frame), the total centre of mass
    is stationary when the terms in e^{i theta2} and e^{i theta4} of sum m G vanish:

        (m c)_input  = m3 a (c3 / b - 1),      (m c)_output = -m3 c c3 / b

    (a input, b coupler, c output lengths). The counterweight on each is the difference
    between that and the link's own m c: returned as body -> (|m c| kg m, its angle rad in
    the link's frame, the link's length m: the radius a counterweight takes by default)."""
    a, b, c, _ = (v * metres for v in fb.abcd)
    def moment(name):
        mass = graph.masses.get(name)
        return 0j if mass is None else mass.mass * complex(*mass.center)
    m3 = graph.masses["coupler"].mass if "coupler" in graph.masses else 0.0
    c3 = moment("coupler") / m3 if m3 > 0 else 0j
    need = {"input": m3 * a * (c3 / b - 1.0), "output": -m3 * c * c3 / b}
    length = {"input": a, "output": c}
    out = {}
    for name, target in need.items():
        extra = target - moment(name)
        out[name] = (abs(extra), cmath.phase(extra) if abs(extra) > 0 else 0.0, length[name])
    return out
