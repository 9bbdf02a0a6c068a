"""camgen's runtime dependencies are the libraries it imports, no more (issue 22, item 9): every
requirement of the installed distribution provides a module that the installed package's source
imports, and every output format is written with the same bytes when networkx and lxml (once
runtime dependencies for trimesh's 3MF, which camgen now writes itself) cannot be imported."""
from __future__ import annotations

import ast
import hashlib
import importlib.metadata
import subprocess
import sys
import textwrap
from pathlib import Path

import camgen

#: The libraries no longer installed with camgen: trimesh imports them softly.
DROPPED = ("networkx", "lxml")


def _runtime_requirements() -> list[str]:
    """Distribution names of the installed camgen's requirements outside any extra."""
    names = []
    for requirement in importlib.metadata.requires("camgen") or []:
        if "extra ==" in requirement:
            continue
        name = requirement.split(";")[0].strip()
        for stop in "<>=!~[ ":
            name = name.split(stop)[0]
        names.append(name.lower().replace("_", "-"))
    return names


def _imported_top_level_modules() -> set[str]:
    """Top-level modules named in an import anywhere in the installed package's source."""
    found = set()
    for path in Path(camgen.__file__).parent.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                found |= {alias.name.split(".")[0] for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                found.add(node.module.split(".")[0])
    return found


def _provided_modules(distribution: str) -> set[str]:
    """Top-level modules an installed distribution provides, from its file list: packages (the
    first folder of a file) and single-file modules (``.py``, or compiled: ``name.cpython-...so``)."""
    modules = set()
    for file in importlib.metadata.files(distribution) or []:
        parts = Path(str(file)).parts
        if parts[0].endswith((".dist-info", ".data")) or parts[0] in ("..", "bin"):
            continue
        if len(parts) > 1:
            modules.add(parts[0])
        elif parts[0].endswith((".py", ".so", ".pyd")):
            modules.add(parts[0].split(".")[0])
    return modules


def test_every_runtime_requirement_is_imported_by_camgen():
    imported = _imported_top_level_modules()
    requirements = _runtime_requirements()
    assert requirements and not set(DROPPED) & set(requirements)
    unused = [name for name in requirements if not _provided_modules(name) & imported]
    assert unused == []
    assert not set(DROPPED) & imported  # camgen itself imports neither


_BLOCK = """
import importlib.abc, sys
class _Block(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name.split(".")[0] in {dropped!r}:
            raise ImportError(name + " is not installed")
        return None
sys.meta_path.insert(0, _Block())
"""

_SCENE = """
[output]
formats = ["dxf", "points", "lift", "follower", "stl", "stl_ascii", "3mf", "obj", "ply", "ngc", "html"]

[cams.c]
kind = "motion_law"
base_radius_mm = 40.0
roller_radius_mm = 10.0
thickness_mm = 6.0
rpm = 300.0
bore_diameter_mm = 10.0
segments = [{law = "cycloidal", span_deg = 180.0, lift_mm = 10.0}, {law = "cycloidal", span_deg = 180.0, lift_mm = -10.0}]
"""


def _run(folder: Path, block: bool) -> dict[str, str]:
    """Run the scene of every mesh format in a fresh process: the written files' sha256."""
    code = (_BLOCK.format(dropped=DROPPED) if block else "") + textwrap.dedent("""
        import sys
        from camgen.cli import main
        sys.exit(main(["run", "s.toml", "-o", "out", "--quiet"]))
    """)
    proc = subprocess.run([sys.executable, "-P", "-c", code], capture_output=True, text=True, cwd=folder, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted((folder / "out" / "s").iterdir())}


def test_every_format_is_written_alike_without_networkx_and_lxml(tmp_path):
    """The same scene run twice in the same folder (the report names the scene file): free, then
    with networkx and lxml unimportable; trimesh writes OBJ and PLY, camgen the rest."""
    (tmp_path / "s.toml").write_text(_SCENE)
    free = _run(tmp_path, block=False)
    for path in sorted((tmp_path / "out").rglob("*"), reverse=True):
        path.unlink() if path.is_file() else path.rmdir()
    blocked = _run(tmp_path, block=True)
    assert {"c.3mf", "c.obj", "c.ply", "c.stl", "report.html"} <= set(free)
    assert blocked == free
