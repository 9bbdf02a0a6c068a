"""The design-check report: report.json (:mod:`camgen.report.document`) and report.html
(:mod:`camgen.report.html`, which draws only the data it is given)."""
from __future__ import annotations

from camgen.report.document import REPORT_SCHEMA, report_dict, report_json

__all__ = ["REPORT_SCHEMA", "report_dict", "report_json"]
