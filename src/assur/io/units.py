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

_SPEED_RE = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z/0-9]+)\s*$")


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
    if isinstance(text, bool):
        raise SpecError(f"must be a number or a string like '27 rpm': {text!r}")
    if isinstance(text, (int, float)):
        base = ANGLE[units.angle] if kind == "rotary" else LENGTH[units.length]
        return _finite_speed(float(text) * base, text)
    if not isinstance(text, str):
        raise SpecError(f"must be a number or a string like '27 rpm': {text!r}")
    m = _SPEED_RE.match(text)
    if not m or m.group(2) not in table:
        raise SpecError(f"must be '<number> <unit>' with unit one of {', '.join(table)}: {text!r}")
    return _finite_speed(float(m.group(1)) * table[m.group(2)], text)


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
