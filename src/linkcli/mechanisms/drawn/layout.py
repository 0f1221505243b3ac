"""How the table report prints a drawn linkage's class section (pure Python: io.report reads it)."""

from __future__ import annotations

CLASS_KEYS = ("class", "mobility", "drives", "links", "sliders", "groups")


def class_block(g: dict, fmt) -> tuple[str, list[tuple[str, object]]]:
    """("Structure", rows): the class, the mobility against the drives, and the plan's groups
    one per row (the Assur groups in solve order)."""
    rows = [("class", g["class"]), ("mobility (drives)", f"{g['mobility']} ({g['drives']})"),
            ("links, sliders", f"{g['links']}, {g['sliders']}")]
    rows += [("solved" if k == 0 else "then", group) for k, group in enumerate(g["groups"])]
    return "Structure", rows
