"""Strength (issue 32): pins, links and fatigue over the load cycle, checked against references
written here: a textbook worked example (Shigley's fluctuating-load example), the textbook
formulas of direct shear, bearing, beams, columns and the fatigue criteria, and pin forces from
closed-form statics (a massless four-bar under an output torque: the coupler is a two-force
member, |F| = |T| / (c sin mu), mu the transmission angle) -- never the code's own output.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import run_cli

from linkcli.analysis.beam import internal_forces
from linkcli.analysis.fatigue import column_load, fatigue_factor
from linkcli.mechanisms.newton_euler import link_load

SQRT3 = math.sqrt(3.0)

FIRE_DOOR = """type = "linkage"
[units]
length = "{unit}"
[linkage]
ground = {d}
input = {a}
coupler = {b}
output = {c}
branch = "open"
[motion]
input_speed = 20
steps = {steps}
[loads]
output_torque = {torque}
[joints]
A0 = {{ diameter = {d0}, width = {w0}, shear = "double" }}
A = {{ diameter = {d1}, width = {w1} }}
B = {{ diameter = {d1}, width = {w1}, shear = "single" }}
B0 = {{ diameter = {d0}, width = {w0}, shear = "double" }}
[sections]
input = {{ width = {sw}, thickness = {st} }}
coupler = {{ diameter = {cd} }}
output = {{ diameter = {od}, wall = {ow} }}
[material]
ultimate = 630
yield = 530
endurance = 257
modulus = 207000
[strength]
required = {required}
criterion = "{criterion}"
"""
MM = dict(unit="mm", d=50, a=27.6293, b=57.2363, c=41.1104, steps=36, torque=-20, d0=10, w0=12,
          d1=5, w1=6, sw=20, st=6, cd=8, od=14, ow=2, required=1.5, criterion="goodman")
MATERIAL = dict(ultimate=630.0, yield_=530.0, endurance=257.0, modulus=207000.0)


def report(tmp_path, text: str, name: str = "strength.toml", code: int = 0) -> dict:
    path = tmp_path / name
    path.write_text(text)
    got, out, err = run_cli("analyze", str(path), "--format", "json", "--precision", "17")
    assert got == code, err
    return json.loads(out)


def by_name(rows: list[dict], key: str) -> dict:
    return {row[key]: row for row in rows}


# ---------------------------------------------------------------- textbook references
def goodman(a, m, se, sut):
    return 1.0 / (a / se + m / sut)


def test_fatigue_criteria_reproduce_shigleys_worked_example():
    """Shigley's Mechanical Engineering Design (Budynas & Nisbett, 9th ed.), Example 6-12: a
    1.5 in AISI 1050 CD bar, load 0..16 kip, Kf = 1.85: Sut = 100, Sy = 84, Se = 33.9 kpsi,
    sigma_a = sigma_m = 8.38 kpsi; published nf = 3.66 (Gerber), 3.75 (ASME-elliptic)."""
    sa = sm = 8.38
    assert fatigue_factor(sa, sm, 33.9, 100.0, 84.0, "gerber") == pytest.approx(3.66, abs=0.006)
    assert fatigue_factor(sa, sm, 33.9, 100.0, 84.0, "asme-elliptic") == pytest.approx(3.75, abs=0.006)
    # the same stresses on the modified Goodman and Soderberg lines, by their textbook formulas
    assert fatigue_factor(sa, sm, 33.9, 100.0, 84.0) == pytest.approx(goodman(sa, sm, 33.9, 100.0), rel=1e-14)
    assert fatigue_factor(sa, sm, 33.9, 100.0, 84.0, "soderberg") == pytest.approx(
        1.0 / (sa / 33.9 + sm / 84.0), rel=1e-14)


@pytest.mark.parametrize("a, m", [(10.0, 30.0), (1e-8, 50.0), (40.0, 0.1), (25.0, 0.0)])
def test_gerber_factor_is_the_textbook_root(a, m):
    """Shigley Eq. 6-47: n = 1/2 (Sut/m)^2 (a/Se) [-1 + sqrt(1 + (2 m Se / (Sut a))^2)]; n = Se/a
    without a mean stress. (The textbook form cancels for a mean far below the alternating
    stress, so the cases keep 2 m Se / (Sut a) above 1e-3.)"""
    se, sut = 200.0, 600.0
    want = se / a if m == 0 else 0.5 * (sut / m) ** 2 * (a / se) * (
        -1.0 + math.sqrt(1.0 + (2.0 * m * se / (sut * a)) ** 2))
    assert fatigue_factor(a, m, se, sut, 500.0, "gerber") == pytest.approx(want, rel=1e-6)


def test_compressive_mean_leaves_the_endurance_line_and_unloaded_is_infinite():
    for criterion in ("goodman", "gerber", "soderberg", "asme-elliptic"):
        assert fatigue_factor(50.0, -80.0, 200.0, 600.0, 500.0, criterion) == pytest.approx(4.0)
        assert fatigue_factor(0.0, 0.0, 200.0, 600.0, 500.0, criterion) == math.inf


def test_column_euler_and_johnson_formulas():
    """Shigley Eqs. 4-43, 4-46 (C = 1): Euler beyond (l/k)_1 = sqrt(2 pi^2 E / Sy), the
    Johnson parabola below; both give P/A = Sy / 2 at the transition."""
    e, sy, area, inertia = 207e9, 530e6, 1e-4, 1e-9  # k = sqrt(I/A) = 3.16 mm
    k = math.sqrt(inertia / area)
    transition = math.sqrt(2 * math.pi ** 2 * e / sy)
    long_column = 2.0 * transition * k
    load, mode = column_load(long_column, area, inertia, e, sy)
    assert mode == "euler" and load == pytest.approx(math.pi ** 2 * e * inertia / long_column ** 2)
    short = 0.5 * transition * k
    load, mode = column_load(short, area, inertia, e, sy)
    assert mode == "johnson"
    assert load == pytest.approx(area * (sy - (sy * short / k / (2 * math.pi)) ** 2 / e))
    assert column_load(transition * k, area, inertia, e, sy)[0] == pytest.approx(area * sy / 2)


# ---------------------------------------------------------------- the beam of a link
def test_beam_simply_supported_central_load_and_offset_force():
    """A bar from (0,0) to (L,0) on two pins, a transverse load W at mid-span: M max = W L / 4,
    no axial force; an axial load H at a lever y above the axis adds the couple -H y there
    and the axial force H on the part beyond it."""
    n, length, w, h, lever = 3, 2.0, 100.0, 40.0, 0.25
    pts = lambda x, y=0.0: np.tile([x, y], (n, 1))  # noqa: E731
    loads = (link_load("J1", pts(0.0), [h, w / 2 + h * lever / length]),   # in equilibrium
             link_load("J2", pts(length), [0.0, w / 2 - h * lever / length]),
             link_load("load", pts(length / 2, lever), [-h, -w]))
    beam = internal_forces(loads, np.ones(n, dtype=bool))
    # segments: J1 -> load, load -> J2; N = -(sum of axial loads to the left)
    assert beam.axial[0] == pytest.approx([-h, 0.0])
    left_of_load = -(w / 2 + h * lever / length) * length / 2   # moment of J1's force about mid-span
    assert beam.moment[0, 0] == pytest.approx([0.0, left_of_load])
    assert beam.moment[0, 1] == pytest.approx([left_of_load + h * lever, 0.0], abs=1e-12)
    assert beam.length == pytest.approx(length)
    # W L / 4 when the load is on the axis
    loads = (link_load("J1", pts(0.0), [0.0, w / 2]), link_load("J2", pts(length), [0.0, w / 2]),
             link_load("load", pts(length / 2), [0.0, -w]))
    beam = internal_forces(loads, np.ones(n, dtype=bool))
    assert np.max(np.abs(beam.moment)) == pytest.approx(w * length / 4)


# ---------------------------------------------------------------- the fire door, closed form
def fire_door_forces(p: dict):
    """Per row (phi = k 360/steps): the coupler's tension t (N, from the output's moment
    balance, massless), the transmission angle and the points (m), by the law of cosines."""
    scale = {"mm": 1e-3, "cm": 1e-2, "m": 1.0, "in": 0.0254}[p["unit"]]
    a, b, c, d = (p[k] * scale for k in ("a", "b", "c", "d"))
    phi = np.arange(p["steps"]) * 2 * math.pi / p["steps"]
    pa = np.stack([a * np.cos(phi), a * np.sin(phi)], axis=1)
    b0 = np.array([d, 0.0])
    rho = np.linalg.norm(pa - b0, axis=1)
    mu = np.arccos((b * b + c * c - rho ** 2) / (2 * b * c))  # transmission angle
    theta_rho = np.arctan2(pa[:, 1], pa[:, 0] - d)
    psi = theta_rho - np.arccos((rho ** 2 + c * c - b * b) / (2 * rho * c))  # open branch
    pb = b0 + c * np.stack([np.cos(psi), np.sin(psi)], axis=1)
    cross = lambda u, v: u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]  # noqa: E731
    t = -p["torque"] * b / cross(pb - b0, pa - pb)  # (B - B0) x t (A - B)/b + T = 0
    return t, mu, pa, pb, b0, a, c, scale


def test_fire_door_pin_force_is_torque_over_c_sin_mu(tmp_path):
    rep = report(tmp_path, FIRE_DOOR.format(**MM))
    t, mu, *_ , c, _ = fire_door_forces(MM)
    force = np.abs(MM["torque"]) / (c * np.sin(mu))
    assert np.abs(t) == pytest.approx(force, rel=1e-9)
    pins = by_name(rep["strength"]["pins"], "pin")
    for name in ("A0", "A", "B", "B0"):
        assert pins[name]["force_max"] == pytest.approx(force.max(), rel=1e-9)
        assert pins[name]["force_min"] == pytest.approx(force.min(), rel=1e-9)
        assert pins[name]["at_input"] == 10 * int(np.argmax(force))


@pytest.mark.parametrize("criterion", ["goodman", "gerber", "soderberg", "asme-elliptic"])
def test_fire_door_pins_direct_shear_bearing_and_fatigue(tmp_path, criterion):
    """tau = F / (planes pi d^2/4), sigma_b = F/(d w); tau_a, tau_m = (max -+ min)/2 of the
    cycle; static 0.577 Sy / tau_max, bearing Sy / sigma_b, fatigue on sqrt(3) tau_a, sqrt(3)
    tau_m (von Mises)."""
    p = dict(MM, criterion=criterion)
    rep = report(tmp_path, FIRE_DOOR.format(**p))
    t, *_ , scale = fire_door_forces(p)
    force = np.abs(t)
    pins = by_name(rep["strength"]["pins"], "pin")
    for name, d, w, planes in (("A0", 10, 12, 2), ("A", 5, 6, 1), ("B", 5, 6, 1), ("B0", 10, 12, 2)):
        area_mm2 = planes * math.pi * d * d / 4
        tau = force / area_mm2            # N/mm^2 = MPa
        ta, tm = (tau.max() - tau.min()) / 2, (tau.max() + tau.min()) / 2
        pin = pins[name]
        assert pin["shear"] == ("double" if planes == 2 else "single")
        assert pin["shear_max"] == pytest.approx(tau.max(), rel=1e-9)
        assert pin["bearing_max"] == pytest.approx(force.max() / (d * w), rel=1e-9)
        assert pin["shear_alternating"] == pytest.approx(ta, rel=1e-9)
        assert pin["shear_mean"] == pytest.approx(tm, rel=1e-9)
        assert pin["static_factor"] == pytest.approx(530 / SQRT3 / tau.max(), rel=1e-9)
        assert pin["bearing_factor"] == pytest.approx(530 / (force.max() / (d * w)), rel=1e-9)
        a, m = SQRT3 * ta, SQRT3 * tm
        want = {"goodman": 1 / (a / 257 + m / 630), "soderberg": 1 / (a / 257 + m / 530),
                "asme-elliptic": 1 / math.sqrt((a / 257) ** 2 + (m / 530) ** 2),
                "gerber": 0.5 * (630 / m) ** 2 * (a / 257) * (-1 + math.sqrt(1 + (2 * m * 257 / (630 * a)) ** 2))
                }[criterion]
        assert pin["fatigue_factor"] == pytest.approx(want, rel=1e-9)
        assert pin["factor"] == pytest.approx(min(want, pin["static_factor"], pin["bearing_factor"]))


def end_couple_link(force_at_far_end, e, couple, area, modulus):
    """Fibre stresses (MPa) of a bar loaded at its far end by a force and at its near end by
    a couple (the crank under the drive's torque, the output under the closer's): N = F . e
    over the bar, M = couple at the near end and 0 at the far end, sigma = N/A +- M/Z."""
    axial = np.einsum("nj,nj->n", force_at_far_end, e)
    near = [axial / area + couple / modulus, axial / area - couple / modulus]
    far = [axial / area, axial / area]
    return axial, np.stack(near + far, axis=1) / 1e6


def test_fire_door_links_axial_bending_fatigue_and_buckling(tmp_path):
    """Coupler (round 8): a two-force member in tension t, sigma = t/A. Output (tube 14 x 2):
    the coupler's pull at B, the closer's torque T at B0 (M = T there). Input (rectangle 20 x
    6, width in the plane): the coupler's pull at A, the drive's torque T_in = -(A - A0) x F_A
    at A0. Columns pinned-pinned, Euler or Johnson by slenderness."""
    rep = report(tmp_path, FIRE_DOOR.format(**MM))
    t, mu, pa, pb, b0, a, c, scale = fire_door_forces(MM)
    links = by_name(rep["strength"]["links"], "link")
    e_cd = 8e-3
    coupler_area = math.pi * e_cd ** 2 / 4
    coupler = links["coupler"]
    sigma = t / coupler_area / 1e6
    assert coupler["section"] == "round 8"
    assert coupler["tension"] == pytest.approx(max(t.max(), 0), rel=1e-9)
    assert coupler["compression"] == pytest.approx(max(-t.min(), 0), abs=1e-9)
    assert coupler["stress_max"] == pytest.approx(np.abs(sigma).max(), rel=1e-9)
    assert coupler["bending"] == pytest.approx(0, abs=1e-9)
    sa, sm = (sigma.max() - sigma.min()) / 2, (sigma.max() + sigma.min()) / 2
    assert coupler["fatigue_factor"] == pytest.approx(goodman(sa, sm, 257, 630), rel=1e-9)
    assert coupler["static_factor"] == pytest.approx(530 / np.abs(sigma).max(), rel=1e-9)
    # the output: a tube 14 x 2
    outer, inner = 14e-3, 10e-3
    area = math.pi * (outer ** 2 - inner ** 2) / 4
    inertia = math.pi * (outer ** 4 - inner ** 4) / 64
    unit_ab = (pa - pb) / np.linalg.norm(pa - pb, axis=1)[:, None]
    e_out = (pb - b0) / c
    axial, fibres = end_couple_link(t[:, None] * unit_ab, e_out, MM["torque"], area, inertia / (outer / 2))
    out = links["output"]
    assert out["bending"] == pytest.approx(abs(MM["torque"]), rel=1e-9)
    assert out["stress_max"] == pytest.approx(np.abs(fibres).max(), rel=1e-9)
    assert out["tension"] == pytest.approx(max(axial.max(), 0), rel=1e-9, abs=1e-9)
    assert out["compression"] == pytest.approx(max(-axial.min(), 0), rel=1e-9)
    sa, sm = (fibres.max(0) - fibres.min(0)) / 2, (fibres.max(0) + fibres.min(0)) / 2
    worst = min(goodman(x, y, 257, 630) if y > 0 else 257 / x for x, y in zip(sa, sm))
    assert out["fatigue_factor"] == pytest.approx(worst, rel=1e-9)
    k = math.sqrt(inertia / area)
    pcr = (math.pi ** 2 * 207e9 * inertia / c ** 2 if c / k >= math.sqrt(2 * math.pi ** 2 * 207e9 / 530e6)
           else area * (530e6 - (530e6 * c / k / (2 * math.pi)) ** 2 / 207e9))
    assert out["buckling_load"] == pytest.approx(pcr, rel=1e-9)
    assert out["buckling_factor"] == pytest.approx(pcr / max(-axial.min(), 0), rel=1e-9)
    # the input: rectangle 20 x 6, bending in the plane (Z = t w^2 / 6)
    force_a = -t[:, None] * unit_ab               # the coupler's pull on the crank at A
    torque_in = -(pa[:, 0] * force_a[:, 1] - pa[:, 1] * force_a[:, 0])
    axial, fibres = end_couple_link(force_a, pa / a, torque_in, 20e-3 * 6e-3, 6e-3 * 20e-3 ** 2 / 6)
    crank = links["input"]
    assert crank["bending"] == pytest.approx(np.abs(torque_in).max(), rel=1e-9)
    assert crank["stress_max"] == pytest.approx(np.abs(fibres).max(), rel=1e-9)
    assert crank["at_input"] == 10 * int(np.argmax(np.abs(fibres).max(axis=1)))
    least = 20e-3 * 6e-3 ** 3 / 12               # it buckles out of the plane
    k = math.sqrt(least / 120e-6)
    assert crank["buckling"] == ("euler" if a / k >= math.sqrt(2 * math.pi ** 2 * 207e9 / 530e6) else "johnson")


def test_weakest_part_and_exit_code_follow_the_required_factor(tmp_path):
    rep = report(tmp_path, FIRE_DOOR.format(**MM))
    parts = rep["strength"]["pins"] + rep["strength"]["links"]
    weakest = min(parts, key=lambda r: r["factor"])
    critical = rep["strength"]["critical"]
    assert critical["factor"] == weakest["factor"] and critical["mode"] == weakest["governs"]
    assert rep["status"] == "ok" and critical["factor"] > 1.5
    # the same linkage asked for more than its weakest part gives: infeasible, exit 1, named
    required = math.ceil(critical["factor"] * 10) / 10
    rep = report(tmp_path, FIRE_DOOR.format(**dict(MM, required=required)), code=1)
    assert rep["status"] == "infeasible"
    assert rep["message"].startswith(f"{critical['part']}: {critical['mode']} safety factor")
    assert f"below the required {required:g}" in rep["message"]


@pytest.mark.parametrize("unit, scale", [("cm", 0.1), ("in", 1 / 25.4), ("m", 1e-3)])
def test_sizes_in_any_length_unit_give_the_same_stresses(tmp_path, unit, scale):
    """The same fire door written in cm, in or m (lengths and sizes converted) gives the
    same forces, stresses and factors; sizes are echoed in the file's unit."""
    mm = report(tmp_path, FIRE_DOOR.format(**MM), "mm.toml")["strength"]
    sizes = ("d", "a", "b", "c", "d0", "w0", "d1", "w1", "sw", "st", "cd", "od", "ow")
    other = report(tmp_path, FIRE_DOOR.format(**dict(MM, unit=unit, **{k: MM[k] * scale for k in sizes})),
                   f"{unit}.toml")["strength"]
    for kind, key in (("pins", "pin"), ("links", "link")):
        for a, b in zip(mm[kind], other[kind]):
            for field in ("shear_max", "bearing_max", "stress_max", "bending", "tension", "compression",
                          "static_factor", "fatigue_factor", "buckling_factor", "factor"):
                if field in a and a[field] is not None:
                    assert b[field] == pytest.approx(a[field], rel=1e-9), (a[key], field)
            for field in ("diameter", "width", "length"):
                if field in a:
                    assert b[field] == pytest.approx(a[field] * scale, rel=1e-12)


