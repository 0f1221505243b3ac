"""How the table report prints the five-bar's class section (pure Python: io.report reads it)."""

from __future__ import annotations

CLASS_KEYS = ("class", "shortest", "longest", "two_shortest_plus_longest", "other_two", "phases")


def class_block(g: dict, fmt) -> tuple[str, list[tuple[str, object]]]:
    """("Five-bar class", rows): Ting's class, the two shortest and the longest link, the two
    sums, then each phase's four-bar class (its ground: driven pivot to held elbow)."""
    sl, pq = g["two_shortest_plus_longest"], g["other_two"]
    rel = "vs" if sl is None or pq is None else "<" if sl < pq else ("=" if sl == pq else ">")
    rows = [("class", g["class"]), ("shortest", " and ".join(g["shortest"])), ("longest", g["longest"]),
            ("s1 + s2 + l vs p + q", f"{fmt(sl)} {rel} {fmt(pq)}")]
    for ph in g["phases"]:
        first, last = ph["rows"]
        rows.append((f"phase rows {first}..{last} ({ph['locked']} held)",
                     f"four-bar {ph['class']}, {ph['branch']}, ground {fmt(ph['ground'])}"))
    return "Five-bar class (Ting)", rows
