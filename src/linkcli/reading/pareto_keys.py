"""[objective] minimize = [...]: a Pareto front of two or three objectives (docs/pareto.md), on
path-, function-, motion- and precision-position generation. Pure Python (`check` reads it).

    [objective]
    minimize = ["error", "size"]     # two or three names, the first the one each design minimizes
    points = 20                      # designs the front is sampled at (its epsilon levels)
    reference_point = [2.0, 150.0]   # optional: the hypervolume's reference, one value per objective

A string `minimize` is the single-objective form (reading.robust_keys), read as before.
"""

from __future__ import annotations

import difflib

from linkcli.io.reader import MISSING, Table, describe

OBJECTIVES = ("error", "max-error", "transmission", "size", "link-ratio", "torque", "pin-force",
              "failure-probability")
NEEDS = {"torque": "loads", "pin-force": "loads", "failure-probability": "tolerance"}  # objective -> table
WHY = {"loads": "the loads that make the torques and pin forces",
       "tolerance": "the made linkages whose failures are counted, with allowed_error"}
MIN_OBJECTIVES, MAX_OBJECTIVES = 2, 3
DEFAULT_POINTS, MIN_POINTS, MAX_POINTS = 20, 2, 200
KEYS = ("minimize", "points", "reference_point")


def is_front(root: Table) -> bool:
    """Whether the file asks for a front: [objective] minimize is an array."""
    t = root.data.get("objective")
    return isinstance(t, dict) and isinstance(t.get("minimize"), list)


def read_front(root: Table, meta, allowed: tuple[str, ...] = OBJECTIVES):
    """(ok, Front or None): the front asked for by [objective], None when minimize is not an
    array (the single-objective form, or no [objective]); ok False after an error (recorded,
    one located line each). `allowed`: the objectives the type can measure."""
    if not is_front(root):
        return True, None
    from linkcli.model.front import Front
    t = root.table("objective")
    raw = t.raw("minimize")
    names = _names(t, raw, allowed)
    ok = names is not None and _tables_present(root, t, meta, names)
    points = t.number("points", DEFAULT_POINTS, integer=True, lo=MIN_POINTS, hi=MAX_POINTS,
                      what="an integer number of designs")
    reference = None
    if "reference_point" in t and names is not None:
        reference = t.number_list("reference_point", length=len(names),
                                  what="numbers, one per objective (the report's units)")
        ok = ok and reference is not None
    if not ok or points is None:
        return False, None
    return True, Front(objectives=tuple(names), points=int(points),
                       reference_point=None if reference is None else tuple(float(v) for v in reference),
                       line=root.reader.line_of(("objective", "minimize")))


def _names(t: Table, raw: list, allowed: tuple[str, ...]) -> list[str] | None:
    """The objectives' names, or None after one located error (the first problem found)."""
    if not MIN_OBJECTIVES <= len(raw) <= MAX_OBJECTIVES:
        t.error("minimize", f"an array of {MIN_OBJECTIVES} to {MAX_OBJECTIVES} objectives "
                "(one string alone: a single objective)",
                raw_got=f"{len(raw)} objective{'s' if len(raw) != 1 else ''}")
        return None
    seen: dict[str, int] = {}
    for i, name in enumerate(raw):
        key = f"minimize[{i}]"
        if not isinstance(name, str) or name not in allowed:
            hint = difflib.get_close_matches(name, allowed, n=1, cutoff=0.6) if isinstance(name, str) else []
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            t.error(key, f"one of: {', '.join(allowed)}{extra}", name)
            return None
        if name in seen:
            t.error(key, "each objective once", raw_got=f'"{name}" again (also minimize[{seen[name]}])')
            return None
        seen[name] = i
    return list(raw)


def _tables_present(root: Table, t: Table, meta, names: list[str]) -> bool:
    """Each objective's table is there: [loads] (or [masses]) for torque and pin-force,
    [tolerance] with allowed_error for failure-probability."""
    for i, name in enumerate(names):
        table = NEEDS.get(name)
        if table == "loads" and meta.loads is None:
            t.error(f"minimize[{i}]", f'a [loads] table for "{name}" ({WHY["loads"]})',
                    raw_got="no [loads] table")
            return False
        if table == "tolerance" and (meta.tolerance is None or meta.tolerance.allowed_error is None):
            got = "no [tolerance] table" if meta.tolerance is None else "no allowed_error in [tolerance]"
            t.error(f"minimize[{i}]", f'a [tolerance] table with allowed_error for "{name}" '
                    f'({WHY["tolerance"]})', raw_got=got)
            return False
    return True


def described(value) -> str:
    """A value as the user wrote it (for messages elsewhere)."""
    return describe(MISSING if value is None else value)
