"""The mechanism-job registry: one module per mechanism, one line here (see jobs/base.py)."""
from __future__ import annotations

import importlib

from camgen.jobs.base import MechanismJob

__all__ = ["JOB_MODULES", "get_job", "job_names"]

#: mechanism name -> module defining ``JOB``
JOB_MODULES: dict[str, str] = {
    "horse_leg": "camgen.jobs.horse_leg",
    "machine": "camgen.jobs.machine",
}


def job_names() -> list[str]:
    return sorted(JOB_MODULES)


def get_job(name: str) -> MechanismJob:
    return importlib.import_module(JOB_MODULES[name]).JOB
