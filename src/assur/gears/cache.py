"""A disk cache of the expensive gear results (the rack-cut outlines of :mod:`assur.gears.teeth`, the mesh checks of
:mod:`assur.gears.mesh`), so that ``assur gears``, ``assur wheelstep`` and ``assur report`` on the same design
reuse them across processes.

Where: ``$ASSUR_CACHE_DIR/gears`` when the variable is set (``ASSUR_CACHE_DIR=off`` turns this cache off), else
``$XDG_CACHE_HOME/assur/gears``, else ``~/.cache/assur/gears`` — never the output directory. A cache that cannot be
created or written is skipped silently (the result is computed as without it).

Key: a SHA-256 digest of the result's kind, its inputs as the computation sees them (the sampled pitch curves, the
outlines, the law at the scanned angles: the canonical content of the design for that result, whatever file it came
from), every setting, the digest of the source files of ``assur/gears`` (and ``assur/tolerances.py``) and the versions
of Python, numpy, shapely and GEOS. A change of any of these gives another key, so an entry is never stale.

Entries: one ``.npz`` file each (plain arrays and a JSON text; read with ``allow_pickle=False``), written to a
temporary file in the cache directory and renamed into place (:func:`os.replace`), so a reader sees a whole entry
or none. An entry that cannot be read, or whose stored key differs, is ignored and recomputed (and rewritten).
The directory keeps at most :data:`MAX_ENTRIES` entries (the least recently used are removed).
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import sys
from pathlib import Path

import numpy as np

from ..kernels.cache_root import ENV, cache_root

#: most entries kept in the directory
MAX_ENTRIES = 256
#: the entry layout; part of every key
FORMAT = 1

#: counters of this process: entries read, computed (missing, unreadable or stale), written, rejected (unreadable)
STATS = {"hits": 0, "misses": 0, "writes": 0, "rejected": 0}

_SOURCE_DIGEST: str | None = None


def cache_dir() -> Path | None:
    """The directory of the gear cache, or None when ``ASSUR_CACHE_DIR=off`` (see the module docstring)."""
    return cache_root("gears")


def source_digest() -> str:
    """SHA-256 (hex) of the source files that produce the cached results: ``assur/gears/*.py`` and
    ``assur/tolerances.py`` (names and contents), computed once per process."""
    global _SOURCE_DIGEST
    if _SOURCE_DIGEST is None:
        here = Path(__file__).resolve().parent
        h = hashlib.sha256()
        for path in sorted(here.glob("*.py")) + [here.parent / "tolerances.py"]:
            h.update(path.name.encode() + b"\0")
            h.update(path.read_bytes() if path.is_file() else b"")
            h.update(b"\0")
        _SOURCE_DIGEST = h.hexdigest()
    return _SOURCE_DIGEST


def _environment() -> tuple:
    import shapely
    return (FORMAT, sys.version_info[:2], np.__version__, shapely.__version__, shapely.geos_version_string)


def _feed(h, part) -> None:
    """Hash ``part`` (arrays, numbers, strings, None, and tuples/lists/dicts of them) unambiguously into h."""
    if isinstance(part, np.ndarray):
        a = np.ascontiguousarray(part)
        h.update(f"A{a.dtype.str}{a.shape}".encode())
        h.update(a.tobytes())
    elif isinstance(part, (tuple, list)):
        h.update(f"T{len(part)}(".encode())
        for p in part:
            _feed(h, p)
        h.update(b")")
    elif isinstance(part, dict):
        _feed(h, sorted(part.items()))
    elif isinstance(part, (bool, np.bool_)):
        h.update(b"B1" if part else b"B0")
    elif isinstance(part, (int, np.integer)):
        h.update(f"I{int(part)}".encode())
    elif isinstance(part, (float, np.floating)):
        h.update(f"F{float(part)!r}".encode())     # repr: exact (shortest round-trip), -0.0 and nan distinct
    elif isinstance(part, str):
        h.update(f"S{len(part)}:".encode() + part.encode())
    elif part is None:
        h.update(b"N")
    else:
        raise TypeError(f"cannot key a {type(part).__name__}")


def digest(*parts) -> str:
    """The SHA-256 (hex) of ``parts``: equal parts, equal digest; any change of a value, a dtype or a shape, another."""
    h = hashlib.sha256()
    _feed(h, parts)
    return h.hexdigest()


def entry_path(kind: str, key_parts) -> Path | None:
    """The file of the entry of ``kind`` for ``key_parts`` (None when the cache is off)."""
    d = cache_dir()
    if d is None:
        return None
    return d / f"{kind}-{_key(kind, key_parts)[:40]}.npz"


def _key(kind, key_parts) -> str:
    return digest(kind, source_digest(), _environment(), key_parts)


def cached(kind: str, key_parts, compute, pack, unpack):
    """``compute()``, or its result stored under (kind, key_parts) by an earlier call in any process.

    pack(result) → (arrays {name: ndarray}, meta: JSON-able dict); unpack(arrays, meta) → result. Stored floats
    are exact (arrays as written; JSON floats round-trip), so a hit returns what ``compute()`` returned."""
    d = cache_dir()
    if d is None:
        return compute()
    key = _key(kind, key_parts)
    path = d / f"{kind}-{key[:40]}.npz"
    found = _read(path, key)
    if found is not None:
        try:
            result = unpack(*found)
        except (KeyError, ValueError, TypeError, IndexError):
            STATS["rejected"] += 1
        else:
            STATS["hits"] += 1
            return result
    STATS["misses"] += 1
    result = compute()
    arrays, meta = pack(result)
    _write(d, path, key, arrays, meta)
    return result


def _read(path: Path, key: str):
    """(arrays, meta) of the entry at path if it is whole and holds ``key``, else None."""
    try:
        with np.load(path, allow_pickle=False) as z:
            if str(z["__key__"]) != key:
                raise ValueError("another key")
            meta = json.loads(str(z["__meta__"]))
            arrays = {name: z[name] for name in z.files if not name.startswith("__")}
    except OSError:                    # no entry (or no readable directory)
        return None
    except Exception:  # noqa: BLE001 - a truncated, corrupt or foreign file: ignored, recomputed, rewritten
        STATS["rejected"] += 1
        return None
    try:
        os.utime(path)                 # recently used: kept by the pruning
    except OSError:
        pass
    return arrays, meta


def _write(d: Path, path: Path, key: str, arrays: dict, meta: dict) -> None:
    """Write the entry atomically: a temporary file in the cache directory, then os.replace. Any OSError (no
    space, a read-only directory) leaves no temporary file and no entry."""
    import tempfile
    tmp = None
    try:
        d.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}-", suffix=".tmp", dir=d)
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, __key__=np.array(key), __meta__=np.array(json.dumps(meta, allow_nan=True)), **arrays)
        os.replace(tmp, path)
        tmp = None
        STATS["writes"] += 1
        _prune(d)
    except OSError:
        pass
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass


def _prune(d: Path) -> None:
    """Keep the MAX_ENTRIES most recently used entries."""
    entries = list(d.glob("*.npz"))
    if len(entries) <= MAX_ENTRIES:
        return
    def mtime(p):
        try:
            return p.stat().st_mtime
        except OSError:
            return math.inf
    for p in sorted(entries, key=mtime)[:len(entries) - MAX_ENTRIES]:
        try:
            p.unlink()
        except OSError:
            pass


__all__ = ["ENV", "MAX_ENTRIES", "STATS", "cache_dir", "cached", "digest", "entry_path", "source_digest"]
