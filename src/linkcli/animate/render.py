"""A Scene as the bytes of one animation file: `.gif`, `.mp4` (raster) or `.svg` (smil)."""

from __future__ import annotations

from linkcli.animate.scene import Scene


def render(scene: Scene, fmt: str) -> bytes:
    """The animation of a Scene in format `fmt` (".gif", ".mp4" or ".svg")."""
    from linkcli.animate import raster, smil
    from linkcli.animate.figure import movie
    if fmt == ".svg":
        return smil.svg(movie(scene, dpi=smil.SVG_DPI))
    return raster.mp4(movie(scene)) if fmt == ".mp4" else raster.gif(movie(scene))
