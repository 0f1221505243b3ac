"""[tolerance] against the link lengths a file already fixes: a length tolerance must be
smaller than its link, the clearance smaller than every link (anything larger is a typing
error, not a workshop). Pure Python, so that `linkcli check` finds what `synth` would
(reading.load runs it on every problem; analysis.tolerance runs it again on the solved linkage).
"""

from __future__ import annotations

from linkcli.errors import SolveInputError

LINKS = ("ground", "input", "coupler", "output")


def check_lengths(meta, lengths: dict[str, float], complete: bool) -> None:
    """SolveInputError for the first tolerance not smaller than its known link, then for a
    clearance not smaller than the shortest known link. `lengths`: link -> length for the
    links known (all four when `complete`, the solved or given linkage)."""
    tol = meta.tolerance
    if tol is None or not lengths:
        return
    lines = tol.lines
    same = len(set(tol.lengths.values())) == 1
    order = [k for k in LINKS if k in lengths] + [k for k in lengths if k not in LINKS]  # a drawing's own links last
    for link in order:
        t, length = tol.lengths.get(link, 0.0), lengths[link]
        if t >= length:
            key = "lengths" + ("" if same else f".{link}")
            raise SolveInputError(f"a tolerance smaller than the {link} length ({length:.6g})", f"{t:g}",
                                  path=meta.path, line=lines.get(key), key=f"tolerance.{key}")
    shortest = min(order, key=lambda k: (lengths[k], order.index(k)))
    if tol.clearance >= lengths[shortest]:
        expected = (f"a clearance smaller than the shortest link ({lengths[shortest]:.6g})" if complete
                    else f"a clearance smaller than every link (the {shortest} is {lengths[shortest]:.6g})")
        raise SolveInputError(expected, f"{tol.clearance:g}", path=meta.path, line=lines.get("clearance"),
                              key="tolerance.clearance")


def known_lengths(problem) -> tuple[dict[str, float], bool]:
    """(link -> length, complete) of the lengths a problem fixes before solving."""
    linkage = getattr(problem, "linkage", None)
    if linkage is not None:  # a given linkage: its mechanism says which lengths it has
        from linkcli.mechanisms import schema_of
        return schema_of(linkage.mechanism).known_lengths(linkage), True
    if hasattr(problem, "fixed") and isinstance(problem.fixed, dict):  # function generation
        return {k: float(v) for k, v in problem.fixed.items() if k in LINKS}, False
    bounds = getattr(problem, "lengths", None)
    if isinstance(bounds, dict):  # path generation: a bound lo == hi fixes the length
        return {k: float(lo) for k, (lo, hi) in bounds.items() if k in LINKS and lo == hi}, False
    ground = getattr(problem, "ground", None)
    if isinstance(ground, float):  # precision positions: the ground sets the scale
        return {"ground": ground}, False
    return {}, False
