"""Schema of `type = "linkage"`: a given four-bar, slider-crank or five-bar to analyse.

`[linkage] mechanism = "four-bar"` (the default), `"slider-crank"` (SPEC, "Slider-crank —
the second mechanism") or `"five-bar"`; `read_linkage` dispatches on it for linkage files,
precision-position files and result files alike, and the mechanism's schema reads [motion]
(`read_motion`: one drive at a constant speed, or the five-bar's rows)."""

from __future__ import annotations

from linkcli.io.reader import Table
from linkcli.mechanisms.schema import mechanism_of
from linkcli.mechanisms import schema_of
from linkcli.reading.linkage import keys_mechanism, read_linkage
from linkcli.model import Meta


def parse(root: Table, meta: Meta) -> LinkageProblem | None:
    from linkcli.model import LinkageProblem
    link = root.table("linkage", required=True)
    linkage = read_linkage(link, meta.units) if link else None
    named = mechanism_of(root)  # [motion] as the keys' mechanism's, when [linkage] holds another's
    study = schema_of(keys_mechanism(link, named) or named).read_motion(root, meta, linkage)  # its [motion]
    if linkage is None or study is None:
        return None
    linkage, speed, steps = study
    return LinkageProblem(meta=meta, linkage=linkage, input_speed=speed, steps=steps)
