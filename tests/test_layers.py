"""The import rules of src/assur.

* Layers: a module imports only from its own layer or below (L0 kernels, errors, tolerances; L1 model, structure;
  L2 the engine; L3 analysis, io, gears; L4 synthesis, plot, report, cli, designer).
* No import cycles: the import graph of the modules has no strongly connected component of more than one module.
  Module-level imports, function-level imports and ``importlib.import_module`` strings all count.
* No module imports a ``_private`` name (or a ``_private`` module) of another package.
"""
import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "assur"
# Both the engine package and the top-level modules it replaces, so the map holds before and after the move.
LAYER = {"kernels": 0, "errors": 0, "tolerances": 0,
         "model": 1, "structure": 1,
         "engine": 2, "compile": 2, "plan": 2, "solve": 2, "state": 2, "compiled_backend": 2, "spatial_plan": 2,
         "analysis": 3, "io": 3, "gears": 3, "kinetostatics": 3, "wheelstep": 3,
         "synthesis": 4, "plot": 4, "report": 4, "cli": 4, "designer": 4, "__main__": 4, "__root__": 4}


# ---------------------------------------------------------------------------------------------------------------
# The downward-layer rule (by top-level name; a name taken from the package root counts as the top layer)

def top_of(path: Path) -> str:
    rel = path.relative_to(SRC)
    return rel.parts[0].removesuffix(".py")


def imported_tops(path: Path):
    """(top-level name under assur, line) for every import in ``path``, at any depth, and every
    ``importlib.import_module("assur....")`` string."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    pkg = path.relative_to(SRC).parts[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level == 0:
                if node.module and node.module.startswith("assur."):
                    yield node.module.split(".")[1], node.lineno
                elif node.module == "assur":
                    for alias in node.names:
                        yield (alias.name if alias.name in LAYER else "__root__"), node.lineno
                continue
            base = list(pkg[: len(pkg) - (node.level - 1)]) if node.level > 1 else list(pkg)
            parts = base + (node.module.split(".") if node.module else [])
            if parts:
                yield parts[0], node.lineno
            else:  # "from . import module", or a name of the package root (the public API, top layer only)
                for alias in node.names:
                    yield (alias.name if alias.name in LAYER else "__root__"), node.lineno
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("assur."):
                    yield alias.name.split(".")[1], node.lineno
                elif alias.name == "assur":
                    yield "__root__", node.lineno
        else:
            name = _import_module_string(node)
            if name is not None and name.startswith("assur."):
                yield name.split(".")[1], node.lineno
    for name, line in _module_strings(tree):
        yield name.split(".")[1], line


MODULES = [p for p in SRC.rglob("*.py") if p.name != "__init__.py" or p.parent != SRC]


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(SRC)))
def test_imports_go_downward(path):
    top = top_of(path)
    if top == "__init__":
        pytest.skip("package root re-exports the public API")
    assert top in LAYER, f"{path.relative_to(SRC)}: assur.{top} has no layer in LAYER"
    mine = LAYER[top]
    for target, line in imported_tops(path):
        assert target in LAYER, f"{path.name}:{line} imports unknown module assur.{target}"
        assert LAYER[target] <= mine, (f"{path.relative_to(SRC)}:{line} (layer {mine}) imports "
                                       f"assur.{target} (layer {LAYER[target]})")


# ---------------------------------------------------------------------------------------------------------------
# The import graph of the modules (nodes: dotted names; a package is its __init__)

def module_name(path: Path) -> str:
    parts = ("assur",) + path.relative_to(SRC).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


PATHS = {module_name(p): p for p in SRC.rglob("*.py")}
PACKAGES = {module_name(p) for p in SRC.rglob("__init__.py")}


def _is_import_module(node) -> bool:
    """Whether ``node`` is a call of ``importlib.import_module`` (or a bare ``import_module``)."""
    if not (isinstance(node, ast.Call) and node.args):
        return False
    func = node.func
    return (func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else None) \
        == "import_module"


def _import_module_string(node):
    """The literal first argument of an ``importlib.import_module("...")`` call, else None."""
    if _is_import_module(node) and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str):
        return node.args[0].value
    return None


def _module_strings(tree):
    """(string, line) for every string constant naming an assur module, in a module that calls
    ``import_module`` with a computed name (e.g. a table of lazily imported modules); else nothing."""
    if not any(_is_import_module(n) and _import_module_string(n) is None for n in ast.walk(tree)):
        return
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value.startswith("assur.") \
                and node.value in PATHS:
            yield node.value, node.lineno


def _absolute(module: str, node: ast.ImportFrom) -> str:
    """The absolute module named by a (possibly relative) ``from X import ...`` in ``module``."""
    if node.level == 0:
        return node.module or ""
    package = module if module in PACKAGES else module.rpartition(".")[0]
    base = package.split(".")
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + (node.module.split(".") if node.module else []))


def _reexports(package: str) -> dict:
    """{name: (absolute module, name there)} for the ``from .x import name`` lines of a package's __init__."""
    out = {}
    for node in ast.parse(PATHS[package].read_text(encoding="utf-8")).body:
        if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith("assur")):
            source = _absolute(package, node)
            for alias in node.names:
                out[alias.asname or alias.name] = (source, alias.name)
    return out


