"""The names [springs], [dampers] and [dynamics] use on a drawn linkage (docs/dynamics.md): the
drawing's own joints and links, read from the file's [joints], [links] and [drive] as written
(the drawing itself is checked where it is read: drawn.schema). Pure Python (`check`)."""

from __future__ import annotations

from linkcli.dynamics.model import Parts


def parts(root, kind: str) -> Parts:
    """Points: every joint (carried by the links listing it, "ground" for a ground pivot, its
    slider block for a slider joint); links: every link of [links]; pins: the joints that join
    two bodies or more. Refused unless [drive] has exactly one entry, a link (a turning drive:
    one degree of freedom)."""
    data = root.data
    joints = data.get("joints") if isinstance(data.get("joints"), dict) else {}
    links = data.get("links") if isinstance(data.get("links"), dict) else {}
    points: dict = {}
    for name, spec in joints.items():
        carried = [link for link, held in links.items() if isinstance(held, list) and name in held]
        if isinstance(spec, dict) and spec.get("ground") is True:
            carried.insert(0, "ground")
        if isinstance(spec, dict) and "slider" in spec:
            carried.append(f"{name} (slider block)")
        points[name] = tuple(carried)
    pins = tuple(name for name, carried in points.items() if len(carried) >= 2)
    drive = data.get("drive")
    refused = None
    if isinstance(drive, dict) and (len(drive) != 1 or next(iter(drive)) not in links):
        refused = ("a drawn linkage with one drive, a link turning about its ground joint (one "
                   "degree of freedom)")
    return Parts(points=points, links=tuple(links), pins=pins, refused=refused)
