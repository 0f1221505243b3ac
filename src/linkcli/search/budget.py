"""The evaluation budget every search counts against, and the exception that ends a stage.

One objective evaluation of one candidate costs one unit. `spend` raises `BudgetSpent`
beyond the current cap (the strategy that set the cap catches it); `add` counts work the
caller has already fitted within `left`. `limit(k)` lowers the cap for one stage. `watch`,
when set, sees every count (the command line's progress display on a terminal).
"""

from __future__ import annotations

from collections.abc import Callable
from contextlib import contextmanager

# Told of every count (n evaluations), for a progress display: set by the command line
# only while stderr is a terminal, else None (no cost beyond this test).
watch: Callable[[int], None] | None = None


class BudgetSpent(Exception):
    """The evaluations allowed (to the whole search or to one stage) are spent; caught by
    the strategy that set the cap, it never leaves a solver."""


class Budget:
    """`used` evaluations against `cap` (the whole budget `total`, or lower within `limit`)."""

    def __init__(self, total: int) -> None:
        self.total = int(total)
        self.cap = self.total
        self.used = 0

    @property
    def left(self) -> int:
        return max(0, self.cap - self.used)

    def spend(self, n: int = 1) -> None:
        """Count n evaluations, or raise BudgetSpent (counting none) if they exceed the cap."""
        if self.used + n > self.cap:
            raise BudgetSpent
        self.used += int(n)
        if watch is not None:
            watch(int(n))

    def add(self, n: int) -> None:
        """Count n evaluations the caller has fitted within `left`."""
        self.used += int(n)
        if watch is not None:
            watch(int(n))

    @contextmanager
    def limit(self, k: int):
        """Within the block, at most k more evaluations (the cap lowered, then restored)."""
        cap = self.cap
        self.cap = min(cap, self.used + int(k))
        try:
            yield self
        finally:
            self.cap = cap
