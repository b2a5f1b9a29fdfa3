"""The sizes, material and fits of the parts: a mechanism's ``[make]`` table with its defaults filled in (SI).

The defaults follow the process and the mechanism's size S (its sketch's bounding box):

- pin: the largest ISO 8734 dowel of at most S/60, at least 3 mm and at most 12 mm, and at most a quarter of the
  shortest distance between two joints of one link (two holes of one plate keep their walls);
- width (the boss diameter and bar width): 2.5 × the pin, rounded up to a millimetre;
- thickness: half the pin rounded up to a standard sheet (2, 3, 4, 5, 6, 8, 10, 12 mm), at least the process's
  minimum (FDM 3 mm, laser-cut 3 mm, machined 4 mm);
- washer: the DIN 125-A washer of the pin (its thickness is the gap between two layers, its outer diameter the
  spacer sleeve's that a pin carries through the layers it crosses);
- clearance, material, density, hole and shaft allowances: by process (:data:`PROCESS_DEFAULTS`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..errors import SpecError
from ..model.making import DOWEL_SERIES, PROCESSES, MakeSpec

#: per process: material, density (kg/m³), least plate thickness, clearance, hole allowance, shaft allowance (m)
PROCESS_DEFAULTS = {
    "fdm": dict(material="PLA", density=1240.0, min_thickness=0.003, clearance=0.001,
                hole_allowance=0.0003, shaft_allowance=-0.0001),
    "laser-cut": dict(material="acrylic (PMMA)", density=1190.0, min_thickness=0.003, clearance=0.0005,
                      hole_allowance=0.0001, shaft_allowance=0.0),
    "machined": dict(material="aluminium 6061-T6", density=2700.0, min_thickness=0.004, clearance=0.0005,
                     hole_allowance=0.00003, shaft_allowance=0.0),
}
#: DIN 125-A washers: pin diameter (m) → (thickness, outer diameter) (m)
WASHERS = {0.001: (0.0003, 0.0025), 0.0015: (0.0003, 0.0035), 0.002: (0.0003, 0.005), 0.0025: (0.0005, 0.006),
           0.003: (0.0005, 0.007), 0.004: (0.0008, 0.009), 0.005: (0.001, 0.010), 0.006: (0.0016, 0.012),
           0.008: (0.0016, 0.016), 0.010: (0.002, 0.020), 0.012: (0.0025, 0.024), 0.016: (0.003, 0.030),
           0.020: (0.003, 0.037)}
#: standard sheet thicknesses (m) the default plate thickness is rounded up to
SHEETS = (0.002, 0.003, 0.004, 0.005, 0.006, 0.008, 0.010, 0.012)
#: density of the steel dowel pins (kg/m³)
STEEL_DENSITY = 7850.0
#: a NEMA 17 motor: shaft diameter, flange size, bolt-circle square side, pilot diameter, bolt hole (m)
NEMA17 = dict(shaft=0.005, flange=0.0423, bolts=0.031, pilot=0.022, bolt_hole=0.0034)


@dataclass(frozen=True, slots=True)
class Settings:
    """Every size of the parts (SI: m, kg/m³). ``given``: the ``[make]`` keys the file (or the command line) set;
    the others are defaults."""
    process: str
    thickness: float
    width: float
    pin: float
    washer: float
    washer_od: float
    clearance: float
    material: str
    density: float
    hole_allowance: float
    shaft_allowance: float
    base_thickness: float
    shaft: float
    given: tuple[str, ...] = ()

    @property
    def pitch(self) -> float:
        """The height of one layer: a plate and the washer gap above it (m)."""
        return self.thickness + self.washer

    @property
    def boss(self) -> float:
        """The radius of a joint boss (half the width), m."""
        return 0.5 * self.width

    @property
    def sleeve(self) -> float:
        """The radius of what a pin carries through a layer it crosses (the washer's, m)."""
        return 0.5 * self.washer_od

    @property
    def shaft_flat(self) -> float:
        """Across the flat of the motor's D-shaft (m): 0.9 of its diameter (a NEMA 17's 5 mm shaft: 4.5 mm)."""
        return 0.9 * self.shaft

    @property
    def shaft_flat_distance(self) -> float:
        """The distance of the D-shaft's flat from its axis (m): across the flat less the radius."""
        return self.shaft_flat - 0.5 * self.shaft

    @property
    def slide_fit(self) -> float:
        """The diametral play of a block in its slot (m): the hole allowance, at least 0.05 mm."""
        return max(self.hole_allowance, 5e-5)

    def as_dict(self) -> dict:
        """The settings as a JSON-ready dict (SI)."""
        return {k: getattr(self, k) for k in self.__slots__}


def _largest_at_most(series, value):
    fit = [d for d in series if d <= value * (1 + 1e-12)]
    return fit[-1] if fit else series[0]


def default_pin(size: float, shortest: float) -> float:
    """The default dowel diameter (m) of a mechanism of size ``size`` whose links' joints are at least
    ``shortest`` apart (m)."""
    want = min(max(size / 60.0, 0.003), 0.012, max(shortest / 4.0, DOWEL_SERIES[0]))
    return _largest_at_most(DOWEL_SERIES, want)


def resolve(spec: MakeSpec | None, *, size: float, shortest: float, clearance: float | None = None,
            process: str | None = None) -> Settings:
    """The settings of a mechanism of size ``size`` (m; its sketch's bounding box) whose joints on one link are
    at least ``shortest`` apart (m): the file's ``[make]`` (``spec``, None: all defaults) with ``clearance`` and
    ``process`` from the command line taking precedence. SpecError for a command-line value out of range."""
    spec = spec or MakeSpec()
    given = set(spec.given())
    if process is not None:
        if process not in PROCESSES:
            raise SpecError([("--process", f"must be one of {', '.join(PROCESSES)}: {process!r}")])
        spec = replace(spec, process=process)
        given.add("process")
    if clearance is not None:
        if not (math.isfinite(clearance) and clearance > 0):
            raise SpecError([("--clearance", f"must be a positive length: {clearance!r}")])
        spec = replace(spec, clearance=clearance)
        given.add("clearance")
    proc = spec.process or "fdm"
    d = PROCESS_DEFAULTS[proc]
    pin = spec.pin or default_pin(size, shortest)
    width = spec.width or math.ceil(2.5 * pin * 1e3 - 1e-9) * 1e-3
    thickness = spec.thickness or max(d["min_thickness"], _smallest_at_least(SHEETS, 0.5 * pin))
    washer_t, washer_od = WASHERS[pin] if pin in WASHERS else (0.2 * pin, 2.0 * pin)
    washer = spec.washer or washer_t
    out = Settings(process=proc, thickness=thickness, width=width, pin=pin, washer=washer,
                   washer_od=min(washer_od, width), clearance=spec.clearance or d["clearance"],
                   material=spec.material or d["material"], density=spec.density or d["density"],
                   hole_allowance=d["hole_allowance"] if spec.hole_allowance is None else spec.hole_allowance,
                   shaft_allowance=d["shaft_allowance"] if spec.shaft_allowance is None else spec.shaft_allowance,
                   base_thickness=spec.base_thickness or max(thickness, 0.006),
                   shaft=spec.shaft or NEMA17["shaft"], given=tuple(sorted(given)))
    _check(out)
    return out


def _smallest_at_least(series, value):
    fit = [d for d in series if d >= value * (1 - 1e-12)]
    return fit[0] if fit else series[-1]


def _check(s: Settings) -> None:
    """SpecError naming the ``[make]`` keys whose values (given or defaulted) do not fit together."""
    problems = []
    if s.width < 1.5 * s.pin:
        problems.append(("make.width", f"{s.width * 1e3:g} mm leaves too little wall around the "
                                       f"⌀{s.pin * 1e3:g} mm pin (at least {1.5 * s.pin * 1e3:g} mm)"))
    if s.width < 1.2 * s.shaft:
        problems.append(("make.shaft", f"a ⌀{s.shaft * 1e3:g} mm motor shaft does not fit a "
                                       f"{s.width * 1e3:g} mm wide crank"))
    if s.washer > s.thickness:
        problems.append(("make.washer", f"{s.washer * 1e3:g} mm is thicker than the {s.thickness * 1e3:g} mm "
                                        f"plates"))
    if s.clearance > s.width:
        problems.append(("make.clearance", f"{s.clearance * 1e3:g} mm is wider than the {s.width * 1e3:g} mm "
                                           f"bars"))
    if problems:
        raise SpecError(problems)


__all__ = ["NEMA17", "PROCESS_DEFAULTS", "STEEL_DENSITY", "Settings", "WASHERS", "default_pin", "resolve"]
