"""The ``[make]`` table of a mechanism file: how ``assur make`` turns the mechanism into parts, as given.

Every field is what the file gave (SI: m, kg/m³) or None where the file left it to the default; the defaults
(which depend on the process and the mechanism's size) are resolved by :mod:`assur.parts.settings`, so a file
written back keeps only what its author wrote.
"""
from __future__ import annotations

from dataclasses import dataclass, fields

#: the manufacturing processes ``assur make`` knows (the file's spelling)
PROCESSES = ("fdm", "laser-cut", "machined")

#: ISO 8734 / ISO 2338 dowel pin diameters (m): the standard series a pin diameter is taken from
DOWEL_SERIES = (0.001, 0.0015, 0.002, 0.0025, 0.003, 0.004, 0.005, 0.006, 0.008, 0.010, 0.012, 0.016, 0.020)


@dataclass(frozen=True, slots=True)
class MakeSpec:
    """The ``[make]`` table: None where the file gives no value (the default applies).

    ``thickness``: plate thickness (m); ``width``: bar width = joint boss diameter (m); ``pin``: dowel diameter (m,
    one of :data:`DOWEL_SERIES`); ``washer``: washer thickness, the gap between two layers (m); ``clearance``: the
    least gap between two parts of one layer over the whole cycle (m); ``material`` (a name) and ``density``
    (kg/m³) of the plates; ``process``: one of :data:`PROCESSES`; ``hole_allowance`` and ``shaft_allowance``: added
    to the diameter of every hole and of every printed pin (m, negative to shrink); ``base_thickness``: the base
    and top plates (m); ``shaft``: the motor shaft diameter (m).
    """
    process: str | None = None
    thickness: float | None = None
    width: float | None = None
    pin: float | None = None
    washer: float | None = None
    clearance: float | None = None
    material: str | None = None
    density: float | None = None
    hole_allowance: float | None = None
    shaft_allowance: float | None = None
    base_thickness: float | None = None
    shaft: float | None = None

    def given(self) -> dict:
        """{field: value} of the fields the file gave, in field order."""
        return {f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) is not None}


#: the keys of a ``[make]`` table that are lengths (converted with the file's length unit)
LENGTH_KEYS = ("thickness", "width", "pin", "washer", "clearance", "hole_allowance", "shaft_allowance",
               "base_thickness", "shaft")
