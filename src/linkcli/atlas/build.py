"""Build the atlas: draw the four-bars, trace their curves, describe their stretches (numpy).

`build(size, seed)` returns the arrays of an `Atlas` (store.py writes and reads them):
the four-bars of `family.draw` (closed curves first: the turning inputs, then the
rocking ones), and the descriptors (`descriptors`) of every stretch of every curve,
in two tables: `rings`, the whole loops of the closed curves (one start-free ring
descriptor each: a closed target is looked up there), and `arcs`, every other stretch
(the closed curves' shorter ones, descriptors.LOOP_ARCS, then the open curves' ones). Curves are traced and
described CHUNK at a time (memory stays flat; the bytes do not depend on the chunk:
every operation is row by row). Deterministic in (size, seed) on every CPU.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from linkcli.atlas import descriptors, family

CHUNK = 2048  # curves traced and described at a time
MIN_SIZE = 1000  # the smallest atlas `linkcli atlas build --size` makes
MAX_SIZE = 2_000_000  # and the largest (about 0.8 GB on disk)


@dataclass
class Tables:
    """What an atlas file holds: the four-bars (`family.Linkages`, closed curves first,
    `closed` of them) and the descriptors (int16): `rings` (closed, 4 RING_HARMONICS), one
    per closed curve, and `arcs` (closed x LOOP_REST + open x OPEN_COUNT, 2 HARMONICS)."""

    linkages: family.Linkages
    closed: int
    rings: np.ndarray
    arcs: np.ndarray


LOOP_REST = sum(count for _, count in descriptors.LOOP_ARCS)  # a closed curve's shorter stretches
OPEN_COUNT = sum(count for _, count in descriptors.OPEN_ARCS)  # an open curve's stretches


def build(size: int, seed: int, progress: Callable[[int, int], None] | None = None) -> Tables:
    """The atlas of `size` four-bars drawn with `seed`; `progress(done, total)` after
    each chunk of curves."""
    linkages = family.draw(size, seed)
    closed = int(np.count_nonzero(linkages.closed))
    rings, arcs_closed, arcs_open = [], [], []
    for at in range(0, size, CHUNK):
        rows = np.arange(at, min(size, at + CHUNK))
        part = linkages.take(rows)
        phi = family.input_angles(part)
        x, y = family.coupler_points(part, phi, family.angle_sines(part, phi))
        for is_closed in (True, False):
            mine = part.closed == is_closed
            if not mine.any():
                continue
            desc = descriptors.curve_descriptors(x[mine], y[mine], rows[mine], is_closed)
            if is_closed:
                rings.append(descriptors.ring_descriptors(x[mine], y[mine]))
                arcs_closed.append(desc)
            else:
                arcs_open.append(desc)
        if progress is not None:
            progress(int(rows[-1]) + 1, size)
    width = 2 * descriptors.HARMONICS
    return Tables(linkages=linkages, closed=closed,
                  rings=np.concatenate(rings) if rings else np.zeros((0, 4 * descriptors.RING_HARMONICS), np.int16),
                  arcs=np.concatenate(arcs_closed + arcs_open) if arcs_closed + arcs_open
                  else np.zeros((0, width), dtype=np.int16))


def stretch_of(closed: int, size: int, table: str, row: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(curve index, stretch index within its curve's `descriptors.arc_table`) of rows of
    the `arcs` table of an atlas with `closed` closed curves of `size` (a row of `rings`
    is its curve's index)."""
    row = np.asarray(row, dtype=np.int64)
    split = closed * LOOP_REST
    in_closed = row < split
    curve = np.where(in_closed, row // LOOP_REST, closed + (row - split) // OPEN_COUNT)
    slot = np.where(in_closed, row % LOOP_REST, (row - split) % OPEN_COUNT)
    return curve, slot
