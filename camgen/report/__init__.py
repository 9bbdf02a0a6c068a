"""The design-check report: report.json (:mod:`camgen.report.document`) and report.html
(:mod:`camgen.report.html`), both drawn from a typed, frozen input alone
(:class:`camgen.report.model.ReportInput`, made from a run by :mod:`camgen.report_data`)."""
from __future__ import annotations

from camgen.report.document import REPORT_SCHEMA, report_dict, report_json

__all__ = ["REPORT_SCHEMA", "report_dict", "report_json"]
