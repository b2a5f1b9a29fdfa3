"""The designer's web server: one page, its static files and one WebSocket, on 127.0.0.1 only.

Every request needs the session's random token (the ``token`` query parameter, or the cookie the page sets);
a ``Host`` header other than 127.0.0.1 or localhost is refused (``TrustedHostMiddleware``); a WebSocket whose
``Origin`` is not the page's own origin is refused. The WebSocket carries the protocol of ``docs/designer.md``;
each request is answered by :class:`~assur.designer.session.Session` in a worker thread, so the progress of a
synthesis keeps streaming while a drag is solved.
"""
from __future__ import annotations

import asyncio
import json
import secrets
import socket
import threading
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from .assembly import module_text
from .session import Session, parse_request

COOKIE = "assur_token"
ALLOWED_HOSTS = ["127.0.0.1", "localhost"]
#: how often the running jobs (a synthesis, a run on the motor) are polled for their messages (s)
SYNTH_POLL = 0.1


def static_dir() -> Path:
    return Path(str(resources.files("assur.designer") / "static"))


def plotly_bundle() -> Path:
    """plotly.js as shipped inside the plotly package (no CDN)."""
    import plotly
    return Path(plotly.__file__).parent / "package_data" / "plotly.min.js"


def _token_ok(request_or_ws, token: str) -> bool:
    given = request_or_ws.query_params.get("token") or request_or_ws.cookies.get(COOKIE) or ""
    return secrets.compare_digest(given.encode(), token.encode())


def create_app(session: Session, token: str):
    """The Starlette application of one session."""
    from starlette.applications import Starlette
    from starlette.middleware import Middleware
    from starlette.middleware.trustedhost import TrustedHostMiddleware
    from starlette.responses import FileResponse, HTMLResponse, PlainTextResponse, Response
    from starlette.routing import Route, WebSocketRoute
    from starlette.websockets import WebSocketDisconnect

    lock = threading.Lock()
    static = static_dir()
    files = {p.name: p for p in static.iterdir() if p.is_file()}
    files["plotly.min.js"] = plotly_bundle()
    types = {".js": "text/javascript", ".css": "text/css", ".html": "text/html", ".svg": "image/svg+xml"}
    headers = {"Cache-Control": "no-store", "X-Content-Type-Options": "nosniff",
               "Content-Security-Policy": "default-src 'self'; connect-src 'self' ws://127.0.0.1:* ws://localhost:*; "
                                          "img-src 'self' data: blob:; style-src 'self' 'unsafe-inline'; "
                                          "script-src 'self' 'unsafe-eval'; frame-ancestors 'none'"}

    def refused(reason: str):
        return PlainTextResponse(f"refused: {reason}\n", status_code=403)

    async def page(request):
        if not _token_ok(request, token):
            return refused("missing or wrong token; open the URL that `assur design` printed")
        html = (static / "index.html").read_text(encoding="utf-8")
        response = HTMLResponse(html, headers=headers)
        response.set_cookie(COOKIE, token, httponly=True, samesite="strict")
        return response

    async def static_file(request):
        if not _token_ok(request, token):
            return refused("missing or wrong token")
        name = request.path_params["name"]
        if name == "designer.js":       # the page's module, joined from static/parts (assembly.py)
            return Response(module_text(), media_type="text/javascript", headers=headers)
        path = files.get(name)
        if path is None:
            return PlainTextResponse("not found\n", status_code=404)
        return FileResponse(path, media_type=types.get(path.suffix, "application/octet-stream"), headers=headers)

    def solve(request: dict):
        with lock:
            return session.handle(request)

    def poll():
        with lock:
            return session.poll_jobs()

    async def send(ws, replies):
        for r in replies:
            await ws.send_text(json.dumps(r.message, allow_nan=False))
            if r.blob is not None:
                await ws.send_bytes(r.blob)

    async def socket_endpoint(ws):
        origin = ws.headers.get("origin", "")
        host = ws.headers.get("host", "")
        if not _token_ok(ws, token):
            await ws.close(code=1008, reason="missing or wrong token")
            return
        if origin != f"http://{host}":
            await ws.close(code=1008, reason=f"foreign origin {origin or '(none)'}")
            return
        await ws.accept()
        sending = asyncio.Lock()
        with lock:
            session.clients += 1

        async def stream_jobs():
            while True:
                await asyncio.sleep(SYNTH_POLL)
                if session.job is not None or session.motor_job is not None:
                    replies = await asyncio.to_thread(poll)
                    if replies:
                        async with sending:
                            await send(ws, replies)

        streamer = asyncio.create_task(stream_jobs())
        try:
            while True:
                message = await ws.receive()
                if message["type"] == "websocket.disconnect":
                    break
                text = message.get("text")
                request = parse_request(text if text is not None else message.get("bytes"))
                replies = await asyncio.to_thread(solve, request)
                async with sending:
                    await send(ws, replies)
        except WebSocketDisconnect:
            pass
        finally:
            streamer.cancel()
            await asyncio.to_thread(leave)

    def leave():
        """A page closed: when it was the last, its running synthesis and run on the motor stop (nobody would see
        them)."""
        with lock:
            session.clients -= 1
            if session.clients <= 0:
                for job in (session.job, session.motor_job):
                    if job is not None and job.running:
                        job.cancel()

    routes = [Route("/", page), Route("/static/{name}", static_file), WebSocketRoute("/ws", socket_endpoint)]
    return Starlette(routes=routes, middleware=[Middleware(TrustedHostMiddleware, allowed_hosts=ALLOWED_HOSTS)])


