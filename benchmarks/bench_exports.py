"""Exports: per format, time (median) and file size against chord tolerance.

Run from the repository root: ``python benchmarks/bench_exports.py``.
Cams: the stride-length three-arc cam (exact arcs) and the tricycle steering cam (spline).
"""
from __future__ import annotations

import _common  # noqa: F401  (shared helpers: median_time, print_table)
from _common import median_time, print_table

import camgen
from camgen.body import BodySpec
from camgen.export.fea import fea_bytes, volume_mesh
from camgen.export.solid import cam_solid, mesh_bytes
from camgen.export.dxf import DxfOptions, contour_to_dxf
from camgen.export.gcode import MachiningSpec, gcode_program
from camgen.export.points import lift_csv, points_csv
from camgen.mechanisms import tricycle as tc
from camgen.synthesis.trajectory import trajectory_from_expression


def main() -> None:
    steering = tc.tricycle_cam(trajectory_from_expression("202.4396*sin(pi*x/1000)", 2000.0))
    cams = {
        "stride_length": (camgen.three_arc_cam(220.0, 160.0, 25.0), BodySpec(20.0, 20.0, 6.0, 2.8, min_wall=3.0)),
        "steering": (steering.profile, BodySpec(8.0, 8.0, 2.0, 1.0, min_wall=3.0)),
    }
    rows = []
    for name, (contour, body) in cams.items():
        for tol in (1e-2, 1e-3, 1e-4):
            jobs = {
                "dxf (bspline)": lambda: contour_to_dxf(contour, body),
                "dxf (biarc)": lambda: contour_to_dxf(contour, body, options=DxfOptions("biarc", tol)),
                "points csv": lambda: points_csv(contour, tol),
                "lift csv (1 deg)": lambda: lift_csv(contour, 0.017453292519943295),
                "solid (manifold)": lambda: cam_solid(contour, body, tol),
                "ngc (biarcs)": lambda: gcode_program(contour, MachiningSpec(thickness=body.thickness, chord_tol=tol, decimals=6)),
                "ngc (lines)": lambda: gcode_program(contour, MachiningSpec(thickness=body.thickness, chord_tol=tol, spline_mode="lines", decimals=6)),
            }
            try:
                import OCP  # noqa: F401

                from camgen.export.step import step_bytes

                if tol == 1e-3:
                    jobs["step (exact)"] = lambda: step_bytes(contour, body, name)
            except ImportError:
                pass
            solid = cam_solid(contour, body, tol)
            for fmt in ("stl", "stl_ascii", "3mf", "obj", "ply"):
                jobs[fmt] = (lambda f: lambda: mesh_bytes(solid, f))(fmt)
            if tol == 1e-3:  # the FEA mesh (gmsh) and its files, at the default element size
                mesh = volume_mesh(contour, body, tol)
                jobs["fea mesh (gmsh wedges)"] = lambda: volume_mesh(contour, body, tol)
                for fmt in ("vtu", "msh", "inp"):
                    jobs[fmt] = (lambda f: lambda: fea_bytes(mesh, f))(fmt)
            for label, job in jobs.items():
                if tol != 1e-3 and label in ("dxf (bspline)", "lift csv (1 deg)", "step (exact)"):
                    continue  # independent of the chord tolerance
                out = job()
                size = len(out) if isinstance(out, (str, bytes)) else len(out.cells) if label.startswith("fea mesh") else len(out.triangles)
                unit = "triangles" if label.startswith("solid") else "elements" if label.startswith("fea mesh") else "bytes"
                seconds = median_time(job, repeats=5, min_total=0.02)
                rows.append([name, f"{tol:g}", label, f"{seconds * 1e3:.2f}", f"{size} {unit}"])
    print_table(["cam", "chord_tol_mm", "format", "time_ms", "size"], rows)


if __name__ == "__main__":
    main()
