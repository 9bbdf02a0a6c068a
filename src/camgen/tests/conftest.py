"""Fixtures and settings shared by the test modules.

The tests ship inside the package and run against the installed copy from any folder
(``python3 -m pytest -q --pyargs camgen``), where no ``pyproject.toml`` is found: the
warning filters are therefore set here, not in the project file.
"""
from __future__ import annotations

import pytest

WARNING_FILTERS = (
    "error",
    "ignore:overflow encountered in scalar multiply:RuntimeWarning",  # meshio reading ASCII STL on NumPy 2
    "ignore:mypy_extensions.TypedDict is deprecated:DeprecationWarning",  # hypothesis' failure report on some installs
)


#: The test modules that count their generated cases (CASE_COUNTS), summed over xdist workers.
COUNTING_MODULES = ("camgen.tests.test_properties", "camgen.tests.test_bad_input")


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
    from camgen.tests.cams import HEIGHT, STRIDE

    return {"stride": camgen.three_arc_cam(*STRIDE), "height": camgen.three_arc_cam(*HEIGHT), "steering": steering.profile}


from camgen.tests.test_properties import pytest_terminal_summary  # noqa: E402,F401  (prints the generated-case counts)
