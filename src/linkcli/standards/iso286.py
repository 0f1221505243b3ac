"""ISO 286 limits and fits for nominal sizes up to 500 mm, as data (docs/tolerance.md).

Sources: ISO 286-1:2010 "Geometrical product specifications (GPS) -- ISO code system for
tolerances on linear sizes -- Part 1: Basis of tolerances, deviations and fits", Table 1
(standard tolerance grades IT1..IT18), Tables 2 and 3 (fundamental deviations of shafts and
holes, and the Delta values of the hole rule); ISO 286-2:2010 (tables of the tolerance
classes) for the rows the tests check. All deviations are in micrometres (um), sizes in mm.
A nominal size D belongs to the size step "over lo up to and including hi" (the first step
is "up to and including 3").

A tolerance class is a fundamental deviation (a letter) and a grade (a number): its zone is
[lower, upper] deviation from the nominal size.

- Shafts a..h: upper deviation es = the table value (<= 0), ei = es - IT.
  Shafts k..u: lower deviation ei = the table value (> 0, k: 0 outside grades 4..7 and
  at sizes up to 3 mm), es = ei + IT. js: +- IT/2 (ISO 286-1:2010; the 1988 edition let an
  odd IT of grades 7..11 round down to whole um: 6..10 mm js7 is +-7.5 here, +-7 there).
- Holes A..H: EI = -es of the shaft of the same letter (the general rule), ES = EI + IT.
  Holes K, M, N up to IT8 and P..U up to IT7: ES = -ei + Delta (the special rule), Delta =
  IT(n) - IT(n - 1) at that size (0 up to 3 mm); above those grades ES = -ei for M and
  P..U, 0 for K and N (N up to 3 mm: -4). ISO 286-1's special case M6 over 250 up to
  315 mm: ES = -9. JS as js. EI = ES - IT.

Covered: hole letters A B C D E F G H JS K M N P R S T U, shaft letters a b c d e f g h js
k m n p r s t u, grades 1..18, nominal sizes over 0 up to 500 mm (A, B, a, b and grades
14..18 only over 1 mm; T and t over 24 mm). Others (J, j, CD, EF, FG, V..ZC, IT0, IT01,
sizes over 500 mm) are not in these tables: `limits` raises FitError naming what is.
"""

from __future__ import annotations

import re
from typing import NamedTuple

MAX_SIZE = 500.0  # mm: the tables end here

# Main size steps (upper limits, mm) of the standard tolerance grades, ISO 286-1 Table 1.
STEPS = (3, 6, 10, 18, 30, 50, 80, 120, 180, 250, 315, 400, 500)
IT = {  # um, one value per main step
    1: (0.8, 1, 1, 1.2, 1.5, 1.5, 2, 2.5, 3.5, 4.5, 6, 7, 8),
    2: (1.2, 1.5, 1.5, 2, 2.5, 2.5, 3, 4, 5, 7, 8, 9, 10),
    3: (2, 2.5, 2.5, 3, 4, 4, 5, 6, 8, 10, 12, 13, 15),
    4: (3, 4, 4, 5, 6, 7, 8, 10, 12, 14, 16, 18, 20),
    5: (4, 5, 6, 8, 9, 11, 13, 15, 18, 20, 23, 25, 27),
    6: (6, 8, 9, 11, 13, 16, 19, 22, 25, 29, 32, 36, 40),
    7: (10, 12, 15, 18, 21, 25, 30, 35, 40, 46, 52, 57, 63),
    8: (14, 18, 22, 27, 33, 39, 46, 54, 63, 72, 81, 89, 97),
    9: (25, 30, 36, 43, 52, 62, 74, 87, 100, 115, 130, 140, 155),
    10: (40, 48, 58, 70, 84, 100, 120, 140, 160, 185, 210, 230, 250),
    11: (60, 75, 90, 110, 130, 160, 190, 220, 250, 290, 320, 360, 400),
    12: (100, 120, 150, 180, 210, 250, 300, 350, 400, 460, 520, 570, 630),
    13: (140, 180, 220, 270, 330, 390, 460, 540, 630, 720, 810, 890, 970),
    14: (250, 300, 360, 430, 520, 620, 740, 870, 1000, 1150, 1300, 1400, 1550),
    15: (400, 480, 580, 700, 840, 1000, 1200, 1400, 1600, 1850, 2100, 2300, 2500),
    16: (600, 750, 900, 1100, 1300, 1600, 1900, 2200, 2500, 2900, 3200, 3600, 4000),
    17: (1000, 1200, 1500, 1800, 2100, 2500, 3000, 3500, 4000, 4600, 5200, 5700, 6300),
    18: (1400, 1800, 2200, 2700, 3300, 3900, 4600, 5400, 6300, 7200, 8100, 8900, 9700),
}

