"""The ``[make]`` table of a mechanism file: how ``assur make`` builds the parts (docs/make.md).

::

    [make]
    process = "fdm"             # "fdm" | "laser-cut" | "machined"
    thickness = 4               # plate thickness (the file's length unit, or "4 mm")
    width = 12                  # bar width = joint boss diameter
    pin = 4                     # dowel diameter: one of the ISO 8734 series (1, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10, 12,
                                # 16, 20 mm)
    washer = 0.8                # washer thickness: the gap between two layers
    clearance = 1               # the least gap between two parts of one layer over the whole cycle
    material = "PLA"
    density = 1240              # kg/m³, or "1.24 g/cm3"
    hole_allowance = 0.3        # added to every hole's diameter (FDM holes print small)
    shaft_allowance = -0.1      # added to every printed pin's diameter
    base_thickness = 6          # the base (and top) plate
    shaft = 5                   # the motor shaft's diameter

Lengths are numbers in the file's length unit or ``"<number> <unit>"`` strings; every problem is added to the
reader's :class:`~assur.io.problems.Problems` at its key (``make.pin`` …) and the whole file is reported at once.
"""
from __future__ import annotations

import math
import re

from ..errors import SpecError
from ..model.making import DOWEL_SERIES, LENGTH_KEYS, PROCESSES, MakeSpec
from . import units as U

#: the keys of a ``[make]`` table, in the order the writer writes them
KEYS = ("process", "material", "density", "thickness", "width", "pin", "washer", "clearance", "hole_allowance",
        "shaft_allowance", "base_thickness", "shaft")
#: density units (kg/m³ per unit)
DENSITY_UNITS = {"kg/m3": 1.0, "kg/m^3": 1.0, "kg/m³": 1.0, "g/cm3": 1000.0, "g/cm^3": 1000.0, "g/cm³": 1000.0,
                 "g/ml": 1000.0, "t/m3": 1000.0}
#: allowances beyond this (m, in magnitude) are a typo, not a fit
MAX_ALLOWANCE = 0.002
#: a density outside this range (kg/m³) is no solid material
DENSITY_RANGE = (10.0, 25000.0)
_QUANTITY = re.compile(r"^\s*([-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?)\s*([^\s0-9].*?)\s*$")


def _density(value, path, P):
    """A density in kg/m³ from a bare number (kg/m³) or ``"1.24 g/cm3"``; None after adding the problem."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        v = float(value)
    elif isinstance(value, str) and _QUANTITY.match(value):
        number, unit = _QUANTITY.match(value).groups()
        if unit not in DENSITY_UNITS:
            P.add(path, f"unknown density unit {unit!r} (known: {', '.join(DENSITY_UNITS)}): {value!r}")
            return None
        v = float(number) * DENSITY_UNITS[unit]
    else:
        P.add(path, f"must be a density: a number (kg/m³) or \"<number> g/cm3\": {value!r}")
        return None
    lo, hi = DENSITY_RANGE
    if not (math.isfinite(v) and lo <= v <= hi):
        P.add(path, f"must be a solid's density between {lo:g} and {hi:g} kg/m³: {value!r}")
        return None
    return v


def _length(value, path, P, units):
    """A length in m (a bare number in the file's unit, or ``"<number> <unit>"``); None after the problem."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        P.add(path, f"must be a length (a number in {units.length}, or \"<number> <unit>\"): {value!r}")
        return None
    try:
        return U.parse_quantity(value, "length", units)
    except SpecError as exc:
        P.add(path, str(exc))
        return None


def _mm(v: float) -> str:
    return f"{v * 1e3:g} mm"


def dowel_diameter(value: float) -> float | None:
    """The standard dowel diameter (m) that ``value`` (m) names, to a part per billion; None for none."""
    for d in DOWEL_SERIES:
        if abs(value - d) <= 1e-9 * d:
            return d
    return None


def read_make(data: dict, P, *, units) -> MakeSpec | None:
    """The ``[make]`` table of a parsed mechanism file as a :class:`~assur.model.making.MakeSpec` (SI), or None
    without one. Problems go to ``P`` at ``make.KEY``."""
    if "make" not in data:
        return None
    t = data["make"]
    if not isinstance(t, dict):
        P.add("make", f"must be a table of the parts' sizes and material: {t!r}")
        return None
    P.unknown_keys(t, KEYS, "make")
    got: dict = {}
    if "process" in t:
        proc = t["process"]
        if proc not in PROCESSES:
            P.add("make.process", f"must be one of {', '.join(PROCESSES)}: {proc!r}")
        else:
            got["process"] = proc
    if "material" in t:
        mat = t["material"]
        if not isinstance(mat, str) or not mat.strip() or len(mat) > 80 or any(c in mat for c in "\n\r\t,\""):
            P.add("make.material", f"must be a material's name (one line of up to 80 characters, no commas or "
                                   f"quotes): {mat!r}")
        else:
            got["material"] = mat.strip()
    if "density" in t:
        got["density"] = _density(t["density"], "make.density", P)
    for key in LENGTH_KEYS:
        if key in t:
            got[key] = _length(t[key], f"make.{key}", P, units)
    _check_lengths(got, P)
    return MakeSpec(**{k: v for k, v in got.items() if v is not None})


def _check_lengths(got: dict, P) -> None:
    """The ranges of the lengths given (each alone, and the ones that must fit together)."""
    for key in ("thickness", "width", "washer", "clearance", "base_thickness", "shaft"):
        v = got.get(key)
        if v is not None and not v > 0:
            P.add(f"make.{key}", f"must be a positive length: {_mm(v)}")
            got[key] = None
    pin = got.get("pin")
    if pin is not None:
        d = dowel_diameter(pin)
        if d is None:
            P.add("make.pin", f"{_mm(pin)} is not a standard dowel diameter (ISO 8734: "
                              f"{', '.join(f'{x * 1e3:g}' for x in DOWEL_SERIES)} mm)")
            got["pin"] = None
        else:
            got["pin"] = d
    for key in ("hole_allowance", "shaft_allowance"):
        v = got.get(key)
        if v is not None and abs(v) > MAX_ALLOWANCE:
            P.add(f"make.{key}", f"must be within ±{_mm(MAX_ALLOWANCE)} (a fit allowance): {_mm(v)}")
            got[key] = None
    width, pin = got.get("width"), got.get("pin")
    if width is not None and pin is not None and width < 1.5 * pin:
        P.add("make.width", f"a boss of {_mm(width)} leaves too little wall around a ⌀{pin * 1e3:g} mm pin "
                            f"(the width must be at least 1.5 × the pin: {_mm(1.5 * pin)})")
    th, washer = got.get("thickness"), got.get("washer")
    if th is not None and washer is not None and washer > th:
        P.add("make.washer", f"a {_mm(washer)} washer is thicker than the {_mm(th)} plates it separates")
    clearance = got.get("clearance")
    if clearance is not None and width is not None and clearance > width:
        P.add("make.clearance", f"a clearance of {_mm(clearance)} is wider than the bars ({_mm(width)})")


def make_table(spec: MakeSpec, length_out, number_out=float) -> dict:
    """The ``[make]`` table of a spec for the writer: the given values, lengths through ``length_out`` (SI → the
    file's unit) and the density through ``number_out``, in :data:`KEYS` order."""
    given = spec.given()
    out = {}
    for key in KEYS:
        if key not in given:
            continue
        v = given[key]
        out[key] = length_out(v) if key in LENGTH_KEYS else number_out(v) if key == "density" else v
    return out


__all__ = ["DENSITY_UNITS", "KEYS", "dowel_diameter", "make_table", "read_make"]
