"""The atlas file: a versioned header with a checksum, then the tables (numpy, zlib).

Layout: MAGIC (16 bytes), the header's length (8 bytes, little-endian), the header (JSON,
UTF-8, sorted keys), then the sections in the header's order, each little-endian and
contiguous. The header holds the format VERSION, how the atlas was made (size, seed and
the descriptor constants), the sections (name, dtype, shape) and `payload_bytes` and
`crc32` of everything after it. `read` checks the magic, the version, the constants
(an atlas of another build of linkcli is foreign), the length (truncated) and the
checksum (damaged) before trusting a byte, and raises `AtlasFileError` with the reason.

`write` writes a temporary file beside the target and renames it (another process never
sees half a file; two that build at once write the same bytes).
"""

from __future__ import annotations

import json
import os
import zlib

import numpy as np

from linkcli.atlas import descriptors, family
from linkcli.atlas.build import Tables

MAGIC = b"LINKCLI-ATLAS\x00\x00\x00"
VERSION = 2  # 2: whole loops by one start-free ring descriptor each; small cranks near the change point
MAX_HEADER = 1 << 16  # a header longer than this is not ours
READ_BLOCK = 1 << 24  # the checksum is taken while reading, this many bytes at a time


class AtlasFileError(Exception):
    """A file that is not a usable atlas: `reason` says why (one line)."""

    def __init__(self, reason: str) -> None:
        super().__init__(reason)
        self.reason = reason


def constants() -> dict:
    """What the bytes of an atlas depend on besides size and seed: a file made with other
    values is foreign (its descriptors would not compare with this build's)."""
    return {"samples": family.SAMPLES, "points": descriptors.POINTS, "harmonics": descriptors.HARMONICS,
            "quant": descriptors.QUANT, "loop_arcs": [list(a) for a in descriptors.LOOP_ARCS],
            "ring": [descriptors.RING_POINTS, descriptors.RING_HARMONICS, descriptors.RING_QUANT],
            "open_arcs": [list(a) for a in descriptors.OPEN_ARCS], "classes": list(family.CLASSES),
            "class_shares": list(family.CLASS_SHARES), "lengths": [family.LENGTH_LO, family.LENGTH_HI],
            "point_radius": family.POINT_RADIUS,
            "edge": [family.EDGE_SHARE, list(family.EDGE_INPUT), list(family.EDGE_MARGIN), list(family.EDGE_POINT)]}


def _sections(tables: Tables) -> list[tuple[str, np.ndarray]]:
    lk = tables.linkages
    return [("lengths", lk.lengths.astype("<f4")), ("point", lk.point.astype("<f4")),
            ("sign", lk.sign.astype("i1")), ("kind", lk.kind.astype("i1")),
            ("rings", tables.rings.astype("<i2")), ("arcs", tables.arcs.astype("<i2"))]


def encode(tables: Tables, size: int, seed: int) -> bytes:
    """The file's bytes."""
    sections = _sections(tables)
    payload = b"".join(np.ascontiguousarray(a).tobytes() for _, a in sections)
    header = {"format": "linkcli coupler-curve atlas", "version": VERSION, "size": size, "seed": seed,
              "closed": tables.closed, "constants": constants(),
              "sections": [{"name": n, "dtype": a.dtype.str, "shape": list(a.shape)} for n, a in sections],
              "payload_bytes": len(payload), "crc32": zlib.crc32(payload)}
    text = json.dumps(header, sort_keys=True, separators=(",", ":")).encode("utf-8")
    return MAGIC + len(text).to_bytes(8, "little") + text + payload


