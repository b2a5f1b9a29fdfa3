"""Co-design of a mechanism and the non-circular gear pair that drives it (layer 3; docs/codesign.md).

A walking leg whose foot moves at an exactly constant horizontal speed over the central part of its stride, and
paper 001's wheel-step mover whose gears lose their corners, share one law (a window where the ratio follows the
mechanism, a C² transfer that closes the turn), one set of gear checks and one transfer search:

- :mod:`~assur.codesign.law`: the leg's foot law x(q), the window, the transfer basis and :class:`CodesignLaw`;
- :mod:`~assur.codesign.checks`: :class:`GearChecks` and :func:`gear_checks` (convexity, centrode pressure angle,
  ratio range, undercut, tooth counts) of either co-design;
- :mod:`~assur.codesign.margins`: the same checks as fast margins on fixed samples, and the search's objective;
- :mod:`~assur.codesign.transfer`: the leg's transfer search (:func:`optimize_transfer`, :func:`codesign`,
  :func:`tradeoff`); :mod:`~assur.codesign.joint`: the leg's dimensions and its law together
  (:func:`optimize_codesign`); :mod:`~assur.codesign.screen`: a necessary condition on the leg alone, and
  :mod:`~assur.codesign.widest`: the widest window it allows and what stops the target one;
- :mod:`~assur.codesign.torque`: the motor torque the drive asks for, its limit, the before/after cost;
- :mod:`~assur.codesign.wheelstep_law` and :mod:`~assur.codesign.wheelstep`: the wheel-step drive redesigned.

Gear geometry (laws, pitch curves, teeth, mesh, design files) is :mod:`assur.gears`'s; the faces are
``assur codesign`` (:mod:`assur.cli.codesign`), its files (:mod:`assur.report.codesign`) and ``assur wheelstep``.
"""
from .checks import GearChecks, gear_checks
from .joint import JointDesign, optimize_codesign
from .law import CodesignLaw, FootLaw, foot_law, geared_vx_spread
from .screen import critical_fraction, window_screen
from .torque import drive_cost, peak_torque
from .transfer import (CodesignProblem, CodesignResult, TransferDesign, codesign, optimize_transfer, tradeoff,
                       window_pressure_bound)
from .wheelstep import WheelStepCodesign, paper_pair, wheelstep_codesign
from .widest import WidestWindow, widest_window

__all__ = ["CodesignLaw", "CodesignProblem", "CodesignResult", "FootLaw", "GearChecks", "JointDesign",
           "TransferDesign", "WheelStepCodesign", "WidestWindow", "codesign", "critical_fraction", "drive_cost", "foot_law",
           "gear_checks", "geared_vx_spread", "optimize_codesign", "optimize_transfer", "paper_pair",
           "peak_torque", "tradeoff", "wheelstep_codesign", "widest_window", "window_pressure_bound", "window_screen"]
