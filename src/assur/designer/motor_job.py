"""The run on the motor from the designer's page, in a separate process so that drags stay responsive.

**What runs.** :class:`MotorJob` checks a request at once (:func:`check_runnable`: the committed document is a
mechanism with one driver and a ``[motor]``; else :class:`~.document.EditRefused`, and a file without a motor gets
the located hint of :func:`motor_hint` instead of an error), then runs in a worker process ("spawn" context, daemon)
what ``assur simulate FILE`` runs on that document: the file reader, ``compile``, the document's
:class:`~assur.analysis.study.Study` and :func:`~assur.dynamics.cycle.cycle_simulation` on it (the Study's
``motor_run``, which reuses the Study's solved turn): the mechanism from rest on its motor to its periodic steady
state, the kinetostatic estimate of δ beside it and the joints' reactions over the run. A request may give a
``time`` instead (``assur simulate --time``): the run for that long, which a mechanism that does not turn fully needs
(it has no steady state; its run stops where it can go no further: a dead centre, the limit of assembly, the end of
a stroke). The numbers are those of ``assur simulate`` to round-off (``tests/test_designer_motor.py``).

**Messages** (:meth:`MotorJob.poll`): one ``motor_done`` per run, with ``status`` "finished" (the run ended: at its
steady state, or stopped by an event), "failed" (the run could not be made: the reason) or "cancelled"; ``summary``
(the JSON object of ``assur simulate --json`` without its ``file``, or None), ``stop`` (the event that ended the run:
``kind``, ``t`` s, ``q`` the input (rad or m, not wrapped), ``speed``, ``message``; None when it failed), ``message``
(one sentence) and the run's samples as arrays (SI, each (n,)): ``t``, ``q``, ``speed``, ``accel`` and, with a
motor, ``effort`` (at the driver), ``motor_torque``, ``motor_speed``, ``power`` and ``current`` (where the motor's
torque constant is known). Cancel stops the worker at once: a run has no partial result worth keeping.
"""
from __future__ import annotations

import copy
import queue as queue_module
import secrets
import time

from .document import EditRefused
from .worker_process import stop_process

#: the arrays of a run the page receives (those that are None are left out)
RUN_ARRAYS = ("t", "q", "speed", "accel", "effort", "motor_torque", "motor_speed", "power", "current")
#: how long a finished worker's message may take to arrive after the process ended (s)
LAST_MESSAGE_WAIT = 0.5


def motor_hint(doc: dict) -> dict | None:
    """How to add a motor to a document without one: ``{"message", "where", "example"}`` (``where`` the table to add,
    ``example`` its TOML text for the document's first driver), or None when the document has a motor or no driver
    a motor could turn."""
    if isinstance(doc.get("motor"), dict):
        return None
    drivers = [d for d in doc.get("drivers", []) if isinstance(d, dict)]
    if not drivers:
        return None
    first = drivers[0]
    name = first.get("name", "the driver")
    linear = first.get("kind", "rotary") == "linear"
    lines = ["[motor]", f'driver = "{name}"']
    if linear:
        lines += ['kind = "force"', 'force = "500 N"']
    else:
        lines += ['kind = "dc"', 'stall_torque = "1 N*m"', 'no_load_speed = "3000 rpm"', "gear_ratio = 5"]
    what = "a force on" if linear else "a motor on"
    return {"message": f"no [motor] in this file: add {what} the driver '{name}' (a [motor] table after "
                       f"[[drivers]]; docs/format.md, Motors) to run it from rest on its motor",
            "where": "motor", "example": "\n".join(lines)}


