"""The `strength` section (docs/strength.md): pins in shear and bearing, links in tension,
compression, bending and buckling, each with a static and a fatigue safety factor over the
load cycle of the `forces` section, and the weakest part.

The loads come from the mechanism's home (`Mechanism.member_forces`: the forces on every link
and through every pin at the forces section's rows); this module never asks which mechanism
it holds. Part sizes are in the file's length unit ([joints], [sections]), strengths in MPa
([material]); stresses leave in MPa, forces in N, moments in N m. A stress below
linkcli.noise.NOISE_FLOOR times its part's stress scale (the problem's force scale over the
area) is 0; peaks tied within linkcli.noise.TIE go to the first row in sweep order.

Pins (a pin in single and double shear and its bearing stress: Shigley's Mechanical
Engineering Design, ch. 3; Norton, Machine Design, "direct shear" and "bearing stress"):
average shear tau = F / (planes pi d^2 / 4) (single shear one plane, double two), bearing
sigma_b = F / (d w), with F the magnitude of the pin force; the shear's cycle gives the
fatigue factor through von Mises (sigma' = sqrt(3) tau), its peak the static factor
0.577 Sy / tau_max; bearing's static factor is Sy / sigma_b. Links: the beam
of linkcli.analysis.beam, fibre stresses N/A +- M/Z at every load point, the static factor
Sy / |sigma|_max, the fatigue factor of the worst fibre's cycle, and the pinned-pinned column
of analysis.fatigue.column_load against the largest compression.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.analysis.beam import internal_forces
from linkcli.analysis.cross_section import properties
from linkcli.analysis.fatigue import VON_MISES_SHEAR, column_load, cycle, fatigue_factor, static_factor
from linkcli.analysis.forces import metres_per_unit
from linkcli.errors import SolveInputError
from linkcli.noise import first_max, first_min, snap

MPA = 1e6  # Pa per MPa
MAX_LISTED = 6


def section(mech, computed, speed: float, meta, notes: list) -> dict:
    """The strength section of the rows `computed` = (phi, inputs, LoadRows) of the forces
    section (analysis.forces.study_rows): material, criterion, required, pins [], links [],
    critical, rows []. Parts without sizes are listed under `unchecked` and named in a note."""
    phi, inputs, rows = computed
    spec, units = meta.strength, meta.units
    metres = metres_per_unit(units)
    members = mech.member_forces(phi, speed, meta.loads, metres, rows)
    if members is None:
        raise SolveInputError("a mechanism whose loads on each link are known for [material] (the "
                              "strength section)", f"the {mech.name}, which does not give them yet",
                              path=meta.path, line=spec.lines.get("material"), key="material")
    _check_names(members, meta)
    valid = ~rows.singular
    for load_set in members.loads.values():
        for load in load_set:
            valid &= np.all(np.isfinite(load.force), axis=1) & np.isfinite(load.couple)
    inputs = np.asarray(inputs, dtype=float)
    sizes = {j.name: j for j in meta.joints if j.diameter is not None and j.width is not None}
    pins = [_pin(name, force, sizes[name], spec, inputs, valid, metres, rows.force_scale)
            for name, force in members.pins.items() if name in sizes]
    links, plates = [], []
    for name, joints in members.links.items():
        if name not in meta.link_sections:
            continue
        if len(joints) != 2 or name in members.not_bars:
            plates.append(name)
            continue
        links.append(_link(name, members.loads[name], meta.link_sections[name], spec, inputs, valid,
                           metres, rows.force_scale))
    unchecked = ([f"pin {n}" for n in members.pins if n not in sizes]
                 + [f"link {n}" for n in members.links if n not in meta.link_sections or n in plates])
    out = {"material": _material(spec), "criterion": spec.criterion, "required": spec.required,
           "pins": [p.report for p in pins], "links": [k.report for k in links],
           "critical": _critical(pins, links, inputs)}
    if unchecked:
        out["unchecked"] = unchecked
        notes.append(_unchecked_note(unchecked, plates, members.not_bars))
    no_pin = [name for name in sizes if name not in members.pins]
    if no_pin:
        notes.append(f"[joints] {', '.join(no_pin)}: not a revolute pin (a slider's guide, a point on "
                     "one link only), its sizes are not checked for strength")
    if spec.endurance_listed:
        notes.append(f"endurance {spec.endurance:g} MPa is the listed specimen value of {spec.name} "
                     "(fully reversed, polished), not corrected for the part's surface, size and "
                     "loading: give [material] endurance for the part (docs/strength.md)")
    out["rows"] = _rows(pins, links, inputs, valid)
    return out


def shortfall(strength: dict, angle_unit: str) -> str | None:
    """The report's message when the weakest part's factor is below the required one, else
    None."""
    critical = strength.get("critical") or {}
    factor, required = critical.get("factor"), strength.get("required", 1.0)
    if factor is None or factor >= required:
        return None
    return (f"{critical['part']}: {critical['mode']} safety factor {factor:.3g} is below the "
            f"required {required:g} (at input {critical['at_input']:.6g} {angle_unit})")


# ---------------------------------------------------------------- parts
class _Part:
    """One checked part: its report row, its factor and mode, where, and its stress over the
    cycle for the rows table and the plot."""

    def __init__(self, kind: str, name: str, report: dict, stress: np.ndarray) -> None:
        self.kind, self.name, self.report, self.stress = kind, name, report, stress

    @property
    def factor(self) -> float:
        value = self.report["factor"]
        return math.inf if value is None else value


def _pin(name, force, joint, spec, inputs, valid, metres, force_scale) -> _Part:
    """Shear (average, per plane) and bearing of one pin over the valid rows."""
    d, w = joint.diameter * metres, joint.width * metres
    area = joint.shear_planes * math.pi * d * d / 4.0
    size = np.hypot(force[:, 0], force[:, 1])
    magnitude = snap(np.where(valid, size, 0.0), force_scale)
    shear = magnitude / area / MPA
    bearing = magnitude / (d * w) / MPA
    cycle_rows = shear[valid] if np.any(valid) else np.zeros(1)
    alternating, mean = cycle(cycle_rows)
    peak = int(first_max(np.where(valid, magnitude, -np.inf)))
    static = float(static_factor(VON_MISES_SHEAR * shear[peak], spec.yield_))
    bearing_factor = float(static_factor(bearing[peak], spec.yield_))
    fatigue = float(fatigue_factor(VON_MISES_SHEAR * alternating, VON_MISES_SHEAR * mean,
                                   spec.endurance, spec.ultimate, spec.yield_, spec.criterion))
    factor, mode = _weakest({"fatigue": fatigue, "static": static, "bearing": bearing_factor})
    report = {"pin": name, "diameter": joint.diameter, "width": joint.width, "shear": joint.shear,
              "force_max": float(magnitude[peak]),
              "force_min": float(np.min(magnitude[valid])) if np.any(valid) else 0.0,
              "shear_max": float(shear[peak]), "bearing_max": float(bearing[peak]),
              "at_input": float(inputs[peak]),
              "shear_alternating": float(alternating), "shear_mean": float(mean),
              "static_factor": _finite(static), "bearing_factor": _finite(bearing_factor),
              "fatigue_factor": _finite(fatigue), "factor": _finite(factor), "governs": mode}
    return _Part("pin", name, report, np.where(valid, shear, np.nan))


def _link(name, loads, shape, spec, inputs, valid, metres, force_scale) -> _Part:
    """Axial force, bending, fibre stresses and buckling of one binary link."""
    from linkcli.reading.strength import describe_section
    beam = internal_forces(loads, valid)
    props = properties(shape, metres)
    axial = snap(np.where(valid[:, None], beam.axial, 0.0), force_scale)
    moment = snap(np.where(valid[:, None, None], beam.moment, 0.0), force_scale * beam.length)
    direct = (axial / props.area)[:, :, None]
    bent = moment / props.modulus
    fibres = np.concatenate([direct + bent, direct - bent], axis=2).reshape(len(axial), -1) / MPA
    fibres = snap(fibres, force_scale / props.area / MPA)
    counted = fibres[valid] if np.any(valid) else np.zeros((1, fibres.shape[1]))
    alternating, mean = cycle(counted)
    factors = fatigue_factor(alternating, mean, spec.endurance, spec.ultimate, spec.yield_,
                             spec.criterion)
    worst = int(first_min(factors))
    fatigue = float(factors[worst])
    largest = np.max(np.abs(fibres), axis=1)
    peak = int(first_max(np.where(valid, largest, -np.inf)))
    static = float(static_factor(largest[peak], spec.yield_))
    tension = np.max(axial, axis=1)
    compression = np.max(-axial, axis=1)
    bending = np.max(np.abs(moment), axis=(1, 2))
    at_tension = int(first_max(np.where(valid, tension, -np.inf)))
    at_compression = int(first_max(np.where(valid, compression, -np.inf)))
    at_bending = int(first_max(np.where(valid, bending, -np.inf)))
    pushed = max(float(compression[at_compression]), 0.0)
    critical_load, mode = column_load(beam.length, props.area, props.least_inertia,
                                      spec.modulus * MPA, spec.yield_ * MPA)
    buckling = critical_load / pushed if pushed > 0 else math.inf
    factor, governs = _weakest({"fatigue": fatigue, "static": static, "buckling": buckling})
    report = {"link": name, "section": describe_section(shape), "length": beam.length / metres,
              "tension": max(float(tension[at_tension]), 0.0),
              "tension_at": float(inputs[at_tension]) if tension[at_tension] > 0 else None,
              "compression": pushed, "compression_at": float(inputs[at_compression]) if pushed > 0 else None,
              "bending": float(bending[at_bending]),
              "bending_at": float(inputs[at_bending]) if bending[at_bending] > 0 else None,
              "stress_max": float(largest[peak]), "at_input": float(inputs[peak]),
              "alternating": float(alternating[worst]), "mean": float(mean[worst]),
              "static_factor": _finite(static), "fatigue_factor": _finite(fatigue),
              "buckling_load": float(critical_load), "buckling": mode,
              "buckling_factor": _finite(buckling), "factor": _finite(factor), "governs": governs}
    return _Part("link", name, report, np.where(valid, largest, np.nan))


def _weakest(factors: dict) -> tuple[float, str]:
    """(smallest factor, its mode); ties go to the first named (fatigue, static, ...)."""
    mode = min(factors, key=lambda k: factors[k])
    return factors[mode], mode


def _finite(value: float):
    return None if not math.isfinite(value) else float(value)


def _critical(pins, links, inputs) -> dict | None:
    """The weakest part (ties: pins before links, each in the mechanism's order): part, kind,
    name, factor, mode and the input where its governing load peaks."""
    parts = [p for p in pins + links if p.report["factor"] is not None]
    if not parts:
        return None
    weakest = parts[int(first_min(np.array([p.factor for p in parts])))]
    r = weakest.report
    at = {"buckling": r.get("compression_at"), "bearing": r["at_input"]}.get(r["governs"], r["at_input"])
    return {"part": f"{weakest.kind} {weakest.name}", "kind": weakest.kind, "name": weakest.name,
            "factor": r["factor"], "mode": r["governs"], "at_input": at}


def _rows(pins, links, inputs, valid) -> list[dict]:
    """One row per forces row: input, each pin's shear and each link's largest fibre stress
    (MPa; null at a dead point)."""
    def column(values):
        return [v if math.isfinite(v) else None for v in np.asarray(values, dtype=float).tolist()]
    pin_cols = {p.name: column(p.stress) for p in pins}
    link_cols = {k.name: column(k.stress) for k in links}
    out = []
    for i, angle in enumerate(inputs.tolist()):
        row = {"input": angle}
        if pin_cols:
            row["pins"] = {name: values[i] for name, values in pin_cols.items()}
        if link_cols:
            row["links"] = {name: values[i] for name, values in link_cols.items()}
        out.append(row)
    return out


def _material(spec) -> dict:
    out = {"name": spec.name} if spec.name else {}
    out.update(ultimate=spec.ultimate, yield_strength=spec.yield_, endurance=spec.endurance,
               modulus=spec.modulus)
    if spec.source:
        out["source"] = spec.source
    return out


def _unchecked_note(unchecked: list[str], plates: list[str], not_bars: dict[str, str]) -> str:
    """Names the unchecked parts and why: no size, a plate, or a link that is no bar (its
    home's reason, e.g. a slider's guide)."""
    shown = ", ".join(unchecked[:MAX_LISTED]) + (f" and {len(unchecked) - MAX_LISTED} more"
                                                 if len(unchecked) > MAX_LISTED else "")
    why = "no size given ([joints] diameter and width, [sections])"
    solid = [name for name in plates if name not in not_bars]
    if solid:
        why += f"; {', '.join(solid)}: a plate of three or more joints (bars only are checked)"
    for name in plates:
        if name in not_bars:
            why += f"; {name}: {not_bars[name]} (bars only are checked)"
    return f"strength not checked for {shown}: {why}"


def _check_names(members, meta) -> None:
    """Part sizes that name no pin or link of this linkage (a drawn linkage names its own):
    exit 2, located."""
    import difflib
    for name, shape in meta.link_sections.items():
        if name not in members.links:
            hint = difflib.get_close_matches(name, list(members.links), n=1, cutoff=0.5)
            extra = f' (did you mean "{hint[0]}"?)' if hint else ""
            raise SolveInputError(f"a link of the linkage: one of {', '.join(members.links)}{extra}",
                                  f'link "{name}"', path=meta.path, line=shape.line,
                                  key=f"sections.{name}")
