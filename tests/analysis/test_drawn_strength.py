"""The strength section of drawn linkages (docs/drawn.md "Strength", docs/strength.md), checked
against references written here, never the code's own output:

- every link's loads (`member_forces`) sum to zero force and zero moment at every row, on every
  drawn example and on drawings with several drives, a linear drive on a cylinder, sliders and
  pins joining three links, all with masses, gravity, torques and forces (d'Alembert);
- a four-bar written as a drawing gives the named four-bar's strength section (the fire door of
  problems/firedoor_strength.toml), every number to 1e-6;
- a massless Watt six-bar under an output torque: the two-force link C-D carries the force of
  closed-form statics on the output, T / ((D - O6) x e), with positions from circle
  intersections written here, and buckles by Euler's formula;
- a pin joining three links (a four-bar's rocker pin driving a slider's rod): its shear is the
  largest of the three two-force members' forces, solved here from the pin's equilibrium.
"""

from __future__ import annotations

import json
import math
import tomllib

import numpy as np
import pytest
from conftest import ROOT, run_cli

REL = 1e-6


def write(tmp_path, text: str, name: str = "drawn.toml") -> str:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return str(path)


def strength_report(path: str, code: int = 0) -> dict:
    got, out, err = run_cli("analyze", path, "--format", "json", "--precision", "17")
    assert got == code, err
    return json.loads(out)


def drawing(name: str) -> str:
    """An example's drawing, without its loads, masses and tolerances."""
    text = (ROOT / "problems" / f"{name}.toml").read_text(encoding="utf-8")
    for table in ("[loads]", "[masses]", "[tolerance]"):
        if table in text:
            text = text[:text.index(table)]
    return text


def circle_circle(p, r, q, s, side):
    """The intersection of the circles (p, r) and (q, s) on `side` (the sign of
    (q - p) x (X - p)), rows of points."""
    d = q - p
    dist = np.hypot(d[:, 0], d[:, 1])
    along = (dist ** 2 + r * r - s * s) / (2 * dist)
    h = np.sqrt(r * r - along ** 2)
    e = d / dist[:, None]
    normal = np.stack([-e[:, 1], e[:, 0]], axis=1)
    return p + along[:, None] * e + side * h[:, None] * normal


def cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def unit(v):
    return v / np.hypot(v[..., 0], v[..., 1])[..., None]


# ---------------------------------------------------------------- equilibrium of every link
def masses_of(bodies) -> str:
    """A mass for each body: a link's centre off its axis, with an inertia of its own; a
    slider's block (a joint's name, upper case) a point mass."""
    return "\n".join(f'{name} = {{ mass = {0.1 + 0.05 * k:g} }}' if name.isupper() else
                     f'{name} = {{ mass = {0.1 + 0.05 * k:g}, center = [{4 + k:g}, {2 - k:g}], '
                     f'inertia = {(1 + k) * 1e-5:g} }}' for k, name in enumerate(bodies))


def five_bar() -> str:
    a = (15 * math.cos(math.radians(60)), 15 * math.sin(math.radians(60)))
    b = (40 + 15 * math.cos(math.radians(120)), 15 * math.sin(math.radians(120)))
    c = (20.0, a[1] + math.sqrt(40 ** 2 - 12.5 ** 2))
    return f"""type = "linkage"
[linkage]
mechanism = "drawn"
[joints]
O1 = {{ at = [0, 0], ground = true }}
O2 = {{ at = [40, 0], ground = true }}
A = {{ at = [{a[0]!r}, {a[1]!r}] }}
B = {{ at = [{b[0]!r}, {b[1]!r}] }}
C = {{ at = [{c[0]!r}, {c[1]!r}] }}
[links]
left = ["O1", "A"]
right = ["O2", "B"]
upper_left = ["A", "C"]
upper_right = ["B", "C"]
[drive]
left = {{ speed = 20 }}
right = {{ speed = -35 }}
[motion]
steps = 24
"""


