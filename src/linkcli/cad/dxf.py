"""`--dxf FILE.dxf`: the design as a DXF drawing (R2010, through ezdxf), in the global frame
and the file's length unit (`$INSUNITS`: mm 4, cm 5, m 6, in 1; `$MEASUREMENT` follows).

Drawn from a Scene (linkcli.animate.scene), whatever the mechanism: the linkage at its
reference position (the first target's input; without targets, input 0 of a full turn or
the middle of a rocking arc; the flipper at its start), each kind on its own layer:

| layer | what | entities |
|---|---|---|
| GROUND | ground pivots | CIRCLE |
| PINS | moving pins (a pin whose path is traced too: its circle and a PATHS point) | CIRCLE |
| LINKS | each link: a line between consecutive pins (a plate closed round its pins) | LINE |
| OUTLINES | each link with a width: its pins wrapped at half the width (cad.outline) | LINE, ARC |
| GUIDES | slider guides over the slider's travel | LINE |
| SLIDERS | slider blocks | LWPOLYLINE (closed) |
| PATHS | traced paths (the coupler curve) over the motion; the traced points | LWPOLYLINE, POINT |
| TARGETS | target points, pose origins; a pose's x axis | POINT, LINE |
| POSITIONS | the linkage at its precision positions (the animation's ghosts) | LINE |
| LABELS | joint names, link names with their lengths, target numbers | TEXT |

A pin circle's diameter is the joint's `[joints] diameter` when given, else PIN_SHARE of the
drawing's size. Link outlines need widths (a link's `[sections]` width, or the diameter of a
round or tube one, from the problem's `[sections]`): a link without one is a line. Coordinates are rounded to 1e-13 of the drawing's
size (a power of ten: the same bytes on every CPU when the last bits of a sine differ);
metadata (dates, GUIDs) are fixed, so the same result gives the same bytes.
"""

from __future__ import annotations

import contextlib
import io
import math
from collections import Counter

import numpy as np

from linkcli.animate.scene import Scene

UNITS = {"mm": 4, "cm": 5, "m": 6, "in": 1}  # $INSUNITS codes (ezdxf.units)
LAYERS = {  # name -> AutoCAD colour index
    "GROUND": 8, "PINS": 7, "LINKS": 5, "OUTLINES": 4, "GUIDES": 8, "SLIDERS": 30, "PATHS": 6,
    "TARGETS": 1, "POSITIONS": 9, "LABELS": 7,
}
PIN_SHARE = 0.02  # a pin circle's diameter without [joints] diameter, share of the drawing's size
TEXT_SHARE = 0.015  # text height, share of the drawing's size
DIGITS = 13  # coordinates to 1e-13 of the drawing's size


