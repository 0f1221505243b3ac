"""Hints for keys in the wrong place: a top-level key written under a [table] header (TOML
puts every key after `[units]` into `units`)."""

from __future__ import annotations

from linkcli.errors import SchemaError


def top_level_hint(path: tuple[str, ...], key: str, top_level_keys: set[str]) -> str | None:
    """The `expected` text for an unknown key inside a table that is a top-level key."""
    if path and key in top_level_keys:
        return (f"a known key (did you mean the top-level key {key}? keys after a [table] "
                "header belong to that table)")
    return None


def refuse_misplaced_type(reader, kind) -> None:
    """No top-level `type`, but a table holds one (written after its header): say so."""
    if kind is not None:
        return
    for name, table in reader.data.items():
        if isinstance(table, dict) and "type" in table:
            raise SchemaError(top_level_hint((name,), "type", {"type"}), f'"type" inside [{name}]',
                              path=reader.path, line=reader.line_of((name, "type")), key=f"{name}.type")
