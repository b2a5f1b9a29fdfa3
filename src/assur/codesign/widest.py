"""The widest constant-speed window a walking leg can have, judged on the leg alone (docs/codesign.md, "The widest
window in the atlas"): the key by which the atlas's walking legs are ranked for a co-designed gear drive.

:func:`widest_window` combines the two necessary conditions of :mod:`assur.codesign.screen` and
:func:`~assur.codesign.transfer.window_pressure_bound` into one summary of a leg's foot law:

- ``window``: the widest window fraction f the leg passes :func:`~assur.codesign.screen.window_screen` at
  (:func:`~assur.codesign.screen.critical_fraction`); a gear pair passing every check with that window may exist,
  none exists with a wider one;
- at a ``target`` fraction (the co-design's goal, 0.9): the screen there (its slack and the margin that sets it), and
  the window's pressure-angle bound (rad): whatever k and the transfer, the pitch curves' centrode pressure angle
  inside the window reaches it. A bound above the allowed pressure angle stops that window on its own.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import SpecError
from .law import FootLaw
from .screen import WindowScreen, critical_fraction, window_screen
from .transfer import window_pressure_bound

__all__ = ["WidestWindow", "widest_window"]

#: the window fraction the co-design aims at (the issue's goal: constant speed over the central 90 % of the stride)
TARGET = 0.9
#: the narrowest window the search looks at; a leg failing the screen there has ``window`` None
LOWEST = 0.5


@dataclass(frozen=True)
class WidestWindow:
    """A leg's widest screened window and what stops it at ``target``.

    ``window``: the widest fraction passing the screen (within ``tolerance``), None when even :data:`LOWEST` fails;
    ``at_window``: the screen there (None with ``window``); ``at_target``: the screen at ``target`` (None when the
    window does not exist there: x not monotone over it); ``pressure_bound``: the window's pressure-angle bound at
    ``target`` (rad, None likewise); ``max_pressure_angle`` (rad): the checks' limit."""
    window: float | None
    at_window: WindowScreen | None
    target: float
    at_target: WindowScreen | None
    pressure_bound: float | None
    max_pressure_angle: float
    tolerance: float

    @property
    def stopped_by_pressure(self) -> bool:
        """True when the window's own pressure-angle bound at ``target`` exceeds the limit: no k, no transfer
        reaches the target window."""
        return self.pressure_bound is not None and self.pressure_bound > self.max_pressure_angle

    def as_dict(self) -> dict:
        """Plain data (degrees for angles): ``window``, ``window_k``, ``target``, ``target_slack``,
        ``target_worst`` (the margin that sets the slack), ``pressure_bound_deg``, ``stopped_by_pressure``."""
        t = self.at_target
        return {"window": self.window, "window_k": None if self.at_window is None else self.at_window.k,
                "target": self.target, "target_slack": None if t is None else t.slack,
                "target_worst": None if t is None else t.worst,
                "pressure_bound_deg": None if self.pressure_bound is None else math.degrees(self.pressure_bound),
                "stopped_by_pressure": self.stopped_by_pressure}


def widest_window(foot: FootLaw, *, target: float = TARGET, max_pressure_angle: float = math.radians(30.0),
                  tolerance: float = 1e-3, **options) -> WidestWindow:
    """The leg's :class:`WidestWindow`: the widest window passing the screen in [:data:`LOWEST`, 0.99] (bisection to
    ``tolerance``), the screen and the pressure-angle bound at ``target``; ``options`` go to the screen
    (:func:`~assur.codesign.screen.window_screen`: ratio bounds, driving turns, sampling)."""
    screen = dict(options, max_pressure_angle=max_pressure_angle)
    window = critical_fraction(foot, low=LOWEST, tol=tolerance, **screen)
    at_window = _screen(foot, window, screen)
    if at_window is None or not at_window.feasible:
        window, at_window = None, None
    at_target = _screen(foot, target, screen)
    try:
        bound = window_pressure_bound(foot, target, driving_turns=int(options.get("driving_turns", 1)))
    except SpecError:
        bound = None
    return WidestWindow(window, at_window, float(target), at_target, bound, float(max_pressure_angle),
                        float(tolerance))


def _screen(foot: FootLaw, fraction: float, options: dict) -> WindowScreen | None:
    try:
        return window_screen(foot, fraction, **options)
    except SpecError:                     # the window does not exist there
        return None
