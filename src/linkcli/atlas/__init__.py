"""The coupler-curve atlas: timing-free path synthesis starts from a lookup (SPEC, "The
coupler-curve atlas"; docs/atlas.md).

About 100,000 four-bars of every Grashof class, both branches and coupler points all
over the coupler (`family`), their coupler curves traced and described stretch by
stretch, free of place, size, turn, start and direction (`descriptors`), built by a
seeded, deterministic `build` into a checksummed file (`store`) in the user's cache
(`cache`, on first use) or by `linkcli atlas build`. A free-timing path search looks
its targets up (`lookup`): the most similar stretches, placed back onto the targets,
become starts of its usual search, which polishes and confirms them as any other.

`starts_for` is the one entry point the search calls; nothing here is imported until it
does (a four-bar analysis or a prescribed-timing problem never loads the atlas).
"""

from __future__ import annotations


def applies(problem) -> bool:
    """Whether a problem's search uses the atlas: a four-bar path generation with free
    timing whose `[solver] atlas` is not false, solved by the multistart."""
    solver = problem.meta.solver
    return (problem.meta.type == "path-generation" and getattr(problem, "timing", None) == "free"
            and getattr(problem, "mechanism", "four-bar") == "four-bar"
            and solver.method in ("auto", "multistart") and getattr(solver, "atlas", None) is not False)


def starts_for(design, count: int):
    """Up to `count` starts for a free-timing path design (path_generation.model.Design)
    from the atlas, best first: (x, sign, s, cost, evaluations) in the design's own
    variables and the targets' frame; None without an atlas (said on stderr once) or
    when none of its four-bars may serve the design's bounds and constraints."""
    from linkcli.atlas import cache, lookup
    atlas = cache.get()
    if atlas is None:
        return None
    return lookup.starts(design, atlas, count)
