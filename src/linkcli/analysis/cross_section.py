"""Properties of a link's cross-section (model.LinkSection), in metres: area, the section
modulus for bending in the plane of motion, and the least second moment (a column buckles
about its weakest axis). Standard formulas (Shigley's Mechanical Engineering Design,
Table A-18):

    rectangle w x t (w in the plane)   A = w t,  I_plane = t w^3/12,  Z = t w^2/6,
                                        I_min = min(t w^3, w t^3)/12
    round d                             A = pi d^2/4,  I = pi d^4/64,  Z = pi d^3/32
    tube D, wall s (d = D - 2 s)        A = pi (D^2 - d^2)/4,  I = pi (D^4 - d^4)/64,  Z = 2 I / D
"""

from __future__ import annotations

import math
from typing import NamedTuple

from linkcli.model import LinkSection


class Properties(NamedTuple):
    area: float  # m^2
    modulus: float  # section modulus Z for bending in the plane of motion, m^3
    least_inertia: float  # smallest second moment of area, m^4


def properties(section: LinkSection, metres: float) -> Properties:
    """The section's properties with its lengths times `metres` in metres."""
    if section.shape == "rectangle":
        w, t = section.width * metres, section.thickness * metres
        return Properties(w * t, t * w * w / 6.0, min(t * w ** 3, w * t ** 3) / 12.0)
    outer = section.diameter * metres
    inner = 0.0 if section.shape == "round" else outer - 2.0 * section.wall * metres
    inertia = math.pi * (outer ** 4 - inner ** 4) / 64.0
    return Properties(math.pi * (outer ** 2 - inner ** 2) / 4.0, 2.0 * inertia / outer, inertia)