# ---------------------------------------------------------------- loads between the pins
COUPLER_LOAD = """type = "linkage"
[linkage]
ground = 4
input = 1
coupler = 3.5
output = 3
coupler_point = [1.5, 1.0]
[units]
length = "m"
[motion]
input_speed = {speed}
steps = 24
[loads]
coupler_force = [0, -100]
gravity = [0, -9.81]
[masses]
coupler = {{ mass = 2.0, center = [1.75, 0.2], inertia = 0.5 }}
[sections]
coupler = {{ width = 0.04, thickness = 0.01 }}
[material]
name = "aisi-1020-hr"
"""


def test_coupler_bending_from_a_force_off_the_line_and_its_mass(tmp_path):
    """The seed's loads case (force (0, -100) N at P = (1.5, 1.0) in the coupler frame) with a
    massive coupler (centre G = (1.75, 0.2)): along the axis A (x = 0), P (1.5), G (1.75), B
    (3.5). By the statics of the part left of a cut (A's force and P's, carried to the axis
    with its couple -y F.e) and of the part right of it (B's force), the bending moment and
    axial force on either side of P and G need no inertia term; the fibre stresses N/A +- M/Z
    there are the extremes. Pin forces from the forces section (checked against Newton-Euler
    in test_loads.py)."""
    rep = report(tmp_path, COUPLER_LOAD.format(speed=90))
    rows, strength = rep["forces"]["rows"], rep["strength"]
    coupler = by_name(strength["links"], "link")["coupler"]
    assert strength["material"]["name"] == "AISI 1020 HR" and strength["material"]["yield_strength"] == 210
    a_len, b_len, c_len, d_len = 1.0, 3.5, 3.0, 4.0
    area, z = 0.04 * 0.01, 0.01 * 0.04 ** 2 / 6
    moments, fibres = [], []
    for row in rows:
        phi = math.radians(row["input"])
        pa = np.array([a_len * math.cos(phi), a_len * math.sin(phi)])
        rho = np.linalg.norm(pa - [d_len, 0])
        psi = math.atan2(pa[1], pa[0] - d_len) - math.acos((rho ** 2 + c_len ** 2 - b_len ** 2) / (2 * rho * c_len))
        pb = np.array([d_len, 0]) + c_len * np.array([math.cos(psi), math.sin(psi)])
        e = (pb - pa) / b_len
        n = np.array([-e[1], e[0]])
        f_a = np.array([row["pins"]["A"]["x"], row["pins"]["A"]["y"]])      # input on coupler at A
        f_b = -np.array([row["pins"]["B"]["x"], row["pins"]["B"]["y"]])     # output on coupler at B
        f_p = np.array([0.0, -100.0])
        m_p_left = -1.5 * (f_a @ n)                       # A's force about the cut at x = 1.5
        m_p_right = m_p_left - 1.0 * (f_p @ e)            # P's couple carried to the axis
        m_g_left = m_p_right - 0.25 * (f_a @ n + f_p @ n)
        m_g_right = -(3.5 - 1.75) * (f_b @ n)             # minus B's force about the cut at x = 1.75
        axial = [-(f_a @ e), -(f_a @ e), -(f_a @ e + f_p @ e), f_b @ e]
        ends = [m_p_left, m_p_right, m_g_left, m_g_right]
        moments.append(ends)
        fibres.append([s * m / z + f / area for m, f in zip(ends, axial) for s in (1, -1)])
    moments, fibres = np.abs(np.array(moments)), np.abs(np.array(fibres)) / 1e6
    assert coupler["bending"] == pytest.approx(moments.max(), rel=1e-9)
    assert coupler["stress_max"] == pytest.approx(fibres.max(), rel=1e-9)
    assert coupler["at_input"] == pytest.approx(15 * int(np.argmax(fibres.max(axis=1))))


