"""The designer in a notebook: ``assur.designer.Designer(mech)`` shows the page of ``assur design`` as a Jupyter widget
(anywidget), on the same :class:`~assur.designer.session.Session` and the same messages (``docs/designer.md``).

The page's ES module (joined from ``static/parts`` by :mod:`.assembly`) and style sheet are the widget's ``_esm``
and ``_css``. The front
end sends each request with ``model.send(request)``; the widget answers with ``self.send(message,
buffers=[blob])`` (a message with ``"binary": true`` carries its float64 arrays in its first buffer). While a
synthesis or a run on the motor goes, a daemon thread polls :meth:`Session.poll_jobs` and sends their messages as
they come.

The 3D view of a spatial file needs plotly.js; nothing is loaded from the network: for a spatial document the
widget's ``_plotly_js`` trait carries ``plotly.min.js`` from the plotly Python package, which the page evaluates
when ``window.Plotly`` is missing (it is the empty string for a planar document).

This module imports anywidget (the ``widget`` extra: ``pip install 'assur[widget]'``); ``import assur`` does not
import it: ``assur.designer.Designer`` loads this module on first use.
"""
from __future__ import annotations

import copy
import threading
from pathlib import Path

from ..errors import require
from .assembly import module_text
from .session import Reply, Session, doc_of_toml, document_of

anywidget = require("anywidget", "assur.designer.Designer", "pip install 'assur[widget]'")
import traitlets  # noqa: E402  (anywidget's dependency)

#: how often the running jobs (a synthesis, a run on the motor) are polled for their messages (s)
SYNTH_POLL = 0.1

_STATIC = Path(__file__).resolve().parent / "static"


def plotly_source() -> str:
    """plotly.js as shipped inside the plotly Python package (no CDN)."""
    from .server import plotly_bundle
    return plotly_bundle().read_text(encoding="utf-8")


def _is_toml_text(source: str) -> bool:
    """A string is ``assur/1`` text (not a file name) when it spans lines or starts like a TOML document."""
    head = source.lstrip()
    return "\n" in source or head.startswith(("format", "[", "#"))


def _session_of(source) -> Session:
    from ..model.mechanism import Mechanism
    if isinstance(source, Session):
        return source
    if isinstance(source, Mechanism):
        return Session(*document_of(source))
    if isinstance(source, Path):
        return Session.of_file(source)
    if isinstance(source, str):
        if _is_toml_text(source):
            return Session(doc_of_toml(source, "the TOML text given to assur.designer.Designer"))
        return Session.of_file(source)
    raise TypeError(f"assur.designer.Designer needs a Mechanism, a file path or assur/1 TOML text, not {type(source).__name__}")


class Designer(anywidget.AnyWidget):
    """The interactive designer of a mechanism in a notebook.

    ``source``: an :class:`assur.Mechanism`, the path of a mechanism file (``str`` or :class:`~pathlib.Path`;
    Save writes it back) or ``assur/1`` TOML text. Show it as a cell's value; read the current design back with
    :attr:`document`, :attr:`toml` and :attr:`mechanism`, and the page's numbers with :meth:`result`.
    """

    _esm = module_text()
    _css = _STATIC / "designer.css"
    #: plotly.js for the 3D view of a spatial document ("" for a planar one)
    _plotly_js = traitlets.Unicode("").tag(sync=True)

    def __init__(self, source, **kwargs):
        super().__init__(**kwargs)
        self.session = _session_of(source)
        self._lock = threading.RLock()
        self._poller: threading.Thread | None = None
        self._polling = False
        self._need_plotly()
        self.on_msg(self._on_custom_msg)

    # -- the current design --------------------------------------------------------------------------------
    @property
    def document(self) -> dict:
        """The committed document (a copy, in the file's units)."""
        with self._lock:
            return copy.deepcopy(self.session.doc)

    @property
    def toml(self) -> str:
        """The committed document as ``assur/1`` text."""
        with self._lock:
            return self.session.text(self.session.doc)

    @property
    def mechanism(self):
        """The committed document as an :class:`assur.Mechanism`."""
        from ..io.mechanism_file import from_dict
        return from_dict(self.document, source="the designer's document")

    def result(self) -> tuple[dict, dict]:
        """(message, arrays) of the committed document as the page receives them: the ``result`` message
        (``cycle``, ``model``, ``diagnostics``, …) and its arrays by name (numpy, SI)."""
        from .payload import unpack
        with self._lock:
            reply = self.session.result(None)
        return reply.message, unpack(reply.message.get("arrays", {}), reply.blob)

    # -- the comm ------------------------------------------------------------------------------------------
    def handle(self, request: dict) -> list[Reply]:
        """Answer one request of the page with the session (as the widget does for a message from the front
        end) and send the replies; returns them."""
        with self._lock:
            replies = self.session.handle(request)
            # a spatial document needs plotly.js on the page before its result arrives
            self._need_plotly()
        self._send_replies(replies)
        if any(r.message.get("type") in ("synth_started", "motor_started") for r in replies):
            self._start_poller()
        return replies

    def _on_custom_msg(self, widget, content, buffers) -> None:
        self.handle(content)

    def _send_replies(self, replies) -> None:
        for r in replies:
            self.send(r.message, buffers=None if r.blob is None else [r.blob])

    def _need_plotly(self) -> None:
        if not self._plotly_js and int(self.session.doc.get("dimension", 2)) == 3:
            self._plotly_js = plotly_source()

    # -- the jobs' messages (a synthesis's progress, a run on the motor's end) ------------------------------------
    def _start_poller(self) -> None:
        with self._lock:
            if self._polling:
                return
            self._polling = True
            self._poller = threading.Thread(target=self._poll_jobs, name="assur-designer-jobs", daemon=True)
            self._poller.start()

    def _poll_jobs(self) -> None:
        stop = threading.Event()
        while not stop.wait(SYNTH_POLL):
            with self._lock:
                replies = self.session.poll_jobs()
                running = self.session.jobs_running
            if replies:
                self._send_replies(replies)
            if not running:
                with self._lock:        # a job started after this finds no poller and starts one
                    if not self.session.jobs_running:
                        self._polling = False
                        return

    def close(self) -> None:
        """Cancel a running synthesis and close the widget."""
        session = getattr(self, "session", None)
        if session is not None:
            session.close()
        super().close()
