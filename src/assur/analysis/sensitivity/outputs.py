"""The outputs of a mechanism and their exact derivatives by every parameter, over a solved run.

Names (what ``assur sensitivity --of`` takes):

=============================  ==========================================================================
``P.x``, ``P.y``               a point's position (m)
``P.vx``, ``P.vy``             its velocity at the drivers' speeds (m/s); ``P.ax``, ``P.ay`` its acceleration
``link.angle``, ``link.omega`` a body's angle (rad) and angular velocity (rad/s)
``mu.J``                       the transmission angle of the dyad solving J (rad)
``driver.effort``              a driver's effort: a crank's torque (N·m), an actuator's force (N)
``R.P``, ``R.P.x``, ``R.P.y``  the reaction at joint P (magnitude, components; N); ``R.P@link`` picks the pair of
                               a joint of three or more bodies by its later body; a slide's ``R.slot``
``gait.step``, ``gait.lift``,  a walking leg's step length, lift and sag (m) and duty factor: by the envelope theorem
``gait.sag``, ``gait.duty``    at their refined extremes, with the contact arc's ends moving with the parameters
=============================  ==========================================================================

Each :class:`Output` holds the values (n,) and the derivatives (n, n_params) (SI per SI unit of each parameter); a
gait metric is one number with (n_params,) derivatives.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import SpecError
from .forces import _at, angle_of, coefficient, multipliers
from .implicit import solve_motion
from .reactions import reactions
from .series import Series, abs_complex, arg


@dataclass(frozen=True)
class Output:
    """One output over the run: ``value`` (n,) (or a float) and ``derivative`` (n, n_params) (or (n_params,)) in SI,
    ``unit`` its SI unit, ``kind`` its family (position, velocity, acceleration, angle, rate, transmission, effort,
    reaction, gait)."""
    name: str
    kind: str
    unit: str
    value: np.ndarray
    derivative: np.ndarray


def _parts(x: Series, k: int = 0, factor: float = 1.0):
    """(value (n,), derivative (n, P)) of the k-th time coefficient of a series (times ``factor``)."""
    v = x.v[k][..., 0, 0] * factor
    d = x.e1[k][..., 0] * factor if x.e1 is not None else np.zeros(v.shape + (0,))
    return v, d


class Outputs:
    """Every output of a plan over a solved state (lazily, by family)."""

    def __init__(self, plan, state, *, forces: bool = True):
        self.plan, self.state = plan, state
        self.n = int(np.prod(state.shape)) if state.shape else 1
        self.motion = solve_motion(plan, state)
        self.with_forces = forces
        self._cache: dict[str, Output] = {}
        self._families: set = set()

    # -- families ---------------------------------------------------------------------------------------------
    def _kinematics(self):
        plan, mo = self.plan, self.motion
        world, _ = _at(mo.closure, mo.X, mo.params)
        for i, p in enumerate(plan.point_names):
            z = world(plan.point_body[i], p)
            for axis, part in (("x", np.real), ("y", np.imag)):
                for k, (suffix, kind, unit, f) in enumerate((("", "position", "m", 1.0), ("v", "velocity", "m/s", 1.0),
                                                             ("a", "acceleration", "m/s²", 2.0))):
                    v, d = _parts(z, k, f)
                    name = f"{p}.{suffix}{axis}"
                    self._cache[name] = Output(name, kind, unit, part(v), part(d))
        cl = mo.closure
        for b in cl.moving:
            th = angle_of(mo.X, cl, b)
            name = plan.body_names[b]
            v, d = _parts(th)
            self._cache[f"{name}.angle"] = Output(f"{name}.angle", "angle", "rad", v, d)
            v, d = _parts(th, 1)
            self._cache[f"{name}.omega"] = Output(f"{name}.omega", "rate", "rad/s", v, d)

    def _transmission(self):
        plan, mo = self.plan, self.motion
        world, pose = _at(mo.closure, [x.truncate(1) for x in mo.X], [x.truncate(1) for x in mo.params])
        cl = mo.closure
        _, lines = cl.geometry([x.truncate(1) for x in mo.params])

        def P(name):
            return world(plan.point_body[plan.point_index(name)], name)

        def angle(a, b, acute):
            t = arg(a.conj() * b)
            v, d = _parts(t)
            s = np.sign(v)
            v, d = np.abs(v), d * s[:, None]
            if acute:
                big = v > math.pi / 2
                v = np.where(big, math.pi - v, v)
                d = np.where(big[:, None], -d, d)
            return v, d

        def line_dir(k):
            return pose[plan.lines[k][2]][1] * lines[k][1]

        for st in plan.steps:
            if st.kind == "RRR":
                v, d = angle(P(st.point_a) - P(st.joint), P(st.point_b) - P(st.joint), False)
            elif st.kind == "RRP":
                v, d = angle(P(st.joint) - P(st.point_a), line_dir(st.line) * 1j, True)
            elif st.kind == "RPR":
                v, d = angle(P(st.slider_point) - P(st.guide_point), line_dir(st.line) * 1j, True)
            elif st.kind in ("PRP", "PPR"):
                la, lb = (st.line_a, st.line_b) if st.kind == "PRP" else (st.outer_line, st.inner_line)
                v, d = angle(line_dir(la), line_dir(lb), True)
            else:
                continue
            key = st.key_point or f"step{plan.steps.index(st)}"
            self._cache[f"mu.{key}"] = Output(f"mu.{key}", "transmission", "rad", v, d)

    def _forces(self):
        plan = self.plan
        inputs = np.broadcast_to(np.asarray(self.state.inputs, float),
                                 tuple(self.state.shape) + (plan.n_inputs,)).reshape(self.n, -1)
        mult = multipliers(self.motion, plan, inputs)
        for k, name in enumerate(plan.input_names):
            unit = "N·m" if plan.input_kinds[k] == "rotary" else "N"
            self._cache[f"{name}.effort"] = Output(f"{name}.effort", "effort", unit, mult.effort[:, k],
                                                   mult.effort_derivative[:, :, k])
        t = self.motion.closure.tables
        names = [fp.name for fp in t.pairs]
        for k, (fp, r) in enumerate(zip(t.pairs, reactions(plan, self.motion, mult))):
            if r is None or fp.kind == "T":
                continue
            base = f"R.{fp.name}" if names.count(fp.name) == 1 else f"R.{fp.name}@{plan.body_names[fp.later]}"
            v, d = _parts(r)
            self._cache[f"{base}.x"] = Output(f"{base}.x", "reaction", "N", v.real, d.real)
            self._cache[f"{base}.y"] = Output(f"{base}.y", "reaction", "N", v.imag, d.imag)
            v, d = _parts(abs_complex(r))
            self._cache[base] = Output(base, "reaction", "N", v, d)

    _FAMILIES = {"kinematics": "_kinematics", "transmission": "_transmission", "forces": "_forces"}

    def _family_of(self, name: str) -> str:
        if name.startswith("mu."):
            return "transmission"
        if name.startswith("R.") or name.endswith(".effort"):
            return "forces"
        return "kinematics"

    def _ensure(self, family: str):
        if family in self._families:
            return
        if family == "forces" and not self.with_forces:
            raise SpecError([("--of", "forces need a mechanism with one driver (and its masses or loads)")])
        getattr(self, self._FAMILIES[family])()
        self._families.add(family)

    def names(self, families=("kinematics", "transmission", "forces")) -> list[str]:
        for f in families:
            if f == "forces" and not self.with_forces:
                continue
            self._ensure(f)
        return list(self._cache)

    def __getitem__(self, name: str) -> Output:
        if name not in self._cache:
            self._ensure(self._family_of(name))
        if name not in self._cache:
            known = ", ".join(sorted(self.names())[:12])
            raise SpecError([("--of", f"unknown output {name!r} (e.g. {known}, …; gait.step, gait.lift …)")])
        return self._cache[name]
