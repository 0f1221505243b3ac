"""The exact check of a design of the shared search: every constraint it breaks on the fine
grid of its model (Model.check), each named with how much and in which unit -- what makes a
design infeasible, what the search's ranking and the Solution's message use.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.synthesis.model import Model
from linkcli.textnum import num

FEASIBLE = 1e-7  # a constraint broken by at most this (radians, or the drawing's size) is met: below
# what six printed digits resolve (1e-6 of an angle or a length), where a settle on several
# closures binding at one drive value (Jansen's leg: B, C and E together) ends ~1e-8 beyond


def violations(model: Model, x, s) -> list[tuple[str, float, str, str]]:
    """Every constraint the design breaks on the fine grid (FINE deg over its travel):
    (constraint, amount, message, unit: "length" | "angle")."""
    ev, order = model.check(np.asarray(x, dtype=float), float(s))
    out = []
    bad_targets = [k + 1 for k in np.flatnonzero(~ev.valid[0])]
    over = "the full turn" if model.crank else "the travel from the drawn position through the targets"
    for m, (kind, closure) in enumerate(model.kinds):
        g = float(ev.g[0, m])
        if not g > FEASIBLE:
            continue
        at = f"{num(math.degrees(float(ev.at[0, m])))} deg"
        if kind == "transmission":
            side = "below" if m < len(model.kinds) - len(model.pop.closures) else "above"
            out.append(("transmission", g, f"the transmission angle at {closure} is {side} the window over "
                        f"{over} (at drive angle {at})", "angle"))
        elif bad_targets and ev.anchor[0, m] >= 0:
            out.append(("assembly", g * model.size, f"the closure at {closure} cannot close at target"
                        + ("s " if len(bad_targets) > 1 else " ") + ", ".join(map(str, bad_targets))
                        + " on its drawn side", "length"))
        elif model.crank:
            out.append(("drive", g * model.size, f"the driving link cannot turn fully: the closure at {closure} "
                        f"locks (a dead point near drive angle {at})", "length"))
        else:
            out.append(("branch", g * model.size, f"the closure at {closure} locks between the drawn position "
                        f"and the targets (near drive angle {at}): the linkage would change branch", "length"))
    if order > 0:
        out.append(("order", order, "the targets are not reached in order within one turn of the drive", "angle"))
    return out
