"""ISO 286-1 standard tolerance grades IT1 … IT18 by nominal size (the limits-and-fits table).

:data:`TABLE` holds ISO 286-1:2010, Table 1 (standard tolerance values, µm) for nominal sizes up to 500 mm; above
500 mm (up to 3150 mm) the grades IT6 … IT18 follow the standard's formula, the tolerance factor
I = 0.004·D + 2.1 µm (D the geometric mean of the size range's limits, mm) times the grade's multiplier. The tests
compare the table with the formula i = 0.45·∛D + 0.001·D that underlies it (ISO 286-1, Annex A).
"""
from __future__ import annotations

import math

from ...errors import SpecError

#: the upper limits (mm) of the nominal size ranges up to 500 mm (each range is (previous, limit]; the first 0–3)
LIMITS = (3, 6, 10, 18, 30, 50, 80, 120, 180, 250, 315, 400, 500)
#: IT1 … IT18 (µm) for each range of :data:`LIMITS` (ISO 286-1:2010, Table 1; IT12 … IT18 given there in mm)
TABLE = {
    3: (0.8, 1.2, 2, 3, 4, 6, 10, 14, 25, 40, 60, 100, 140, 250, 400, 600, 1000, 1400),
    6: (1, 1.5, 2.5, 4, 5, 8, 12, 18, 30, 48, 75, 120, 180, 300, 480, 750, 1200, 1800),
    10: (1, 1.5, 2.5, 4, 6, 9, 15, 22, 36, 58, 90, 150, 220, 360, 580, 900, 1500, 2200),
    18: (1.2, 2, 3, 5, 8, 11, 18, 27, 43, 70, 110, 180, 270, 430, 700, 1100, 1800, 2700),
    30: (1.5, 2.5, 4, 6, 9, 13, 21, 33, 52, 84, 130, 210, 330, 520, 840, 1300, 2100, 3300),
    50: (1.5, 2.5, 4, 7, 11, 16, 25, 39, 62, 100, 160, 250, 390, 620, 1000, 1600, 2500, 3900),
    80: (2, 3, 5, 8, 13, 19, 30, 46, 74, 120, 190, 300, 460, 740, 1200, 1900, 3000, 4600),
    120: (2.5, 4, 6, 10, 15, 22, 35, 54, 87, 140, 220, 350, 540, 870, 1400, 2200, 3500, 5400),
    180: (3.5, 5, 8, 12, 18, 25, 40, 63, 100, 160, 250, 400, 630, 1000, 1600, 2500, 4000, 6300),
    250: (4.5, 7, 10, 14, 20, 29, 46, 72, 115, 185, 290, 460, 720, 1150, 1850, 2900, 4600, 7200),
    315: (6, 8, 12, 16, 23, 32, 52, 81, 130, 210, 320, 520, 810, 1300, 2100, 3200, 5200, 8100),
    400: (7, 9, 13, 18, 25, 36, 57, 89, 140, 230, 360, 570, 890, 1400, 2300, 3600, 5700, 8900),
    500: (8, 10, 15, 20, 27, 40, 63, 97, 155, 250, 400, 630, 970, 1550, 2500, 4000, 6300, 9700),
}
#: the ranges above 500 mm (upper limits, mm) and the grade multipliers of IT6 … IT18 (ISO 286-1, §5)
LARGE_LIMITS = (630, 800, 1000, 1250, 1600, 2000, 2500, 3150)
MULTIPLIERS = {6: 10, 7: 16, 8: 25, 9: 40, 10: 64, 11: 100, 12: 160, 13: 250, 14: 400, 15: 640, 16: 1000,
               17: 1600, 18: 2500}


def tolerance(grade: int, size_mm: float) -> float:
    """The standard tolerance (µm) of grade ``grade`` (1 … 18) for a nominal size ``size_mm`` (mm, 0 < size ≤ 3150;
    a size at or below 3 mm — including 0, an offset that is zero by design — takes the first range)."""
    grade, size = int(grade), abs(float(size_mm))
    if not 1 <= grade <= 18:
        raise SpecError([("grade", f"an IT grade is 1 … 18: {grade}")])
    if size <= 500:
        limit = next(L for L in LIMITS if size <= L)
        return float(TABLE[limit][grade - 1])
    if size > LARGE_LIMITS[-1]:
        raise SpecError([("size", f"ISO 286 tabulates nominal sizes up to 3150 mm: {size:g} mm")])
    if grade < 6:
        raise SpecError([("grade", f"above 500 mm this table holds IT6 … IT18: IT{grade}")])
    k = next(i for i, L in enumerate(LARGE_LIMITS) if size <= L)
    lo = 500 if k == 0 else LARGE_LIMITS[k - 1]
    D = math.sqrt(lo * LARGE_LIMITS[k])
    return MULTIPLIERS[grade] * (0.004 * D + 2.1)


def parse_grade(text) -> int:
    """``"IT7"``, ``"it7"`` or ``7`` → 7; SpecError otherwise."""
    s = str(text).strip().upper()
    s = s[2:] if s.startswith("IT") else s
    try:
        g = int(s)
    except ValueError:
        raise SpecError([("grade", f"an IT grade is written IT1 … IT18: {text!r}")]) from None
    if not 1 <= g <= 18:
        raise SpecError([("grade", f"an IT grade is written IT1 … IT18: {text!r}")])
    return g
