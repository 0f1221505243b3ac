"""User text on its way to a terminal: one line, no control characters, a sane length.

A title, a file name, a key or a value read from a file may hold terminal escapes
("\\u001b[2J" clears the screen) or newlines. `one_line` writes every non-printable
character as Python writes it in a string literal (`\\x1b`, `\\n`, `\\u2028`), so the text
is shown, never obeyed; `line` makes an error or status line of it; `shown` also cuts it to a given length with "..."; `terminal_safe`
applies `one_line` to every string (keys and values) of a report before it is printed as a
table.

The length of an error line is bounded where the error is made (`errors.bounded`).
"""

from __future__ import annotations

SHOWN_LIMIT = 200  # characters of a text `shown` keeps by default


def one_line(text: str) -> str:
    """Non-printable characters escaped as in a Python literal (printable text unchanged)."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def line(text: str) -> str:
    """One line of terminal output -- an error line, a status line (`FILE: ok`) -- with
    its newline: every control character escaped (one_line), so a file name holding
    "\\x1b[31m" or a newline is shown, never obeyed, and stays on its line. Every line
    linkcli writes to stderr, and `check`'s status lines, are made by this."""
    return one_line(text.rstrip("\n")) + "\n"


def write_error(text: str) -> None:
    """`line(text)` on stderr; a stderr that cannot take it (closed, full, or None) is
    ignored, as there is nowhere left to say so. Every error line linkcli writes goes here."""
    import sys
    try:
        sys.stderr.write(line(text))
    except (OSError, AttributeError, ValueError):
        pass


def shown(text: str, limit: int = SHOWN_LIMIT) -> str:
    """`one_line(text)`, cut to `limit` characters with a trailing "..." when longer."""
    text = one_line(text)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def terminal_safe(node):
    """A copy of a report (dicts, lists, scalars) with every string passed through one_line."""
    if isinstance(node, str):
        return one_line(node)
    if isinstance(node, dict):
        return {one_line(k) if isinstance(k, str) else k: terminal_safe(v) for k, v in node.items()}
    if isinstance(node, list):
        items = [terminal_safe(v) for v in node]
        return node.like(items) if hasattr(node, "like") else items  # report.Elided keeps its class
    return node
