"""The five-bar's own report sections (docs/five_bar.md): linkage, grashof (Ting's class and
each phase's four-bar), transmission (over the rows: at P, at the elbows, the condition
number, the nearest singularity; each phase's four-bar over its span), motion (the rows'
ranges and the task, echoed so that `analyze` of a result reproduces it) and kinematics
(one row per row of [motion]).

Conventions of every number: global frame (A0 at `ground_pivot`, the ground line at
`ground_angle`); angles in the file's angle unit, positions wrapped to (-180, 180]; the
Jacobian columns dP/dinput and dP/dinput2 in length unit per angle unit (P's velocity for
unit speeds of that drive, the other held); velocity and acceleration of P in length unit
per s and per s^2 for the drives' [motion] input_speeds and input_accelerations (0 for a drive
held by a phase on its rows). Round-off is 0 under the noise floor (linkcli.noise) of the
linkage's size (positions), its size per rad (Jacobian), its size times the largest speed
(velocity) or speed^2 + acceleration (acceleration). Ties (two equal extremes or margins)
go to the first row, and between singularities to the left chain, the right chain, then P.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.columns import TRANSMISSION_BAND
from linkcli.mechanisms.columns import angle_out as _ang
from linkcli.mechanisms.columns import turn_out as _dang
from linkcli.mechanisms.five_bar import kinematics as kin
from linkcli.mechanisms.five_bar.track import Track, listed, size
from linkcli.mechanisms.four_bar import kinematics as four
from linkcli.noise import first_max, first_min, snap, snap_series
from linkcli.textnum import num

SINGULARITIES = ("I left", "I right", "II distal in line")  # margin order: the tie rule


def branch_name(track: Track | None, fb) -> str:
    """The branch reported: the track's (a path's first row decides it), else the given one."""
    if track is None:
        return fb.branch or "left"
    return "left" if track.side > 0 else "right"


def linkage_section(fb, track: Track | None, u) -> dict:
    scale = size(fb)
    return {"mechanism": "five-bar", "ground": fb.ground, "input": fb.input, "input2": fb.input2,
            "coupler": fb.coupler, "coupler2": fb.coupler2, "branch": branch_name(track, fb),
            "ground_pivot": [snap(float(v), scale) for v in fb.ground_pivot],
            "ground_angle": _ang(u, fb.ground_angle)}


def class_section(fb, track: Track | None) -> dict:
    """Ting's five-bar class, and per phase the class of the four-bar left (four-bar names:
    input = the driven crank, coupler = its distal link, output = the held chain's distal
    link, ground = from the driven crank's pivot to the held elbow)."""
    out = kin.grashof(fb.lengths)
    phases = []
    for bar in (track.phases if track is not None else []):
        if bar is None:
            continue
        ph = bar.phase
        phases.append({"rows": [ph.first, ph.last], "locked": ph.locked, "ground": bar.d,
                       "branch": bar.branch, **four.grashof(bar.a, bar.b, bar.c, bar.d)})
    out["phases"] = phases
    return out


def margins(track: Track):
    """(mu_P, mu_A, mu_B, margin (3, M), nearest (M,)): the transmission angles, each one's
    distance from its singular values 0 and pi, and the index of the nearest (SINGULARITIES
    order, ties to the first)."""
    mu_p, mu_a, mu_b = track.pose.transmissions()
    margin = np.stack([np.minimum(m, np.pi - m) for m in (mu_a, mu_b, mu_p)])
    return mu_p, mu_a, mu_b, margin, first_min(margin.T)


def singularity_names(track: Track, mu_a, mu_b, nearest) -> list[str]:
    """Per row the nearest singularity by name: "I left stretched|folded", "I right ...",
    "II distal in line"."""
    names = []
    for k, i in enumerate(np.asarray(nearest).tolist()):
        if i == 2:
            names.append(SINGULARITIES[2])
        else:
            mu = (mu_a, mu_b)[i][k]
            names.append(f"{SINGULARITIES[i]} {'stretched' if mu > math.pi / 2 else 'folded'}")
    return names


