"""How the table report prints the four-bar's class section (pure Python: io.report reads it)."""

from __future__ import annotations

CLASS_KEYS = ("class", "shortest", "longest", "s_plus_l", "p_plus_q")


def class_block(g: dict, fmt) -> tuple[str, list[tuple[str, object]]]:
    """("Grashof", rows): the class, the shortest and longest link, s + l against p + q."""
    sl, pq = g["s_plus_l"], g["p_plus_q"]
    rel = "vs" if sl is None or pq is None else "<" if sl < pq else ("=" if sl == pq else ">")
    return "Grashof", [("class", g["class"]), ("shortest", g["shortest"]), ("longest", g["longest"]),
                       ("s + l vs p + q", f"{fmt(sl)} {rel} {fmt(pq)}")]
