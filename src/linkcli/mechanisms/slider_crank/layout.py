"""How the table report prints the slider-crank's class section (pure Python: io.report reads it)."""

from __future__ import annotations

CLASS_KEYS = ("class", "crank_plus_offset", "coupler")


def class_block(g: dict, fmt) -> tuple[str, list[tuple[str, object]]]:
    """("Class", rows): the class and the test a + |e| <= b that decides it."""
    a_e, b = g["crank_plus_offset"], g["coupler"]
    rel = "<" if a_e < b else ("=" if a_e == b else ">")
    return "Class", [("class", g["class"]), ("input + |offset| vs coupler", f"{fmt(a_e)} {rel} {fmt(b)}")]