def _extremes(values, ok):
    """(min, row, max, row) over the rows where ok, ties to the first row."""
    lo = np.where(ok, values, np.inf)
    hi = np.where(ok, values, -np.inf)
    i, j = int(first_min(lo)), int(first_max(hi))
    return float(lo[i]), i, float(hi[j]), j


def transmission_section(track: Track, u, notes: list) -> dict:
    """Over the rows: mu at P (min, max and their rows), at each elbow, the worst condition
    number and its row, the nearest singularity (its name, its margin as an angle, the row);
    per phase the extremes of its four-bar's transmission angle over the driven input's span
    (closed form, four_bar.kinematics.transmission_extremes: exact, not only at the rows)."""
    ok = track.valid
    mu_p, mu_a, mu_b, margin, nearest = margins(track)
    mn, i, mx, j = _extremes(mu_p, ok)
    out = {"min": _dang(u, mn), "max": _dang(u, mx), "row_at_min": i, "row_at_max": j}
    for name, mu in (("left_elbow", mu_a), ("right_elbow", mu_b)):
        lo, _, hi, _ = _extremes(mu, ok)
        out[f"{name}_min"], out[f"{name}_max"] = _dang(u, lo), _dang(u, hi)
    kappa = kin.condition(track.pose)
    _, _, worst, k = _extremes(kappa, ok)
    out["condition_max"] = worst
    out["row_at_condition_max"] = k
    least = margin[nearest, np.arange(track.rows)]
    _, r, _, _ = _extremes(least, ok)
    names = singularity_names(track, mu_a, mu_b, nearest)
    out["nearest_singularity"] = names[r]
    out["singularity_margin"] = _dang(u, least[r])
    out["row_at_singularity"] = r
    if track.phases:
        out["phases"] = [_phase_transmission(bar, u) for bar in track.phases if bar is not None]
    band = TRANSMISSION_BAND
    if math.degrees(mn) < band[0] * (1 - 1e-9) or math.degrees(mx) > band[1] * (1 + 1e-9):
        notes.append(f"transmission angle at P leaves the recommended {band[0]:g}..{band[1]:g} deg band "
                     f"({num(math.degrees(mn))}..{num(math.degrees(mx))} deg over the rows)")
    _mode_notes(track, notes)
    return out


def _phase_transmission(bar, u) -> dict:
    ph = bar.phase
    phi = np.unwrap(bar.phi)
    lo, hi = float(phi.min()), float(phi.max())
    if hi - lo >= four.TWO_PI:
        lo, hi = 0.0, four.TWO_PI
    mn, at_mn, mx, at_mx = four.transmission_extremes(bar.a, bar.b, bar.c, bar.d, lo, hi)
    return {"rows": [ph.first, ph.last], "locked": ph.locked, "min": _dang(u, mn), "max": _dang(u, mx),
            f"{ph.driven}_at_min": _ang(u, at_mn + bar.beta), f"{ph.driven}_at_max": _ang(u, at_mx + bar.beta)}


def _mode_notes(track: Track, notes: list) -> None:
    """A note where a chain's working mode changes between two rows (it passed stretched or
    folded: a type I singularity, which driven cranks pass, P momentarily losing a direction)."""
    m1, m2 = track.pose.modes()
    for name, m in (("left", m1), ("right", m2)):
        both = track.valid[:-1] & track.valid[1:]
        change = np.flatnonzero(both & (m[:-1] * m[1:] < 0)) + 1
        if change.size:
            notes.append(f"the {name} chain passes stretched or folded (type I singularity) before "
                         f"{listed(change)}: its working mode changes there")


def motion_section(track: Track, u) -> dict:
    """rows; the drives' ranges and P's over the rows reached; the task echoed as a problem
    file writes it (inputs as reached, input_speeds, input_accelerations, phases)."""
    fb, ok = track.fb, track.valid
    p = track.pose
    out: dict = {"rows": track.rows}
    if ok.any():
        for key, phi in (("input_range", p.phi1), ("input2_range", p.phi2)):
            unwrapped = np.unwrap(phi[ok])
            out[key] = [_ang(u, float(unwrapped.min())), _ang(u, float(unwrapped.max()))]
        x, y = track.to_global(p.px[ok], p.py[ok])
        scale = size(fb) + math.hypot(*fb.ground_pivot)
        out["x_range"] = [snap(float(x.min()), scale), snap(float(x.max()), scale)]
        out["y_range"] = [snap(float(y.min()), scale), snap(float(y.max()), scale)]
    out.update(motion_echo(track, u))
    return out