CYLINDER = f"""type = "linkage"
[linkage]
mechanism = "drawn"
[joints]
O = {{ at = [0, 0], ground = true }}
C0 = {{ at = [60, 0], ground = true }}
P = {{ at = [20, 34.64101615137754], slider = {math.degrees(math.atan2(34.64101615137754, -40.0))!r}, guide = "cylinder" }}
[links]
arm = ["O", "P"]
cylinder = ["C0", "P"]
[drive]
P = {{ speed = 5 }}
[motion]
steps = 9
span = [-10, 10]
"""


def shared_pin(a=15.0, b=35.0, c=30.0, d=40.0, rod=45.0, phi0=70.0):
    """A crank-rocker O2-A-B-O4 whose rocker pin B also drives a rod B-C to a slider C on the
    x axis: B joins the coupler, the rocker and the rod. (text, lengths, drawn points)."""
    A = np.array([[a * math.cos(math.radians(phi0)), a * math.sin(math.radians(phi0))]])
    B = circle_circle(A, b, np.array([[d, 0.0]]), c, -1.0).tolist()
    A = A.tolist()
    C = [B[0][0] + math.sqrt(rod ** 2 - B[0][1] ** 2), 0.0]
    text = f"""type = "linkage"
[linkage]
mechanism = "drawn"
[joints]
O2 = {{ at = [0, 0], ground = true }}
O4 = {{ at = [{d!r}, 0], ground = true }}
A = {{ at = [{A[0][0]!r}, {A[0][1]!r}] }}
B = {{ at = [{B[0][0]!r}, {B[0][1]!r}], diameter = 4, width = 5 }}
C = {{ at = [{C[0]!r}, 0], slider = 0, diameter = 4, width = 5 }}
[links]
crank = ["O2", "A"]
coupler = ["A", "B"]
rocker = ["O4", "B"]
rod = ["B", "C"]
[drive]
crank = {{ speed = 30 }}
[motion]
steps = 36
"""
    return text, (a, b, c, d, rod)


def equilibrium_cases():
    """name -> (drawing, bodies with a mass, extra [loads] lines)."""
    return {
        "watt": (drawing("drawn_watt"), ["crank", "coupler", "rocker", "link", "output"],
                 "torques = { output = -1.5, rocker = 0.4 }\nforces = { D = [3, -20], B = [1, 2] }"),
        "stephenson": (drawing("drawn_stephenson"), ["crank", "rod", "left", "right", "plate"],
                       "torques = { right = 0.8 }\nforces = { C = [5, -4] }"),
        "jansen": (drawing("drawn_jansen"), ["m", "j", "k", "bde", "c", "f", "ghi"],
                   "forces = { F = [0, 30] }"),
        "shaper": (drawing("drawn_shaper"), ["crank", "rocker", "rod", "A", "C"],
                   "torques = { rocker = 0.3 }\nforces = { C = [-30, 0], B = [2, 1] }"),
        "five-bar, two drives": (five_bar(), ["left", "right", "upper_left", "upper_right"],
                                 "torques = { upper_right = 0.2 }\nforces = { C = [4, -10] }"),
        "cylinder, linear drive": (CYLINDER, ["arm", "cylinder", "P"],
                                   "torques = { arm = -2.0 }\nforces = { P = [1, -3] }"),
        "shared pin": (shared_pin()[0], ["crank", "coupler", "rocker", "rod", "C"],
                       "forces = { C = [-40, 0], B = [0, -5] }"),
    }


