"""GIF and MP4 of a Movie: the still parts rendered once (matplotlib's Agg canvas), each
frame the moving parts drawn over a copy of them (blitting), FRAME_MS a frame.

GIF (Pillow): every frame mapped, without dithering, onto one palette: the 256 commonest
colours of three frames spread over the motion (each pixel to its nearest, so that the
drawing's flat colours stay exact); loops forever.
MP4 (imageio-ffmpeg's ffmpeg binary): H.264 (libx264, CRF 20, yuv420p), one thread and
ffmpeg's bitexact flags, no metadata. Both give identical bytes from run to run.
"""

from __future__ import annotations

import os
import tempfile

import numpy as np

from linkcli.animate.figure import Movie

FRAME_MS = 50  # milliseconds a frame: 20 frames a second
FRAMES = "frames drawn"  # what the progress display counts
PALETTE_FRAMES = 3
MP4_OPTIONS = ["-crf", "20", "-preset", "medium", "-threads", "1", "-fflags", "+bitexact",
               "-flags:v", "+bitexact", "-map_metadata", "-1"]


def rgb_frames(mv: Movie):
    """Each frame as an (h, w, 3) uint8 array, in order."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from linkcli.plots.common import STYLE
    from linkcli import progress
    canvas = FigureCanvasAgg(mv.figure)
    progress.start(FRAMES)
    with matplotlib.rc_context(STYLE):
        canvas.draw()  # the still parts (animated artists are left out)
        still = canvas.copy_from_bbox(mv.figure.bbox)
        for k in range(mv.frames):
            canvas.restore_region(still)
            mv.pose(k)
            for part in mv.parts:
                mv.axes.draw_artist(part.artist)
            yield np.asarray(canvas.buffer_rgba())[..., :3].copy()
            progress.count(FRAMES, 1, mv.frames)  # a terminal's progress display (linkcli.progress)


def common_colours(rgb: np.ndarray, most: int = 256) -> np.ndarray:
    """The `most` commonest colours of an (h, w, 3) uint8 picture, (most, 3) uint8, the
    commonest first (ties: the smaller 0xRRGGBB first), padded with black: the flat
    colours of a drawing stay exact, its anti-aliased edges take the nearest of them."""
    values, counts = np.unique(packed(rgb).ravel(), return_counts=True)
    keep = values[np.lexsort((values, -counts))][:most]
    out = np.zeros((most, 3), dtype=np.uint8)
    out[:len(keep)] = np.stack([(keep >> 16) & 255, (keep >> 8) & 255, keep & 255], axis=1)
    return out


def packed(rgb: np.ndarray) -> np.ndarray:
    """0xRRGGBB of each pixel of an (..., 3) uint8 array."""
    return (rgb[..., 0].astype(np.uint32) << 16) | (rgb[..., 1].astype(np.uint32) << 8) | rgb[..., 2]


def nearest(rgb: np.ndarray, palette: np.ndarray) -> np.ndarray:
    """(h, w) uint8 indices of the palette colour nearest each pixel (Euclidean in RGB; a
    tie to the lower index): a colour of the palette maps to itself."""
    values, inverse = np.unique(packed(rgb).ravel(), return_inverse=True)
    colours = np.stack([(values >> 16) & 255, (values >> 8) & 255, values & 255], axis=1).astype(np.int32)
    d = ((colours[:, None, :] - palette[None, :, :].astype(np.int32)) ** 2).sum(axis=2)
    return np.argmin(d, axis=1).astype(np.uint8)[inverse].reshape(rgb.shape[:2])


def gif(mv: Movie) -> bytes:
    """The animated GIF (module docstring)."""
    import io

    from PIL import Image
    frames = list(rgb_frames(mv))
    picks = sorted({int(i) for i in np.linspace(0, len(frames) - 1, PALETTE_FRAMES)})
    palette = common_colours(np.concatenate([frames[i] for i in picks], axis=0))
    indexed = []
    for frame in frames:
        index = nearest(frame, palette)
        image = Image.frombytes("P", (index.shape[1], index.shape[0]), index.tobytes())
        image.putpalette(palette.ravel().tolist())
        indexed.append(image)
    buf = io.BytesIO()
    indexed[0].save(buf, format="GIF", save_all=True, append_images=indexed[1:], duration=FRAME_MS, loop=0,
                    optimize=False)
    return buf.getvalue()


def mp4(mv: Movie) -> bytes:
    """The H.264 MP4 (module docstring); the ffmpeg binary comes with imageio-ffmpeg."""
    import imageio_ffmpeg
    width, height = (int(round(v)) for v in mv.figure.bbox.size)
    with tempfile.TemporaryDirectory(prefix="linkcli-") as tmp:
        path = os.path.join(tmp, "movie.mp4")
        writer = imageio_ffmpeg.write_frames(path, (width, height), fps=1000 / FRAME_MS, codec="libx264",
                                             quality=None, macro_block_size=16, ffmpeg_log_level="error",
                                             output_params=list(MP4_OPTIONS))
        writer.send(None)
        try:
            for frame in rgb_frames(mv):
                writer.send(np.ascontiguousarray(frame))
        finally:
            writer.close()
        with open(path, "rb") as handle:
            return handle.read()