def write(path: str, data: bytes) -> None:
    """Write `data` to `path` through a temporary file and a rename (OSError on failure,
    the temporary file removed)."""
    folder = os.path.dirname(os.path.abspath(path))
    tmp = os.path.join(folder, f".{os.path.basename(path)}.{os.getpid()}.tmp")
    try:
        with open(tmp, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def read_header(handle) -> dict:
    """The header of an open atlas file (AtlasFileError if it is not one of this version)."""
    if handle.read(len(MAGIC)) != MAGIC:
        raise AtlasFileError("not an atlas file")
    raw = handle.read(8)
    length = int.from_bytes(raw, "little") if len(raw) == 8 else -1
    if not 0 < length <= MAX_HEADER:
        raise AtlasFileError("truncated or damaged header")
    text = handle.read(length)
    try:
        header = json.loads(text.decode("utf-8"))
    except (UnicodeDecodeError, ValueError):
        raise AtlasFileError("truncated or damaged header") from None
    if not isinstance(header, dict) or header.get("format") != "linkcli coupler-curve atlas":
        raise AtlasFileError("not an atlas file")
    if header.get("version") != VERSION:
        raise AtlasFileError(f"format version {header.get('version')!r}, this linkcli reads version {VERSION}")
    if header.get("constants") != constants():
        raise AtlasFileError("made by another build of linkcli (other descriptor constants)")
    return header


TABLES = ("arcs",)  # the stretch descriptors: `read(..., as_float32=True)` converts them
BLOCK_ROWS = 1 << 16  # descriptor rows read, checked and converted at a time: one block


def read(path: str, as_float32: bool = False) -> tuple[dict, dict[str, np.ndarray]]:
    """(header, {section name: array}) of the atlas at `path`; AtlasFileError when it is
    not a usable atlas of this version (OSError when it cannot be read). With `as_float32`
    the descriptor tables come as float32 blocks (what a lookup uses): (blocks, width,
    BLOCK_ROWS), block b holding rows b BLOCK_ROWS .. transposed (each a contiguous matrix
    for one product), the last padded with zeros; converted block by block as they are
    read, so that the file's int16 copy is never held whole."""
    with open(path, "rb") as handle:
        header = read_header(handle)
        try:
            specs = [(s["name"], np.dtype(s["dtype"]), tuple(int(v) for v in s["shape"]))
                     for s in header["sections"]]
            expected = int(header["payload_bytes"])
            crc = int(header["crc32"])
        except (KeyError, TypeError, ValueError):
            raise AtlasFileError("damaged header") from None
        sizes = [dt.itemsize * int(np.prod(shape)) for _, dt, shape in specs]
        if (sum(sizes) != expected or any(dt.kind not in "fi" for _, dt, _ in specs)
                or any(len(shape) != 2 for name, _, shape in specs if name in TABLES)):
            raise AtlasFileError("damaged header")
        arrays, got, check = {}, 0, 0
        for (name, dt, shape), nbytes in zip(specs, sizes):
            if as_float32 and name in TABLES:
                rows, width = shape
                out = np.zeros((max(1, -(-rows // BLOCK_ROWS)), width, BLOCK_ROWS), dtype=np.float32)
                step = BLOCK_ROWS * width * dt.itemsize
                for block, at in enumerate(range(0, rows, BLOCK_ROWS)):
                    want = min(step, nbytes - at * width * dt.itemsize)
                    chunk = handle.read(want)
                    got += len(chunk)
                    check = zlib.crc32(chunk, check)
                    if len(chunk) < want:
                        raise AtlasFileError(f"truncated ({got:,} of its {expected:,} bytes of tables)")
                    part = np.frombuffer(chunk, dtype=dt).reshape(-1, width).T
                    out[block, :, :part.shape[1]] = part
                arrays[name] = out
                continue
            chunk = handle.read(nbytes)
            got += len(chunk)
            check = zlib.crc32(chunk, check)
            if len(chunk) < nbytes:
                raise AtlasFileError(f"truncated ({got:,} of its {expected:,} bytes of tables)")
            arrays[name] = np.frombuffer(chunk, dtype=dt).reshape(shape)
        if handle.read(1):
            raise AtlasFileError("longer than its header says")
        if check != crc:
            raise AtlasFileError("checksum mismatch (the file is damaged)")
    need = {"lengths", "point", "sign", "kind", "rings", "arcs"}
    if not need <= set(arrays):
        raise AtlasFileError("damaged header (a section is missing)")
    return header, arrays
