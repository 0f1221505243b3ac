"""Hints for the textbook names of the links: a newcomer writes `crank = 30` where linkcli
(the conventions of docs/format.md) says `input`. Such a key is still unknown (an error, never a silent
alias); its message names the key meant."""

from __future__ import annotations

LINK_SYNONYMS = {  # textbook name -> linkcli's key (the conventions of docs/format.md: seed-paper letters a, b, c, d)
    "crank": "input", "driver": "input",
    "rocker": "output", "follower": "output", "lever": "output",
    "connecting_rod": "coupler", "conrod": "coupler", "connecting-rod": "coupler",
    "frame": "ground", "base": "ground", "fixed_link": "ground",
}


def link_name_hint(key: str, allowed) -> str | None:
    """'a known key (did you mean "input"? ...)' for a textbook link name whose linkcli key
    the table holds, else None."""
    meant = LINK_SYNONYMS.get(key.strip().lower())
    if meant is None or meant not in allowed:
        return None
    return (f'a known key (did you mean "{meant}"? linkcli names the links input, coupler, '
            "output and ground)")