@pytest.mark.parametrize("case", list(equilibrium_cases()))
def test_every_links_loads_are_in_equilibrium(case, tmp_path):
    """Sum of forces and of moments (about the origin: couples plus r x F) of each link's loads
    is zero at every row; its first loads are its joints', in [links] order."""
    from linkcli import mechanisms
    from linkcli.analysis.forces import metres_per_unit
    from linkcli.reading.load import load
    text, bodies, extra = equilibrium_cases()[case]
    text += f"[loads]\ngravity = [0.4, -9.81]\n{extra}\n[masses]\n{masses_of(bodies)}\n"
    problem = load(write(tmp_path, text))
    mech = mechanisms.of(problem.linkage)
    phi, _ = mech.study().rows(36)
    metres = metres_per_unit(problem.meta.units)
    rows = mech.load_rows(phi, 1.0, problem.meta.loads, metres)
    members = mech.member_forces(phi, 1.0, problem.meta.loads, metres, rows)
    drawn = tomllib.loads(text)
    links = drawn["links"]
    ground = {name for name, joint in drawn["joints"].items() if joint.get("ground")}
    assert members.links == {name: tuple(joints) for name, joints in links.items()}
    ok = ~rows.singular
    assert ok.sum() >= len(phi) - 1
    for link, loads in members.loads.items():
        assert [one.name for one in loads[:len(links[link])]] == links[link]
        names = [one.name for one in loads[len(links[link]):]]
        assert set(names) <= {"drive", "torque", "force", "inertia"} and "inertia" in names
        pivot = [k for k, joint in enumerate(links[link]) if joint in ground]
        for one in loads:  # a couple (drive or load torque) acts at the link's ground pivot
            if one.name in ("drive", "torque") and pivot and not np.any(one.force):
                assert np.array_equal(one.at, loads[pivot[0]].at), link
        force = sum(load.force for load in loads)[ok]
        moment = sum(load.couple + cross(load.at, load.force) for load in loads)[ok]
        scale = max(np.abs(load.force[ok]).max() for load in loads)
        reach = max(np.abs(load.at[ok]).max() for load in loads)
        assert np.abs(force).max() < 1e-10 * scale, link
        assert np.abs(moment).max() < 1e-10 * scale * reach, link


# ---------------------------------------------------------------- the fire door, drawn
def fire_door_drawn(reverse_output: bool = False) -> str:
    """problems/firedoor_strength.toml as a drawing: A0 at the origin, B0 on the x axis, the
    crank at 0 deg, B on the open branch (SPEC section 1: psi = theta_rho - alpha); the same
    loads, masses, part sizes and material. `reverse_output`: the output drawn B -> B0 (its
    frame from B: the mass's centre at c - x along it), its pivot second."""
    named = tomllib.loads((ROOT / "problems" / "firedoor_strength.toml").read_text(encoding="utf-8"))
    lk = named["linkage"]
    output = '["B0", "B"]'
    if reverse_output:
        output = '["B", "B0"]'
        centre = named["masses"]["output"]["center"]
        named["masses"]["output"]["center"] = [lk["output"] - centre[0], -centre[1]]
    a, b, c, d = lk["input"], lk["coupler"], lk["output"], lk["ground"]
    ax, ay = a, 0.0
    rho, theta_rho = math.hypot(ax - d, ay), math.atan2(ay, ax - d)
    psi = theta_rho - math.acos((rho * rho + c * c - b * b) / (2 * rho * c))
    bx, by = d + c * math.cos(psi), c * math.sin(psi)
    at = {"A0": (0.0, 0.0), "A": (ax, ay), "B": (bx, by), "B0": (float(d), 0.0)}

    def inline(table: dict) -> str:
        return "{ " + ", ".join(f"{k} = {json.dumps(v)}" for k, v in table.items()) + " }"

    joints = "\n".join(f"{name} = {{ at = [{x!r}, {y!r}]{', ground = true' if name in ('A0', 'B0') else ''}, "
                       + inline(size)[2:] for name, size in named["joints"].items() for x, y in [at[name]])
    masses = "\n".join(f"{name} = {inline(m)}" for name, m in named["masses"].items())
    sections = "\n".join(f"{name} = {inline(s)}" for name, s in named["sections"].items())
    material = "\n".join(f"{k} = {json.dumps(v)}" for k, v in named["material"].items())
    strength = "\n".join(f"{k} = {json.dumps(v)}" for k, v in named["strength"].items())
    return f"""type = "linkage"
[linkage]
mechanism = "drawn"
[joints]
{joints}
[links]
input = ["A0", "A"]
coupler = ["A", "B"]
output = {output}
[drive]
input = {{ speed = {named['motion']['input_speed']} }}
[motion]
steps = {named['motion']['steps']}
[loads]
gravity = {json.dumps(named['loads']['gravity'])}
torques = {{ output = {named['loads']['output_torque']} }}
[masses]
{masses}
[sections]
{sections}
[material]
{material}
[strength]
{strength}
"""


