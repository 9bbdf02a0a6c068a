"""Fixtures shared by the test modules."""
from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def default_run(tmp_path_factory):
    """``camgen run`` of the bundled default scene, once per test session: its output folder."""
    from camgen.cli import main

    out = tmp_path_factory.mktemp("run")
    assert main(["run", "-o", str(out)]) == 0
    return out / "default"
