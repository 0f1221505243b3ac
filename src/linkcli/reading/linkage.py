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


def keys_mechanism(t: Table | None, mechanism: str) -> str | None:
    """The one other mechanism whose keys [linkage] holds, all of them its own, with some not
    `mechanism`'s; None when no single mechanism fits (or the keys are `mechanism`'s)."""
    if t is None:
        return None
    own = schema_of(mechanism).keys
    given = [k for k in t.keys() if k != "mechanism"]
    if not given or all(k in own for k in given):
        return None
    fits = [name for name in NAMES if name != mechanism and all(k in schema_of(name).keys for k in given)]
    return fits[0] if len(fits) == 1 else None


def other_mechanism(t: Table, mechanism: str) -> str | None:
    """The mechanism the keys say (keys_mechanism) when it is not `mechanism` (a result file of
    a five-bar whose `mechanism` was changed to "four-bar"): one located line names it,
    instead of one per key it blames (each foreign key, each missing one, a branch of the
    other's words); the tables that follow the mechanism ([motion]) are read as the keys'
    mechanism's. None when no single mechanism fits."""
    other = keys_mechanism(t, mechanism)
    if other is None:
        return None
    own = schema_of(mechanism).keys
    given = [k for k in t.keys() if k != "mechanism"]
    strange = [k for k in given if k not in own]
    t.allow(*t.keys())
    where = "mechanism" if "mechanism" in t else strange[0]
    t.error(where, f"the mechanism whose keys [linkage] holds: mechanism = \"{other}\" "
            f"({', '.join(strange)} {'is' if len(strange) == 1 else 'are'} a {other}'s, not a {mechanism}'s)",
            raw_got=f'mechanism = "{mechanism}"' + ("" if "mechanism" in t else " (the default)"))
    return other


def read_linkage(t: Table, units, choices: tuple[str, ...] = NAMES):
    """[linkage] of any mechanism in `choices`: its model dataclass; None when in error."""
    mechanism = read_mechanism(t, choices)
    if mechanism is None:  # one line for the mechanism, none for keys that depend on it
        t.allow(*dict.fromkeys(k for name in NAMES for k in schema_of(name).keys))
        return None
    if other_mechanism(t, mechanism) is not None:
        return None
    foreign = refuse_foreign(t, mechanism)
    linkage = schema_of(mechanism).read(t, units)
    return None if foreign else linkage
