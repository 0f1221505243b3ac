"""GIF and MP4 of a Movie: the still parts rendered once (matplotlib's Agg canvas), each
frame the moving parts drawn over a copy of them (blitting), FRAME_MS a frame.

GIF (Pillow): every frame mapped, without dithering, onto one palette: the 256 commonest
colours of three frames spread over the motion; loops forever.
MP4 (imageio-ffmpeg's ffmpeg binary): H.264 (libx264, CRF 20, yuv420p), one thread and
ffmpeg's bitexact flags, no metadata. Both give identical bytes from run to run.
"""

from __future__ import annotations

import os
import tempfile

import numpy as np

from linkcli.animate.figure import Movie

FRAME_MS = 50  # milliseconds a frame: 20 frames a second
PALETTE_FRAMES = 3
MP4_OPTIONS = ["-crf", "20", "-preset", "medium", "-threads", "1", "-fflags", "+bitexact",
               "-flags:v", "+bitexact", "-map_metadata", "-1"]


def rgb_frames(mv: Movie):
    """Each frame as an (h, w, 3) uint8 array, in order."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from linkcli.plots.common import STYLE
    canvas = FigureCanvasAgg(mv.figure)
    with matplotlib.rc_context(STYLE):
        canvas.draw()  # the still parts (animated artists are left out)
        still = canvas.copy_from_bbox(mv.figure.bbox)
        for k in range(mv.frames):
            canvas.restore_region(still)
            mv.pose(k)
            for part in mv.parts:
                mv.axes.draw_artist(part.artist)
            yield np.asarray(canvas.buffer_rgba())[..., :3].copy()


def common_colours(rgb: np.ndarray, most: int = 256) -> np.ndarray:
    """The `most` commonest colours of an (h, w, 3) uint8 picture, (most, 3) uint8, the
    commonest first (ties: the smaller 0xRRGGBB first), padded with black: the flat
    colours of a drawing stay exact, its anti-aliased edges take the nearest of them."""
    packed = (rgb[..., 0].astype(np.uint32) << 16) | (rgb[..., 1].astype(np.uint32) << 8) | rgb[..., 2]
    values, counts = np.unique(packed.ravel(), return_counts=True)
    keep = values[np.lexsort((values, -counts))][:most]
    out = np.zeros((most, 3), dtype=np.uint8)
    out[:len(keep)] = np.stack([(keep >> 16) & 255, (keep >> 8) & 255, keep & 255], axis=1)
    return out


def gif(mv: Movie) -> bytes:
    """The animated GIF (module docstring)."""
    import io

    from PIL import Image
    frames = list(rgb_frames(mv))
    picks = sorted({int(i) for i in np.linspace(0, len(frames) - 1, PALETTE_FRAMES)})
    palette = Image.new("P", (1, 1))
    palette.putpalette(common_colours(np.concatenate([frames[i] for i in picks], axis=0)).ravel().tolist())
    indexed = [Image.fromarray(f).quantize(palette=palette, dither=Image.Dither.NONE) for f in frames]
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
