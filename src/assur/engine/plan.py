"""The compiled solve plan: frozen, design-independent, shared by a whole population.

A plan holds the Assur-group order as a table of typed step records, the branch signs fixed from
the sketch, the parameter map (names, kinds and sketch defaults) and name tables. It holds no
numbers that a design changes: those come in ``params (..., n_params)`` at solve time.

Flat, read-only arrays (as in MuJoCo's ``mjmodel.h``; ``-1`` pads unused slots)::

    step_kind   (n_steps,)     int8   index into STEP_KINDS
    step_in     (n_steps, 3)   int32  the known points a step reads (point indices)
    step_out    (n_steps,)     int32  the point a branched step solves (its key point), or -1
    step_param  (n_steps, 3)   int32  the parameters a step reads directly (input zero, lengths)
    branch      (n_steps,)     int8   assembly branch sign ±1 (1 for unbranched steps)
    param_kind  (n_params,)    int8   index into PARAM_KINDS: length, angle or number

Caches never live on a plan: backends keep theirs in ``weakref.WeakKeyDictionary`` objects keyed
by the plan (plans compare and hash by identity).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import ClassVar

import numpy as np

from ..errors import ArgumentTypeError, SpecError, UnknownNameError
from ..model.mechanism import Mechanism, require_mechanism  # noqa: F401 - re-exported for the engine
from ..structure.assur import Structure

#: step kinds; the position in this tuple is the integer code in ``plan.step_kind``
STEP_KINDS = ("frame", "crank", "RRR", "RRP", "RPR", "PRP", "PPR", "newton", "RSS", "gear", "cam", "cam_slide")
#: parameter kinds; the position in this tuple is the integer code in ``plan.param_kind``
PARAM_KINDS = ("length", "angle", "number")
#: planar dyads with two assemblies (a sign chosen once at compile time)
BRANCHED = ("RRR", "RRP", "RPR")


# -- step records --------------------------------------------------------------------------------------
@dataclass(frozen=True, slots=True)
class Side:
    """One side of a dyad: a body, or a driven actuator (cylinder + rod of input length).

    ``actuator``: (cylinder body, rod body, input index) of a driven actuator, else None.
    """
    body: int
    actuator: tuple[int, int, int] | None = None


class StepRecord:
    """Common interface of the step records: ``kind``, ``bodies`` (the bodies the step places),
    ``key_point`` (the point a branch refers to, or None) and ``branch`` (±1). Each record names, as class
    constants, the field holding its key point and the fields of the known points and parameters it reads."""
    __slots__ = ()
    kind: ClassVar[str] = ""
    key_field: ClassVar[str | None] = None
    point_fields: ClassVar[tuple[str, ...]] = ()
    param_fields: ClassVar[tuple[str, ...]] = ()
    branch: int = 1

    @property
    def key_point(self) -> str | None:
        return None if self.key_field is None else getattr(self, self.key_field)

    def points_in(self) -> tuple[str, ...]:
        """The already known points the step reads."""
        return tuple(getattr(self, f) for f in self.point_fields)

    def params_in(self) -> tuple[int, ...]:
        """The parameter indices the step reads directly."""
        return tuple(getattr(self, f) for f in self.param_fields)

    def with_branch(self, sign: int) -> "StepRecord":
        return replace(self, branch=int(sign))


@dataclass(frozen=True, slots=True)
class FrameStep(StepRecord):
    """Place the frame (body 0) and its points."""
    kind: ClassVar[str] = "frame"
    bodies: tuple[int, ...] = (0,)


@dataclass(frozen=True, slots=True)
class CrankStep(StepRecord):
    """A link turning about a frame pivot: θ = sense·q[input] + params[zero_param]."""
    kind: ClassVar[str] = "crank"
    point_fields: ClassVar[tuple[str, ...]] = ("pivot",)
    param_fields: ClassVar[tuple[str, ...]] = ("zero_param",)
    bodies: tuple[int, ...]
    pivot: str
    arm: str
    input: int
    zero_param: int
    sense: int


@dataclass(frozen=True, slots=True)
class GearStep(CrankStep):
    """A link turning about a frame pivot, driven through a gear pair: a crank step (sense 1) whose ``input``
    indexes the plan's gear slots after its inputs (the driven link's rotation from the sketch, a jet in the inputs:
    :class:`GearSlot`); ``gear`` indexes ``mechanism.gears``."""
    kind: ClassVar[str] = "gear"
    gear: int = 0


@dataclass(frozen=True, slots=True)
class GearSlot:
    """How a gear pair's driven rotation follows from the inputs: its driving link's rotation from the sketch is
    x = ``sense``·(q[source] − ``sketch``) (``source`` an input, or an earlier slot at ``n_inputs + j`` with sense 1
    and sketch 0), and the driven link's is ``gear.relative(x)``. ``gear`` indexes ``mechanism.gears``."""
    gear: int
    source: int
    sense: float
    sketch: float


