"""Non-circular gear pairs: transmission laws, pitch curves, the paper-001 sector method, design files.

Public names: :func:`pitch_pair`, :class:`PitchCurve`, :class:`PitchPair` (pitch.py); the laws
:class:`WheelStepLaw`, :func:`law_from_callable`, :func:`law_from_table`, :func:`law_from_ratio` (law.py);
:class:`GearError` (:mod:`assur.errors`). Sector model, Tables 1–3 and the paper's tooth outlines:
:mod:`assur.gears.sectors`; the wheel-step mover's shoe: :mod:`assur.gears.wheelstep`; a design's data:
:mod:`assur.gears.design` (its files are read by :mod:`assur.io.gear_file`). Gear geometry only: designing a
mechanism and its gears together is :mod:`assur.codesign`'s.
"""
from ..errors import GearError
from .law import (TransmissionLaw, WheelStepLaw, law_from_callable, law_from_ratio, law_from_table)
from .pitch import (ClosureReport, Corner, CurvatureReport, PitchCurve, PitchPair, check_module, closure_report,
                    curvature_report, find_corners, pitch_pair, speed_law)

__all__ = ["GearError", "TransmissionLaw", "WheelStepLaw", "law_from_callable", "law_from_ratio", "law_from_table",
           "ClosureReport", "Corner", "CurvatureReport", "PitchCurve", "PitchPair", "check_module", "closure_report",
           "curvature_report", "find_corners", "pitch_pair", "speed_law"]


def __getattr__(name: str):
    """``GearPair``: the deprecated name of :class:`PitchPair` (warns with a DeprecationWarning)."""
    if name == "GearPair":
        import warnings
        warnings.warn("assur.gears.GearPair is deprecated: use PitchPair (a pair of pitch curves; GearPair names a "
                      "mechanism's gear pair, assur.model.gearing.GearPair)", DeprecationWarning, stacklevel=2)
        return PitchPair
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
