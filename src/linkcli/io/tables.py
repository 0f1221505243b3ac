"""Table layouts a problem type may ask of the table report (`report_tables` of its
sections.py), described without rich: linkcli.report draws them."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class KeyValues:
    """A two-column table: (label, value) rows."""

    title: str
    rows: list


@dataclass(frozen=True)
class Rows:
    """A table of row dicts, one column per key; `headers` maps a key to its heading;
    `no_wrap`: cells never wrap."""

    title: str
    rows: list
    headers: dict | None = None
    no_wrap: bool = False