def render(scene: Scene, widths: dict[str, float] | None = None, diameters: dict[str, float] | None = None) -> bytes:
    """The DXF of a Scene: `widths` link name -> width (outlines), `diameters` joint name ->
    pin diameter (length unit)."""
    import ezdxf
    from ezdxf.enums import TextEntityAlignment

    from linkcli.plots.common import SLIDER_SHARE, guide_ends, num
    size = scene.size
    grid = 10.0 ** (math.floor(math.log10(size)) - DIGITS)

    def q(xy) -> tuple[float, float]:
        return tuple(float(round(float(v) / grid) * grid) + 0.0 for v in xy)

    with fixed_metadata():
        doc = ezdxf.new("R2010", units=UNITS[scene.units.length])
    for name, color in LAYERS.items():
        doc.layers.add(name, color=color)
    msp = doc.modelspace()
    ref = scene.reference
    at = {name: np.asarray(xy, dtype=float)[0] for name, xy in ref.joints.items()}
    text = TEXT_SHARE * size
    diameters = diameters or {}

    def label(words: str, xy, layer: str = "LABELS") -> None:
        msp.add_text(words, height=text, dxfattribs={"layer": layer}).set_placement(
            q(np.asarray(xy) + 0.6 * text), align=TextEntityAlignment.BOTTOM_LEFT)

    carried = Counter(j for joints in ref.links.values() for j in joints)
    for name, xy in at.items():
        traced = name in ref.traced and name not in ref.ground
        if traced:
            msp.add_point(q(xy), dxfattribs={"layer": "PATHS"})
        if not traced or carried[name] >= 2 or name in ref.sliders:  # a pin, traced or not
            radius = 0.5 * (diameters.get(name) or PIN_SHARE * size)
            msp.add_circle(q(xy), radius, dxfattribs={"layer": "GROUND" if name in ref.ground else "PINS"})
        label(name, xy)
    for name, joints in ref.links.items():
        _link_lines(msp, [at[j] for j in joints], "LINKS", q)
        if len(joints) == 2:
            p, r = (at[j] for j in joints)
            label(f"{name} {num(float(np.hypot(*(r - p))), 6)} {scene.units.length}", 0.5 * (p + r))
        else:
            label(name, np.mean([at[j] for j in joints], axis=0))
        if widths and widths.get(name):
            _outline(msp, [at[j] for j in joints], widths[name], q)
    for guide in ref.guides:
        ends = guide_ends(scene.paths, guide)
        msp.add_line(q(ends[0]), q(ends[1]), dxfattribs={"layer": "GUIDES"})
    for name in ref.sliders:
        w = SLIDER_SHARE * size
        x, y = at[name]
        corners = [(x - w / 2, y - w / 3), (x + w / 2, y - w / 3), (x + w / 2, y + w / 3), (x - w / 2, y + w / 3)]
        msp.add_lwpolyline([q(c) for c in corners], close=True, dxfattribs={"layer": "SLIDERS"})
    for name in scene.paths.traced:
        for piece in _pieces(np.asarray(scene.paths.joints[name], dtype=float)):
            closed = scene.full_turn and len(piece) == len(scene.paths.valid)
            msp.add_lwpolyline([q(p) for p in piece], close=closed, dxfattribs={"layer": "PATHS"})
    for k, xy in enumerate(scene.points):
        msp.add_point(q(xy), dxfattribs={"layer": "TARGETS"})
        label(str(k + 1), xy)
    for k, (x, y, angle) in enumerate(scene.poses):
        arm = 0.12 * size
        msp.add_point(q((x, y)), dxfattribs={"layer": "TARGETS"})
        msp.add_line(q((x, y)), q((x + arm * math.cos(angle), y + arm * math.sin(angle))),
                     dxfattribs={"layer": "TARGETS"})
        label(str(k + 1), (x, y))
    ghosts = scene.ghosts
    if ghosts is not None:
        for k in np.flatnonzero(ghosts.valid):
            row = {name: np.asarray(xy, dtype=float)[k] for name, xy in ghosts.joints.items()}
            for joints in ghosts.links.values():
                _link_lines(msp, [row[j] for j in joints], "POSITIONS", q)
    return _bytes(doc)


def _link_lines(msp, pts, layer: str, q) -> None:
    """A bar's line, or a plate's lines round its pins (closed)."""
    pairs = list(zip(pts, pts[1:])) + ([(pts[-1], pts[0])] if len(pts) > 2 else [])
    for p, r in pairs:
        msp.add_line(q(p), q(r), dxfattribs={"layer": layer})


def _outline(msp, pts, width: float, q) -> None:
    from linkcli.cad.outline import outline
    for piece in outline(np.array(pts), width):
        if piece[0] == "line":
            msp.add_line(q(piece[1]), q(piece[2]), dxfattribs={"layer": "OUTLINES"})
        else:
            _, centre, radius, start, end = piece
            msp.add_arc(q(centre), radius, start, end, dxfattribs={"layer": "OUTLINES"})


def _pieces(xy: np.ndarray) -> list[np.ndarray]:
    """The runs of finite rows of an (n, 2) path (a gap where it does not assemble)."""
    ok = np.all(np.isfinite(xy), axis=1)
    cuts = np.flatnonzero(np.diff(ok.astype(np.int8))) + 1
    return [part for part, good in zip(np.split(xy, cuts), np.split(ok, cuts)) if good[0] and len(part) > 1]


@contextlib.contextmanager
def fixed_metadata():
    """ezdxf's option for reproducible files, on while a document is made and written:
    fixed dates, GUIDs and ezdxf marker strings instead of the clock's."""
    import ezdxf
    before = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = before


def _bytes(doc) -> bytes:
    """The document as DXF text (UTF-8), its metadata fixed."""
    stream = io.StringIO()
    with fixed_metadata():
        doc.write(stream)
    return stream.getvalue().encode("utf-8")