# Intermediate size steps (upper limits, mm) of the fundamental deviations, ISO 286-1 Tables 2, 3.
SUBSTEPS = (3, 6, 10, 14, 18, 24, 30, 40, 50, 65, 80, 100, 120, 140, 160, 180, 200, 225, 250,
            280, 315, 355, 400, 450, 500)


def _by_main(values) -> tuple:
    """A deviation given per main step, repeated over the intermediate steps it spans."""
    return tuple(values[_main_index(hi)] for hi in SUBSTEPS)


def _main_index(size: float) -> int:
    return next(i for i, hi in enumerate(STEPS) if size <= hi)


# Shafts a..h: upper deviation es (um), per intermediate step.
SHAFT_UPPER = {
    "a": (-270, -270, -280, -290, -290, -300, -300, -310, -320, -340, -360, -380, -410, -460, -520,
          -580, -660, -740, -820, -920, -1050, -1200, -1350, -1500, -1650),
    "b": (-140, -140, -150, -150, -150, -160, -160, -170, -180, -190, -200, -220, -240, -260, -280,
          -310, -340, -380, -420, -480, -540, -600, -680, -760, -840),
    "c": (-60, -70, -80, -95, -95, -110, -110, -120, -130, -140, -150, -170, -180, -200, -210,
          -230, -240, -260, -280, -300, -330, -360, -400, -440, -480),
    "d": _by_main((-20, -30, -40, -50, -65, -80, -100, -120, -145, -170, -190, -210, -230)),
    "e": _by_main((-14, -20, -25, -32, -40, -50, -60, -72, -85, -100, -110, -125, -135)),
    "f": _by_main((-6, -10, -13, -16, -20, -25, -30, -36, -43, -50, -56, -62, -68)),
    "g": _by_main((-2, -4, -5, -6, -7, -9, -10, -12, -14, -15, -17, -18, -20)),
    "h": (0,) * len(SUBSTEPS),
}
# Shafts k..u: lower deviation ei (um), per intermediate step (None: not defined there).
SHAFT_LOWER = {
    "k": _by_main((0, 1, 1, 1, 2, 2, 2, 3, 3, 4, 4, 4, 5)),  # grades 4..7; else 0
    "m": _by_main((2, 4, 6, 7, 8, 9, 11, 13, 15, 17, 20, 21, 23)),
    "n": _by_main((4, 8, 10, 12, 15, 17, 20, 23, 27, 31, 34, 37, 40)),
    "p": _by_main((6, 12, 15, 18, 22, 26, 32, 37, 43, 50, 56, 62, 68)),
    "r": (10, 15, 19, 23, 23, 28, 28, 34, 34, 41, 43, 51, 54, 63, 65, 68, 77, 80, 84, 94, 98, 108,
          114, 126, 132),
    "s": (14, 19, 23, 28, 28, 35, 35, 43, 43, 53, 59, 71, 79, 92, 100, 108, 122, 130, 140, 158, 170,
          190, 208, 232, 252),
    "t": (None, None, None, None, None, None, 41, 48, 54, 66, 75, 91, 104, 122, 134, 146, 166, 180,
          196, 218, 240, 268, 294, 330, 360),
    "u": (18, 23, 28, 33, 33, 41, 48, 60, 70, 87, 102, 124, 144, 170, 190, 210, 236, 258, 284, 315,
          350, 390, 435, 490, 540),
}
SHAFTS = tuple(SHAFT_UPPER) + ("js",) + tuple(SHAFT_LOWER)
HOLES = tuple(s.upper() for s in SHAFTS)
SPECIAL_UP_TO = {"K": 8, "M": 8, "N": 8}  # the special rule (Delta) up to this grade; P..U: 7
CLASS = re.compile(r"([A-Za-z]{1,2})(\d{1,2})")
FIT = re.compile(r"([A-Z]{1,2})(\d{1,2})/([a-z]{1,2})(\d{1,2})")


