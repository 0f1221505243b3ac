"""The coupler-curve atlas: timing-free path synthesis starts from a lookup (SPEC, "The
coupler-curve atlas"; docs/atlas.md).

About 100,000 four-bars of every Grashof class, both branches and coupler points all
over the coupler (`family`), their coupler curves traced and described stretch by
stretch, free of place, size, turn, start and direction (`descriptors`), built by a
seeded, deterministic `build` into a checksummed file (`store`) in the user's cache
(`cache`, on first use) or by `linkcli atlas build`. A free-timing path search looks
its targets up: the most similar stretches, placed back onto the targets,
become starts of its usual search, which polishes and confirms them as any other
(types/path_generation/atlas_starts.py: the lookup and the placing back, in the search's
own variables).

Nothing here is imported until a free-timing search asks (a four-bar analysis or a
prescribed-timing problem never loads the atlas). It knows no problem type.
"""