@dataclass(frozen=True, slots=True)
class CamStep(CrankStep):
    """An oscillating follower driven by a cam: a crank step (sense 1) about the follower's frame pivot whose
    ``input`` indexes the plan's slots (inputs, gear slots, then cam slots: :class:`CamSlot`); ``cam`` indexes
    ``mechanism.cams``."""
    kind: ClassVar[str] = "cam"
    cam: int = 0


@dataclass(frozen=True, slots=True)
class CamSlideStep(StepRecord):
    """A translating follower driven by a cam: the follower ``bodies[0]`` slides on the frame line ``line`` (index
    into ``plan.lines``) without turning, its reference point at ``params[start_param] + slot`` along the line from
    the line's point (``input`` indexes the plan's slots, as for :class:`CamStep`); ``cam`` indexes
    ``mechanism.cams``."""
    kind: ClassVar[str] = "cam_slide"
    param_fields: ClassVar[tuple[str, ...]] = ("start_param",)
    bodies: tuple[int, ...]
    line: int
    input: int
    start_param: int
    cam: int = 0


@dataclass(frozen=True, slots=True)
class CamSlot:
    """How a cam pair's follower motion follows from the inputs: the cam's rotation from the sketch is
    x = ``sense``·(q[source] − ``sketch``) (``source`` an input, or an earlier slot with sense 1 and sketch 0), and
    the follower's move from the sketch is ``lift_sign``·``cam.relative(x)`` (m along its slide, or rad about its
    pivot). ``cam`` indexes ``mechanism.cams``."""
    cam: int
    source: int
    sense: float
    sketch: float
    lift_sign: float


@dataclass(frozen=True, slots=True)
class RRRStep(StepRecord):
    """Two sides hinged at known points A, B and to each other at the joint J (circle ∩ circle)."""
    kind: ClassVar[str] = "RRR"
    key_field: ClassVar[str | None] = "joint"
    point_fields: ClassVar[tuple[str, ...]] = ("point_a", "point_b")
    bodies: tuple[int, ...]
    side_a: Side
    point_a: str
    side_b: Side
    point_b: str
    joint: str
    branch: int = 1


@dataclass(frozen=True, slots=True)
class RRPStep(StepRecord):
    """A side hinged at the known point A and a slider on a known guide line, hinged at J
    (circle ∩ line). ``line``: index into ``plan.lines``."""
    kind: ClassVar[str] = "RRP"
    key_field: ClassVar[str | None] = "joint"
    point_fields: ClassVar[tuple[str, ...]] = ("point_a",)
    bodies: tuple[int, ...]
    side_a: Side
    point_a: str
    slider: int
    line: int
    joint: str
    branch: int = 1


@dataclass(frozen=True, slots=True)
class RPRStep(StepRecord):
    """A guide hinged at a known point and a slider hinged at another, sliding on each other."""
    kind: ClassVar[str] = "RPR"
    key_field: ClassVar[str | None] = "slider_point"
    point_fields: ClassVar[tuple[str, ...]] = ("guide_point", "slider_point")
    bodies: tuple[int, ...]
    guide: int
    guide_point: str
    slider: int
    slider_point: str
    line: int
    branch: int = 1


@dataclass(frozen=True, slots=True)
class PRPStep(StepRecord):
    """Two bodies sliding on known lines, hinged to each other at J (line ∩ line)."""
    kind: ClassVar[str] = "PRP"
    key_field: ClassVar[str | None] = "joint"
    bodies: tuple[int, ...]
    body_a: int
    line_a: int
    body_b: int
    line_b: int
    joint: str


@dataclass(frozen=True, slots=True)
class PPRStep(StepRecord):
    """Body a hinged at the known point A, body b sliding on a known line (``outer_line``), a and b
    sliding on each other (``inner_line``)."""
    kind: ClassVar[str] = "PPR"
    key_field: ClassVar[str | None] = "point_a"
    point_fields: ClassVar[tuple[str, ...]] = ("point_a",)
    bodies: tuple[int, ...]
    body_a: int
    point_a: str
    body_b: int
    outer_line: int
    inner_line: int


