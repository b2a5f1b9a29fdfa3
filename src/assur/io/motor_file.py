"""The ``[motor]`` table of a mechanism file (and the ``--motor`` option, the same keys): read, checked, written.

Read by :mod:`assur.io.mechanism_file` after the drivers; every problem is added to the reader's
:class:`~assur.io.problems.Problems` with its location (``motor.stall_torque``, or ``--motor.stall_torque`` for
the option). Numbers are converted to SI; speeds are read as driver speeds are (``"3000 rpm"``, or a bare number
in the file's angle unit per second; a linear speed in its length unit per second).
"""
from __future__ import annotations

import math

from ..errors import SpecError
from ..model.motor import LINEAR_MOTOR_KINDS, MOTOR_KINDS, ROTARY_MOTOR_KINDS, Motor
from . import units as U

#: the keys every motor may have, and the keys of each kind
COMMON_KEYS = ("kind", "driver", "gear_ratio", "lead", "efficiency", "rotor_inertia", "flywheel_inertia")
KIND_KEYS = {
    "torque": ("torque",),
    "force": ("force",),
    "dc": ("stall_torque", "no_load_speed", "stall_current", "torque_constant", "resistance", "voltage"),
    "induction": ("breakdown_torque", "breakdown_slip", "synchronous_speed"),
    "table": ("speed", "torque", "force"),
    "hydraulic": ("pressure", "area", "flow"),
}
#: the quantity kind (io.units) of each scalar key; speeds are read separately
_SCALARS = {"torque": "torque", "force": "force", "stall_torque": "torque", "stall_current": "current",
            "torque_constant": "torque_constant", "resistance": "resistance", "voltage": "voltage",
            "breakdown_torque": "torque", "pressure": "pressure", "area": "area", "flow": "flow",
            "rotor_inertia": "inertia", "flywheel_inertia": "inertia"}
_SPEEDS = ("no_load_speed", "synchronous_speed")


def _number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and abs(x) < 1e12


def _positive(P, path, value, kind):
    """``value`` (a quantity of ``kind``) in SI when positive, else None after adding the problem."""
    try:
        v = U.parse_quantity(value, kind)
    except SpecError as exc:
        P.add(path, str(exc))
        return None
    if not v > 0:
        P.add(path, f"must be positive: {value!r}")
        return None
    return v


def _speed(P, path, value, kind, units, positive=True):
    try:
        v = U.parse_speed(value, kind, units)
    except SpecError as exc:
        P.add(path, str(exc))
        return None
    if positive and not v > 0:
        P.add(path, f"must be a positive speed: {value!r}")
        return None
    return v