# ---------------------------------------------------------------- the slider-crank
SLIDER = """type = "linkage"
[linkage]
mechanism = "slider-crank"
input = 40
coupler = 120
offset = 10
[motion]
input_speed = 1
steps = 36
[loads]
output_force = -500
[joints]
A0 = {{ diameter = 8, width = 10, shear = "double" }}
A = {{ diameter = 6, width = 8 }}
B = {{ diameter = 6, width = 8 }}
{guide}
[sections]
coupler = {{ width = 10, thickness = 5 }}
[material]
name = "6061-T6"
"""


def test_slider_crank_rod_is_a_two_force_member(tmp_path):
    """Massless, quasi-static, a force F along the guide on the slider: the rod carries
    F / cos(theta3) along itself (theta3 from a sin(phi) + b sin(theta3) = e), every pin that
    force; the guide is no pin (its sizes get a note); the crank is not sized (a note)."""
    rep = report(tmp_path, SLIDER.format(guide='guide = { diameter = 6, width = 8 }'))
    strength = rep["strength"]
    phi = np.radians(np.arange(36) * 10.0)
    theta = np.arcsin((10 - 40 * np.sin(phi)) / 120)
    rod = -500 / np.cos(theta)          # tension positive: the load pulls the slider to -x
    pins = by_name(strength["pins"], "pin")
    assert set(pins) == {"A0", "A", "B"}
    assert pins["B"]["force_max"] == pytest.approx(np.abs(rod).max(), rel=1e-9)
    assert pins["A"]["shear_max"] == pytest.approx(np.abs(rod).max() / (math.pi * 9), rel=1e-9)
    coupler = by_name(strength["links"], "link")["coupler"]
    assert coupler["tension"] == pytest.approx(max(rod.max(), 0), rel=1e-9)
    assert coupler["stress_max"] == pytest.approx(np.abs(rod).max() / 50, rel=1e-9)
    assert strength["unchecked"] == ["link input"]
    assert any("guide: not a revolute pin" in n for n in rep["notes"])
    assert any("endurance 95 MPa is the listed specimen value of 6061-T6" in n for n in rep["notes"])


