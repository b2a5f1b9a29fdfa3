"""The import rules of a package, checked against a declared layer table.

The table is a Markdown table in a document (docs/architecture.md for assur), introduced by the line
``<!-- layer table -->``, with the columns ``package | layer | may also import``: every top-level package or module
of the package root, its layer (0 is the lowest), and the packages of its own layer it may import. A module may
import any package of a lower layer, the packages its row lists, and its own package; nothing else.

:func:`violations` reads a package tree and returns one line per broken rule:

* ``cycle of modules``: a strongly connected component of the module import graph (more than one module);
* ``cycle of packages``: the same on the graph of the top-level packages;
* ``not allowed``: an import of a package of a higher layer, or of the same layer that the table does not list;
* ``no layer``: a top-level package or module missing from the table, or a table row naming nothing;
* ``private``: a ``_private`` name or module of another package;
* ``root``: a module inside the package importing the package root (``from .. import x``, ``import assur``);
* ``dynamic``: an ``__import__`` or ``importlib.import_module`` call whose module is not a literal string (a
  literal is read like an import), outside the modules the document declares on a line
  ``<!-- dynamic imports: pkg.module, … -->`` (the one gateway that imports optional third-party packages by name).

Every import counts, at module level or inside a function. The package root's ``__init__`` (the public API, which
loads its names lazily) is exempt from the layer and root rules, and its lazy table's strings count as its imports.
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

TABLE_MARK = "<!-- layer table -->"


# -- the declared table -------------------------------------------------------------------------------------
def read_dynamic(document: Path) -> frozenset:
    """The modules (dotted, below the root) allowed to import by a computed name, from the document's
    ``<!-- dynamic imports: … -->`` line (empty without one)."""
    m = re.search(r"<!-- dynamic imports:([^>]*)-->", Path(document).read_text(encoding="utf-8"))
    return frozenset(x.strip() for x in m.group(1).split(",") if x.strip()) if m else frozenset()


def read_table(document: Path) -> dict[str, tuple[int, frozenset]]:
    """{package: (layer, packages of its layer it may import)} of the table after :data:`TABLE_MARK`."""
    text = Path(document).read_text(encoding="utf-8")
    if TABLE_MARK not in text:
        raise ValueError(f"{document}: no '{TABLE_MARK}' line")
    rows = {}
    for line in text.split(TABLE_MARK, 1)[1].lstrip().splitlines():
        if not line.startswith("|"):
            break
        cells = [c.strip().strip("`") for c in line.strip().strip("|").split("|")]
        if cells[0] in ("package", "") or set(cells[0]) <= set("-: "):
            continue
        allowed = frozenset(p.strip().strip("`") for p in re.split(r"[,\s]+", cells[2]) if p.strip().strip("`"))
        rows[cells[0]] = (int(cells[1]), allowed)
    return rows


# -- the modules and their imports -------------------------------------------------------------------------
class Tree:
    """The modules of a package directory ``root`` (named ``name``): dotted names, paths, packages and, per module,
    its imports of the package as (target module, written source, written name, line)."""

    def __init__(self, root: Path, name: str | None = None):
        self.root = Path(root)
        self.name = name or self.root.name
        self.paths = {self.module_name(p): p for p in sorted(self.root.rglob("*.py"))}
        self.packages = {self.module_name(p) for p in self.root.rglob("__init__.py")}
        self.trees = {m: ast.parse(p.read_text(encoding="utf-8")) for m, p in self.paths.items()}
        self.reexports = {pkg: self._reexports(pkg) for pkg in self.packages}
        self.imports = {m: list(self._imports(m)) for m in self.paths}

    def module_name(self, path: Path) -> str:
        parts = (self.name,) + path.relative_to(self.root).with_suffix("").parts
        return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)

    def top(self, module: str) -> str:
        """The top-level package or module of ``module`` (``gears`` for pkg.gears.law), ``__root__`` for the root."""
        parts = module.split(".")
        return parts[1] if len(parts) > 1 else "__root__"

    def _absolute(self, module: str, node: ast.ImportFrom) -> str:
        if node.level == 0:
            return node.module or ""
        package = module if module in self.packages else module.rpartition(".")[0]
        base = package.split(".")
        base = base[: len(base) - (node.level - 1)]
        return ".".join(base + (node.module.split(".") if node.module else []))

    def _reexports(self, package: str) -> dict:
        out = {}
        for node in self.trees[package].body:
            if isinstance(node, ast.ImportFrom):
                source = self._absolute(package, node)
                if source == self.name or source.startswith(self.name + "."):
                    for alias in node.names:
                        out[alias.asname or alias.name] = (source, alias.name)
        return out

    def resolve(self, module: str, name: str, seen=()) -> str:
        """The module defining ``name`` of ``from module import name``: a submodule, the module a package's
        __init__ re-exports it from, else ``module``."""
        if f"{module}.{name}" in self.paths:
            return f"{module}.{name}"
        if module in self.reexports and name in self.reexports[module] and (module, name) not in seen:
            source, original = self.reexports[module][name]
            if source in self.paths:
                return self.resolve(source, original, seen + ((module, name),))
        return module

    def _ours(self, name: str) -> bool:
        return name == self.name or name.startswith(self.name + ".")

    def _imports(self, module: str):
        tree = self.trees[module]
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                source = self._absolute(module, node)
                if self._ours(source):
                    for alias in node.names:
                        yield self.resolve(source, alias.name), source, alias.name, node.lineno
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    if self._ours(alias.name):
                        yield alias.name, alias.name, None, node.lineno
            else:
                literal = dynamic_import(node)
                if isinstance(literal, str) and self._ours(literal):
                    yield literal, literal, None, node.lineno
        if any(dynamic_import(n) is False for n in ast.walk(tree)):    # a table of lazily imported modules
            for node in ast.walk(tree):
                if isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value in self.paths:
                    yield node.value, node.value, None, node.lineno

    def dynamic_calls(self, module: str):
        """Lines of ``__import__``/``import_module`` calls whose module is not a literal string."""
        return [n.lineno for n in ast.walk(self.trees[module]) if dynamic_import(n) is False]


def dynamic_import(node):
    """For a call of ``__import__`` or ``importlib.import_module``: its literal module string, or False when the
    module is computed; None for any other node."""
    if not isinstance(node, ast.Call):
        return None
    f = node.func
    name = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else None
    if name not in ("import_module", "__import__"):
        return None
    if node.args and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str):
        return node.args[0].value
    return False


# -- the rules --------------------------------------------------------------------------------------------
def strongly_connected_components(graph: dict) -> list:
    """Tarjan's algorithm: the strongly connected components of ``graph`` ({node: iterable}), each sorted; nodes
    outside the graph's keys are ignored."""
    index, low, on_stack, stack, components = {}, {}, set(), [], []

    def visit(node):
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for succ in graph[node]:
            if succ not in graph:
                continue
            if succ not in index:
                visit(succ)
                low[node] = min(low[node], low[succ])
            elif succ in on_stack:
                low[node] = min(low[node], index[succ])
        if low[node] == index[node]:
            component = []
            while True:
                succ = stack.pop()
                on_stack.discard(succ)
                component.append(succ)
                if succ == node:
                    break
            components.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return components


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def violations(tree: Tree, table: dict, dynamic_ok=frozenset()) -> list[str]:
    """Every broken rule of the module docstring, one line each (empty when the tree keeps the table).
    ``dynamic_ok``: modules (dotted below the root, e.g. ``errors``) allowed to import by a computed name."""
    out = []
    rel = {m: f"{p.relative_to(tree.root.parent)}" for m, p in tree.paths.items()}
    root = tree.name
    tops = {tree.top(m) for m in tree.paths} - {"__root__"}
    for t in sorted(tops - table.keys()):
        out.append(f"no layer: {root}.{t} is not in the layer table")
    for t in sorted(table.keys() - tops):
        out.append(f"no layer: the table names {t}, which {root} does not have")
    # cycles of modules and of packages
    graph = {m: [t for t, *_ in tree.imports[m]] for m in tree.paths}
    for comp in strongly_connected_components(graph):
        if len(comp) > 1:
            members = set(comp)
            lines = "; ".join(f"{rel[m]}:{line} imports {t}" for m in comp for t, _, _, line in tree.imports[m]
                              if t in members)
            out.append(f"cycle of modules: {', '.join(comp)} ({lines})")
    pgraph: dict = {}
    for m, imps in tree.imports.items():
        if m == root:
            continue
        pgraph.setdefault(tree.top(m), set()).update(tree.top(t) for t, *_ in imps if tree.top(t) != "__root__")
    for comp in strongly_connected_components(pgraph):
        if len(comp) > 1:
            out.append(f"cycle of packages: {', '.join(comp)}")
    # the table, the root, private names, dynamic imports
    for m, imps in sorted(tree.imports.items()):
        mine = tree.top(m)
        for line in tree.dynamic_calls(m):
            if m != root and m.split(".", 1)[-1] not in dynamic_ok:
                out.append(f"dynamic: {rel[m]}:{line} imports a module by a computed name")
        if m == root:
            continue
        for target, source, name, line in imps:
            theirs = tree.top(target)
            if theirs == "__root__":
                out.append(f"root: {rel[m]}:{line} imports the package root ({source}"
                           f"{'.' + name if name else ''})")
                continue
            if theirs != mine:
                written = source.split(".") + ([name] if name else [])
                private = [part for part in written if _private(part)]
                if private:
                    out.append(f"private: {rel[m]}:{line} imports {'.'.join(written)} (private of {theirs})")
            if theirs == mine or mine not in table or theirs not in table:
                continue
            (lm, allowed), (lt, _) = table[mine], table[theirs]
            if lt > lm or (lt == lm and theirs not in allowed):
                why = "a higher layer" if lt > lm else "its own layer, not listed"
                out.append(f"not allowed: {rel[m]}:{line} ({mine}, layer {lm}) imports {target} ({theirs}, "
                           f"layer {lt}: {why})")
    return out
