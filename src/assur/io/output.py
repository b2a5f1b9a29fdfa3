"""Safe outputs: a file or a whole output directory appears complete or not at all; CSV and JSON text.

``atomic_file(path)`` yields a temporary path to write; on success it becomes ``path``:

- a regular file (or a new name) is replaced atomically (the temporary file sits next to it);
- ``-`` is standard output, and a character device, block device or FIFO (``/dev/null``, a named pipe,
  ``/dev/stdout`` into a pipe) is written through: the complete content is copied into it, the node itself is never
  replaced; a reader that closes the pipe early (``| head``) raises BrokenPipeError, which the command line ends
  quietly with status 0, as Unix tools do;
- a symbolic link is followed: what it points to is written by the rules above and the link stays;
- a directory, a socket or an empty path is refused with :class:`~assur.errors.OutputError`.

``atomic_directory(out_dir)`` yields a temporary directory next to ``out_dir`` to fill with one run's files.
On success it *becomes* ``out_dir``: an output directory holds exactly one run's files. An existing
``out_dir`` is replaced only when it is empty or an earlier output (it holds the marker file
``.assur-output``); any other existing directory is refused, so no user file is ever deleted. Temporary
directories that an interrupted run left (``.NAME.<pid>.*.tmp`` of a process that no longer runs) are
removed on the next run. On any failure, including Ctrl-C, the temporaries are removed and directories
created for the output are removed again; messages name the user's path, never a temporary one.
``write_csv`` writes a table through ``atomic_file``; ``json_text`` gives strict JSON.
"""
from __future__ import annotations

import contextlib
import csv
import json
import math
import os
import shutil
import stat
import sys
import tempfile
from pathlib import Path

import numpy as np

from ..errors import OutputError


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: the file that marks a directory as an output of assur (which a later run may replace)
MARKER = ".assur-output"


def _target(path) -> Path:
    """The path to write: ``path`` with symbolic links followed; OutputError for an empty path. A link to a device
    or a pipe stays as given (``/dev/stdout`` into a pipe resolves to ``/proc/<pid>/fd/pipe:[…]``, a name that
    cannot be opened, while the link itself opens the pipe)."""
    if str(path) == "":
        raise OutputError("the output path is empty")
    path = Path(path)
    if not path.is_symlink():
        return path
    try:
        mode = path.stat().st_mode
    except OSError:
        mode = 0
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) or stat.S_ISFIFO(mode):
        return path
    return Path(os.path.realpath(path))


def _write_through(path: Path) -> bool:
    """True for ``-`` and for a device or FIFO: written through, never replaced."""
    if str(path) == "-":
        return True
    try:
        mode = path.stat().st_mode
    except OSError:
        return False
    return stat.S_ISCHR(mode) or stat.S_ISBLK(mode) or stat.S_ISFIFO(mode)


def is_standard_output(path) -> bool:
    """True when ``path`` is this process's standard output (``-``, ``/dev/stdout`` or another name of the same
    file or pipe): a command writing its data there sends its report lines to standard error instead."""
    if path is None:
        return False
    if str(path) == "-":
        return True
    try:
        here, there = os.fstat(sys.stdout.fileno()), os.stat(path)
    except (OSError, ValueError, AttributeError):
        return False
    return (here.st_dev, here.st_ino) == (there.st_dev, there.st_ino)


def check_writable(path) -> Path:
    """OutputError unless ``path`` can take an output (see :func:`atomic_file`). Returns its directory."""
    target = _target(path)
    if _write_through(target):
        return target.parent
    if target.is_dir():
        raise OutputError(f"cannot write {path}: it is a directory")
    if target.exists() and not target.is_file():
        raise OutputError(f"cannot write {path}: it is not a regular file (a socket?); it is never replaced")
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"cannot write {path}: the directory {parent} does not exist")
    return parent


@contextlib.contextmanager
def atomic_file(path):
    """Yield a temporary path (with ``path``'s suffix) to write; on success it becomes ``path`` by the rules
    of this module: a regular file is replaced atomically, ``-``, devices and FIFOs are written through."""
    parent = check_writable(path)
    target = _target(path)
    through = _write_through(target)
    suffix = "" if str(target) == "-" else target.suffix
    fd, tmp = tempfile.mkstemp(prefix=f".{target.stem or 'out'}.", suffix=f".tmp{suffix}",
                               dir=None if through else parent)
    os.close(fd)
    tmp = Path(tmp)
    os.chmod(tmp, 0o666 & ~_umask())
    try:
        yield tmp
        try:
            if not through:
                os.replace(tmp, target)
            elif str(target) == "-":
                sys.stdout.flush()
                sys.stdout.buffer.write(tmp.read_bytes())
                sys.stdout.flush()
            else:
                with open(target, "wb") as out, open(tmp, "rb") as src:
                    shutil.copyfileobj(src, out)
        except BrokenPipeError:
            raise                   # the reader has gone (``| head``): the command ends quietly (cli.main)
        except OSError as exc:
            raise OutputError(f"cannot write {path}: {exc.strerror or exc}") from None
    finally:
        with contextlib.suppress(OSError):
            tmp.unlink()


