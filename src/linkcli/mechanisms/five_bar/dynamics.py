"""The five-bar for linkcli.analysis.dynamics: its bodies and pins (BodyGraph, as its loads name
them: five_bar.loads), two drives, and its kinematic coefficients (five_bar.coefficients).

Bodies: `input` (frame A0 -> A), `input2` (B0 -> B), `coupler` (A -> P), `coupler2` (B -> P);
drives `input` (phi1, turning the input) and `input2` (phi2, turning input2), the drive values
q = (phi1, phi2), the cranks' angles from the ground line A0 -> B0, counter-clockwise. A force
at a joint acts on the first link listed there (A on input, B on input2, P on coupler), as the
loads apply the coupler force; P is traced.
"""

from __future__ import annotations

from linkcli.mechanisms.protocol import BodyGraph

PINS = (("A0", "A0", "ground", "input"), ("A", "A", "input", "coupler"), ("P", "P", "coupler", "coupler2"),
        ("B", "B", "input2", "coupler2"), ("B0", "B0", "ground", "input2"))
DRIVES = (("input", "input"), ("input2", "input2"))


def body_graph(fb, case, metres: float) -> BodyGraph:
    """The four moving links with the masses, forces and torques of `case` (module docstring)."""
    from linkcli.mechanisms.newton_euler import in_metres
    masses = in_metres(case.masses, metres)
    points = {"A0": ("input", (0.0, 0.0)), "A": ("input", (fb.input * metres, 0.0)),
              "P": ("coupler", (fb.coupler * metres, 0.0)), "B": ("input2", (fb.input2 * metres, 0.0)),
              "B0": ("input2", (0.0, 0.0))}
    loads = case.loads
    forces = (("P", tuple(loads.coupler_force)),) if any(loads.coupler_force) else ()
    named = {name: masses.of(name) for name in ("input", "input2", "coupler", "coupler2")}
    return BodyGraph(bodies=("input", "input2", "coupler", "coupler2"), blocks=(),
                     masses={k: v for k, v in named.items() if v is not None}, points=points, pins=PINS,
                     guides=(), drive="input", forces=forces,
                     couples=tuple((k, float(t)) for k, t in loads.torques if t),
                     gravity=tuple(loads.gravity), drives=DRIVES, traced=("P",))
