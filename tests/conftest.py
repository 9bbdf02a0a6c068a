"""Fixtures and settings shared by the test modules, and the guard that they test the installed
camgen.

The tests live in the checkout (``tests/``) and run against the package *installed* from it
(``pip install ".[test]"``, then ``python3 -P -m pytest -q -n auto tests``), never against the
checkout's own ``camgen/`` folder: only the installed package shows a file missing from the
wheel.  Python puts the current folder first on the module path for ``python -m`` and ``-c``
(pytest-xdist's workers, subprocesses of the tests), so this file takes the checkout off the path
before anything imports camgen, asks the processes the tests start to do the same
(``PYTHONSAFEPATH``), and stops the run loudly if camgen still comes from the checkout.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

CHECKOUT = Path(__file__).resolve().parent.parent


def _in_checkout(entry: str) -> bool:
    return Path(entry or os.getcwd()).resolve() == CHECKOUT


sys.path[:] = [entry for entry in sys.path if not _in_checkout(entry)]
os.environ["PYTHONSAFEPATH"] = "1"  # `python -m camgen` in a test, xdist's workers: no current folder on the path

import camgen  # noqa: E402  (after the path is cleaned)

if Path(camgen.__file__).resolve().is_relative_to(CHECKOUT / "camgen"):
    pytest.exit(f"the tests imported the checkout's camgen ({camgen.__file__}), not the installed package: install it "
                "(python3 -m pip install \".[test]\") and run python3 -P -m pytest -q tests", returncode=4)

WARNING_FILTERS = (
    "error",
    "ignore:overflow encountered in scalar multiply:RuntimeWarning",  # meshio reading ASCII STL on NumPy 2
    "ignore:mypy_extensions.TypedDict is deprecated:DeprecationWarning",  # hypothesis' failure report on some installs
)


#: The test modules that count their generated cases (CASE_COUNTS), summed over xdist workers.
COUNTING_MODULES = ("test_properties", "test_bad_input")


def pytest_configure(config: pytest.Config) -> None:
    for line in WARNING_FILTERS:
        config.addinivalue_line("filterwarnings", line)
    if config.pluginmanager.hasplugin("xdist"):
        config.pluginmanager.register(_WorkerCounts(), "camgen-worker-counts")


class _WorkerCounts:
    """With pytest-xdist (``-n 2``) the generated cases run in worker processes: each worker sends
    its case counts to the controller, which adds them up for the terminal summary."""

    @pytest.hookimpl
    def pytest_sessionfinish(self, session: pytest.Session) -> None:
        import sys

        output = getattr(session.config, "workeroutput", None)
        if output is not None:  # a worker
            output["camgen_case_counts"] = {
                name: [[family, outcome, n] for (family, outcome), n in getattr(sys.modules.get(name), "CASE_COUNTS", {}).items()]
                for name in COUNTING_MODULES}

    @pytest.hookimpl(optionalhook=True)
    def pytest_testnodedown(self, node, error) -> None:
        import importlib

        for name, rows in getattr(node, "workeroutput", {}).get("camgen_case_counts", {}).items():
            counts = importlib.import_module(name).CASE_COUNTS
            for family, outcome, n in rows:
                counts[(family, outcome)] += n


@pytest.fixture
def tmp_path(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A new empty folder for each test, in pytest's base temporary folder (kept as pytest keeps
    it), as pytest's own ``tmp_path`` makes it but without its ``<name>current`` symlink: pytest
    replaces that link for every test, and a link to a long path has a data block whose release
    costs milliseconds on a busy ext4 disk (mounted with ``discard``), for each of the suite's
    thousands of tests that take a folder."""
    import re
    import tempfile

    name = re.sub(r"[\W]", "_", request.node.name)[:30]
    return Path(tempfile.mkdtemp(prefix=name, dir=tmp_path_factory.getbasetemp()))


@pytest.fixture(scope="session")
def default_run(tmp_path_factory):
    """``camgen run`` of the bundled default scene, once per test session: its output folder."""
    from camgen.cli import main

    out = tmp_path_factory.mktemp("run")
    assert main(["run", "-o", str(out)]) == 0
    return out / "default"


@pytest.fixture(scope="session")
def steering():
    """The tricycle steering cam of paper 004 (eq. 15 path, Table 2 device)."""
    from camgen.mechanisms import tricycle as tc
    from camgen.synthesis.trajectory import trajectory_from_expression

    return tc.tricycle_cam(trajectory_from_expression("202.4396*sin(pi*x/1000)", 2000.0))


@pytest.fixture(scope="session")
def contours(steering):
    """The stride and height cams of paper 000 and the tricycle steering cam's profile."""
    import camgen
    from cams import HEIGHT, STRIDE

    return {"stride": camgen.three_arc_cam(*STRIDE), "height": camgen.three_arc_cam(*HEIGHT), "steering": steering.profile}


from test_properties import pytest_terminal_summary  # noqa: E402,F401  (prints the generated-case counts)