def motion_echo(track: Track, u) -> dict:
    """The task as a problem file writes it (so that `analyze` of a result reproduces it):
    inputs (the drive angles of every row, when all are reached), input_speeds,
    input_accelerations, phases."""
    mo, p = track.fb.motion, track.pose
    out: dict = {}
    if track.valid.all():
        out["inputs"] = [[_ang(u, a), _ang(u, b)] for a, b in zip(p.phi1.tolist(), p.phi2.tolist())]
    out["input_speeds"] = [_dang(u, w) for w in mo.speeds]
    out["input_accelerations"] = [_dang(u, a) for a in mo.accelerations]
    if mo.phases:
        out["phases"] = [{"rows": [ph.first, ph.last], "locked": ph.locked} for ph in mo.phases]
    return out


def kinematics_rows(track: Track, u) -> list[dict]:
    """One row per row of [motion] (the module docstring's conventions): row, input, input2,
    point, dpoint_dinput, dpoint_dinput2, velocity, acceleration, condition, transmission (at
    P), transmission_left, transmission_right (at the elbows A, B), modes (each chain's
    working mode, "+" or "-", "0" on its singularity), singularity (the nearest), margin (its
    distance as an angle), and phase (the held drive) when [motion] has phases. A row that
    is not reached holds only its row number (and its inputs when they were given)."""
    fb, p, ok = track.fb, track.pose, track.valid
    scale = size(fb)
    per_unit = u.to_rad(1.0)
    x, y = track.to_global(p.px, p.py)
    (j11, j21), (j12, j22) = kin.jacobian(p)
    j = [track.turned(j11, j21), track.turned(j12, j22)]
    v = track.turned(*kin.velocity(p, track.w1, track.w2))
    a = track.turned(*kin.acceleration(p, track.w1, track.w2, track.al1, track.al2))
    rate = float(max(np.max(np.abs(track.w1)), np.max(np.abs(track.w2))))
    rate2 = rate * rate + float(max(np.max(np.abs(track.al1)), np.max(np.abs(track.al2))))
    where = scale + math.hypot(*fb.ground_pivot)
    cols = {"point": (snap_series(x, where), snap_series(y, where)),
            "dpoint_dinput": tuple(snap_series(c * per_unit, scale * per_unit) for c in j[0]),
            "dpoint_dinput2": tuple(snap_series(c * per_unit, scale * per_unit) for c in j[1]),
            "velocity": tuple(snap_series(c, scale * rate) for c in v),
            "acceleration": tuple(snap_series(c, scale * rate2) for c in a)}
    kappa = kin.condition(p)
    mu_p, mu_a, mu_b, margin, nearest = margins(track)
    names = singularity_names(track, mu_a, mu_b, nearest)
    least = margin[nearest, np.arange(track.rows)]
    m1, m2 = p.modes()
    held = {}
    for ph in fb.motion.phases:
        held.update({k: f"{ph.locked} held" for k in range(ph.first, ph.last + 1)})
    given = fb.motion.inputs is not None
    rows = []
    for k in range(track.rows):
        row: dict = {"row": k}
        if ok[k] or given:
            row["input"], row["input2"] = _ang(u, p.phi1[k]), _ang(u, p.phi2[k])
        if ok[k]:
            for name, (cx, cy) in cols.items():
                row[name] = [_finite(cx[k]), _finite(cy[k])]
            row["condition"] = _finite(kappa[k])
            row["transmission"] = _dang(u, mu_p[k])
            row["transmission_left"] = _dang(u, mu_a[k])
            row["transmission_right"] = _dang(u, mu_b[k])
            row["modes"] = _mode(m1[k]) + _mode(m2[k])
            row["singularity"] = names[k]
            row["margin"] = _dang(u, least[k])
        if held:
            row["phase"] = held.get(k)
        rows.append(row)
    return rows


def _finite(x) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def _mode(sign) -> str:
    return "+" if sign > 0 else ("-" if sign < 0 else "0")
