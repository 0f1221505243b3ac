"""[loads] and [masses] (docs/loads.md), read and checked in
one place for every problem whose result is a linkage (and for result files read by
`analyze`). Returns a `LoadCase`; no numerics here.

    [loads]   coupler_force = [Fx, Fy]  N at the coupler point, global frame
              output_torque = T         N m on the output link, counter-clockwise + (four-bar)
              output_force  = F         N on the slider along +x (slider-crank)
              gravity       = [gx, gy]  m/s^2, acts on the masses
    [masses]  input / coupler / output (slider-crank: slider) =
              { mass = kg, center = [x, y] (length unit, the link's own frame), inertia = kg m^2 }
"""

from __future__ import annotations

from linkcli.io.reader import Table
from linkcli.mechanisms.schema import mechanism_of


def refuse_loads(root: Table, kind: str, types_with_linkage: tuple[str, ...]) -> None:
    """[loads] or [masses] on a type whose result is not a linkage: one located line each."""
    for name in ("loads", "masses"):
        if name in root:
            root.raw(name)  # known (refused here, not again as an unknown key)
            root.error(name, f"a problem whose result is a linkage ({', '.join(types_with_linkage)}) "
                       f"for [{name}]", raw_got=f'type = "{kind}", which has no linkage')


def read_loads(root: Table, kind: str) -> LoadCase | None:
    """The load case of a problem, or None when it has neither [loads] nor [masses] (or when
    they hold errors, recorded on the reader)."""
    if "loads" not in root and "masses" not in root:
        return None
    from linkcli.mechanisms import schema_of
    return schema_of(mechanism_of(root)).read_load_case(root, kind)
