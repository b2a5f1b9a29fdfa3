"""Where the package keeps what it computes once and reuses across processes (generated kernels, gear results).

``$ASSUR_CACHE_DIR/<kind>``, else ``$XDG_CACHE_HOME/assur/<kind>``, else ``~/.cache/assur/<kind>``;
``ASSUR_CACHE_DIR=off`` keeps nothing across processes (:func:`cache_root` returns None)."""
from __future__ import annotations

import os
from pathlib import Path

#: the environment variable that moves (or, set to ``off``, disables) the caches
ENV = "ASSUR_CACHE_DIR"
#: values of ENV that disable the caches
OFF = ("off",)


def cache_root(kind: str) -> Path | None:
    """The cache directory of ``kind`` ('kernels', 'gears'), or None when the caches are off."""
    base = os.environ.get(ENV, "").strip()
    if base.lower() in OFF:
        return None
    if base:
        return Path(base).expanduser() / kind
    xdg = os.environ.get("XDG_CACHE_HOME", "").strip()
    return (Path(xdg) if xdg else Path.home() / ".cache") / "assur" / kind