def same(a, b, where: str, scale: float) -> None:
    """Every number of two JSON trees to REL (numbers far below the part's scale as 0)."""
    if isinstance(a, dict):
        assert set(a) == set(b), where
        for key in a:
            same(a[key], b[key], f"{where}.{key}", scale)
    elif isinstance(a, list):
        assert len(a) == len(b), where
        for k, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{where}[{k}]", scale)
    elif isinstance(a, float) or isinstance(b, float):
        assert math.isclose(a, b, rel_tol=REL, abs_tol=1e-12 * scale), f"{where}: named {a!r}, drawn {b!r}"
    else:
        assert a == b, f"{where}: named {a!r}, drawn {b!r}"


@pytest.mark.parametrize("reverse_output", [False, True])
def test_the_fire_door_drawn_has_the_named_fire_doors_strength(reverse_output, tmp_path):
    """Every number of the strength section, the output drawn either way (the door closer's
    torque acts at its pivot B0, where the named four-bar puts it)."""
    named = strength_report(str(ROOT / "problems" / "firedoor_strength.toml"))["strength"]
    drawn = strength_report(write(tmp_path, fire_door_drawn(reverse_output)))["strength"]
    assert [p["pin"] for p in drawn["pins"]] == ["A0", "A", "B", "B0"]
    assert [k["link"] for k in drawn["links"]] == ["input", "coupler", "output"]
    assert drawn["critical"]["part"] == "pin A" and "unchecked" not in drawn
    same(named, drawn, "strength", 1e4)


# ---------------------------------------------------------------- a Watt six-bar's two-force link
def with_pin_sizes(text: str, names) -> str:
    """A drawing whose joints `names` are sized as pins (d 4, w 5 mm)."""
    lines = text.splitlines()
    for k, row in enumerate(lines):
        if row.split("=")[0].strip() in names and "{ at" in row:
            lines[k] = row.rstrip()[:-1].rstrip() + ", diameter = 4, width = 5 }"
    return "\n".join(lines) + "\n"


def watt_with_pins() -> str:
    """drawn_watt's drawing with the pins C and D sized."""
    return with_pin_sizes(drawing("drawn_watt"), ("C", "D"))


WATT_STRENGTH = """
[loads]
torques = {{ output = {torque} }}
[sections]
link = {{ width = 8, thickness = {thickness} }}
crank = {{ width = 10, thickness = 4 }}
rocker = {{ width = 10, thickness = 4 }}
[material]
ultimate = 630
yield = 530
endurance = 257
modulus = 207000
"""


def watt_statics(text: str, inputs_deg, torque: float):
    """The massless Watt six-bar of `text` at crank angles `inputs_deg`, by circle
    intersections on the drawn sides: (C, D, axial force of C-D, tension positive). The
    output O6-D carries the torque T and the link's force f e at D (e along C -> D); its
    moments about O6: (D - O6) x (f e) + T = 0. The link feels -f e at D: tension -f."""
    j = {name: np.array(v["at"], dtype=float) for name, v in tomllib.loads(text)["joints"].items()}
    n = len(inputs_deg)
    phi = np.radians(inputs_deg)
    rows = lambda p: np.broadcast_to(p, (n, 2))  # noqa: E731
    dist = lambda p, q: float(np.hypot(*(p - q)))  # noqa: E731
    side = lambda p, q, x: float(np.sign(cross(q - p, x - p)))  # noqa: E731
    A = dist(j["A"], j["O2"]) * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    B = circle_circle(A, dist(j["A"], j["B"]), rows(j["O4"]), dist(j["O4"], j["B"]),
                      side(j["A"], j["O4"], j["B"]))
    turn = np.arctan2(B[:, 1] - j["O4"][1], B[:, 0] - j["O4"][0]) - math.atan2(*(j["B"] - j["O4"])[::-1])
    arm = j["C"] - j["O4"]
    C = j["O4"] + np.stack([np.cos(turn) * arm[0] - np.sin(turn) * arm[1],
                            np.sin(turn) * arm[0] + np.cos(turn) * arm[1]], axis=1)
    D = circle_circle(C, dist(j["C"], j["D"]), rows(j["O6"]), dist(j["O6"], j["D"]),
                      side(j["C"], j["O6"], j["D"]))
    e = unit(D - C)
    f = -torque / (cross(D - j["O6"], e) / 1000.0)  # lever in m
    return C, D, -f, dist(j["C"], j["D"])


