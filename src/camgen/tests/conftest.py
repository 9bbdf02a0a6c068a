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


def pytest_configure(config: pytest.Config) -> None:
    for line in WARNING_FILTERS:
        config.addinivalue_line("filterwarnings", line)


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