def read_motor(spec, P, units, drivers, path: str = "motor") -> Motor | None:
    """The Motor of a ``[motor]`` table ``spec`` (a dict), or None after adding its problems to ``P``.
    ``drivers``: the mechanism's drivers (their names and kinds)."""
    if not isinstance(spec, dict):
        P.add(path, "must be a table: kind = \"dc\", stall_torque = …, no_load_speed = … (docs/dynamics.md)")
        return None
    n_before = len(P)
    kind = spec.get("kind")
    if kind not in MOTOR_KINDS:
        P.add(f"{path}.kind", f"must be one of {', '.join(MOTOR_KINDS)}: {kind!r}")
        P.unknown_keys(spec, COMMON_KEYS + tuple(k for ks in KIND_KEYS.values() for k in ks if k not in COMMON_KEYS),
                       path)
        return None
    allowed = COMMON_KEYS + KIND_KEYS[kind]
    for k in spec:
        if k not in allowed:
            known = any(k in ks for ks in KIND_KEYS.values())
            P.add(f"{path}.{k}", f"does not apply to a {kind!r} motor (its keys: {', '.join(KIND_KEYS[kind])})"
                  if known else f"unknown key (allowed: {', '.join(allowed)})")
    # the driver
    names = [d.name for d in drivers]
    if not drivers:
        P.add(path, "a motor needs a driver: the mechanism has none")
        return None
    dname = spec.get("driver", names[0])
    if dname not in names:
        P.add(f"{path}.driver", f"unknown driver {dname!r} (known: {', '.join(names)})")
        return None
    driver = drivers[names.index(dname)]
    linear = driver.kind == "linear"
    vals: dict = {}
    for k, q in _SCALARS.items():
        if k in spec and k in allowed:
            if k in ("rotor_inertia", "flywheel_inertia"):
                try:
                    v = U.parse_quantity(spec[k], q)
                except SpecError as exc:
                    P.add(f"{path}.{k}", str(exc))
                    continue
                if v < 0:
                    P.add(f"{path}.{k}", f"must not be negative: {spec[k]!r}")
                    continue
                vals[k] = v
            elif k in ("torque", "force") and kind == "table":
                continue
            elif k in ("torque", "force"):
                try:
                    vals[k] = U.parse_quantity(spec[k], q)
                except SpecError as exc:
                    P.add(f"{path}.{k}", str(exc))
            else:
                v = _positive(P, f"{path}.{k}", spec[k], q)
                if v is not None:
                    vals[k] = v
    for k in _SPEEDS:
        if k in spec and k in allowed:
            v = _speed(P, f"{path}.{k}", spec[k], "rotary", units)
            if v is not None:
                vals[k] = v
    # the drive train
    if "gear_ratio" in spec:
        g = spec["gear_ratio"]
        if linear:
            P.add(f"{path}.gear_ratio", f"the driver {dname!r} is linear: a rotary motor on it needs lead (the "
                                        "actuator's travel per motor turn), not gear_ratio")
        elif not _number(g) or g <= 0:
            P.add(f"{path}.gear_ratio", f"must be a positive number (motor turns per turn of the crank): {g!r}")
        else:
            vals["gear_ratio"] = float(g)
    if "lead" in spec:
        if not linear:
            P.add(f"{path}.lead", f"the driver {dname!r} is a crank: lead is for a rotary motor on a linear driver "
                                  "(give gear_ratio for a gearbox)")
        else:
            try:
                lead = U.parse_quantity(spec["lead"], "length", units)
            except SpecError as exc:
                P.add(f"{path}.lead", str(exc))
            else:
                if lead > 0:
                    vals["lead"] = lead
                else:
                    P.add(f"{path}.lead", f"must be a positive length (travel per motor turn): {spec['lead']!r}")
    if "efficiency" in spec:
        e = spec["efficiency"]
        if not _number(e) or not 0 < e <= 1:
            P.add(f"{path}.efficiency", f"must be a number in (0, 1]: {e!r}")
        else:
            vals["efficiency"] = float(e)
    if "flywheel_inertia" in vals and linear:
        P.add(f"{path}.flywheel_inertia", f"a flywheel turns with a crank; the driver {dname!r} is linear")
    # the kind's own checks
    linear_table = False
    if kind == "table":
        linear_table = _read_table(spec, P, path, units, linear, vals)
    pushes = kind in LINEAR_MOTOR_KINDS or linear_table
    if pushes and not linear:
        P.add(f"{path}.kind", f"a {kind!r} motor pushes a linear driver; the driver {dname!r} is a crank "
                              f"(rotary motors: {', '.join(ROTARY_MOTOR_KINDS)}, table with torque)")
    if linear and not pushes and kind != "table" and "lead" not in spec:
        P.add(f"{path}.lead", f"a rotary motor on the linear driver {dname!r} needs lead (the actuator's travel "
                              "per motor turn)")
    if pushes and ("rotor_inertia" in spec or "lead" in spec):
        for k in ("rotor_inertia", "lead"):
            if k in spec:
                P.add(f"{path}.{k}", f"a {kind!r} motor acts on the actuator itself: {k} does not apply")
    required = {"torque": ("torque",), "force": ("force",), "induction": KIND_KEYS["induction"],
                "hydraulic": KIND_KEYS["hydraulic"]}.get(kind, ())
    for k in required:
        if k not in spec:
            P.add(f"{path}.{k}", f"a {kind!r} motor needs {k}")
    if kind == "dc":
        sets = (("stall_torque", "no_load_speed"), ("torque_constant", "resistance", "voltage"))
        given = [s for s in sets if any(k in spec for k in s)]
        if len(given) != 1:
            P.add(path, "a DC motor needs stall_torque and no_load_speed, or torque_constant, resistance and "
                        "voltage (one of the two)")
        else:
            for k in given[0]:
                if k not in spec:
                    P.add(f"{path}.{k}", f"a DC motor given by {', '.join(given[0])} needs {k}")
            if "stall_current" in spec and given[0] is sets[1]:
                P.add(f"{path}.stall_current", "follows from voltage / resistance: give it only with stall_torque")
    if kind == "induction" and "breakdown_slip" in spec:
        s = spec["breakdown_slip"]
        if not _number(s) or not 0 < s < 1:
            P.add(f"{path}.breakdown_slip", f"must be a number in (0, 1) (the slip of the breakdown torque): {s!r}")
        else:
            vals["breakdown_slip"] = float(s)
    if len(P) > n_before:
        return None
    table = vals.pop("table", ())
    return Motor(kind=kind, driver=dname, table=table, linear_table=linear_table, **vals)


