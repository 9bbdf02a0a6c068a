"""Record the hash of every output file of every bundled template: the reference of
test_golden.py.  Run it with the code whose outputs are the reference, e.g. before a refactor:

    python3 -P tests/golden/regenerate.py "<why>" tests/golden/template_outputs.json   (camgen installed: pip install .)

(only when outputs change on purpose; say why in the commit message).
"""
from __future__ import annotations

import hashlib
import importlib.metadata as metadata
import json
import pathlib
import sys
import tempfile

TEMPLATES = ("default", "horse_leg", "motion_law", "tricycle", "plate_cam", "flat_follower", "knife_follower", "oscillating_roller",
             "oscillating_flat", "lift_table", "groove_cam", "conjugate_cam", "constant_breadth", "linear_cam",
             "barrel_cam", "packaging_machine", "wire_edm_cam")
LIBRARIES = ("numpy", "scipy", "manifold3d", "trimesh", "meshio")


def template_hashes(outdir: str | pathlib.Path) -> dict[str, dict[str, str]]:
    """Run every template through the Python API into ``outdir``; file name -> sha256 per template."""
    from camgen.pipeline import run_scene
    from camgen.scene import load_template

    hashes = {}
    for name in TEMPLATES:
        run_scene(load_template(name), outdir)
        folder = pathlib.Path(outdir) / name
        hashes[name] = {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir())}
    return hashes


def library_versions() -> dict[str, str]:
    """Versions of the libraries whose results reach the files ("missing" where not installed)."""
    versions = {}
    for name in LIBRARIES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = "missing"
    return versions


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        record = {"commit": sys.argv[1], "libraries": library_versions(), "templates": template_hashes(tmp)}
    pathlib.Path(sys.argv[2]).write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