class FitError(ValueError):
    """A fit or a size outside these tables; the message says what is covered."""


class Zone(NamedTuple):
    """A tolerance zone: lower and upper deviation from the nominal size, um."""

    lower: float
    upper: float


class Fit(NamedTuple):
    """A hole/shaft fit at a nominal size (mm): both zones (um) and the kind of fit."""

    text: str
    size: float
    hole: Zone
    shaft: Zone

    @property
    def clearance(self) -> tuple[float, float]:
        """(least, largest) diametral clearance, um: hole minus shaft (negative: interference)."""
        return self.hole.lower - self.shaft.upper, self.hole.upper - self.shaft.lower

    @property
    def kind(self) -> str:
        least, largest = self.clearance
        return "clearance" if least >= 0 else ("interference" if largest <= 0 else "transition")


def _sub_index(size: float) -> int:
    return next(i for i, hi in enumerate(SUBSTEPS) if size <= hi)


def _check_size(size: float) -> None:
    if not 0.0 < size <= MAX_SIZE:
        raise FitError(f"a nominal size over 0 up to {MAX_SIZE:g} mm (the ISO 286 tables here), "
                       f"found {size:g} mm")


def it(grade: int, size: float) -> float:
    """The standard tolerance IT<grade> at a nominal size (mm), um (ISO 286-1 Table 1)."""
    _check_size(size)
    if grade not in IT:
        raise FitError(f"a grade from 1 to 18, found {grade}")
    if grade >= 14 and size <= 1.0:
        raise FitError(f"a size over 1 mm for grade {grade} (IT14..IT18 start there), found {size:g} mm")
    return float(IT[grade][_main_index(size)])


def shaft(letter: str, grade: int, size: float) -> Zone:
    """The zone of shaft class <letter><grade> at a nominal size (mm), um."""
    tol = it(grade, size)
    if letter == "js":
        return _js(tol)
    if letter in ("a", "b") and size <= 1.0:
        raise FitError(f"a size over 1 mm for shaft {letter} (not used up to 1 mm), found {size:g} mm")
    i = _sub_index(size)
    if letter in SHAFT_UPPER:
        es = float(SHAFT_UPPER[letter][i])
        return Zone(es - tol, es)
    if letter not in SHAFT_LOWER:
        raise FitError(f"a shaft letter of ISO 286 in linkcli's tables ({', '.join(SHAFTS)}), found \"{letter}\"")
    ei = SHAFT_LOWER[letter][i]
    if ei is None:
        raise FitError(f"a size over 24 mm for shaft {letter} (defined from there), found {size:g} mm")
    if letter == "k" and not 4 <= grade <= 7:
        ei = 0
    return Zone(float(ei), float(ei) + tol)


