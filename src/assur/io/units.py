"""Unit conversion at the file boundary. Inside the toolkit: m, rad, s."""
from __future__ import annotations

import math
import re
import warnings

from ..errors import AssumedUnitsWarning, SpecError

LENGTH = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "dm": 1e-1, "km": 1e3, "in": 0.0254, "ft": 0.3048}
ANGLE = {"rad": 1.0, "deg": math.pi / 180.0}
#: angular speed units, factor to rad/s
ANGULAR_SPEED = {"rad/s": 1.0, "deg/s": math.pi / 180.0, "rpm": 2.0 * math.pi / 60.0,
                 "rev/s": 2.0 * math.pi, "1/s": 2.0 * math.pi, "rev/min": 2.0 * math.pi / 60.0}

#: "<number> <unit>": the number, then the unit (spaces, "·" or "*" between unit factors, "^2" or "²")
_QUANTITY_RE = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S.*?)\s*$")

#: mass units, factor to kg
MASS = {"kg": 1.0, "g": 1e-3, "t": 1e3}
#: moment of inertia units, factor to kg·m² (every mass unit times m², cm², mm²)
INERTIA = {f"{mu}*{lu}^2": mf * LENGTH[lu] ** 2 for mu, mf in MASS.items() for lu in ("m", "cm", "mm")}
#: force units, factor to N
FORCE = {"N": 1.0, "kN": 1e3, "mN": 1e-3, "lbf": 4.4482216152605}
#: torque units, factor to N·m
TORQUE = {"N*m": 1.0, "N*mm": 1e-3, "N*cm": 1e-2, "kN*m": 1e3, "mN*m": 1e-3, "lbf*in": 4.4482216152605 * 0.0254,
          "lbf*ft": 4.4482216152605 * 0.3048}
#: a motor's electrical and hydraulic quantities (``[motor]``), factor to V, Ω, A, N·m/A, Pa, m², m³/s
VOLTAGE = {"V": 1.0, "mV": 1e-3, "kV": 1e3}
RESISTANCE = {"ohm": 1.0, "Ω": 1.0, "mohm": 1e-3, "mΩ": 1e-3, "kohm": 1e3, "kΩ": 1e3}
CURRENT = {"A": 1.0, "mA": 1e-3}
TORQUE_CONSTANT = {"N*m/A": 1.0, "mN*m/A": 1e-3, "N*cm/A": 1e-2, "N*mm/A": 1e-3}
PRESSURE = {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "bar": 1e5, "psi": 6894.757293168}
AREA = {"m^2": 1.0, "cm^2": 1e-4, "mm^2": 1e-6, "in^2": 0.00064516}
FLOW = {"m^3/s": 1.0, "L/min": 1e-3 / 60.0, "l/min": 1e-3 / 60.0, "L/s": 1e-3, "l/s": 1e-3, "cm^3/s": 1e-6}
#: the tables of :func:`parse_quantity`: kind → (units, example); a bare number is in SI (kg, kg·m², N, N·m …)
QUANTITIES = {"mass": (MASS, "1 kg"), "inertia": (INERTIA, "0.02 kg*m^2"), "force": (FORCE, "100 N"),
              "torque": (TORQUE, "5 N*m"), "voltage": (VOLTAGE, "24 V"), "resistance": (RESISTANCE, "1.5 ohm"),
              "current": (CURRENT, "2 A"), "torque_constant": (TORQUE_CONSTANT, "0.05 N*m/A"),
              "pressure": (PRESSURE, "100 bar"), "area": (AREA, "20 cm^2"), "flow": (FLOW, "10 L/min")}
#: a mass, inertia, force or torque above this in magnitude (SI) is a typo, not a machine
MAX_QUANTITY = 1e12
#: the largest magnitude (SI) a quantity of each kind may have, with the physical reason (docs/format.md, "Bounds"):
#: a larger value is a typo or a unit slip, and it would only give forces that no machine carries (the other kinds:
#: MAX_QUANTITY)
LIMITS = {
    "mass": (1e8, "kg", "100 000 t: more than the heaviest moving machine parts (a ship lift's caisson, 15 500 t)"),
    "inertia": (MAX_QUANTITY, "kg*m^2", "a typo, not a machine"),
    "force": (1e9, "N", "1 GN: more than the largest forging presses (0.8 GN)"),
    "torque": (1e9, "N*m", "1 GN·m: a hundred times the largest marine diesel engine's shaft torque (7.6 MN·m)"),
}
#: the largest acceleration of free fall (m/s²) a [dynamics] gravity may have: about 100 g (a frame accelerating
#: faster is a projectile, not a mechanism's ground)
MAX_GRAVITY = 1000.0


def _unit_name(text: str) -> str:
    """A unit as written, in the tables' spelling: "kg·m²", "kg m^2" and "kg * m^2" all read "kg*m^2"."""
    text = text.replace("·", "*").replace("⋅", "*").replace("²", "^2").replace("³", "^3")
    text = re.sub(r"\s*\*\s*", "*", text.strip())
    return re.sub(r"\s+", "*", text)


def _quantity(text, table: dict[str, float], bare: float, example: str) -> float:
    """``text`` ("<number> <unit>" with a unit of ``table``, or a number in units of ``bare``) times its factor.
    Raises SpecError naming the accepted units."""
    if isinstance(text, bool) or not isinstance(text, (int, float, str)):
        raise SpecError(f"must be a number or a string like '{example}': {text!r}")
    if not isinstance(text, str):
        return float(text) * bare
    m = _QUANTITY_RE.match(text)
    unit = _unit_name(m.group(2)) if m else None
    if unit not in table:
        raise SpecError(f"must be '<number> <unit>' with unit one of {', '.join(table)}: {text!r}")
    return float(m.group(1)) * table[unit]


