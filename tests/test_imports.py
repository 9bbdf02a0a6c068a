"""The import graph of the installed camgen (issue 22, item 4): no cycle anywhere, no module
reaching into another module's private names, and a report that imports nothing of the run.

Every module of the installed package is parsed (``ast``), and every import statement in it
counts: at the top, inside functions (camgen imports its heavy modules lazily) and under
``if TYPE_CHECKING:`` (a type-only import is still a dependency a reader follows, and mypy
resolves it).  ``from camgen.a import b`` is an edge to the module ``camgen.a.b`` when there is
one, else to ``camgen.a``; the implicit import of a parent package is not an edge (every module
would then depend on ``camgen``).  Imports are resolved by the rules of the language reference
("The import system", 5.7: relative imports), written out here, not by importing anything.
"""
from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import camgen

PACKAGE = Path(camgen.__file__).resolve().parent


@dataclass(frozen=True)
class Edge:
    """``source`` imports ``target`` at ``line``; ``names``: the names it takes from there
    (``from target import names``), empty for ``import target``."""

    source: str
    target: str
    line: int
    names: tuple[str, ...] = ()


def modules(root: Path, package: str) -> dict[str, Path]:
    """Module name -> file of every module under ``root`` (the folder of ``package``)."""
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = [package, *path.relative_to(root).with_suffix("").parts]
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def _absolute(module: str | None, level: int, importer: str, is_package: bool) -> str:
    """The absolute name of ``from <level dots><module> import ...`` written in ``importer``."""
    if level == 0:
        return module or ""
    base = importer.split(".")
    base = base[: len(base) - (level - 1)] if is_package else base[: len(base) - level]
    return ".".join(base + ([module] if module else []))


def edges(found: dict[str, Path]) -> list[Edge]:
    """Every import of one module of ``found`` by another (or by itself), wherever it stands."""
    out = []
    for name, path in found.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        is_package = path.name == "__init__.py"
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    target = alias.name
                    while target and target not in found:  # "import a.b.c" of a name inside a module
                        target = target.rpartition(".")[0]
                    if target:
                        out.append(Edge(name, target, node.lineno))
            elif isinstance(node, ast.ImportFrom):
                base = _absolute(node.module, node.level, name, is_package)
                for alias in node.names:
                    sub = f"{base}.{alias.name}"
                    if sub in found:  # "from package import module"
                        out.append(Edge(name, sub, node.lineno))
                    elif base in found:
                        out.append(Edge(name, base, node.lineno, (alias.name,)))
    return out


def cycles(graph_edges: list[Edge]) -> list[tuple[list[str], list[Edge]]]:
    """(its modules, one cycle through them as edges in order) for every strongly connected
    component of the graph that has a cycle (Tarjan's algorithm, "Depth-first search and linear graph algorithms", SIAM J.
    Comput. 1972); a module importing itself is a cycle of one edge."""
    successors: dict[str, list[Edge]] = {}
    for edge in graph_edges:
        successors.setdefault(edge.source, []).append(edge)
        successors.setdefault(edge.target, [])
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for edge in successors[node]:
            if edge.target not in index:
                visit(edge.target)
                low[node] = min(low[node], low[edge.target])
            elif edge.target in on_stack:
                low[node] = min(low[node], index[edge.target])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            components.append(component)

    for node in sorted(successors):
        if node not in index:
            visit(node)
    found = []
    for component in components:
        members = set(component)
        start = min(component)
        # the shortest way from start back to itself inside the component (breadth first)
        came: dict[str, Edge] = {}
        frontier = [start]
        closing = None
        while frontier and closing is None:
            following = []
            for node in frontier:
                for edge in successors[node]:
                    if edge.target == start:
                        closing = edge
                        break
                    if edge.target in members and edge.target not in came:
                        came[edge.target] = edge
                        following.append(edge.target)
                if closing is not None:
                    break
            frontier = following
        if closing is None:
            continue  # a single module that does not import itself
        path = [closing]
        while path[0].source != start:
            path.insert(0, came[path[0].source])
        found.append((sorted(members), path))
    return found


def describe(cycle: list[Edge]) -> str:
    """``a (line 12) -> b (line 3) -> a``: each module with the line of its import of the next."""
    return " -> ".join(f"{edge.source} (line {edge.line})" for edge in cycle) + f" -> {cycle[-1].target}"


