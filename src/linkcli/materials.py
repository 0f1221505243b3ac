"""The named materials a `[material] name = "..."` may give (docs/strength.md), each with its
source. Pure Python: the reader and `check` use it without numpy.

Values in MPa. `ultimate` and `yield` are tensile; `endurance` is the fully reversed
specimen value, NOT corrected for the part's surface, size, loading or reliability (the Marin
factors: give `[material] endurance` for the part to use a corrected value); `modulus` is
Young's modulus.

Steels: ASTM minimum tensile and yield strengths of hot-rolled (HR) and cold-drawn (CD) bar,
18 to 32 mm, from Budynas & Nisbett, *Shigley's Mechanical Engineering Design*, 9th/10th ed.,
Table A-20 (after the 1986 SAE Handbook, p. 2.15); endurance S'e = 0.5 Sut, the rotating-beam
estimate for Sut <= 1400 MPa (ibid., Eq. 6-8); modulus 207 GPa (ibid., Table A-5, carbon steel).

Aluminium alloys (no endurance limit): typical tensile, yield and fatigue strength at 5e8
cycles of fully reversed stress (R.R. Moore specimen), modulus the mean of tension and
compression, from the Aluminum Association's typical mechanical properties of wrought alloys
(*Aluminum Standards and Data*; the same values in ASM Handbook vol. 2).
"""

from __future__ import annotations

from typing import NamedTuple

SHIGLEY_A20 = ("Shigley's Mechanical Engineering Design (Budynas & Nisbett), Table A-20; "
               "endurance 0.5 Sut (Eq. 6-8), modulus Table A-5")
ALUMINUM_ASSOCIATION = ("Aluminum Association, typical properties of wrought alloys (Aluminum "
                        "Standards and Data); fatigue strength at 5e8 cycles, R.R. Moore")


class Material(NamedTuple):
    """Strengths (MPa) of one material and where they come from."""

    ultimate: float
    yield_: float
    endurance: float
    modulus: float
    source: str


def _steel(ultimate: float, yield_: float) -> Material:
    return Material(ultimate, yield_, 0.5 * ultimate, 207_000.0, SHIGLEY_A20)


MATERIALS: dict[str, Material] = {
    "AISI 1018 CD": _steel(440.0, 370.0),
    "AISI 1020 HR": _steel(380.0, 210.0),
    "AISI 1020 CD": _steel(470.0, 390.0),
    "AISI 1045 HR": _steel(570.0, 310.0),
    "AISI 1045 CD": _steel(630.0, 530.0),
    "AISI 1050 CD": _steel(690.0, 580.0),
    "6061-T6": Material(310.0, 275.0, 95.0, 69_000.0, ALUMINUM_ASSOCIATION),
    "2024-T3": Material(485.0, 345.0, 140.0, 73_000.0, ALUMINUM_ASSOCIATION),
    "7075-T6": Material(570.0, 505.0, 160.0, 72_000.0, ALUMINUM_ASSOCIATION),
}


def _key(name: str) -> str:
    """A name compared without case, spaces, hyphens or underscores ("aisi-1045-cd")."""
    return "".join(ch for ch in name.casefold() if ch not in " -_")


def lookup(name: str) -> tuple[str, Material] | None:
    """(the listed name, its Material) for `name` written in any case and spacing; None when
    it is not in the list."""
    wanted = _key(name)
    for listed, material in MATERIALS.items():
        if _key(listed) == wanted:
            return listed, material
    return None


def suggestion(name: str) -> str | None:
    """The listed name closest to `name` (for "did you mean"), or None."""
    import difflib
    keys = {_key(listed): listed for listed in MATERIALS}
    hint = difflib.get_close_matches(_key(name), list(keys), n=1, cutoff=0.5)
    return keys[hint[0]] if hint else None
