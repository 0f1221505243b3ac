"""Where the atlas lives and how a search gets it: once per process, built on first use.

The default atlas (DEFAULT_SIZE four-bars, seed DEFAULT_SEED) is a file in the user's
cache folder (`platformdirs.user_cache_dir("linkcli")`: ~/.cache/linkcli on Linux,
~/Library/Caches/linkcli on macOS, %LOCALAPPDATA%\\linkcli\\Cache on Windows; the
environment variable LINKCLI_CACHE_DIR names another folder), built there by the first
search that needs it (about 10 s, said on stderr in one line) or by `linkcli atlas
build`. LINKCLI_ATLAS names an atlas file to use instead (`linkcli atlas build --out`;
measurements at other sizes); it is never rebuilt.

`get()` returns the loaded atlas, or None, and says why on stderr once per process:
a damaged, truncated or foreign file in the cache is built again; a cache folder that
cannot be written (read-only, full) leaves the search without the atlas.
"""

from __future__ import annotations

import os

import numpy as np

from linkcli.atlas import descriptors, store

DEFAULT_SIZE = 100_000
DEFAULT_SEED = 0
CACHE_ENV = "LINKCLI_CACHE_DIR"
FILE_ENV = "LINKCLI_ATLAS"

_memo: dict[str, object] = {}  # "atlas": the loaded Atlas or None, once per process
_said: set[str] = set()


class Atlas:
    """A loaded atlas: its four-bars (float64 copies of the stored float32 values), the
    `closed` count (closed curves first), the ring descriptors of the closed curves'
    loops (`rings`, the stored integers, with their magnitudes |c_k| `ring_mags` (float32,
    IEEE-rounded square roots) and squared norms `ring_norms` (exact integers in float64):
    the same bits on every CPU), and the stretch descriptors as float32 blocks (store.read: (blocks,
    10, store.BLOCK_ROWS), each block's descriptors as contiguous columns, zero-padded) of
    integer values (descriptors.QUANT: their products and sums below 2^24 are exact), with
    the reciprocals of their norms (blocks, BLOCK_ROWS) (float32, IEEE-rounded: the same on
    every CPU; 0 for padding), and the real row count."""

    def __init__(self, header: dict, arrays: dict[str, np.ndarray], path: str) -> None:
        from linkcli.atlas.family import Linkages
        self.path = path
        self.size = int(header["size"])
        self.seed = int(header["seed"])
        self.closed = int(header["closed"])
        self.linkages = Linkages(arrays["lengths"].astype(float), arrays["point"].astype(float),
                                 arrays["sign"].astype(float), arrays["kind"].astype(np.int8))
        self.rings = np.ascontiguousarray(arrays["rings"])  # int16: a match converts its candidates
        re, im = descriptors.ring_parts(self.rings.astype(np.float64))
        self.ring_mags = np.sqrt(re * re + im * im).astype(np.float32)
        self.ring_norms = np.zeros(len(self.rings))
        for k in range(re.shape[1]):
            self.ring_norms += re[:, k] * re[:, k] + im[:, k] * im[:, k]  # integers: exact
        del re, im
        self.arcs = arrays["arcs"]  # store.read(..., as_float32=True): float32 blocks
        shapes = {s["name"]: s["shape"] for s in header["sections"]}
        self.arc_rows = int(shapes["arcs"][0])
        # (size, 6) ground 1, input, coupler, output, coupler point: each four-bar at its own size
        self.shapes = np.concatenate([np.ones((self.size, 1)), self.linkages.lengths, self.linkages.point], axis=1)
        self.arc_scale = _reciprocal_norms(self.arcs)

    @property
    def nbytes(self) -> int:
        return sum(a.nbytes for a in (self.linkages.lengths, self.linkages.point, self.linkages.sign,
                                      self.linkages.kind, self.shapes, self.rings, self.ring_mags, self.ring_norms,
                                      self.arcs, self.arc_scale))


