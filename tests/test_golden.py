"""Every bundled template gives byte-identical files to a recorded reference.

golden/template_outputs.json holds the sha256 of every file of every template as written by the
code its "commit" names.  It proved the cam-kind/output registry refactor (b99c518) byte-identical
to the code before it (5a3620e), and guards every later change since: it is re-recorded only when
outputs change on purpose (golden/regenerate.py; the commit message says why).  Every file camgen
formats itself (DXF, CSV tables, G-code) is compared always; the rest (meshes, reports: they hold
numbers of the meshing library's triangulation) when the installed library versions are the
recorded ones.
"""
from __future__ import annotations

import json
from pathlib import Path

from golden.regenerate import library_versions, template_hashes


def test_every_template_writes_the_recorded_bytes(tmp_path):
    record = json.loads((Path(__file__).parent / "golden" / "template_outputs.json").read_text())
    same_libraries = record["libraries"] == library_versions()
    now = template_hashes(tmp_path)
    assert sorted(now) == sorted(record["templates"])
    for template, expected in record["templates"].items():
        assert sorted(now[template]) == sorted(expected), template  # the same files
        for name, digest in expected.items():
            if same_libraries or name.endswith((".csv", ".ngc", ".dxf")):
                assert now[template][name] == digest, f"{template}/{name} differs from the recorded bytes ({record['commit']})"
