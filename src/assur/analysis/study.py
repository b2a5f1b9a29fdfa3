"""The Study: one solved working cycle of a mechanism and everything derived from it, computed once.

A :class:`Study` is to analysis what :class:`~assur.engine.State` is to kinematics: built once from a plan, its
parameters and a number of samples, read-only, with typed fields that are computed on first use and kept. Its
run is solved once, with order 2 (positions, velocities, accelerations and the analogues): one turn of a crank
(``steps`` inputs ``linspace(0, 2π, steps, endpoint=False)``), a linear driver's working stroke (endpoints
included), or the ``ranges`` given. Every other field reads that run; root searches (dead centres, gait extremes,
buildable edges) refine it with scalar solves through :meth:`Study.state_at`.

Every face (``assur analyze``, ``report``, ``plot``, ``animate``, ``forces``, the designer, the co-design
summary) builds one Study and reads its fields; :meth:`Study.as_dict` is the one JSON form (what ``assur analyze
--json`` prints). A new quantity is one field here and one formatter in its face.

Fields (None where they do not apply; SI units):

==================  ===============================================================================================
``structure``       the plan's :class:`~assur.structure.assur.Structure` (mobility, Assur groups)
``inputs``          (n, n_inputs) the run's inputs; ``moving`` the index of the input that moves; ``turn`` whether
                    the run is one full turn of the only input (the cycle the analyses below need)
``state``           the run's :class:`~assur.engine.State` (n,), order 2
``buildable``       :class:`Buildability`: buildable ranges with refined ends, unbuildable samples (a turn)
``transmission``    {solved point: μ (n,)} transmission angle of every closed-form dyad (planar)
``dead_centres``    [:class:`~assur.analysis.transmission.DeadCentre`] in the input's angle (a turn, planar)
``links``           per moving link its angle range, turns per input turn, largest |ω| and |α|
``output_link``     the output member: a rocker's swing or a slide's stroke, extremes and time ratio, or None
``four_bars``       every four-bar loop's Grashof class and inversion
``gait``            :class:`~assur.analysis.gait.GaitMetrics` of a walking leg; ``gait_curves``, ``gait_error``
``module``          :class:`~assur.analysis.gait.ModuleMetrics` of a walking module of several legs
``population_gait`` the sampled gait (no refinement: what a drag previews and synthesis optimises)
``actuators``       a linear driver's working-stroke summary (dict)
``spatial``         [:class:`~assur.analysis.spatial.DyadSummary`] of a spatial mechanism's R–S–S dyads
``instant_centres`` :class:`~assur.analysis.instant_centres.InstantCentres`: every relative instant centre over the
                    run (planar); ``centres_at(q)`` at other inputs; ``centrodes(a, b)``, ``inflection(body)``
``cams``            {pair: :class:`~assur.cams.geometry.CamGeometry`} of the file's cam pairs (profile, checks)
``sensitivity``     :class:`~assur.analysis.sensitivity.Sensitivity`: exact derivatives of every output over the
                    run with respect to every parameter (planar)
``forces``          :class:`~assur.kinetostatics.result.Forces` over the run (a file with masses or loads)
``force_cycle``     :class:`~assur.kinetostatics.overview.ForceCycle` (forces, drive summary, the module's gait
                    forces); ``force_summary`` its JSON form
``motor_run``       the run on the file's ``[motor]`` from rest to steady speed (:mod:`assur.dynamics`), or None
``parts``           the parts of ``assur make`` on the fewest certified layers (:mod:`assur.parts`)
==================  ===============================================================================================
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..errors import SpecError, StructureError, UnbuildableError
from .sampling import CYCLE_STEPS, Cycle

__all__ = ["Buildability", "Study", "Sweep"]


@dataclass(frozen=True)
class Buildability:
    """Where a turn assembles: ``ranges`` [(start, end)] (rad; ends refined to the toggle positions),
    ``unbuildable`` (samples of the turn that cannot be assembled) of ``steps``, and of those ``ambiguous``: samples
    the walks from the sketch reach on one assembly going forward and on another going back (the sketch's assembly
    does not close over a turn; ``State.ambiguous``)."""
    ranges: list
    unbuildable: int
    steps: int
    ambiguous: int = 0

    @property
    def full_rotation(self) -> bool:
        return self.unbuildable == 0

    @property
    def toggle_positions(self) -> list[float]:
        """The ends of the buildable ranges (rad), sorted; empty when the crank turns fully."""
        return [] if self.full_rotation else sorted({a for r in self.ranges for a in r})


@dataclass(frozen=True)
class Sweep:
    """A solved run of a plan as figures draw it: ``inputs (n, n_inputs)`` (SI), the ``state`` (n,), the x-axis
    values ``axis`` in display units (degrees for a crank, the file's length unit for an actuator) with its
    ``axis_label``, ``cyclic`` (one full turn, endpoint excluded) and ``moving`` (the input on the x axis)."""
    plan: object
    inputs: np.ndarray
    state: object
    axis: np.ndarray
    axis_label: str
    cyclic: bool
    moving: int

    @property
    def n(self) -> int:
        return len(self.inputs)

    @classmethod
    def of(cls, plan, inputs, state, moving: int, cyclic: bool) -> "Sweep":
        from ..io.units import LENGTH
        if plan.input_kinds[moving] == "rotary":
            axis, label = np.degrees(inputs[:, moving]), f"{plan.input_names[moving]} angle φ [°]"
        else:
            unit = plan.mechanism.units.length
            axis, label = inputs[:, moving] / LENGTH[unit], f"{plan.input_names[moving]} length [{unit}]"
        return cls(plan, inputs, state, axis, label, cyclic, moving)


class Study(Cycle):
    """One solved run of a plan at fixed parameters and the quantities derived from it (module docstring).

    plan: a compiled plan; params: (n_params,) (default the plan's defaults); steps: samples of the run;
    ranges: one (start, stop) pair per input (SI) instead of the natural cycle (a crank's turn, a linear driver's
    stroke). The run itself (``inputs``, ``state``, ``grid()``, ``state_at(q)``, ``frames(n)``) is the
    :class:`~assur.analysis.sampling.Cycle` it extends."""

    def __repr__(self) -> str:
        name = self.plan.mechanism.name or "mechanism"
        return f"Study({name!r}, {self.steps} samples{', ranges' if self.ranges else ''})"

    @cached_property
    def sweep(self) -> Sweep:
        """The run as a :class:`Sweep` for the figures (no new solve)."""
        return Sweep.of(self.plan, self.inputs, self.state, self.moving, self.cyclic)

    def frame_sweep(self, n: int) -> Sweep:
        """:meth:`frames` as a :class:`Sweep` (an animation's positions, a table's rows)."""
        inputs, state = self.frames(n)
        return Sweep.of(self.plan, inputs, state, self.moving, self.cyclic)

    # -- structure ----------------------------------------------------------------------------------------
    @property
    def structure(self):
        """The plan's Structure (decomposed once, when the plan was compiled)."""
        return self.plan.structure

    @cached_property
    def header(self) -> dict:
        """The JSON head of the summary: structure, parameters, inputs, samples (see :func:`.overview.summary_header`)."""
        from .overview import summary_header
        return summary_header(self.plan, self.params, self.steps, structure=self.structure)

    # -- the cycle analyses (one turn of a crank) ---------------------------------------------------------
    def _planar_turn(self) -> bool:
        return self.turn and self.plan.dimension == 2

    @cached_property
    def buildable(self) -> Buildability | None:
        """Buildable ranges and unbuildable samples of the turn (None without a turn)."""
        if not self.turn:
            return None
        from .transmission import buildable_ranges
        ranges, bad, steps = buildable_ranges(self)
        return Buildability(ranges, bad, steps, int(np.count_nonzero(self.grid()[1].ambiguous)))

    @cached_property
    def transmission(self) -> dict | None:
        """{solved point: μ (n,) rad} of every closed-form dyad over the run (planar)."""
        if self.plan.dimension != 2:
            return None
        from .transmission import transmission_angles
        return transmission_angles(self.plan, self.state, self.params)

    @cached_property
    def dead_centres(self) -> list:
        """The dead centres of every crank over the turn, in the input's angle (planar; [] otherwise)."""
        if not self._planar_turn():
            return []
        from .transmission import dead_centres
        return dead_centres(self)

    @cached_property
    def links(self) -> dict | None:
        """{link: :class:`~assur.analysis.links.LinkMotion`}: angle range, turns per input turn, largest |ω| and |α|
        (a turn)."""
        if not self.turn:
            return None
        from .links import link_motions
        return link_motions(self)

    @cached_property
    def output_link(self):
        """The :class:`~assur.analysis.links.OutputMember` (a rocker's swing or a slide's stroke, its extremes and
        the time ratio; a planar turn), or None."""
        if not self._planar_turn():
            return None
        from .links import output_link
        return output_link(self)

    @cached_property
    def four_bars(self) -> list:
        """The :class:`~assur.analysis.fourbar.FourBarLoop` of every four-bar loop (planar): Grashof class and
        inversion, from the design's lengths."""
        if self.plan.dimension != 2:
            return []
        from .fourbar import four_bar_loops
        return four_bar_loops(self.plan, self.params)

    @cached_property
    def _gait(self):
        """(metrics, curves, error) of the file's walking leg over the turn (None, None, None without a foot)."""
        if not self._planar_turn() or self.plan.mechanism.gait is None:
            return None, None, None
        from .gait import gait_metrics_and_curves
        try:
            gm, gc = gait_metrics_and_curves(self)
        except UnbuildableError as exc:
            return None, None, str(exc)
        return gm, gc, None

    @property
    def gait(self):
        """The :class:`~assur.analysis.gait.GaitMetrics` of the file's foot (exact: extremes and arc ends refined),
        None without a foot or when the crank cannot turn fully (then :attr:`gait_error` says why)."""
        return self._gait[0]

    @property
    def gait_curves(self):
        """The sampled gait curves over the turn (plots), None as :attr:`gait`."""
        return self._gait[1]

    @property
    def gait_error(self) -> str | None:
        """Why a walking leg has no gait (the crank cannot turn fully), else None."""
        return self._gait[2]

    @cached_property
    def module(self):
        """The :class:`~assur.analysis.gait.ModuleMetrics` of a walking module of several legs, else None."""
        g = self.plan.mechanism.gait
        if self.gait is None or len(g.phases) < 2:
            return None
        from .gait import module_metrics
        return module_metrics(self.gait, g.phases, self.steps)

    @cached_property
    def population_gait(self) -> dict | None:
        """The gait on the run's samples alone (no refinement), as synthesis evaluates it: ``step``, ``lift``,
        ``sag``, ``duty``, ``top``, ``speed_mean``, ``speed_spread``, ``vx_spread``, ``vx_spread_90`` (floats, NaN
        when a sample fails); None without a foot."""
        g = self.plan.mechanism.gait
        if not self._planar_turn() or g is None:
            return None
        from .gait import population_gait
        i = self.plan.point_index(g.foot)
        st = self.state
        pg = population_gait(st.pos[None, :, i], np.asarray(st.valid, dtype=bool)[None],
                             st.dpos_dq[None, :, i, :, 0], ground=g.ground, up=g.up_vector,
                             omega=abs(float(self.plan.speeds[0])))
        return {k: float(v[0]) for k, v in pg.items()}

    # -- other runs ---------------------------------------------------------------------------------------
    @cached_property
    def actuators(self) -> dict | None:
        """A linear driver's working-stroke summary (one linear input; see
        :func:`~assur.analysis.actuators.stroke_summary`), or ``{"note": …}`` when its stroke is unknown."""
        p = self.plan
        if p.dimension != 2 or p.n_inputs != 1 or p.input_kinds[0] == "rotary":
            return None
        from .actuators import stroke_summary
        try:
            return stroke_summary(p, self.params, steps=min(self.steps, CYCLE_STEPS))
        except SpecError as exc:
            return {"note": f"a linear input has no natural cycle ({exc}); use 'assur solve' with a stroke range"}

    @cached_property
    def spatial(self) -> list | None:
        """The R–S–S dyads' summaries of a spatial mechanism over the turn (None otherwise)."""
        if self.plan.dimension != 3 or not self.turn:
            return None
        from .spatial import dyad_summaries
        return dyad_summaries(self)

    # -- instant centres, centrodes, cams ---------------------------------------------------------------------
    @cached_property
    def instant_centres(self):
        """Every relative instant centre over the run (:class:`~.instant_centres.InstantCentres`, planar; else None)."""
        if self.plan.dimension != 2:
            return None
        from .instant_centres import instant_centres
        return instant_centres(self.plan, self.state)

    def centres_at(self, q):
        """The instant centres at inputs ``q (k,)`` of the moving input (a refinement solve)."""
        from .instant_centres import instant_centres
        return instant_centres(self.plan, self.state_at(np.atleast_1d(np.asarray(q, dtype=float))))

    def centrodes(self, moving, fixed="frame"):
        """The fixed and moving centrodes of body ``moving`` relative to ``fixed`` over the run
        (:class:`~.centrodes.Centrodes`; kept per pair)."""
        key = ("centrodes", moving, fixed)
        cache = self.__dict__.setdefault("_pairs", {})
        if key not in cache:
            from .centrodes import centrodes
            cache[key] = centrodes(self.plan, self.state, moving, fixed)
        return cache[key]

    def inflection(self, body):
        """The inflection circle of ``body`` relative to the frame over the run (:class:`~.centrodes.Inflection`)."""
        key = ("inflection", body)
        cache = self.__dict__.setdefault("_pairs", {})
        if key not in cache:
            from .centrodes import inflection_circle
            cache[key] = inflection_circle(self.plan, self.state, body)
        return cache[key]

    @cached_property
    def cams(self) -> dict:
        """{cam pair name: :class:`~assur.cams.geometry.CamGeometry`} at the study's parameters (the sketch as x = 0)."""
        from ..cams.followers import from_plan
        return {cp.name: from_plan(self.plan, k, self.params) for k, cp in enumerate(self.plan.mechanism.cams)}

    @cached_property
    def sensitivity(self):
        """Exact derivatives of every output over the run by every parameter
        (:class:`~assur.analysis.sensitivity.Sensitivity`, planar; else None)."""
        if self.plan.dimension != 2:
            return None
        from .sensitivity import sensitivity
        return sensitivity(self)

    # -- forces ----------------------------------------------------------------------------------------------
    @property
    def has_loads(self) -> bool:
        """Whether the file gives the force analysis something to carry (a mass, a load or a body weight)."""
        from ..kinetostatics.overview import has_loads
        return has_loads(self.plan.mechanism)

    @cached_property
    def forces(self):
        """The :class:`~assur.kinetostatics.result.Forces` over the run (the run's State; nothing solved again);
        StructureError with several drivers."""
        from ..kinetostatics.overview import cycle_forces
        return cycle_forces(self)

    @cached_property
    def force_cycle(self):
        """The forces over the run, the drive summary and a walking module's gait forces
        (:class:`~assur.kinetostatics.overview.ForceCycle`)."""
        from ..kinetostatics.overview import force_cycle
        return force_cycle(self, run_forces=self.forces)

    @cached_property
    def force_summary(self) -> dict:
        """The JSON form of :attr:`force_cycle`."""
        from ..kinetostatics.overview import force_summary
        return force_summary(self.force_cycle)

    # -- dynamics ------------------------------------------------------------------------------------------
    @cached_property
    def motor_run(self):
        """The run on the file's ``[motor]`` from rest to its periodic steady state, with the kinetostatic speed
        fluctuation beside it and the joints' reactions over time
        (:class:`~assur.dynamics.cycle.MotorRun`), reusing this Study's solved turn; None without a motor."""
        if self.plan.mechanism.motor is None or not self.turn:
            return None
        from ..dynamics.cycle import cycle_simulation
        return cycle_simulation(self)

    # -- parts ---------------------------------------------------------------------------------------------
    @cached_property
    def parts(self):
        """The parts of ``assur make`` with the file's ``[make]`` settings (:class:`~assur.parts.Parts`: plates,
        pins, the certified conflicts over this run and the fewest layers with their certificate), for a planar
        mechanism; SpecError for what cannot be made or stacked."""
        if self.plan.dimension != 2:
            raise SpecError([("dimension", "assur make builds planar mechanisms (dimension = 2)")])
        from ..parts import make_parts
        return make_parts(self)

    # -- the one dict --------------------------------------------------------------------------------------
    def as_dict(self, *, forces: bool | None = None) -> dict:
        """The JSON-ready summary (SI): what ``assur analyze --json`` prints (without its ``file``). ``forces``:
        include the force summary (default: when the file has masses or loads and one driver)."""
        from .summary import summary_dict
        out = summary_dict(self)
        if forces is None:
            forces = self.has_loads and self.plan.n_inputs == 1
        if forces:
            out["forces"] = self.force_summary
        return out

    def _repr_html_(self) -> str:
        from ..model.display import html_table
        return html_table("Study (SI)", self.as_dict(forces=False).items())


def as_turn_study(source, params=None, steps: int = CYCLE_STEPS) -> Study:
    """The Study of ``source`` (a Study, or a plan at ``params`` and ``steps``) for an analysis of one crank turn:
    StructureError unless the plan has one input."""
    study = Study.of(source, params, steps)
    if study.plan.n_inputs != 1:
        raise StructureError(f"this analysis needs one input; the mechanism has {study.plan.n_inputs} "
                             f"({', '.join(study.plan.input_names)})")
    return study