def _reciprocal_norms(table: np.ndarray) -> np.ndarray:
    """1 / |X|^2 of each descriptor (blocks, BLOCK_ROWS) (0 for a zero one: padding): the
    squared norms are integer sums below 2^24, exact in float32."""
    norms = np.zeros((table.shape[0], table.shape[2]), dtype=np.float32)
    for k in range(table.shape[1]):
        norms += table[:, k] * table[:, k]
    with np.errstate(divide="ignore"):
        return np.where(norms > 0, np.float32(1.0) / norms, np.float32(0.0)).astype(np.float32)


def cache_dir() -> str:
    given = os.environ.get(CACHE_ENV)
    if given:
        return given
    import platformdirs
    return platformdirs.user_cache_dir("linkcli", appauthor=False)


def atlas_path(size: int, seed: int) -> str:
    """The cache's file for an atlas of `size` four-bars drawn with `seed`."""
    return os.path.join(cache_dir(), f"atlas-v{store.VERSION}-{size}-{seed}.bin")


def default_path() -> str:
    return atlas_path(DEFAULT_SIZE, DEFAULT_SEED)


def say(text: str) -> None:
    """One line on stderr, once per process."""
    if text in _said:
        return
    _said.add(text)
    from linkcli.io.terminal_text import write_error
    write_error(f"linkcli: {text}")


def load(path: str) -> Atlas:
    header, arrays = store.read(path, as_float32=True)
    return Atlas(header, arrays, path)


def get() -> Atlas | None:
    """The atlas for this process (loaded once), or None when there is none to use."""
    if "atlas" not in _memo:
        _memo["atlas"] = _find()
    return _memo["atlas"]


def forget() -> None:
    """Drop the loaded atlas and what was said (tests, and `atlas build` in-process)."""
    _memo.clear()
    _said.clear()


def _find() -> Atlas | None:
    chosen = os.environ.get(FILE_ENV)
    if chosen:
        try:
            return load(chosen)
        except store.AtlasFileError as exc:
            say(f"{chosen} ({FILE_ENV}): not a usable atlas ({exc.reason}); searching without the atlas")
        except OSError as exc:
            say(f"{chosen} ({FILE_ENV}): cannot read it ({exc.strerror or exc}); searching without the atlas")
        return None
    path = default_path()
    try:
        return load(path)
    except (FileNotFoundError, NotADirectoryError):
        why = "not built yet"
    except store.AtlasFileError as exc:
        why = exc.reason
    except OSError as exc:
        say(f"{path}: cannot read the atlas ({exc.strerror or exc}); searching without the atlas")
        return None
    return _rebuild(path, why)


def _rebuild(path: str, why: str) -> Atlas | None:
    """Build the default atlas into `path` (its folder made if need be), saying so; None
    (said once) when the folder cannot be written."""
    from linkcli.atlas.build import build
    try:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        probe = os.path.join(os.path.dirname(path), f".probe.{os.getpid()}")
        with open(probe, "wb"):
            pass
        os.unlink(probe)
    except OSError as exc:
        say(f"cannot write the coupler-curve atlas to {path} ({exc.strerror or exc}); searching without the atlas")
        return None
    say(f"{path}: {why}; building the coupler-curve atlas ({DEFAULT_SIZE:,} four-bars, about 10 s, once)")
    tables = build(DEFAULT_SIZE, DEFAULT_SEED)
    data = store.encode(tables, DEFAULT_SIZE, DEFAULT_SEED)
    try:
        store.write(path, data)
    except OSError as exc:
        say(f"cannot write the coupler-curve atlas to {path} ({exc.strerror or exc}); searching without the atlas")
        return None
    del tables, data
    try:
        atlas = load(path)
    except (store.AtlasFileError, OSError) as exc:  # written, and not read back as written
        say(f"{path}: the atlas just written does not read back ({getattr(exc, 'reason', exc)}); "
            "searching without the atlas")
        return None
    return atlas