def _remove_stale_temporaries(parent: Path, name: str) -> None:
    """Remove ``.NAME.<pid>.*.tmp`` directories of runs that no longer run (SIGKILL leaves them)."""
    for old in parent.glob(f".{name}.*.tmp"):
        parts = old.name[len(name) + 2:].split(".")
        if not (old.is_dir() and parts and parts[0].isdigit()):
            continue
        pid = int(parts[0])
        if pid == os.getpid():
            continue
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            shutil.rmtree(old, ignore_errors=True)
        except OSError:
            pass


def check_output_directory(out_dir) -> Path:
    """OutputError unless :func:`atomic_directory` may write ``out_dir`` (checked before a long computation too):
    not empty as a path, not a file, empty or an earlier output of assur. Returns the directory (symlinks
    resolved)."""
    if str(out_dir) == "":
        raise OutputError("the output directory path is empty")
    out_dir = Path(out_dir)
    if out_dir.is_symlink():
        out_dir = Path(os.path.realpath(out_dir))
    if out_dir.exists() and not out_dir.is_dir():
        raise OutputError(f"cannot write {out_dir}: it is not a directory")
    if out_dir.is_dir() and any(out_dir.iterdir()) and not (out_dir / MARKER).exists():
        raise OutputError(f"cannot write into {out_dir}: it holds files that are not an earlier output of assur "
                          f"(no {MARKER}); choose a new directory or empty it")
    return out_dir


@contextlib.contextmanager
def atomic_directory(out_dir):
    """Yield a temporary directory next to ``out_dir``; on success it becomes ``out_dir`` (one run's files).

    Missing parents are created, and removed again on failure. An existing ``out_dir`` must be empty or an
    earlier output (holding ``.assur-output``)."""
    out_dir = check_output_directory(out_dir)
    parent = out_dir.parent if str(out_dir.parent) else Path(".")
    created = [p for p in reversed([parent, *parent.parents]) if not p.exists()]
    for p in created:
        p.mkdir()
    if not created:
        _remove_stale_temporaries(parent, out_dir.name)
    tmp = old = None
    try:
        tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.{os.getpid()}.", suffix=".tmp", dir=parent))
        os.chmod(tmp, 0o777 & ~_umask())
        yield tmp
        (tmp / MARKER).write_text("This directory is an output of assur: a later run into it replaces it whole.\n",
                                  encoding="utf-8")
        try:
            if out_dir.is_dir():
                old = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.{os.getpid()}.", suffix=".tmp", dir=parent))
                os.rename(out_dir, old / "previous")
            os.rename(tmp, out_dir)
        except OSError as exc:
            if old is not None and (old / "previous").exists() and not out_dir.exists():
                os.rename(old / "previous", out_dir)
            raise OutputError(f"cannot write {out_dir}: {exc.strerror or exc}") from None
        tmp = None
    except BaseException:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        for p in reversed(created):
            with contextlib.suppress(OSError):
                p.rmdir()
        raise
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)


def csv_cell(v):
    """A table cell as written by :func:`write_csv`: floats as their shortest round-trip text (``repr``) or
    ``nan``, numpy integers as ints, anything else as it is."""
    if isinstance(v, (float, np.floating)):
        v = float(v)
        return "nan" if not math.isfinite(v) else repr(v)
    if isinstance(v, (np.integer,)):
        return int(v)
    return v


def write_csv(path, header, rows, *, cell=csv_cell, line_end: str = "\r\n") -> Path:
    """Write a table atomically as CSV: ``header`` (names with units), then ``rows`` (sequences of values),
    each value written as ``cell(value)`` (default :func:`csv_cell`) and each line ended by ``line_end``."""
    path = Path(path)
    with atomic_file(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            w = csv.writer(fh, lineterminator=line_end)
            w.writerow(list(header))
            for r in rows:
                w.writerow([cell(v) for v in r])
    return path


def json_ready(x):
    """Strict-JSON data: non-finite floats → None; numpy scalars and arrays → Python numbers and lists."""
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


__all__ = ["MARKER", "OutputError", "atomic_directory", "atomic_file", "check_writable", "csv_cell", "json_ready", "json_text",
           "write_csv"]