@dataclass(frozen=True, slots=True)
class NewtonStep(StepRecord):
    """A group without a closed form (a triad or higher), solved by batched Newton iterations."""
    kind: ClassVar[str] = "newton"
    bodies: tuple[int, ...]
    group: object          # the structure's AssurGroup


#: a frame point of a spatial plan: (point, x, y, z parameter indices)
@dataclass(frozen=True, slots=True)
class SpatialFrameStep(StepRecord):
    """Place the frame's points from their (x, y, z) parameters."""
    kind: ClassVar[str] = "frame"
    points: tuple[tuple[str, int, int, int], ...]
    bodies: tuple[int, ...] = (0,)

    @property
    def body(self):
        return 0


@dataclass(frozen=True, slots=True)
class SpatialCrankStep(StepRecord):
    """A link turning about a frame revolute at ``pivot`` (axis from ``pivot.axis.gamma1/2``).

    ``extra``: further points of the link, (point, u, v, w parameter indices) in its hinge frame."""
    kind: ClassVar[str] = "crank"
    point_fields: ClassVar[tuple[str, ...]] = ("pivot",)
    param_fields: ClassVar[tuple[str, ...]] = ("zero_param", "length_param", "axial_param")
    body: int
    pivot: str
    arm: str
    input: int
    length_param: int
    axial_param: int
    zero_param: int
    sense: int
    extra: tuple = ()

    @property
    def bodies(self):
        return (self.body,)


@dataclass(frozen=True, slots=True)
class RSSStep(StepRecord):
    """An R–S–S dyad: the rocker ``body`` hinged on the frame revolute D, the coupler from the known
    point A; B on the branch s = sign det[A − D, e, B − D]."""
    kind: ClassVar[str] = "RSS"
    key_field: ClassVar[str | None] = "joint"
    point_fields: ClassVar[tuple[str, ...]] = ("pivot", "start")
    param_fields: ClassVar[tuple[str, ...]] = ("rocker_length_param", "rocker_axial_param", "coupler_length_param")
    body: int
    pivot: str          # D
    start: str          # A
    joint: str          # B
    coupler: int
    rocker_length_param: int
    rocker_axial_param: int
    coupler_length_param: int
    rocker_extra: tuple = ()
    coupler_extra: tuple = ()
    branch: int = 1
    #: (V1 × e)_X and |V1| at the sketch input, V1 = A − D: the paper's W = s·sign((V1 × e)_X)
    sketch_v3x: float = float("nan")
    sketch_v1_norm: float = float("nan")


    @property
    def bodies(self):
        return (self.body, self.coupler)




def _readonly(a, dtype) -> np.ndarray:
    a = np.array(a, dtype=dtype)
    a.setflags(write=False)
    return a


def _padded(rows, width: int) -> np.ndarray:
    out = np.full((len(rows), width), -1, dtype=np.int32)
    for i, r in enumerate(rows):
        out[i, :len(r)] = r
    out.setflags(write=False)
    return out


