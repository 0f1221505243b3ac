"""The made parts of a tolerance study: what [tolerance], its general-tolerance classes, the
[joints] fits or a scheme say about each toleranced dimension, pin and play of a mechanism's
Model. analysis.tolerance multiplies its unit draws by these (docs/tolerance.md).

Lengths: +- t per dimension; a class "ISO 2768-m" gives the general tolerance of ISO 2768-1
at the dimension's nominal size (standards.iso2768). Pins and plays: one radial clearance,
or per joint its ISO 286 fit at its [joints] diameter (standards.iso286): the hole and the
shaft are each made within their zones (uniform, or normal with the half zone as 3 sigma,
as the lengths), and the radial clearance is half the hole minus the shaft.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkcli.errors import SolveInputError
from linkcli.standards import iso286, iso2768

UM_TO_MM = 1e-3


@dataclass(frozen=True)
class FitZones:
    """ISO 286 fits of k joints in the file's length unit: `mid` (k,) the diametral
    clearance between the zones' middles, `hole` and `shaft` (k,) the zones' half widths.
    A made joint's radial clearance is (mid + hole vh - shaft vs) / 2, vh and vs its unit
    draws (uniform on [-1, 1], or normal with sigma 1/3); below 0 it cannot run."""

    names: tuple[str, ...]
    fits: tuple[str, ...]
    mid: np.ndarray
    hole: np.ndarray
    shaft: np.ndarray

    def radii(self, v: np.ndarray) -> np.ndarray:
        """(rows, k) radial clearances from unit draws v (rows, k, 2): hole, shaft."""
        return 0.5 * (self.mid + self.hole * v[..., 0] - self.shaft * v[..., 1])

    def zones(self) -> list[tuple[float, float]]:
        """Per joint, (hole half width, shaft half width): the toleranced diameters."""
        return [(float(h), float(s)) for h, s in zip(self.hole, self.shaft)]


@dataclass(frozen=True)
class Parts:
    """What a study makes: `scale` (columns,) the +- tolerance of each toleranced dimension,
    `clearance` the pins' radial clearance (a number, or FitZones of every pin), `play` the
    plays' size (a number, or FitZones of every play)."""

    scale: np.ndarray
    clearance: float | FitZones
    play: float | FitZones

    def with_scale(self, scale: np.ndarray) -> "Parts":
        return Parts(np.asarray(scale, dtype=float), self.clearance, self.play)

    @property
    def pins_drawn(self) -> bool:
        return isinstance(self.clearance, FitZones) or self.clearance > 0

    @property
    def plays_drawn(self) -> bool:
        return isinstance(self.play, FitZones) or self.play > 0


def column_key(model, column: str) -> str:
    """The [tolerance] lengths key of a Model column (a four-bar's coupler_point_x is
    `coupler_point`); Models that do not say use the column's name."""
    return getattr(model, "keys", {}).get(column, column)


def scales(model, problem, lengths: dict, general: dict, where: tuple[str, int | None]) -> np.ndarray:
    """(columns,) +- tolerances: lengths[key] (or the home's `column_scale(lengths)`, where
    its links hold several dimensions), or the ISO 2768-1 general tolerance of the class
    general[key] at the column's nominal size. `where` (key, line) locates errors."""
    mm = problem.meta.units.mm_per_length
    nominal = getattr(model, "nominal", model.known)
    own = getattr(model, "column_scale", None)  # a home whose links hold several dimensions
    given = own(lengths) if own is not None else None
    out = []
    for i, column in enumerate(model.columns):
        key = column_key(model, column)
        if key in general:
            size = float(nominal.get(column, 0.0))
            try:
                out.append(iso2768.deviation(general[key], size * mm) / mm)
            except iso2768.GeneralToleranceError as exc:
                expected, _, found = str(exc).partition(", found ")
                raise SolveInputError(f"{expected}; give the {column} a tolerance of its own, e.g. "
                                      f"lengths = {{ {key} = 0.1, ... }}", f"{column} {found}",
                                      path=problem.meta.path, line=where[1], key=where[0]) from None
        elif given is not None:
            out.append(float(given[i]))
        else:
            out.append(float(lengths.get(key, 0.0)))
    return np.array(out)


def fit_zones(names: tuple[str, ...], fits: dict, problem, what: str, where) -> FitZones:
    """FitZones of the joints `names`: each one's fit (`fits`, else its [joints] fit) at its
    [joints] diameter; SolveInputError naming a joint without one."""
    meta = problem.meta
    joints = {j.name: j for j in meta.joints}
    mm = meta.units.mm_per_length
    texts, mid, hole, shaft = [], [], [], []
    for name in names:
        joint = joints.get(name)
        text = fits.get(name) or (joint.fit if joint is not None else None)
        if text is None or joint is None or joint.diameter is None:
            raise SolveInputError(f"a fit for every {what} ({', '.join(names)}): {name} = "
                                  f'{{ diameter = ..., fit = "H7/g6" }} in [joints]',
                                  f"none for {name}", path=meta.path, line=where[1], key=where[0])
        fit = iso286.limits(text, joint.diameter * mm)  # checked when read (reading.tolerance_keys)
        to_unit = UM_TO_MM / mm
        texts.append(text)
        mid.append(((fit.hole.lower + fit.hole.upper) - (fit.shaft.lower + fit.shaft.upper)) / 2 * to_unit)
        hole.append((fit.hole.upper - fit.hole.lower) / 2 * to_unit)
        shaft.append((fit.shaft.upper - fit.shaft.lower) / 2 * to_unit)
    return FitZones(tuple(names), tuple(texts), np.array(mid), np.array(hole), np.array(shaft))


def parts(model, problem, *, lengths: dict | None = None, general: dict | None = None,
          fits: dict | None = None, where=None) -> Parts:
    """The made parts of the file's [tolerance] (or of a scheme: its lengths, general classes
    and fits; a scheme that names fits uses fits for every pin, the ones it does not name
    from [joints], and the guide's fit when it has one; a scheme of lengths alone keeps the
    [tolerance] clearance, a number or "fits")."""
    tol = problem.meta.tolerance
    lengths = tol.lengths if lengths is None else lengths
    general = tol.general if general is None else general
    where = where or ("tolerance.lengths", tol.lines.get("lengths"))
    scale = scales(model, problem, lengths, general, where)
    scheme = bool(fits)  # a scheme of lengths alone compares lengths at the file's clearance
    fits = fits or {}
    clearance: float | FitZones = float(tol.clearance)
    play: float | FitZones = float(model.play_size(tol))
    if tol.clearance_fits or scheme:
        at = where if scheme else ("tolerance.clearance", tol.lines.get("clearance"))
        pins = getattr(model, "pin_names", None)
        if pins is None:
            raise SolveInputError("a mechanism whose tolerance model names its pins, for fits",
                                  "a model without pin names", path=problem.meta.path, line=at[1], key=at[0])
        clearance = fit_zones(tuple(pins), fits, problem, "pin", at)
        plays = tuple(getattr(model, "play_names", ()))
        given = {j.name for j in problem.meta.joints if j.fit}
        if plays and all(p in fits or p in given for p in plays):
            play = fit_zones(plays, fits, problem, "play", at)
    return Parts(scale, clearance, play)
