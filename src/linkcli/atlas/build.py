"""Build the atlas: draw the four-bars, trace their curves, describe their stretches (numpy).

`build(size, seed)` returns the arrays of an `Atlas` (store.py writes and reads them):
the four-bars of `family.draw` (closed curves first: the turning inputs, then the
rocking ones), and the descriptors (`descriptors`) of every stretch of every curve,
in two tables: `loops`, the whole loops of the closed curves (descriptors.LOOP_ARCS'
first entry: a closed target is looked up there), and `arcs`, every other stretch (the
closed curves' shorter ones, then the open curves' ones). Curves are traced and
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
    `closed` of them) and the stretch descriptors (int16): `loops` (closed x LOOPS, 2
    HARMONICS) and `arcs` (closed x LOOP_REST + open x OPEN_COUNT, 2 HARMONICS)."""

    linkages: family.Linkages
    closed: int
    loops: np.ndarray
    arcs: np.ndarray


LOOPS = descriptors.LOOP_ARCS[0][1]  # whole-loop stretches of a closed curve
LOOP_REST = sum(count for _, count in descriptors.LOOP_ARCS) - LOOPS  # its shorter ones
OPEN_COUNT = sum(count for _, count in descriptors.OPEN_ARCS)  # an open curve's stretches


def build(size: int, seed: int, progress: Callable[[int, int], None] | None = None) -> Tables:
    """The atlas of `size` four-bars drawn with `seed`; `progress(done, total)` after
    each chunk of curves."""
    linkages = family.draw(size, seed)
    closed = int(np.count_nonzero(linkages.closed))
    loops, arcs_closed, arcs_open = [], [], []
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
                desc = desc.reshape(-1, LOOPS + LOOP_REST, desc.shape[1])
                loops.append(desc[:, :LOOPS].reshape(-1, desc.shape[2]))
                arcs_closed.append(desc[:, LOOPS:].reshape(-1, desc.shape[2]))
            else:
                arcs_open.append(desc)
        if progress is not None:
            progress(int(rows[-1]) + 1, size)
    width = 2 * descriptors.HARMONICS
    empty = np.zeros((0, width), dtype=np.int16)
    return Tables(linkages=linkages, closed=closed,
                  loops=np.concatenate(loops) if loops else empty,
                  arcs=np.concatenate(arcs_closed + arcs_open) if arcs_closed + arcs_open else empty)


def stretch_of(closed: int, size: int, table: str, row: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(curve index, stretch index within its curve's `descriptors.arc_table`) of rows of
    the `loops` or `arcs` table of an atlas with `closed` closed curves of `size`."""
    row = np.asarray(row, dtype=np.int64)
    if table == "loops":
        return row // LOOPS, row % LOOPS
    split = closed * LOOP_REST
    in_closed = row < split
    curve = np.where(in_closed, row // LOOP_REST, closed + (row - split) // OPEN_COUNT)
    slot = np.where(in_closed, LOOPS + row % LOOP_REST, (row - split) % OPEN_COUNT)
    return curve, slot