def hole(letter: str, grade: int, size: float) -> Zone:
    """The zone of hole class <LETTER><grade> at a nominal size (mm), um (general and special
    rules of ISO 286-1; module docstring)."""
    tol = it(grade, size)
    if letter == "JS":
        return _js(tol)
    low = letter.lower()
    if letter not in HOLES:
        raise FitError(f"a hole letter of ISO 286 in linkcli's tables ({', '.join(HOLES)}), found \"{letter}\"")
    if low in SHAFT_UPPER:
        lower = -shaft(low, grade, size).upper  # general rule: EI = -es
        return Zone(lower, lower + tol)
    if SHAFT_LOWER[low][_sub_index(size)] is None:
        raise FitError(f"a size over 24 mm for hole {letter} (defined from there), found {size:g} mm")
    ei = shaft(low, 6, size).lower  # the fundamental deviation ei of k..u (grade 6: k's value)
    if letter in SPECIAL_UP_TO:
        special = grade <= SPECIAL_UP_TO[letter]
        beyond = {"K": 0.0, "M": -ei, "N": 0.0 if size > 3 else -ei}[letter]
    else:
        special = grade <= 7
        beyond = -ei
    upper = -ei + _delta(grade, size) if special else beyond
    if letter == "M" and grade == 6 and 250 < size <= 315:
        upper = -9.0  # ISO 286-1, Table 3, the special case of M6
    return Zone(upper - tol, upper)


def _delta(grade: int, size: float) -> float:
    """Delta = IT(n) - IT(n - 1) of the hole rule, for grades 3..8 over 3 mm, else 0."""
    if size <= 3 or not 3 <= grade <= 8:
        return 0.0
    return it(grade, size) - it(grade - 1, size)


def _js(tol: float) -> Zone:
    return Zone(-tol / 2, tol / 2)


def parse(text: str) -> tuple[str, int, str, int]:
    """"H7/g6" -> ("H", 7, "g", 6); FitError for another form."""
    m = FIT.fullmatch(text)
    if m is None:
        raise FitError(f'a fit "HOLE/shaft" such as "H7/g6" (hole letters upper case, shaft '
                       f'letters lower case, each with its grade), found "{text}"')
    for grade in (m.group(2), m.group(4)):
        if len(grade) > 1 and grade.startswith("0"):  # IT01 (not int("01") = IT1), or a grade written "07"
            raise FitError(f'a grade from 1 to 18 written without a leading 0 (IT01 is not in '
                           f'linkcli\'s tables), found "{grade}" in "{text}"')
    return m.group(1), int(m.group(2)), m.group(3), int(m.group(4))


def limits(text: str, size: float) -> Fit:
    """The fit `text` ("H7/g6") at nominal size `size` (mm): both zones (FitError outside the
    tables)."""
    hole_letter, hole_grade, shaft_letter, shaft_grade = parse(text)
    if hole_letter not in HOLES:
        raise FitError(f"a hole letter of ISO 286 in linkcli's tables ({', '.join(HOLES)}), "
                       f'found "{hole_letter}" in "{text}"')
    if shaft_letter not in SHAFTS:
        raise FitError(f"a shaft letter of ISO 286 in linkcli's tables ({', '.join(SHAFTS)}), "
                       f'found "{shaft_letter}" in "{text}"')
    return Fit(text, size, hole(hole_letter, hole_grade, size), shaft(shaft_letter, shaft_grade, size))


def clearance_fit_problem(text: str, diameter_mm: float) -> tuple[str, str] | None:
    """(expected, found) when `text` is no clearance fit of ISO 286 at that diameter (a
    running joint needs clearance: hole at least as large as the shaft), else None."""
    try:
        fit = limits(text, diameter_mm)
    except FitError as exc:
        expected, _, found = str(exc).partition(", found ")
        return expected, found
    least, largest = fit.clearance
    if fit.kind != "clearance":
        return (f"a clearance fit for a running joint (least clearance >= 0), e.g. \"H7/g6\"",
                f'"{text}" at {diameter_mm:g} mm, a{"n" if fit.kind == "interference" else ""} '
                f"{fit.kind} fit (clearance {least:g}..{largest:g} um)")
    return None
