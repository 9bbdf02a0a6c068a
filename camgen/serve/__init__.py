"""``camgen serve``: a local HTTP server for the live design page (issue 29).

:mod:`camgen.serve.server` is the HTTP server and its routing (the safety rules: loopback, the
Host header, the body cap, the served paths); :mod:`camgen.serve.api` computes what each endpoint
answers (testable without HTTP); :mod:`camgen.serve.schema_json` is the scene schema as JSON,
:mod:`camgen.serve.payload` a run's cams as the page draws them, :mod:`camgen.serve.files` the
files made for download (kept in memory under a random token), :mod:`camgen.serve.remedies` the
scene keys that change a check's value.  ``page.html`` is the page (one self-contained file).
Nothing here is imported by ``camgen run``.
"""
from __future__ import annotations

__all__: list[str] = []