REEXPORTS = {package: _reexports(package) for package in PACKAGES}


def resolve(module: str, name: str, seen=()) -> str:
    """The module that defines ``name`` of ``from module import name``: the submodule when ``name`` is one,
    else the module a package's __init__ re-exports it from, else ``module`` itself."""
    if f"{module}.{name}" in PATHS:
        return f"{module}.{name}"
    if module in REEXPORTS and name in REEXPORTS[module] and (module, name) not in seen:
        source, original = REEXPORTS[module][name]
        if source in PATHS:
            return resolve(source, original, seen + ((module, name),))
    return module


def imports_of(module: str):
    """(target module, names as written, line) for every import of an assur module in ``module``, at any depth,
    and every ``importlib.import_module("assur....")`` string. ``names`` is empty for ``import x``."""
    tree = ast.parse(PATHS[module].read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            source = _absolute(module, node)
            if source == "assur" or source.startswith("assur."):
                for alias in node.names:
                    yield resolve(source, alias.name), (source, alias.name), node.lineno
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == "assur" or alias.name.startswith("assur."):
                    yield alias.name, (alias.name, None), node.lineno
        else:
            name = _import_module_string(node)
            if name is not None and (name == "assur" or name.startswith("assur.")):
                yield name, (name, None), node.lineno
    for name, line in _module_strings(tree):
        yield name, (name, None), line


EDGES = {module: sorted({(target, line) for target, _, line in imports_of(module)}) for module in PATHS}


def strongly_connected_components(graph: dict) -> list:
    """Tarjan's algorithm: the strongly connected components of ``graph`` ({node: iterable of nodes}), each a
    sorted list; nodes outside the graph's keys are ignored."""
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


def test_tarjan_finds_the_cycles_of_a_small_graph():
    graph = {"a": ["b"], "b": ["c"], "c": ["a", "d"], "d": ["e"], "e": ["d"], "f": ["f", "a"], "g": ["outside"]}
    found = sorted(strongly_connected_components(graph))
    assert found == [["a", "b", "c"], ["d", "e"], ["f"], ["g"]]


def test_no_import_cycles():
    graph = {module: [target for target, _ in edges] for module, edges in EDGES.items()}
    cycles = [c for c in strongly_connected_components(graph) if len(c) > 1]
    report = []
    for component in sorted(cycles):
        members = set(component)
        lines = [f"    {PATHS[m].relative_to(SRC.parent)}:{line} imports {target}"
                 for m in component for target, line in EDGES[m] if target in members]
        report.append(f"cycle of {len(component)} modules: {', '.join(component)}\n" + "\n".join(lines))
    assert not cycles, f"{len(cycles)} import cycle(s) in src/assur:\n" + "\n".join(report)


def package_of(module: str) -> str:
    """The top-level package a module belongs to: ``gears`` for assur.gears.law, ``assur`` for assur.compile."""
    parts = module.split(".")
    return parts[1] if len(parts) > 2 or (module in PACKAGES and len(parts) == 2) else "assur"


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def test_no_private_imports_across_packages():
    found = []
    for module, path in sorted(PATHS.items()):
        for target, (source, name), line in imports_of(module):
            if package_of(target) == package_of(module):
                continue
            written = source.split(".") + ([name] if name else [])
            private = [part for part in written if _private(part)]
            if private:
                found.append(f"  {path.relative_to(SRC.parent)}:{line} imports {'.'.join(written)} "
                             f"(private {', '.join(private)} of package {package_of(target)})")
    assert not found, "private names imported from another package:\n" + "\n".join(found)


def test_core_import_is_light():
    """`import assur` must not import matplotlib or scipy.optimize (heavy deps load lazily)."""
    import subprocess
    import sys
    code = "import sys, assur; print(','.join(m for m in ('matplotlib', 'scipy.optimize') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == ""
