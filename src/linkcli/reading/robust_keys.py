"""[objective] minimize and [constraints] defect_free of a synthesis that can design for
reliability (path and function generation; docs/tolerance.md, "Designs that minimize
failure"). Pure Python (`check` reads them).

    [objective]
    minimize = "failure-probability"   # or "error" (the default: least squares)
    [constraints]
    defect_free = 0.99                 # made linkages that assemble on the design's branch
                                       # at every target: at least this share
"""

from __future__ import annotations

from linkcli.io.reader import Table
from linkcli.reading.pareto_keys import is_front

OBJECTIVES = ("error", "failure-probability")
DEFAULT_DEFECT_FREE = 0.99


def read_objective(root: Table, meta) -> tuple[str, float] | None:
    """(minimize, defect_free); None after an error (recorded). failure-probability needs a
    [tolerance] table with allowed_error; defect_free belongs to it only."""
    t = root.table("objective")
    if is_front(root):  # an array: a Pareto front of several objectives (reading.pareto_keys)
        minimize = "error"
    else:
        minimize = t.string("minimize", "error", choices=OBJECTIVES) if t is not None else "error"
    con = root.table("constraints")
    defect_free = DEFAULT_DEFECT_FREE
    if con is not None and "defect_free" in con:
        defect_free = con.number("defect_free", what="a share of made linkages in (0, 1]")
        if defect_free is not None and not 0.0 < defect_free <= 1.0:
            con.error("defect_free", "a share of made linkages in (0, 1]", defect_free)
            defect_free = None
        if minimize == "error":
            con.error("defect_free", 'defect_free only with [objective] minimize = "failure-probability"',
                      con.raw("defect_free"))
            return None
    if minimize is None or defect_free is None:
        return None
    from linkcli.registry import problem_type
    if minimize == "failure-probability" and not problem_type(meta.type).tolerance:  # a motion design
        design = meta.type.removesuffix("-generation")
        t.error("minimize", f'"error" for a {design} design (it takes no [tolerance]: no made linkage\'s '
                "failure to count)", raw_got='"failure-probability"')
        return None
    if minimize == "failure-probability":
        tol = meta.tolerance
        raw = root.data.get("tolerance")
        if tol is not None and tol.allowed_error is None and isinstance(raw, dict) and "allowed_error" in raw:
            return None  # given, but bad: its own line says so
        if tol is None or tol.allowed_error is None:
            where = ("tolerance", "allowed_error") if "tolerance" in root else ("objective", "minimize")
            root.reader.error(where, 'a [tolerance] table with allowed_error for minimize = '
                              '"failure-probability" (a made linkage fails beyond it)',
                              raw_got="none" if tol is None else "no allowed_error")
            return None
    return minimize, defect_free
