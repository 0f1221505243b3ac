"""Numbers inside messages and notes that follow `--precision` like every other number.

A solver or an analysis writes `f"mu falls to {num(x)} deg"`: `num` wraps the full-precision
value in two private-use characters, so the text can be joined, concatenated and pickled as
an ordinary string. The writers (JSON, TOML, table, stderr) call `render(text, digits)`,
which replaces every wrapped value by the value rounded to `digits` significant digits
(noise handled where the value was computed; -0 prints as 0).
"""

from __future__ import annotations

import math
import re

OPEN, CLOSE = "\ue000", "\ue001"
_WRAPPED = re.compile(f"{OPEN}([-+]?(?:[0-9.]+(?:e[-+]?[0-9]+)?|inf|nan)){CLOSE}")


def num(value: float) -> str:
    """The value, wrapped for `render`: repr keeps every bit."""
    return f"{OPEN}{float(value)!r}{CLOSE}"


def show(value: float, digits: int) -> str:
    """A number as printed in text: `digits` significant digits, no trailing zeros, no -0."""
    if not math.isfinite(value):
        return "inf" if value > 0 else ("-inf" if value < 0 else "nan")
    text = f"{value:.{digits}g}"
    return "0" if float(text) == 0.0 else text


def render(text: str, digits: int = 6) -> str:
    """The text with every wrapped number shown to `digits` significant digits."""
    if OPEN not in text:
        return text
    return _WRAPPED.sub(lambda m: show(float(m.group(1)), digits), text)
