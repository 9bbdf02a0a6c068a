"""The installed package is the checkout's camgen/ and templates/, nothing missing and no tests
(issue 22, item 1): what `pip install .` put in site-packages, compared with the checkout."""
from __future__ import annotations

import importlib.metadata
import subprocess
import sys
from pathlib import Path

import camgen
from helpers import CHECKOUT


def _installed() -> set[str]:
    """The files of the installed distribution, as paths relative to site-packages."""
    files = importlib.metadata.files("camgen") or []
    return {str(f).replace("\\", "/") for f in files}


def test_the_tests_import_the_installed_package():
    assert not Path(camgen.__file__).resolve().is_relative_to(CHECKOUT / "camgen")
    assert f"camgen/{Path(camgen.__file__).name}" in _installed()


def test_every_module_of_the_checkout_is_installed_and_no_test():
    installed = _installed()
    modules = {f"camgen/{p.relative_to(CHECKOUT / 'camgen').as_posix()}" for p in (CHECKOUT / "camgen").rglob("*.py")}
    assert modules and modules <= installed, sorted(modules - installed)  # pyproject's package list is complete
    assert not [f for f in installed if f.startswith(("tests/", "camgen/tests/"))]
    assert not [f for f in installed if Path(f).name.startswith("test_") or Path(f).name == "conftest.py"]


def test_the_templates_are_installed_as_camgen_templates():
    installed = _installed()
    scenes = {p.name for p in (CHECKOUT / "templates").iterdir() if p.suffix in (".toml", ".csv")}
    assert scenes and {f"camgen/templates/{name}" for name in scenes} <= installed
    from camgen.scene import template_names

    assert set(template_names()) == {Path(name).stem for name in scenes if name.endswith(".toml")}


def test_the_program_lists_and_runs_its_templates_from_another_folder(tmp_path):
    """`camgen templates` and `camgen run` from a folder that is not the checkout."""
    listing = subprocess.run([sys.executable, "-m", "camgen", "templates"], capture_output=True, text=True, cwd=tmp_path)
    names = [line.split()[0] for line in listing.stdout.splitlines()]
    assert listing.returncode == 0 and names == sorted(p.stem for p in (CHECKOUT / "templates").glob("*.toml"))
    run = subprocess.run([sys.executable, "-m", "camgen", "run", "-q"], capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "outputs" / "default" / "report.json").is_file()


def test_type_checkers_read_the_installed_package_s_annotations(tmp_path):
    """camgen ships py.typed (PEP 561): mypy, run on a user's file outside the checkout, checks calls
    into the installed camgen against its annotations (without the marker it skips camgen with an
    import-untyped error and sees no types)."""
    assert "camgen/py.typed" in _installed()
    user = tmp_path / "user.py"
    # wrap_pi returns an array: assigning it to a str is an error only a checker reading the annotation finds
    user.write_text("from camgen.geometry import wrap_pi\n\nangle: str = wrap_pi(0.0)\n")
    checked = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental", "--cache-dir", str(tmp_path / "cache"),
                              "--follow-imports", "silent", "--python-version", "3.11", str(user)],
                             capture_output=True, text=True, cwd=tmp_path)
    out = checked.stdout + checked.stderr
    assert "import-untyped" not in out and "import-not-found" not in out, out
    assert checked.returncode == 1 and 'user.py:3: error: Incompatible types in assignment' in out and "[assignment]" in out, out