def _read_table(spec, P, path, units, linear, vals) -> bool:
    """A ``table`` motor's rows (speed, effort) into ``vals['table']``; returns whether they are (m/s, N) rows."""
    efforts = [k for k in ("torque", "force") if k in spec]
    if len(efforts) != 1:
        P.add(path, "a table motor needs speed = [...] and one of torque = [...] (a motor shaft) or force = [...] "
                    "(a linear driver)")
        return False
    effort = efforts[0]
    pushes = effort == "force"
    speeds, values = spec.get("speed"), spec[effort]
    if not isinstance(speeds, list) or len(speeds) < 2:
        P.add(f"{path}.speed", f"must be a list of at least 2 speeds: {speeds!r}")
        return pushes
    if not isinstance(values, list) or len(values) != len(speeds):
        n = len(values) if isinstance(values, list) else values
        P.add(f"{path}.{effort}", f"needs one value per speed: {n!r} for {len(speeds)} speeds")
        return pushes
    kind = "linear" if pushes else "rotary"
    xs = [_speed(P, f"{path}.speed[{j}]", v, kind, units, positive=False) for j, v in enumerate(speeds)]
    ys = []
    for j, v in enumerate(values):
        try:
            ys.append(U.parse_quantity(v, effort))
        except SpecError as exc:
            P.add(f"{path}.{effort}[{j}]", str(exc))
            ys.append(None)
    if any(x is None for x in xs) or any(y is None for y in ys):
        return pushes
    bad = [j for j in range(1, len(xs)) if xs[j] <= xs[j - 1]]
    if bad:
        P.add(f"{path}.speed[{bad[0]}]", f"speeds must increase strictly: {speeds[bad[0] - 1]!r} then "
                                         f"{speeds[bad[0]]!r}")
        return pushes
    vals["table"] = tuple(zip(xs, ys))
    return pushes


def parse_motor_option(text: str, units, drivers) -> Motor:
    """The Motor of a ``--motor`` option: the keys of ``[motor]`` as a TOML inline table's body
    (``kind = "dc", stall_torque = "2 N*m", no_load_speed = "3000 rpm"``). Raises SpecError with the location."""
    from .problems import Problems
    from .toml_reader import parse_toml
    body = text.strip()
    if body.startswith("{") and body.endswith("}"):
        body = body[1:-1]
    try:
        spec = parse_toml(f"motor = {{{body}}}", "--motor")["motor"]
    except SpecError as exc:
        raise SpecError([("--motor", f"must be KEY = VALUE pairs separated by commas, as in a TOML inline table "
                                     f"(kind = \"dc\", stall_torque = \"2 N*m\", no_load_speed = \"3000 rpm\"): "
                                     f"{text!r} ({exc})")]) from None
    P = Problems()
    motor = read_motor(spec, P, units, drivers, path="--motor")
    P.raise_if_any()
    return motor


def motor_table(motor: Motor, m, _out) -> dict:
    """The ``[motor]`` table of ``motor`` in the file's units: each value loads back to exactly the same SI value
    (speeds as rpm or rad/s text, the other quantities as bare SI numbers written by ``_out(si, factor=1)``, the
    writer's shortest exact number)."""
    t: dict = {"kind": motor.kind, "driver": motor.driver}
    for k in ("torque", "force", "stall_torque", "stall_current", "torque_constant", "resistance", "voltage",
              "breakdown_torque", "breakdown_slip", "pressure", "area", "flow"):
        v = getattr(motor, k)
        if v is not None:
            t[k] = _out(v)
    for k in _SPEEDS:
        v = getattr(motor, k)
        if v is not None:
            t[k] = U.format_speed(v, "rotary", m.units)
    if motor.table:
        kind = "linear" if motor.linear_table else "rotary"
        t["speed"] = [U.format_speed(x, kind, m.units) for x, _ in motor.table]
        t["force" if motor.linear_table else "torque"] = [_out(y) for _, y in motor.table]
    if motor.gear_ratio != 1.0:
        t["gear_ratio"] = _out(motor.gear_ratio)
    if motor.lead is not None:
        t["lead"] = _out(motor.lead, U.LENGTH[m.units.length])
    if motor.efficiency != 1.0:
        t["efficiency"] = _out(motor.efficiency)
    for k in ("rotor_inertia", "flywheel_inertia"):
        if getattr(motor, k):
            t[k] = _out(getattr(motor, k))
    return t


__all__ = ["COMMON_KEYS", "KIND_KEYS", "motor_table", "parse_motor_option", "read_motor"]