def private_uses(found: dict[str, Path]) -> list[str]:
    """Every place a module takes a private name (``_x``, not a dunder) of another camgen
    module: ``from camgen.m import _x``, and ``m._x`` where ``m`` names a camgen module
    (``import camgen.m as m``, ``from camgen import m``)."""

    def private(name: str) -> bool:
        return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))

    out = []
    for name, path in found.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        is_package = path.name == "__init__.py"
        aliases: dict[str, str] = {}  # local name -> camgen module it is bound to
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name in found and alias.asname:
                        aliases[alias.asname] = alias.name
            elif isinstance(node, ast.ImportFrom):
                base = _absolute(node.module, node.level, name, is_package)
                for alias in node.names:
                    if f"{base}.{alias.name}" in found:
                        aliases[alias.asname or alias.name] = f"{base}.{alias.name}"
                    elif base in found and base != name and private(alias.name):
                        out.append(f"{name}:{node.lineno}: from {base} import {alias.name}")
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in aliases
                    and aliases[node.value.id] != name and private(node.attr)):
                out.append(f"{name}:{node.lineno}: {node.value.id}.{node.attr} ({aliases[node.value.id]})")
    return sorted(set(out))


# ------------------------------------------------------------------------------------- the tests
def test_the_import_graph_of_camgen_has_no_cycle():
    found = modules(PACKAGE, "camgen")
    graph = edges(found)
    # the walk sees the imports it must: inside a function (pipeline's lazy imports) and type-only ones
    pairs = {(e.source, e.target) for e in graph}
    assert ("camgen.pipeline", "camgen.staging") in pairs  # inside run_scene
    assert ("camgen.kinds.base", "camgen.contour") in pairs or ("camgen.kinds.base", "camgen.body") in pairs  # if TYPE_CHECKING
    loops = cycles(graph)
    assert not loops, "import cycles (each module with the line of its import of the next):\n" + "\n".join(
        f"{describe(path)}  (the knot: {', '.join(members)})" for members, path in loops)


def test_the_report_imports_nothing_of_the_run():
    """report.json and report.html draw the typed input they are given (camgen.report.model, made
    by camgen.report_data): the report's modules import each other and camgen.errors, never the
    pipeline, a kind, the checks, the scene or a job."""
    found = modules(PACKAGE, "camgen")

    def in_report(name: str) -> bool:
        return name == "camgen.report" or name.startswith("camgen.report.")

    assert {"camgen.report.html", "camgen.report.model", "camgen.report.document"} <= set(found)
    outside = sorted(f"{e.source} (line {e.line}) -> {e.target}" for e in edges(found)
                     if in_report(e.source) and not (in_report(e.target) or e.target == "camgen.errors"))
    assert not outside, "the report imports modules of the run:\n" + "\n".join(outside)


def test_no_module_takes_a_private_name_of_another():
    uses = private_uses(modules(PACKAGE, "camgen"))
    assert not uses, "private names used outside their module (make them public, with a docstring):\n" + "\n".join(uses)


# ------------------------------------------------------------ the detectors on a planted package
def _package(root: Path, files: dict[str, str]) -> dict[str, Path]:
    for name, text in files.items():
        path = root / "pkg" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return modules(root / "pkg", "pkg")


def test_a_cycle_through_a_type_only_and_a_function_level_import_is_found_and_named(tmp_path):
    found = _package(tmp_path, {
        "__init__.py": "",
        "a.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from pkg.sub.b import B\n",
        "sub/__init__.py": "",
        "sub/b.py": "def f():\n    from ..c import g\n    return g\n",
        "c.py": "import pkg.a\nfrom pkg import d\n",
        "d.py": "import os\n",  # imported, in no cycle
    })
    loops = cycles(edges(found))
    assert [(members, describe(path)) for members, path in loops] == [
        (["pkg.a", "pkg.c", "pkg.sub.b"], "pkg.a (line 3) -> pkg.sub.b (line 2) -> pkg.c (line 1) -> pkg.a")]
    # without the type-only import there is none
    (tmp_path / "pkg" / "a.py").write_text("")
    assert cycles(edges(modules(tmp_path / "pkg", "pkg"))) == []


def test_a_module_importing_itself_is_a_cycle(tmp_path):
    found = _package(tmp_path, {"__init__.py": "", "a.py": "def f():\n    from . import a\n"})
    assert [describe(path) for _, path in cycles(edges(found))] == ["pkg.a (line 2) -> pkg.a"]


def test_private_names_taken_from_another_module_are_found(tmp_path):
    found = _package(tmp_path, {
        "__init__.py": "",
        "a.py": "_x = 1\nx = 2\n__all__ = ['x']\n",
        "b.py": "from pkg.a import _x, x, __all__\nfrom pkg import a as m\nimport pkg.a as n\n"
                "print(m._x, n._x, m.x, m.__doc__)\n_y = 3\nprint(_y)\n",
        "c.py": "def f():\n    from .a import _x\n",
        "d.py": "_z = 1\ndef f():\n    from pkg import d\n    return d._z\n",  # its own private name: allowed
    })
    assert private_uses(found) == ["pkg.b:1: from pkg.a import _x", "pkg.b:4: m._x (pkg.a)", "pkg.b:4: n._x (pkg.a)",
                                   "pkg.c:2: from pkg.a import _x"]