def parse_quantity(text, kind: str, units=None) -> float:
    """A mass (kg), moment of inertia (kg·m²), force (N), torque (N·m) or, with the file's ``units``, a length
    (m) or an angle (rad) from ``"<number> <unit>"`` or a bare number (SI; a length or angle in the file's unit). Raises
    SpecError on a bad unit or a value that is not finite or beyond its bound in :data:`LIMITS` (a length or an
    angle: 1e9 m or rad)."""
    if kind in ("length", "angle"):
        if kind == "length":
            table, example, bare = LENGTH, f"1 {units.length}", LENGTH[units.length]
        else:
            table, example, bare = ANGLE, f"30 {units.angle}", ANGLE[units.angle]
        limit = 1e9
        if not (math.isfinite(value := _quantity(text, table, bare, example)) and abs(value) < limit):
            raise SpecError(f"must be a finite {kind} below {limit:g} (SI): {text!r}")
        return value
    (table, example), bare = QUANTITIES[kind], 1.0
    value = _quantity(text, table, bare, example)
    limit, unit, why = LIMITS.get(kind, (MAX_QUANTITY, "(SI)", "a typo, not a machine"))
    if not math.isfinite(value):
        raise SpecError(f"must be a finite {kind}: {text!r}")
    if abs(value) > limit:
        raise SpecError(f"a {kind} of {value:.4g} {unit} is beyond any machine (at most {limit:g} {unit} in "
                        f"magnitude: {why}): {text!r}")
    return value


def linear_speed_units() -> dict[str, float]:
    out = {}
    for name, f in LENGTH.items():
        out[f"{name}/s"] = f
        out[f"{name}/min"] = f / 60.0
    return out


def parse_speed(text, kind: str, units) -> float:
    """A driver speed to SI. ``text`` is a number (file units per second) or ``"27 rpm"``-style.

    Raises SpecError (a ValueError) with the accepted units on a bad value.
    """
    table = ANGULAR_SPEED if kind == "rotary" else linear_speed_units()
    base = ANGLE[units.angle] if kind == "rotary" else LENGTH[units.length]
    return _finite_speed(_quantity(text, table, base, "27 rpm"), text)


#: a driver speed above this (rad/s or m/s) is a typo, not a machine
MAX_SPEED = 1e9


def _finite_speed(value: float, text) -> float:
    if not (math.isfinite(value) and abs(value) < MAX_SPEED):
        raise SpecError(f"must be a finite speed below {MAX_SPEED:g} rad/s or m/s: {text!r}")
    return value


def parse_units(data, problems, default_length: str = "m") -> tuple[str, str]:
    """The ``[units]`` table of a document: (length unit, angle unit), defaults ``default_length`` and deg.

    data: the whole parsed document; each bad key or value is added to ``problems``
    (:class:`~assur.io.problems.Problems`) with its path, and its default is used instead. A document
    without ``[units]`` gets an :class:`~assur.errors.AssumedUnitsWarning` naming the units assumed."""
    if "units" not in data:
        warnings.warn(f"no [units] table: lengths are read in {default_length} and angles in degrees (add "
                      f'[units] length = "mm" or "m", angle = "deg" or "rad")', AssumedUnitsWarning, stacklevel=2)
    table = data.get("units", {})
    if not isinstance(table, dict):
        problems.add("units", "must be a table with 'length' and 'angle'")
        table = {}
    problems.unknown_keys(table, ("angle", "length"), "units")
    length, angle = table.get("length", default_length), table.get("angle", "deg")
    if not isinstance(length, str) or length not in LENGTH:
        problems.add("units.length", f"must be one of {', '.join(LENGTH)}: {length!r}")
        length = default_length
    if not isinstance(angle, str) or angle not in ANGLE:
        problems.add("units.angle", f"must be one of {', '.join(ANGLE)}: {angle!r}")
        angle = "deg"
    return length, angle


def format_speed(value: float, kind: str, units=None) -> str:
    """A speed as text that parses back to exactly ``value``: in rpm (rotary) or the file's length
    unit per second (linear) when that is exact, else in rad/s or m/s."""
    if kind == "rotary":
        candidates = [("rpm", ANGULAR_SPEED["rpm"]), ("rad/s", 1.0)]
    else:
        unit = units.length if units is not None else "m"
        candidates = [(f"{unit}/s", LENGTH[unit]), ("m/s", 1.0)]
    for name, factor in candidates:
        text = f"{value / factor:.12g}"
        if float(text) * factor == value:
            return f"{text} {name}"
    return f"{value!r} {'rad/s' if kind == 'rotary' else 'm/s'}"


def param_unit(kind: str, units) -> tuple[float, str]:
    """(factor SI → the file's unit, unit label: the length unit, '°' or 'rad', or '') of a parameter of
    ``kind`` 'length', 'angle' or 'number' (the plan knows each parameter's: ``plan.param_kind_of(name)``)."""
    if kind == "length":
        return 1.0 / LENGTH[units.length], units.length
    if kind == "angle":
        return 1.0 / ANGLE[units.angle], "°" if units.angle == "deg" else "rad"
    return 1.0, ""
