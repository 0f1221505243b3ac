"""`[linkage]` of any mechanism: its `mechanism` key, then the keys of that mechanism's home
(its `mechanisms.schema.Schema`: `keys` and `read(t, units)`). Pure Python (`check` reads it
without numpy).
"""

from __future__ import annotations

from linkcli.io.reader import Table, describe
from linkcli.mechanisms import DEFAULT, NAMES, schema_of


def read_mechanism(t: Table, choices: tuple[str, ...] = NAMES) -> str | None:
    """`mechanism`: one of `choices`, default mechanisms.DEFAULT; None when bad (error recorded)."""
    return t.string("mechanism", DEFAULT, choices=choices)


def refuse_foreign(t: Table, mechanism: str) -> bool:
    """Keys of another mechanism, not this one's, in this [linkage]: one located error each;
    True if any."""
    own = schema_of(mechanism).keys
    foreign = [k for name in NAMES if name != mechanism for k in schema_of(name).keys if k not in own]
    found = False
    for key in dict.fromkeys(foreign):
        if key in t:
            t.allow(key)  # one message, not a second "unknown key" for the same line
            keys = f"its keys: {', '.join(own)}" if own else "its only key is mechanism"
            t.error(key, f"no {key} in a {mechanism} [linkage] ({keys})",
                    raw_got=f"{key} = {describe(t.data[key])}")
            found = True
    return found


def read_linkage(t: Table, units, choices: tuple[str, ...] = NAMES):
    """[linkage] of any mechanism in `choices`: its model dataclass; None when in error."""
    mechanism = read_mechanism(t, choices)
    if mechanism is None:  # one line for the mechanism, none for keys that depend on it
        t.allow(*dict.fromkeys(k for name in NAMES for k in schema_of(name).keys))
        return None
    foreign = refuse_foreign(t, mechanism)
    linkage = schema_of(mechanism).read(t, units)
    return None if foreign else linkage
