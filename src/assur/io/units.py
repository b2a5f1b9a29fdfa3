"""Unit conversion at the file boundary. Inside the toolkit: m, rad, s."""
from __future__ import annotations

import math
import re

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

    Raises ``ValueError`` with the accepted units on a bad value.
    """
    table = ANGULAR_SPEED if kind == "rotary" else linear_speed_units()
    if isinstance(text, bool):
        raise ValueError(f"must be a number or a string like '27 rpm': {text!r}")
    if isinstance(text, (int, float)):
        base = ANGLE[units.angle] if kind == "rotary" else LENGTH[units.length]
        return float(text) * base
    if not isinstance(text, str):
        raise ValueError(f"must be a number or a string like '27 rpm': {text!r}")
    m = _SPEED_RE.match(text)
    if not m or m.group(2) not in table:
        raise ValueError(f"must be '<number> <unit>' with unit one of {', '.join(table)}: {text!r}")
    return float(m.group(1)) * table[m.group(2)]


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


#: parameter-name endings by kind (planar and spatial plans; see docs/format.md, Parameters)
LENGTH_PARAMS = (".x", ".y", ".z", ".length", ".distance", ".offset", ".axial", ".u", ".v", ".w")
ANGLE_PARAMS = (".angle", ".zero", ".gamma1", ".gamma2")


def param_kind(name: str) -> str:
    """'length', 'angle' or 'number' for a parameter name such as ``crank.length`` or ``slide.angle``."""
    if name.endswith(LENGTH_PARAMS):
        return "length"
    if name.endswith(ANGLE_PARAMS):
        return "angle"
    return "number"


def param_unit(name: str, units) -> tuple[float, str]:
    """(factor SI → the file's unit, unit label: the length unit, '°' or 'rad', or '') of a parameter."""
    kind = param_kind(name)
    if kind == "length":
        return 1.0 / LENGTH[units.length], units.length
    if kind == "angle":
        return 1.0 / ANGLE[units.angle], "°" if units.angle == "deg" else "rad"
    return 1.0, ""