def drivers_end_line(text: str) -> int | None:
    """The line (1-based) of a file's text after which a ``[motor]`` table goes: the last line of its last
    ``[[drivers]]`` table (blank lines and comments after it left out), or None without one."""
    import re
    lines = text.splitlines()
    starts = [i for i, line in enumerate(lines) if re.match(r"\s*\[\[\s*drivers\s*\]\]", line)]
    if not starts:
        return None
    end = len(lines)
    for i in range(starts[-1] + 1, len(lines)):
        if re.match(r"\s*\[", lines[i]):
            end = i
            break
    while end > starts[-1] + 1 and (not lines[end - 1].strip() or lines[end - 1].lstrip().startswith("#")):
        end -= 1
    return end


def located_hint(hint: dict, path: str | None, text: str | None) -> dict:
    """``hint`` (:func:`motor_hint`) with the place in the file to add the table: ``file``, ``line`` (after which)
    and the message saying so, when the file's text has a ``[[drivers]]`` table."""
    line = drivers_end_line(text) if text else None
    if path is None or line is None:
        return hint
    from pathlib import Path
    return {**hint, "file": path, "line": line,
            "message": f"{hint['message']}: in {Path(path).name}, after line {line}"}


def check_runnable(doc: dict, compiled, path: str | None = None, text: str | None = None) -> None:
    """Refuse (:class:`EditRefused`, located) a run of ``doc`` on its motor that cannot start: ``compiled`` is the
    document's :class:`~.compiled.Compiled`; a document without a motor is told where to add one in the file
    ``path`` of text ``text`` (:func:`located_hint`)."""
    stop = compiled.invalid or compiled.error
    if stop is not None:
        raise EditRefused(f"no run on the motor: the document is not a mechanism yet ({stop})", "motor")
    hint = motor_hint(doc)
    if hint is not None:
        raise EditRefused(located_hint(hint, path, text)["message"], hint["where"])
    plan = compiled.plan
    if compiled.mechanism.motor is None:
        raise EditRefused("no run on the motor: the document has no [motor] table and no driver to put one on "
                          "(add a driver first)", "motor")
    if plan.n_inputs != 1:
        raise EditRefused(f"no run on the motor: the forward dynamics takes one driver; this mechanism has "
                          f"{plan.n_inputs} ({', '.join(plan.input_names)})", "drivers")


def _run_message(run) -> str:
    """One sentence on a finished run: how it ended and, at a steady state, its speed."""
    sim = run.simulation
    text = sim.stop.message if sim.stop is not None else "ran"
    return text[:1].upper() + text[1:]


#: the longest run the page may ask for (s)
MAX_TIME = 3600.0


