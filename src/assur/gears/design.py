"""A non-circular gear pair as designed (:class:`GearDesign`) and a wheel-step mover with its drive
(:class:`WheelStepDesign`): frozen dataclasses in SI (m, rad) and their geometry (pitch curves, the paper's
sector model and tooth outlines).

Reading their files (``format = "assur-gears/1"`` and ``"assur-wheelstep/1"``, units at the boundary, every
problem located) is :mod:`assur.io.gear_file`'s; the fields are documented there and in docs/gears.md.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import GearError
from ..tolerances import DEFAULT as TOL
from .law import TransmissionLaw
from .pitch import PitchPair, pitch_pair
from .wheelstep import Shoe

#: relative mismatch allowed between the driving pitch perimeter and z·π·m in envelope mode
PERIMETER_TOLERANCE = TOL.tooth_perimeter
#: sectors method: one tooth per sector, so the circular pitch π·m must match the sector arc s within this fraction
#: (the paper's design: s = 6.2123 mm against π·2 mm = 6.2832 mm, 1.1 % apart)
SECTOR_PITCH_TOLERANCE = 0.10


@dataclass(frozen=True, slots=True)
class GearDesign:
    """A non-circular gear pair as designed (SI: m, rad). ``law`` is the transmission law; ``law_spec`` the law
    table as read (for records). See :mod:`assur.io.gear_file` for the meaning of each field."""
    name: str
    law: TransmissionLaw
    law_spec: dict
    centre_distance: float
    installation_distance: float
    method: str
    module: float
    pressure_angle: float
    backlash: float
    driving_teeth: int
    driven_teeth: int
    sectors: int | None
    addendum: float
    dedendum: float
    clearance: float
    face_width: float | None = None
    bore: float | None = None
    tip_radius: float = 0.0
    profile_shift: float = 0.0
    print_clearance: float = 0.0
    units: tuple = ("mm", "deg")
    description: str = ""
    source: str | None = None
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    @property
    def driving_turns(self) -> int:
        return self.law.driving_turns

    def pair(self, samples: int = 2048) -> PitchPair:
        """The exact pitch curves at the design centre distance (cached per ``samples``)."""
        key = ("pair", samples)
        if key not in self._cache:
            self._cache[key] = pitch_pair(self.law, self.centre_distance, samples=samples)
        return self._cache[key]

    def sector_model(self):
        """The paper's sector model (method "sectors", wheelstep law): one hub step in ``sectors`` sectors."""
        from .sectors import paper_sector_model
        if self.sectors is None:
            raise GearError("this design has no sector scheme (teeth.method = 'envelope')")
        key = "sectors"
        if key not in self._cache:
            self._cache[key] = paper_sector_model(self.law, self.centre_distance, sectors=self.sectors)
        return self._cache[key]


    def sector_outline(self, linking: str = "relieved"):
        """Closed outlines of the paper's tooth scheme (:func:`assur.gears.sectors.sector_outline`), body frames of
        :mod:`assur.gears.pitch`, m."""
        from .sectors import sector_outline
        return sector_outline(self.sector_model(), self.module, self.backlash, linking=linking,
                              dedendum=self.dedendum)


@dataclass(frozen=True, slots=True)
class WheelStepDesign:
    """A wheel-step mover: the shoe geometry and, optionally, its non-circular gear drive."""
    name: str
    shoe: Shoe
    gears: GearDesign | None
    units: tuple = ("m", "deg")
    description: str = ""
    source: str | None = None

    def pair(self, samples: int = 2048) -> PitchPair:
        if self.gears is None:
            raise GearError("this wheel-step design has no [drive] gears file")
        return self.gears.pair(samples)


__all__ = ["GearDesign", "PERIMETER_TOLERANCE", "SECTOR_PITCH_TOLERANCE", "WheelStepDesign"]
