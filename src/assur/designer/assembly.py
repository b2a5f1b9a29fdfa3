"""The designer's page module, assembled from its parts at import time (no build tool, no Node).

The front end lives in ``static/parts/`` as plain ES modules, one per concern: ``util.js`` (units, DOM and geometry
helpers), ``channel.js`` (the request channel, a result's arrays, share links), ``canvas.js`` (the 2D canvas and the
3D view), ``gestures.js`` (the pointer gestures and the tools' clicks), ``panels.js`` (the side panels and plots),
``synthesis.js`` (the synthesis panel), ``motor.js`` (the run on the motor), ``chooser.js``
(the chooser of assemblies) and ``designer.js`` (the Designer itself and ``render``, the entry). Each part imports what it uses from the
others with one-line ``import { … } from "./part.js";`` statements, so the parts also load natively as a module
graph. :func:`module_text` joins them, in :data:`PARTS` order, into the one ES module that the page
(``/static/designer.js``) and the notebook widget (``_esm``) load: the local imports are dropped (every name they
import must be exported by an earlier part) and the parts' ``export`` keywords are removed, except the entry's.
"""
from __future__ import annotations

import functools
import re
from pathlib import Path

#: the parts, each after the parts it imports from; the last is the entry (its exports are the module's)
PARTS = ("util.js", "channel.js", "canvas.js", "gestures.js", "panels.js", "synthesis.js", "motor.js",
         "chooser.js", "designer.js")

_IMPORT = re.compile(r'^import\s*\{([^}]*)\}\s*from\s*"\./([\w-]+\.js)";\s*$')
_DECLARATION = re.compile(r"^(export\s+)?(?:const|let|function|class|async\s+function)\s+([A-Za-z_$][\w$]*)")


class AssemblyError(RuntimeError):
    """The parts do not join into one module (a defect of the package, found by its tests)."""


def parts_dir() -> Path:
    return Path(__file__).resolve().parent / "static" / "parts"


def assemble(texts: dict[str, str]) -> str:
    """One ES module of the parts ``texts`` (name → source, in :data:`PARTS` order); AssemblyError when an import
    names a part not yet joined or a name that part does not export, or when two parts declare one name."""
    exported: dict[str, set[str]] = {}
    declared: dict[str, str] = {}
    out: list[str] = []
    names = list(texts)
    for position, (name, text) in enumerate(texts.items()):
        entry = position == len(names) - 1
        exports: set[str] = set()
        out.append(f"// ---- {name} " + "-" * max(3, 104 - len(name)))
        for number, line in enumerate(text.splitlines(), 1):
            imported = _IMPORT.match(line)
            if imported:
                part = imported.group(2)
                if part not in exported:
                    raise AssemblyError(f"{name}:{number}: imports from {part}, which is not an earlier part")
                for symbol in (s.strip() for s in imported.group(1).split(",") if s.strip()):
                    if symbol not in exported[part]:
                        raise AssemblyError(f"{name}:{number}: {part} does not export {symbol}")
                continue
            if line.startswith("import "):
                raise AssemblyError(f"{name}:{number}: only one-line imports of other parts are allowed: {line}")
            declaration = _DECLARATION.match(line)
            if declaration:
                symbol = declaration.group(2)
                if symbol in declared:
                    raise AssemblyError(f"{name}:{number}: {symbol} is declared in {declared[symbol]} already")
                declared[symbol] = name
                if declaration.group(1):
                    exports.add(symbol)
                    if not entry:
                        line = line[len(declaration.group(1)):]
            elif line.startswith("export ") and not entry:
                raise AssemblyError(f"{name}:{number}: a part exports declarations only: {line}")
            out.append(line)
        exported[name] = exports
    return "\n".join(out) + "\n"


@functools.lru_cache(maxsize=1)
def module_text() -> str:
    """The page's ES module: the parts of ``static/parts`` joined (see the module docstring)."""
    root = parts_dir()
    return assemble({name: (root / name).read_text(encoding="utf-8") for name in PARTS})


__all__ = ["AssemblyError", "PARTS", "assemble", "module_text", "parts_dir"]
