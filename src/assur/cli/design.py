"""``assur design FILE``: the interactive designer in the browser (``docs/designer.md``).

The server binds 127.0.0.1 only and prints the page's URL with its random token; it needs the ``web`` extra
(starlette, uvicorn, websockets).
"""
from __future__ import annotations


def register(sub) -> None:
    """Add ``assur design`` to the argparse sub-parsers ``sub``."""
    help_ = "edit a mechanism interactively in the browser (a local server on 127.0.0.1)"
    sp = sub.add_parser("design", help=help_, description=help_ + "; needs: pip install 'assur[web]'")
    sp.add_argument("file", metavar="FILE", help="mechanism file (.toml); Save writes it back")
    sp.add_argument("--port", type=int, default=0, metavar="PORT",
                    help="port on 127.0.0.1 (default 0: any free port)")
    sp.add_argument("--no-browser", action="store_true", help="print the URL only; do not open a browser")
    sp.set_defaults(func=cmd_design)


def cmd_design(args) -> int:
    from ..errors import SpecError, require
    if not 0 <= args.port <= 65535:
        raise SpecError([("--port", f"must be from 0 to 65535: {args.port}")])
    for package in ("starlette", "uvicorn", "websockets"):
        require(package, "assur design", "pip install 'assur[web]'")
    from ..designer.server import serve
    from ..designer.session import Session
    session = Session.of_file(args.file)
    try:
        serve(session, port=args.port, open_browser=not args.no_browser,
              announce=lambda line: print(line, flush=True))
    except KeyboardInterrupt:      # Ctrl-C is how a server is stopped: not an error
        print("assur design: stopped", flush=True)
    except OSError as exc:
        from ..errors import OutputError
        raise OutputError(f"cannot serve on 127.0.0.1:{args.port}: {exc.strerror or exc}") from None
    return 0