# ---------------------------------------------------------------- the protocol
@pytest.mark.parametrize("name", ["four-bar", "slider-crank"])
def test_member_forces_keep_every_link_in_equilibrium(name):
    """Each link's loads (pins, drive, coupler force, weight and inertia) sum to zero force
    and zero moment at every row: the d'Alembert form of the homes' Newton-Euler equations."""
    from linkcli import mechanisms
    from linkcli.mechanisms.four_bar.model import FourBar
    from linkcli.mechanisms.slider_crank.model import SliderCrank
    from linkcli.model import LinkMass, LoadCase, Loads, Masses
    linkage = (FourBar(ground=0.4, input=0.1, coupler=0.35, output=0.3, coupler_point=(0.15, 0.1),
                       ground_pivot=(0.05, -0.02), ground_angle=0.3)
               if name == "four-bar" else SliderCrank(input=0.1, coupler=0.3, offset=0.02, coupler_point=(0.1, 0.05)))
    masses = Masses(input=LinkMass(1.0, (0.05, 0.01), 0.002), coupler=LinkMass(2.0, (0.12, -0.03), 0.01),
                    output=LinkMass(1.5, (0.1, 0.02), 0.008) if name == "four-bar" else LinkMass(0.7))
    extra = {"output_torque": -3.0} if name == "four-bar" else {"output_force": 40.0}
    case = LoadCase(Loads(coupler_force=(10.0, -30.0), gravity=(0.5, -9.81), **extra), masses)
    mech = mechanisms.of(linkage)
    phi = np.linspace(0.0, 2 * math.pi, 50, endpoint=False)
    rows = mech.load_rows(phi, 25.0, case, 1.0)
    members = mech.member_forces(phi, 25.0, case, 1.0, rows)
    ok = ~rows.singular
    for link, loads in members.loads.items():
        assert [load.name for load in loads[:2]] == list(members.links[link])
        force = sum(load.force for load in loads)[ok]
        moment = sum(load.couple + load.at[:, 0] * load.force[:, 1] - load.at[:, 1] * load.force[:, 0]
                     for load in loads)[ok]
        scale = max(np.abs(load.force[ok]).max() for load in loads)
        assert np.abs(force).max() < 1e-10 * scale, link
        assert np.abs(moment).max() < 1e-10 * scale, link


