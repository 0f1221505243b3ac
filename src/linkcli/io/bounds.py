"""Values every table shares, within what double precision resolves: a length, a point, the
ratio of a linkage's longest link to its shortest. Pure Python (`check` reads it without numpy);
knows no mechanism and no problem type."""

from __future__ import annotations

from linkcli.io.reader import MISSING, Table

MIN_LENGTH, MAX_LENGTH = 1e-9, 1e9  # file's unit: beyond, squares of lengths lose all precision
MAX_RATIO = 1e6  # longest over shortest link: beyond, double precision cannot resolve the angles
ASSEMBLY_RTOL = 1e-12  # relative: ranges that only touch close at one position and cannot move


def over_ratio(lengths: dict[str, float]) -> tuple[str, str] | None:
    """(longest, shortest) names when the longest length exceeds MAX_RATIO times the
    shortest, else None."""
    longest, shortest = max(lengths, key=lengths.get), min(lengths, key=lengths.get)
    return (longest, shortest) if lengths[longest] > MAX_RATIO * lengths[shortest] else None


def refuse_ratio(t, lengths: dict) -> bool:
    """A located error (and True) when the longest link is over MAX_RATIO times the shortest:
    beyond, double precision cannot resolve the linkage's angles."""
    extremes = over_ratio(lengths)
    if not extremes:
        return False
    longest, shortest = extremes
    t.error(longest, f"a linkage whose longest link is at most {MAX_RATIO:g} times its shortest "
            "(beyond, double precision cannot resolve its angles)",
            raw_got=f"{longest} = {lengths[longest]:g} and {shortest} = {lengths[shortest]:g}, "
            f"{lengths[longest] / lengths[shortest]:.7g} times")
    return True


def bounded_length(t: Table, key: str, default=MISSING, what: str | None = None):
    """A positive length within [MIN_LENGTH, MAX_LENGTH] (a link's, a pin's, a section's: 1e-300
    gave infinite stresses and a buckling load of 0); `default` when absent (MISSING: required),
    None when bad (error recorded, said as `what` when given)."""
    value = t.number(key, default, positive=True, what=what or "a positive length")
    if value is not None and not MIN_LENGTH <= value <= MAX_LENGTH:
        span = f"within [{MIN_LENGTH:g}, {MAX_LENGTH:g}]"
        t.error(key, f"{what}, {span}" if what else f"a length {span}", value)
        return None
    return value


def bounded_point(t: Table, key: str, default):
    """Coordinates [x, y], each at most MAX_LENGTH in magnitude; None when bad."""
    value = t.number_list(key, default, length=2, what="coordinates [x, y]")
    if value is not None and max(abs(v) for v in value) > MAX_LENGTH:
        t.error(key, f"coordinates of magnitude at most {MAX_LENGTH:g}", raw_got=str(value))
        return None
    return value