def test_a_watt_six_bars_two_force_link_by_statics_and_euler(tmp_path):
    torque, width, thickness = 6.0, 8.0, 1.2
    text = watt_with_pins() + WATT_STRENGTH.format(torque=torque, thickness=thickness)
    rep = strength_report(write(tmp_path, text))
    strength = rep["strength"]
    inputs = np.array([row["input"] for row in strength["rows"]])
    assert inputs == pytest.approx(np.arange(36) * 10.0)
    _, _, axial, length = watt_statics(text, inputs, torque)
    link = {k["link"]: k for k in strength["links"]}["link"]
    area = width * thickness
    assert link["length"] == pytest.approx(length, rel=1e-12)
    assert link["tension"] == pytest.approx(max(axial.max(), 0.0), rel=REL, abs=1e-9)
    assert link["compression"] == pytest.approx(max(-axial.min(), 0.0), rel=REL)
    assert link["compression"] > 0 and link["tension"] == 0   # the output's torque pushes C-D
    assert link["bending"] == pytest.approx(0.0, abs=1e-9)    # a massless two-force member
    assert link["stress_max"] == pytest.approx(np.abs(axial).max() / area, rel=REL)
    sigma = [row["links"]["link"] for row in strength["rows"]]
    assert sigma == pytest.approx(np.abs(axial) / area, rel=REL)
    pins = {p["pin"]: p for p in strength["pins"]}
    for name in ("C", "D"):  # each end pin carries the link's force
        assert pins[name]["force_max"] == pytest.approx(np.abs(axial).max(), rel=REL)
        assert pins[name]["force_min"] == pytest.approx(np.abs(axial).min(), rel=REL)
    # Euler: P = pi^2 E I / l^2 about the weakest axis, I = w t^3 / 12 (N, with E in N/mm^2)
    inertia = width * thickness ** 3 / 12.0
    slenderness, transition = length / math.sqrt(inertia / area), math.sqrt(2 * math.pi ** 2 * 207000 / 530)
    assert slenderness > transition and link["buckling"] == "euler"
    euler = math.pi ** 2 * 207000 * inertia / length ** 2
    assert link["buckling_load"] == pytest.approx(euler, rel=1e-12)
    assert link["buckling_factor"] == pytest.approx(euler / -axial.min(), rel=REL)
    assert strength["unchecked"] == ["pin O2", "pin O4", "pin O6", "pin A", "pin B", "link coupler",
                                     "link rocker", "link output"]
    assert any("rocker: a plate of three or more joints" in note for note in rep["notes"])