def test_a_home_without_member_forces_is_told_so(tmp_path, monkeypatch):
    from linkcli.mechanisms.four_bar.home import FourBarMechanism
    from linkcli.mechanisms.protocol import Mechanism
    monkeypatch.setattr(FourBarMechanism, "member_forces", Mechanism.member_forces)
    path = tmp_path / "door.toml"
    path.write_text(FIRE_DOOR.format(**MM))
    code, out, err = run_cli("analyze", str(path))
    assert code == 2 and out == ""
    assert err.strip().endswith("material: expected a mechanism whose loads on each link are known for "
                                "[material] (the strength section), found the four-bar, which does "
                                "not give them yet")


# ---------------------------------------------------------------- sections, formats, input
def test_strength_is_computed_only_with_material(tmp_path, monkeypatch):
    from linkcli.analysis import strength
    calls = []
    monkeypatch.setattr(strength, "section", lambda *a, **k: calls.append(1) or {})
    text = FIRE_DOOR.format(**MM)
    no_material = text[:text.index("[material]")]
    rep = report(tmp_path, no_material)
    assert "strength" not in rep and not calls and "forces" in rep


def test_every_format_has_the_tables(tmp_path):
    path = tmp_path / "door.toml"
    path.write_text(FIRE_DOOR.format(**MM))
    code, out, _ = run_cli("analyze", str(path))
    assert code == 0
    for title in ("Strength", "Pins: shear and bearing", "Links: axial, bending, buckling",
                  "Stress over the cycle"):
        assert title in out
    code, out, _ = run_cli("analyze", str(path), "--format", "csv", "--table", "strength.pins")
    assert code == 0 and out.splitlines()[0].startswith("pin,diameter,width,shear,force_max")
    assert len(out.splitlines()) == 5
    code, out, _ = run_cli("analyze", str(path), "--format", "csv", "--table", "strength.rows")
    assert out.splitlines()[0] == ("input,pins.A0,pins.A,pins.B,pins.B0,links.input,links.coupler,"
                                   "links.output") and len(out.splitlines()) == 37
    code, out, _ = run_cli("analyze", str(path), "--format", "toml")
    import tomllib
    assert tomllib.loads(out)["strength"]["critical"]["part"] == "pin A"


