"""The package's public names (issue 22, item 7): every ``__all__`` of the installed camgen
names only what its module defines, and lists every name another camgen module takes from it
(``from camgen.m import x``, or ``m.x`` where ``m`` is bound to the module).  Private names
(``_x``) are not taken across modules at all (tests/test_imports.py).  The types themselves are
checked by mypy in CI (.ci/run, pyproject's ``[tool.mypy]``)."""
from __future__ import annotations

import ast
import importlib
import sys
from pathlib import Path

from test_imports import PACKAGE, _absolute, edges, modules


def declared_all(module: str) -> list[str] | None:
    """The ``__all__`` of an importable module, or None when it has none."""
    names = getattr(importlib.import_module(module), "__all__", None)
    return None if names is None else list(names)


def _own_nodes(scope: ast.AST) -> list[ast.AST]:
    """The nodes of a module or function body outside the functions nested in it."""
    out, todo = [], list(ast.iter_child_nodes(scope))
    while todo:
        node = todo.pop()
        out.append(node)
        if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            todo.extend(ast.iter_child_nodes(node))
    return out


def _bound_modules(scope: ast.AST, source: str, path: Path, found: dict[str, Path], outer: dict[str, str],
                   out: dict[str, dict[str, set[str]]]) -> None:
    """Record ``alias.name`` uses in ``scope`` where ``alias`` is bound to a camgen module by an
    import in this scope or an enclosing one (and not rebound here), then do the nested functions."""
    own = _own_nodes(scope)
    aliases = dict(outer)
    for node in own:
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store) or isinstance(node, ast.arg):
            aliases.pop(node.id if isinstance(node, ast.Name) else node.arg, None)
    for node in own:
        if isinstance(node, ast.Import):
            aliases.update({a.asname: a.name for a in node.names if a.asname and a.name in found})
        elif isinstance(node, ast.ImportFrom):
            base = _absolute(node.module, node.level, source, path.name == "__init__.py")
            aliases.update({a.asname or a.name: f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in found})
    for node in own:
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in aliases:
            target = aliases[node.value.id]
            if target != source:
                out.setdefault(target, {}).setdefault(node.attr, set()).add(source)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            _bound_modules(node, source, path, found, aliases, out)


def taken_names(found: dict[str, Path]) -> dict[str, dict[str, set[str]]]:
    """module -> name -> the modules that take it: ``from module import name`` (the import
    graph's edges) and ``alias.name`` where ``alias`` is bound to the module in that scope."""
    out: dict[str, dict[str, set[str]]] = {}
    for edge in edges(found):
        if edge.source != edge.target:
            for name in edge.names:
                out.setdefault(edge.target, {}).setdefault(name, set()).add(edge.source)
    for source, path in found.items():
        _bound_modules(ast.parse(path.read_text(encoding="utf-8"), str(path)), source, path, found, {}, out)
    return out


def missing_from_all(found: dict[str, Path]) -> list[str]:
    """``module: name (taken by ...)`` for every public name taken from a module whose ``__all__`` lacks it."""
    out = []
    for module, names in taken_names(found).items():
        public = declared_all(module)
        if public is None:
            continue
        for name, takers in sorted(names.items()):
            if not name.startswith("_") and name not in public:
                out.append(f"{module}: {name} (taken by {', '.join(sorted(takers))})")
    return out


def test_every_name_taken_from_a_module_is_in_its___all__():
    found = modules(PACKAGE, "camgen")
    taken = taken_names(found)
    # the walk sees both ways of taking a name: a from-import and an attribute of a bound module
    assert "wrap_pi" in taken["camgen.geometry"] and "ride_geometry" in taken["camgen.mechanisms.tricycle"]
    missing = missing_from_all(found)
    assert not missing, "names other modules take, missing from their module's __all__:\n" + "\n".join(missing)


def test_every_name_in_an___all___is_defined_by_its_module():
    found = modules(PACKAGE, "camgen")
    declared = {name: declared_all(name) for name in found if not name.endswith("__main__")}  # __main__ runs the program
    assert declared["camgen.geometry"] and declared["camgen.synthesis.followers"]
    undefined = [f"{module}: {name}" for module, names in sorted(declared.items()) if names
                 for name in names if not hasattr(importlib.import_module(module), name)]
    assert not undefined, "names in an __all__ that the module does not define:\n" + "\n".join(undefined)


def test_a_name_taken_but_not_listed_is_found(tmp_path, monkeypatch):
    """The detector on a planted package: ``b`` takes ``x`` by a from-import and ``y`` through
    an alias of ``a``, whose ``__all__`` lists neither; ``c`` takes ``z``, which ``a`` lists."""
    root = tmp_path / "planted_all"
    root.mkdir()
    (root / "__init__.py").write_text("")
    (root / "a.py").write_text('__all__ = ["z"]\nx = y = z = 1\n')
    (root / "b.py").write_text("from planted_all.a import x\nimport planted_all.a as alias\nprint(alias.y)\n")
    (root / "c.py").write_text("from planted_all.a import z\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        missing = missing_from_all(modules(root, "planted_all"))
    finally:
        for name in [m for m in sys.modules if m == "planted_all" or m.startswith("planted_all.")]:
            del sys.modules[name]
    assert missing == ["planted_all.a: x (taken by planted_all.b)", "planted_all.a: y (taken by planted_all.b)"]