# -- plans -----------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class PlanBase:
    """What every plan has (planar and spatial): names, counts, defaults, the step table.

    Parameters
    ----------
    mechanism : Mechanism
        The description the plan was compiled from.
    structure : Structure
        Its mobility and Assur groups.
    steps : tuple of step records
        The solve order.
    param_names : tuple of str
        ``(n_params,)`` parameter names (``crank.length``, ``O2.x`` …), file order.
    defaults : ndarray
        ``(n_params,)`` sketch values, SI, read-only.
    point_names, body_names, input_names : tuple of str
    input_kinds : tuple of str
        ``(n_inputs,)`` 'rotary' | 'linear'.
    sketch_inputs, speeds : ndarray
        ``(n_inputs,)`` the inputs in the sketch (rad, m) and the drivers' speeds (rad/s, m/s), read-only.
    point_body : tuple of int
        ``(n_points,)`` the body whose pose gives each point's position.
    param_kind : ndarray
        ``(n_params,)`` int8 codes into PARAM_KINDS.
    length_scale : float
        The sketch's bounding-box size (m): the scale of relative length tolerances.
    """
    dimension: ClassVar[int] = 0
    mechanism: Mechanism
    structure: Structure
    steps: tuple
    param_names: tuple[str, ...]
    defaults: np.ndarray
    point_names: tuple[str, ...]
    body_names: tuple[str, ...]
    input_names: tuple[str, ...]
    input_kinds: tuple[str, ...]
    sketch_inputs: np.ndarray
    speeds: np.ndarray
    point_body: tuple[int, ...]
    param_kind: np.ndarray
    length_scale: float = 1.0

    def __post_init__(self):
        for name in ("defaults", "sketch_inputs", "speeds"):
            object.__setattr__(self, name, _readonly(getattr(self, name), float))
        object.__setattr__(self, "param_kind", _readonly(self.param_kind, np.int8))

    def __setstate__(self, state):
        """Unpickled arrays come back writable: freeze them again."""
        self.__dict__.update(state)
        self.__post_init__()

    # -- counts and look-ups ----------------------------------------------------------------------------
    @property
    def n_params(self) -> int:
        return len(self.param_names)

    @property
    def n_inputs(self) -> int:
        return len(self.input_names)

    @property
    def n_points(self) -> int:
        return len(self.point_names)

    @property
    def n_bodies(self) -> int:
        return len(self.body_names)

    @property
    def n_steps(self) -> int:
        return len(self.steps)

    def param_index(self, name: str) -> int:
        try:
            return self.param_names.index(name)
        except ValueError:
            raise UnknownNameError([("name", f"unknown parameter {name!r} (known: {', '.join(self.param_names)})")]
                                   ) from None

    def point_index(self, name: str) -> int:
        try:
            return self.point_names.index(name)
        except ValueError:
            raise UnknownNameError([("name", f"unknown point {name!r} (known: {', '.join(self.point_names)})")]
                                   ) from None

    def params_with(self, **changes) -> np.ndarray:
        """A copy of the defaults with named parameters changed (SI), e.g. ``crank.length=0.2``;
        dots in names are written as double underscores: ``params_with(crank__length=0.2)``."""
        p = self.defaults.copy()
        for k, v in changes.items():
            p[self.param_index(k.replace("__", "."))] = v
        return p

    def param_kind_of(self, name: str) -> str:
        """'length', 'angle' or 'number' for a parameter name of this plan."""
        return PARAM_KINDS[int(self.param_kind[self.param_index(name)])]

    def steps_of(self, *kinds: str) -> list:
        """The step records of the given kinds, in solve order."""
        return [s for s in self.steps if s.kind in kinds]

    def newton_steps(self) -> list:
        """The groups without a closed form (a class III triad, a class IV group), solved by Newton iterations, in
        solve order (empty for a spatial plan)."""
        return self.steps_of("newton")

    @property
    def has_newton_groups(self) -> bool:
        """Whether a group of the plan is solved by Newton iterations (:meth:`newton_steps`)."""
        return any(s.kind == "newton" for s in self.steps)

    # -- the flat step table -------------------------------------------------------------------------
    @property
    def step_kind(self) -> np.ndarray:
        """(n_steps,) int8 codes into STEP_KINDS (read-only)."""
        return _readonly([STEP_KINDS.index(s.kind) for s in self.steps], np.int8)

    @property
    def branch(self) -> np.ndarray:
        """(n_steps,) int8 branch signs ±1 (read-only)."""
        return _readonly([s.branch for s in self.steps], np.int8)

    #: the former name of :attr:`branch`
    branch_signs = branch

    @property
    def step_in(self) -> np.ndarray:
        """(n_steps, 3) int32 indices of the known points each step reads, -1 padded (read-only)."""
        return _padded([[self.point_index(p) for p in s.points_in()] for s in self.steps], 3)

    @property
    def step_out(self) -> np.ndarray:
        """(n_steps,) int32 index of the point a step's branch refers to, or -1 (read-only)."""
        return _readonly([-1 if s.key_point is None else self.point_index(s.key_point) for s in self.steps],
                         np.int32)

    @property
    def step_param(self) -> np.ndarray:
        """(n_steps, 3) int32 parameter indices each step reads directly, -1 padded (read-only)."""
        return _padded([s.params_in() for s in self.steps], 3)

    def with_steps(self, steps) -> "PlanBase":
        """A copy with another step table (e.g. other branch signs)."""
        return replace(self, steps=tuple(steps))


