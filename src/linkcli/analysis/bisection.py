"""The one bisection of the tolerance searches: between a point judged good and one judged
bad (a failure count at or below a level, or not), down to where they settle."""

from __future__ import annotations


def boundary(judge, good, bad, value, settled, middle=lambda a, b: 0.5 * (a + b)):
    """(good, value): `judge(x)` -> (is good, value) at each `middle(good, bad)` until
    `settled(good, bad)`; `value` is the good end's."""
    while not settled(good, bad):
        mid = middle(good, bad)
        ok, at = judge(mid)
        if ok:
            good, value = mid, at
        else:
            bad = mid
    return good, value