def run_time(value) -> float | None:
    """A request's ``time`` (s): None (to the steady state) or a positive number up to :data:`MAX_TIME`."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value <= MAX_TIME:
        raise EditRefused(f"the run's time must be a number of seconds in (0, {MAX_TIME:g}], or none (to the "
                          f"steady state): {value!r}", "time")
    return float(value)


def run_document(doc: dict, steps: int, time: float | None = None):
    """``(summary, stop, arrays, message)`` of ``doc`` run on its motor (the module docstring) to its steady state, or
    for ``time`` s (a mechanism that does not turn fully has no steady state: it needs a time, and its run stops
    where it can go no further); raises AssurError where the run cannot be made."""
    import warnings

    import numpy as np

    from ..analysis.study import Study
    from ..dynamics.cycle import cycle_simulation
    from ..engine import compile as compile_plan
    from ..io.mechanism_file import from_dict
    with warnings.catch_warnings():       # the page shows the document's own diagnostics
        warnings.simplefilter("ignore")
        mech = from_dict(doc, source="the designer's document")
        plan = compile_plan(mech)
        study = Study(plan, plan.defaults, steps)
        if study.turn and bool(np.all(study.state.valid)):      # a whole turn: the run reuses the Study's
            run = study.motor_run if time is None else cycle_simulation(study, time=time)
        else:
            run = cycle_simulation(plan, time=time)
    if run is None:
        raise EditRefused("the document has no [motor]", "motor")
    sim = run.simulation
    stop = None if sim.stop is None else {"kind": sim.stop.kind, "t": float(sim.stop.t), "q": float(sim.stop.q),
                                          "speed": float(sim.stop.speed), "message": sim.stop.message}
    arrays = {name: np.asarray(getattr(sim, name), dtype=float) for name in RUN_ARRAYS
              if getattr(sim, name) is not None}
    return run.summary(), stop, arrays, _run_message(run)


def _worker(job_id, doc, steps, time_, out):   # pragma: no cover - runs in a child process
    """The worker process: one run, one ``motor_done`` on ``out``."""
    import signal
    signal.signal(signal.SIGINT, signal.SIG_IGN)       # Ctrl-C in the terminal is the server's to handle
    from ..errors import AssurError
    try:
        summary, stop, arrays, message = run_document(doc, steps, time_)
        out.put(({"type": "motor_done", "job": job_id, "status": "finished", "summary": summary, "stop": stop,
                  "message": message}, arrays))
    except AssurError as exc:
        out.put(({"type": "motor_done", "job": job_id, "status": "failed", "summary": None, "stop": None,
                  "message": f"the run could not be made: {exc}"}, {}))
    except Exception as exc:   # noqa: BLE001 - the page gets the reason
        import traceback
        traceback.print_exc()
        out.put(({"type": "motor_done", "job": job_id, "status": "failed", "summary": None, "stop": None,
                  "message": f"the run failed: {type(exc).__name__}: {exc}"}, {}))


class MotorJob:
    """One run of the page's document on its motor (module docstring): started at once in a worker process;
    :meth:`poll` returns its ``motor_done`` (message, arrays) when it comes, :meth:`cancel` stops it."""

    def __init__(self, doc: dict, steps: int, duration: float | None = None):
        import multiprocessing as mp
        self.id = secrets.token_hex(6)
        self.doc = copy.deepcopy(doc)
        self.created = time.time()
        self._finished = False
        self._cancelled = False
        ctx = mp.get_context("spawn")
        self._queue = ctx.Queue()
        self._process = ctx.Process(target=_worker, name=f"assur-motor-{self.id}", daemon=True,
                                    args=(self.id, self.doc, int(steps), duration, self._queue))
        self._process.start()

    @property
    def running(self) -> bool:
        """The run has not ended, or its ``motor_done`` has not been polled yet."""
        return not self._finished

    def poll(self) -> list[tuple[dict, dict]]:
        """``[(motor_done message, arrays)]`` once the run has ended (never blocks), else []."""
        if self._finished:
            return []
        if self._cancelled:
            return [self._done("cancelled", "the run on the motor was cancelled")]
        try:
            return [self._take(self._queue.get_nowait())]
        except queue_module.Empty:
            pass
        except Exception:   # noqa: BLE001 - a broken message: the worker's end says what happened
            pass
        if self._process.is_alive():
            return []
        try:
            return [self._take(self._queue.get(timeout=LAST_MESSAGE_WAIT))]
        except Exception:   # noqa: BLE001 - it ended without a message (killed, crashed)
            return [self._done("failed", f"the run's process ended unexpectedly (exit code "
                                         f"{self._process.exitcode})")]

    def _take(self, item) -> tuple[dict, dict]:
        self._finished = True
        self._process.join(0)
        message, arrays = item
        message["elapsed"] = time.time() - self.created
        return message, arrays

    def _done(self, status: str, message: str) -> tuple[dict, dict]:
        self._finished = True
        return ({"type": "motor_done", "job": self.id, "status": status, "summary": None, "stop": None,
                 "message": message, "elapsed": time.time() - self.created}, {})

    def cancel(self) -> None:
        """Stop the run at once (its ``motor_done`` says "cancelled")."""
        if self._finished or self._cancelled:
            return
        self._cancelled = True
        stop_process(self._process)


__all__ = ["MAX_TIME", "MotorJob", "check_runnable", "drivers_end_line", "located_hint", "motor_hint", "run_document",
           "run_time"]