@pytest.mark.slow
def test_plot_adds_the_strength_panels(tmp_path):
    pytest.importorskip("matplotlib")
    from linkcli import pipeline
    from linkcli.plot import figure
    path = tmp_path / "door.toml"
    path.write_text(FIRE_DOOR.format(**MM))
    outcome = pipeline.run(str(path), pipeline.Request(mode="analyze", plot=True))
    fig = figure(outcome.result)
    titles = [ax.get_title() for ax in fig.get_axes()]
    assert "Pin shear over the cycle" in titles and "Link stress over the cycle" in titles
    code, _, err = run_cli("analyze", str(path), "--plot", str(tmp_path / "door.png"))
    assert code == 0, err and (tmp_path / "door.png").stat().st_size > 0


BAD = [
    ('[joints]\nA = { diameter = -5, width = 6 }\n[material]\nname = "AISI 1045 CD"',
     "joints.A.diameter: expected a pin diameter > 0 (length unit), found -5"),
    ('[joints]\nA = { diameter = 5, width = 0 }\n[material]\nname = "AISI 1045 CD"',
     "joints.A.width: expected a bearing width > 0 (length unit), found 0"),
    ('[joints]\nA = { diameter = 5 }\n[material]\nname = "AISI 1045 CD"',
     "joints.A.width: expected a bearing width with the pin diameter"),
    ('[sections]\ncoupler = { width = 12 }\n[material]\nname = "AISI 1045 CD"',
     "sections.coupler.thickness: expected a thickness > 0 normal to the plane of motion (length unit), "
     "found nothing (the key is missing)"),
    ('[sections]\ncoupler = { diameter = 8 }\n[material]\nultimate = 400\nyield = 300\nmodulus = 2e5',
     "material.endurance: expected a fully reversed endurance strength > 0 (MPa), corrected for the "
     "part, found nothing (the key is missing)"),
    ('[sections]\ncoupler = { diameter = 8 }\n[material]\nname = "AISI 1054 CD"',
     '(did you mean "AISI 1050 CD"?), found "AISI 1054 CD" (string)'),
    ('[sections]\ncoupler = { diameter = 8 }\n[material]\nname = "6061-T6"\nyield = 400',
     "material.yield: expected a yield strength at most the ultimate strength, found yield 400 MPa "
     "and ultimate 310 MPa"),
    # sizes below 1e-9, as a link's length: 1e-300 and denormals passed as "> 0", then
    # underflowed (the buckling load's division by zero, an internal error; infinite stresses)
    ('[sections]\ncoupler = { width = 12, thickness = 1e-300 }\n[material]\nname = "AISI 1045 CD"',
     "sections.coupler.thickness: expected a thickness > 0 normal to the plane of motion (length unit), "
     "within [1e-09, 1e+09], found 1e-300"),
    ('[sections]\ncoupler = { width = 5e-324, thickness = 4 }\n[material]\nname = "AISI 1045 CD"',
     "sections.coupler.width: expected a width > 0 in the plane of motion (length unit), "
     "within [1e-09, 1e+09], found 5e-324"),
    ('[sections]\ncoupler = { diameter = 8, wall = 9e-10 }\n[material]\nname = "AISI 1045 CD"',
     "sections.coupler.wall: expected a tube wall > 0 (length unit), within [1e-09, 1e+09], found 9e-10"),
    ('[joints]\nA = { diameter = 5, width = 1e-300 }\n[material]\nname = "AISI 1045 CD"',
     "joints.A.width: expected a bearing width > 0 (length unit), within [1e-09, 1e+09], found 1e-300"),
    ('[sections]\ncupler = { diameter = 8 }\n[material]\nname = "6061-T6"',
     'sections.cupler: expected a link of the four-bar: one of input, coupler, output (did you mean '
     '"coupler"?), found link "cupler"'),
]


@pytest.mark.parametrize("tables, line", BAD)
def test_bad_part_sizes_and_materials_are_exit_2_located(tmp_path, tables, line):
    text = FIRE_DOOR.format(**MM)
    text = text[:text.index("[joints]")] + tables + "\n"
    path = tmp_path / "bad.toml"
    path.write_text(text)
    for command in ("check", "analyze"):
        code, out, err = run_cli(command, str(path))
        assert code == 2 and out == ""
        assert line in err, err
        assert all(ln.startswith(f"{path}:") for ln in err.splitlines()), err


def test_check_of_a_strength_file_imports_neither_numpy_nor_scipy():
    import subprocess
    import sys
    code = ("import sys; from linkcli.cli import app\n"
            "try:\n    app(['check', 'problems/firedoor_strength.toml'], prog_name='linkcli')\n"
            "except SystemExit as e:\n    assert e.code == 0, e.code\n"
            "heavy = [m for m in ('numpy', 'scipy') if m in sys.modules]\n"
            "assert not heavy, heavy")
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)
