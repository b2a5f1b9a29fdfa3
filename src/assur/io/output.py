"""Atomic outputs: a file or a whole output directory appears complete or not at all.

``atomic_file(path)`` yields a temporary path next to ``path``; ``atomic_directory(out_dir)`` yields a
temporary directory next to ``out_dir`` to fill with any number of files. On success they are moved
into place (files into an existing directory replace their namesakes one by one); on any failure,
including Ctrl-C, the temporaries are removed and directories created for the output are removed again.
"""
from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import tempfile
from pathlib import Path

from ..errors import AssurError


class OutputError(AssurError, OSError):
    """An output location cannot be used (it is a directory, or its parent does not exist)."""


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def check_writable(path) -> Path:
    """OutputError unless ``path`` can become a file (not a directory; its directory exists).
    Returns the directory."""
    path = Path(path)
    if path.is_dir():
        raise OutputError(f"cannot write {path}: it is a directory")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"cannot write {path}: the directory {parent} does not exist")
    return parent


@contextlib.contextmanager
def atomic_file(path):
    """Yield a temporary path next to ``path`` (same suffix); on success it replaces ``path``."""
    path = Path(path)
    parent = check_writable(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f".tmp{path.suffix}", dir=parent)
    os.close(fd)
    tmp = Path(tmp)
    os.chmod(tmp, 0o666 & ~_umask())
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


@contextlib.contextmanager
def atomic_directory(out_dir):
    """Yield a temporary directory next to ``out_dir``; on success its files become ``out_dir``'s.

    Missing parents are created, and removed again on failure."""
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise OutputError(f"cannot write {out_dir}: it is not a directory")
    parent = out_dir.parent if str(out_dir.parent) else Path(".")
    created = [p for p in reversed([parent, *parent.parents]) if not p.exists()]
    for p in created:
        p.mkdir()
    tmp = None
    try:
        tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.", suffix=".tmp", dir=parent))
        os.chmod(tmp, 0o777 & ~_umask())
        yield tmp
        if out_dir.is_dir():
            for item in sorted(tmp.iterdir()):
                target = out_dir / item.name
                if target.is_dir() and item.is_dir():
                    shutil.rmtree(target)
                os.replace(item, target)
            tmp.rmdir()
        else:
            os.rename(tmp, out_dir)
        tmp = None
    except BaseException:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        for p in reversed(created):
            with contextlib.suppress(OSError):
                p.rmdir()
        raise


def json_ready(x):
    """Strict-JSON data: non-finite floats → None; numpy scalars and arrays → Python numbers and lists."""
    import numpy as np
    if isinstance(x, dict):
        return {str(k): json_ready(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [json_ready(v) for v in x]
    if isinstance(x, np.ndarray):
        return json_ready(x.tolist())
    if isinstance(x, (np.floating, float)):
        x = float(x)
        return x if math.isfinite(x) else None
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.bool_):
        return bool(x)
    return x


def json_text(data) -> str:
    """``data`` as indented strict JSON (UTF-8 text, no NaN)."""
    return json.dumps(json_ready(data), ensure_ascii=False, indent=2, allow_nan=False)


__all__ = ["OutputError", "atomic_directory", "atomic_file", "check_writable", "json_ready", "json_text"]
