"""User text on its way to a terminal: one line, no control characters, a sane length.

A title, a file name, a key or a value read from a file may hold terminal escapes
("\\u001b[2J" clears the screen) or newlines. `one_line` writes every non-printable
character as Python writes it in a string literal (`\\x1b`, `\\n`, `\\u2028`), so the text
is shown, never obeyed; `shown` also cuts it to SHOWN_LIMIT characters with "..." (a
100 000-character key is not a useful line); `terminal_safe` applies `one_line` to every
string (keys and values) of a report before it is printed as a table.
"""

from __future__ import annotations

SHOWN_LIMIT = 200  # characters of a key or value quoted in an error line


def one_line(text: str) -> str:
    """Non-printable characters escaped as in a Python literal (printable text unchanged)."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


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