@dataclass
class RunningServer:
    """A designer server running in a background thread (tests, benchmarks, notebooks): ``url`` (with the
    token), ``port``, ``token``, ``session``; ``stop()`` shuts it down."""
    url: str
    port: int
    token: str
    session: Session
    _server: object
    _thread: threading.Thread

    def stop(self) -> None:
        self._server.should_exit = True
        self._thread.join(timeout=10)
        self.session.close()


def bind(port: int = 0) -> socket.socket:
    """A listening socket on 127.0.0.1 (``port`` 0: any free port)."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    # no Nagle delay (accepted sockets inherit it): an answer's binary frame right after its text frame otherwise
    # waits for the delayed ACK of the first, some 40 ms, now and then
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    sock.bind(("127.0.0.1", int(port)))
    sock.listen(64)
    return sock


def _uvicorn_server(app):
    import uvicorn
    config = uvicorn.Config(app, log_level="warning", ws="websockets-sansio", lifespan="off",
                            ws_per_message_deflate=False)   # loopback: compressing 150 kB per answer costs ms
    return uvicorn.Server(config)


def _warm(session: Session) -> None:
    """Answer the document once (kernels loaded, caches filled), then move every object alive so far out of the
    garbage collector's generations (``gc.freeze``): a full collection of the imported libraries' objects would
    otherwise stall a drag now and then."""
    import gc
    session.handle({"op": "hello", "seq": None})
    _prepare_kernels(session)
    gc.collect()
    gc.freeze()


def _prepare_kernels(session: Session):
    """A mechanism with Newton-solved groups (a triad): its compiled kernel loaded in a background thread (and
    compiled first if it is not cached yet: seconds, once per structure); until it is ready the previews run on
    numpy, then on it (``backend="auto"``: a ready kernel serves every preview once numba is imported). Returns the
    thread, or None."""
    from ..engine.planar import numba_backend
    plan = session.entry(session.doc).plan
    if plan is None or not (numba_backend.available() and numba_backend.newton_covers(plan)):
        return None
    thread = threading.Thread(target=numba_backend.prepare_newton, args=(plan,), daemon=True,
                              name="assur-newton-kernel")
    thread.start()
    return thread


def start_server(session: Session, port: int = 0) -> RunningServer:
    """Serve ``session`` in a background thread; returns when the server accepts connections."""
    token = secrets.token_urlsafe(24)
    sock = bind(port)
    port = sock.getsockname()[1]
    server = _uvicorn_server(create_app(session, token))
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    while not server.started and thread.is_alive():
        threading.Event().wait(0.01)
    return RunningServer(f"http://127.0.0.1:{port}/?token={token}", port, token, session, server, thread)


def serve(session: Session, port: int = 0, open_browser: bool = True, announce=print) -> None:
    """Serve ``session`` until interrupted, printing the URL (and opening it in the browser)."""
    token = secrets.token_urlsafe(24)
    sock = bind(port)
    port = sock.getsockname()[1]
    url = f"http://127.0.0.1:{port}/?token={token}"
    server = _uvicorn_server(create_app(session, token))
    _warm(session)
    announce(f"assur design: {url}")
    announce("(Ctrl-C stops the server)")
    if open_browser:
        import webbrowser
        threading.Timer(0.5, webbrowser.open, args=(url,)).start()
    try:
        server.run(sockets=[sock])
    finally:
        session.close()