# ---------------------------------------------------------------- a pin joining three links
def test_a_pin_of_three_links_carries_the_largest_of_their_forces(tmp_path):
    """Massless, a force P along the guide on the slider C: the rod B-C, the coupler A-B and the
    rocker O4-B are two-force members. The rod's force on the block balances P along the guide:
    the block gets g e (e along B -> C) with g e_x = -P; the rod gets g e at B. At B the three
    links' forces sum to zero: c u_AB + r u_O4B + g e = 0, solved here. The pin's shear is
    max(|c|, |r|, |g|) at each row (docs/drawn.md), the pin C's |g|."""
    text, (a, b, c, d, rod) = shared_pin()
    push = -40.0
    text += f"""[loads]
forces = {{ C = [{push}, 0] }}
[sections]
rod = {{ width = 6, thickness = 3 }}
[material]
name = "AISI 1020 CD"
"""
    strength = strength_report(write(tmp_path, text))["strength"]
    inputs = np.array([row["input"] for row in strength["rows"]])
    phi = np.radians(inputs)
    A = a * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    B = circle_circle(A, b, np.broadcast_to([d, 0.0], A.shape), c, -1.0)
    C = np.stack([B[:, 0] + np.sqrt(rod ** 2 - B[:, 1] ** 2), np.zeros(len(B))], axis=1)
    e, u_ab, u_ob = unit(C - B), unit(B - A), unit(B - np.array([d, 0.0]))
    g = -push / e[:, 0]
    rhs = -g[:, None] * e
    det = cross(u_ab, u_ob)
    coupler_force, rocker_force = cross(rhs, u_ob) / det, cross(u_ab, rhs) / det
    largest = np.max(np.abs(np.stack([coupler_force, rocker_force, g], axis=1)), axis=1)
    area = math.pi * 4.0 ** 2 / 4
    pins = {p["pin"]: p for p in strength["pins"]}
    assert pins["B"]["force_max"] == pytest.approx(largest.max(), rel=REL)
    assert pins["B"]["force_min"] == pytest.approx(largest.min(), rel=REL)
    assert [row["pins"]["B"] for row in strength["rows"]] == pytest.approx(largest / area, rel=REL)
    assert [row["pins"]["C"] for row in strength["rows"]] == pytest.approx(np.abs(g) / area, rel=REL)
    # which link gives the largest force changes over the turn: the choice is made row by row
    assert len(set(np.argmax(np.abs(np.stack([coupler_force, rocker_force, g], axis=1)), axis=1))) > 1
    link = {k["link"]: k for k in strength["links"]}["rod"]
    assert link["tension"] == pytest.approx(max((-g).max(), 0.0), rel=REL, abs=1e-9)
    assert link["compression"] == pytest.approx(max(g.max(), 0.0), rel=REL, abs=1e-9)


# ---------------------------------------------------------------- what is not a bar
def test_a_binary_link_carrying_a_guide_is_no_bar(tmp_path):
    """The cylinder (pivot C0 and the piston's slider P) is listed unchecked with its reason;
    the arm, a bar O-P, is checked."""
    text = CYLINDER + """[loads]
torques = { arm = -2.0 }
[sections]
arm = { width = 10, thickness = 3 }
cylinder = { diameter = 20, wall = 2 }
[material]
name = "AISI 1020 HR"
"""
    rep = strength_report(write(tmp_path, text))
    strength = rep["strength"]
    assert [k["link"] for k in strength["links"]] == ["arm"]
    assert "link cylinder" in strength["unchecked"]
    assert any("cylinder: carries a slider's guide (the block runs along it, no bar between two "
               "pins) (bars only are checked)" in note for note in rep["notes"])


def test_a_section_naming_no_link_of_the_drawing_is_refused(tmp_path):
    text = watt_with_pins() + WATT_STRENGTH.format(torque=1.0, thickness=2).replace(
        "rocker = {", "rockr = {")
    path = write(tmp_path, text)
    for command in ("analyze", "check"):  # check names it too (it passed check, exit 0)
        code, out, err = run_cli(command, path)
        assert code == 2 and out == ""
        assert 'sections.rockr: expected a link of the drawing: one of crank, coupler, rocker, link, ' \
               'output (did you mean "rocker"?), found link "rockr"' in err


def test_jansens_pins_of_three_bodies_and_a_point_are_told_apart(tmp_path):
    """Jansen's A (crank m, j, k) and Q (ground, bde, c) join three bodies: pins; F, a point of
    the foot only, is none (its sizes get a note); bde, a plate, is listed unchecked."""
    text = with_pin_sizes(drawing("drawn_jansen"), ("A", "Q", "F")) + """[loads]
forces = { F = [0, 30] }
[sections]
j = { width = 8, thickness = 3 }
bde = { width = 8, thickness = 3 }
[material]
name = "6061-T6"
"""
    rep = strength_report(write(tmp_path, text))
    strength = rep["strength"]
    assert [p["pin"] for p in strength["pins"]] == ["Q", "A"]
    assert [k["link"] for k in strength["links"]] == ["j"]
    assert "link bde" in strength["unchecked"] and "pin F" not in strength["unchecked"]
    assert any(note.startswith("[joints] F: not a revolute pin") for note in rep["notes"])
    assert any("bde: a plate of three or more joints" in note for note in rep["notes"])