@dataclass(frozen=True, eq=False)
class PlanarPlan(PlanBase):
    """The compiled plan of a planar mechanism.

    Besides :class:`PlanBase`: ``geometry_program`` (per body, how its local point coordinates follow
    from the parameters: see :mod:`assur.engine.planar.geometry`), ``lines`` (per slide line:
    (kind, name, guide body, slider body, through point, angle param, offset param, reference point,
    u_slider)), ``sketch_poses`` ((x, y, θ) of every body at the sketch inputs: the Newton solver's
    seed) and ``gear_slots``. The compiled backend traces the plan's step executors (:mod:`assur.engine.planar.traced`):
    the plan carries nothing for it.
    """
    dimension: ClassVar[int] = 2
    geometry_program: tuple = field(repr=False, default=())
    lines: tuple = field(repr=False, default=())
    sketch_poses: tuple = field(repr=False, default=())
    #: per gear pair, in solve order: how its driven rotation follows from the inputs (:class:`GearSlot`)
    gear_slots: tuple = field(repr=False, default=())
    #: per cam pair, in solve order: how its follower's move follows from the inputs (:class:`CamSlot`); their slot
    #: indices follow the inputs' and the gear slots'
    cam_slots: tuple = field(repr=False, default=())

    def dyad_steps(self) -> list:
        """The closed-form dyad steps (RRR, RRP, RPR, PRP, PPR), in solve order."""
        return self.steps_of("RRR", "RRP", "RPR", "PRP", "PPR")

    def crank_steps(self) -> list:
        return self.steps_of("crank")


@dataclass(frozen=True, eq=False)
class SpatialPlan(PlanBase):
    """The compiled plan of a spatial mechanism (``dimension = 3``): a crank followed by R–S–S dyads.

    ``body_frames``, per body, how its frame is defined: ('frame',) | ('hinged', pivot, axis point) |
    ('coupler', U, other, pin body, pin local) | ('idle', A, B).
    """
    dimension: ClassVar[int] = 3
    body_frames: tuple = field(repr=False, default=())

    def rss_steps(self) -> list:
        """The R–S–S dyad steps, in solve order."""
        return self.steps_of("RSS")

    def with_branch(self, point: str, s: int | None = None, *, w: int | None = None) -> "SpatialPlan":
        """A copy with the branch of the dyad solving ``point`` set explicitly: ``s`` = ±1
        (sign det[A − D, e, B − D]), or the paper's ``w`` of eq. (21), converted by
        s = W·sign(V3_X) with V3 = (A − D) × e at the sketch input (SpecError where V3_X = 0)."""
        steps = list(self.steps)
        for i, st in enumerate(steps):
            if st.kind == "RSS" and st.key_point == point:
                if (s is None) == (w is None):
                    raise SpecError([("branch", "give exactly one of s or w (±1)")])
                if w is not None:
                    if w not in (1, -1):
                        raise SpecError([("branch.w", f"must be +1 or −1: {w!r}")])
                    if abs(st.sketch_v3x) <= 1e-12 * st.sketch_v1_norm:
                        raise SpecError([("branch.w", f"the paper's W is undefined for '{point}': V3_X = 0 at the "
                                                      "sketch (the rocker axis lies in a plane containing X); give s")])
                    s = int(w * np.sign(st.sketch_v3x))
                if s not in (1, -1):
                    raise SpecError([("branch.s", f"must be +1 or −1: {s!r}")])
                steps[i] = st.with_branch(s)
                return self.with_steps(steps)
        raise SpecError([("branch", f"'{point}' is not solved by an R–S–S dyad "
                                    f"(dyad points: {', '.join(s.key_point for s in self.rss_steps())})")])

    def crank_steps(self) -> list:
        return self.steps_of("crank")


def require_plan(plan, what: str = "plan", planar: bool = False):
    """``plan`` when it is a plan from ``assur.compile`` (a planar one with ``planar``), else ArgumentTypeError
    naming the argument ``what`` (a Mechanism or a path given where its plan belongs gets the call to make)."""
    kinds = PlanarPlan if planar else PlanBase
    if isinstance(plan, kinds):
        return plan
    got = type(plan).__name__
    hint = ""
    if isinstance(plan, Mechanism):
        hint = ": compile it first, plan = assur.compile(mechanism)"
    elif isinstance(plan, str) or hasattr(plan, "__fspath__"):
        hint = ": load and compile the file first, plan = assur.compile(assur.load(path))"
    need = "a planar plan" if planar else "a plan"
    if planar and isinstance(plan, PlanBase):
        got = "a spatial plan"
    raise ArgumentTypeError([(what, f"must be {need} from assur.compile, not {got}{hint}")])

