"""Where the front's chains of levels are solved: in this process, or spread by the command.

The chains of a front (two per row of levels, one from each end: linkcli.pareto.front, 3.)
are independent solves, so `synth --jobs N` on one file and `--cluster` may solve them
elsewhere; the command's pipeline installs a map for the solve (`using`), the front search
calls `map_levels`. The results are the same whichever map runs them (each chain depends on
the anchors only).
"""

from __future__ import annotations

import contextlib
import contextvars
from collections.abc import Callable, Iterable

_MAP: contextvars.ContextVar = contextvars.ContextVar("linkcli_front_map", default=None)


@contextlib.contextmanager
def using(mapper: Callable | None):
    """Within the block, `map_levels` runs through `mapper(function, items) -> results in
    order` (None: in this process)."""
    token = _MAP.set(mapper)
    try:
        yield
    finally:
        _MAP.reset(token)


def map_levels(function: Callable, items: Iterable) -> list:
    """[function(item) for item in items], through the installed map when there is one."""
    items = list(items)
    mapper = _MAP.get()
    if mapper is None or len(items) < 2:
        return [function(item) for item in items]
    return list(mapper(function, items))
