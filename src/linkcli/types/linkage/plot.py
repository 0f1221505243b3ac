"""linkage analysis: each mechanism draws its own study (`mechanisms/<name>/plot.py`): the
linkage to scale beside its motion over the drive's range."""

from __future__ import annotations

NEEDS = ("linkage",)


def draw(fig, result) -> None:
    from linkcli import mechanisms
    return mechanisms.module(result.solution.linkage.mechanism, "plot").draw(fig, result)
