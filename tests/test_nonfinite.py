"""The guard against NaN and infinity in written files reads numbers, not names (issue "Trust,
round 2", item 5): names holding ``nan`` or ``inf`` run (``name = "v1.nan"``, a cam ``cam-inf``, a
scene file ``nan.toml``), and a NaN planted where a number stands in the output of every text
writer is still refused, naming the file and the line where it was planted."""
from __future__ import annotations

import importlib.util
import re

import pytest

from camgen.cli import main
from camgen.nonfinite import first_nonfinite

# --------------------------------------------------------------------------------------------
# The rules of each format, on hand-written text (line numbers counted by hand)
# --------------------------------------------------------------------------------------------
FORMAT_CASES = [
    # (file name, text, expected (line, word) or None)
    ("x_points.csv", "# camgen point list of cam 'nan' (scene 'v1.inf')\nx_mm,y_mm\n1.0,2.0\n", None),
    ("x_points.csv", "# cam 'cam-inf'\nx_mm,y_mm\n1.0,2.0\n3.0,-inf\n", (4, "-inf")),
    ("x_points.csv", 'name,x_mm\n"nan",1.0\n"a",NaN\n', (3, "NaN")),
    ("x_lift.csv", "# scene 'nan.toml'\nangle,r\n0,Infinity\n", (3, "Infinity")),
    ("x.ngc", "(camgen: cam 'nan', scene 'inf')\n; inf\nG0 X1.0000 Y2.0000\nG1 X-inf Y1.0\n", (4, "-inf")),
    ("x.ngc", "(cam 'inf')\nG1 X1.0 Ynan F100\n", (2, "nan")),
    ("x.ngc", "(camgen: cam 'cam-inf', scene 'v1.nan')\nG1 X1.0 Y2.0\nM2\n", None),
    ("x.dxf", "  0\nLAYER\n  2\nnan\n  0\nLINE\n 10\n1.5\n 20\ninf\n", (10, "inf")),
    ("x.dxf", "  0\nLAYER\n  2\nnan\n  1\ninf\n999\nNaN\n 10\n0.0\n", None),  # names, text and a comment
    ("x.step", "#7 = PRODUCT('nan','cam-inf','',(#8));\n#8 = A('it''s nan');\n#12 = CARTESIAN_POINT('',(0.,nan,0.));\n",
     (3, "nan")),
    ("x.step", "#1 = FILE_NAME('nan.step\nline two inf',\n'x');\n", None),  # a string across lines
    ("x_ascii.stl", "solid nan\n  facet normal 0 0 1\n    outer loop\n      vertex 1 inf 0\n", (4, "inf")),
    ("x_ascii.stl", "solid inf\nendsolid inf\n", None),
    ("x.obj", "# nan\no nan\nv 1.0 2.0 3.0\nv nan 1.0 2.0\n", (4, "nan")),
    ("x.msh", '$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 "nan"\n$EndPhysicalNames\n$Nodes\n1\n1 0 inf 0\n',
     (10, "inf")),
    ("x.inp", "*HEADING\ncamgen cam 'nan': inf wedges\n** nan\n*NODE, NSET=NALL\n1, 0, 40, 0\n2, nan, 1, 0\n", (6, "nan")),
    ("x.vtu", '<DataArray type="Float64" Name="nan" format="ascii">\n1 2 inf\n</DataArray>\n', (2, "inf")),
    ("x.vtu", '<DataArray type="Float64" Name="inf" format="binary">\nAAAnanAAA/inf/\n</DataArray>\n', None),
    ("x.ply", "ply\nformat ascii 1.0\ncomment nan\nend_header\n1 nan 2\n", (5, "nan")),
    ("x_ascii.stl", b"solid nan\n  facet normal 0 0 1\n      vertex 1 0 nan\n", (3, "nan")),  # bytes as written
    ("x.stl", b"camgen binary STL 'nan'" + bytes(57) + b"\x01\x00\x00\x00" + b" nan " * 10, None),  # binary: not read
    ("other.txt", "scene 'nan'\nvalue = nan\n", (2, "nan")),
]


@pytest.mark.parametrize("name, text, expected", FORMAT_CASES)
def test_the_guard_finds_numbers_where_numbers_stand(name, text, expected):
    assert first_nonfinite(name, text) == expected


# --------------------------------------------------------------------------------------------
# Names that hold the letters run
# --------------------------------------------------------------------------------------------
_CAM = 'kind = "three_arc"\na_mm = 22.0\nb_mm = 16.0\nc_mm = 6.0\nrpm = 30.0\nbore_diameter_mm = 4.0\n'
TEXT_FORMATS = '["dxf", "points", "lift", "follower", "ngc"]'

#: (scene file stem, scene name or None, cam name, the cam's source note): issue item 5's cases.
NAME_CASES = [
    ("s", "v1.nan", "x", None),
    ("s", "nan", "x", None),
    ("s", "NaN", "x", None),
    ("s", "inf", "x", None),
    ("s", "Inf-2", "x", None),
    ("s", "infinity", "x", None),
    ("s", "scene", "cam-inf", None),
    ("s", "scene", "nan", None),
    ("s", "scene", "INF", None),
    ("s", "scene", "x.nan", None),
    ("s", "scene", "Infinity", None),
    ("nan", None, "x", None),
    ("inf", None, "inf", None),
    ("s", "scene", "x", "nan inf -inf NaN Infinity"),
    ("v2.inf", None, "cam-nan", "-inf"),
]


@pytest.mark.parametrize("stem, scene_name, cam, source", NAME_CASES)
def test_names_holding_nan_or_inf_run(stem, scene_name, cam, source, tmp_path, capsys):
    text = (f'name = "{scene_name}"\n' if scene_name else "") + f"[output]\nformats = {TEXT_FORMATS}\n[cams.\"{cam}\"]\n" + _CAM
    if source:
        text += f'source = "{source}"\n'
    path = tmp_path / f"{stem}.toml"
    path.write_text(text)
    status = main(["run", str(path), "-q", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status == 0 and err == "", err
    folder = tmp_path / "out" / (scene_name or stem)
    written = {p.name: p.read_text() for p in folder.iterdir() if p.suffix in (".csv", ".ngc", ".dxf")}
    assert {f"{cam}.dxf", f"{cam}_points.csv", f"{cam}.ngc"} <= set(written)
    shown = scene_name or stem
    assert any(shown in content for content in written.values()) or any(cam in content for content in written.values())


_STEP = importlib.util.find_spec("OCP") is not None
ALL_TEXT_FORMATS = ["dxf", "points", "lift", "follower", "ngc", "stl_ascii", "obj", "msh", "inp", "vtu", "ply", "stl"] + (["step"] if _STEP else [])


def test_every_text_writer_runs_with_names_holding_nan_and_inf(tmp_path, capsys):
    """Every text writer, the trajectory cam's ride table and the leg's path table, with names
    of cams and scene and a source note spelt like non-finite numbers."""
    text = f'name = "inf"\n[output]\nformats = {ALL_TEXT_FORMATS}\n'.replace("'", '"')
    text += '[cams.nan]\n' + _CAM + 'source = "NaN -inf"\n'
    text += '[cams.Inf]\nkind = "trajectory"\nexpression = "202.4396*sin(pi*x/1000)"\nperiod_mm = 2000.0\nrpm = 30.0\n'
    text += '[cams.xINF]\nkind = "three_arc"\na_mm = 220.0\nb_mm = 160.0\nc_mm = 25.0\nrpm = 30.0\n'
    text += '[cams.infinity]\nkind = "three_arc"\na_mm = 220.0\nb_mm = 220.0\nc_mm = 10.0\nrpm = 30.0\n'
    text += '[mechanisms.horse_leg]\nstride_cam = "xINF"\nheight_cam = "infinity"\ninclinations_deg = [12.5]\n'
    path = tmp_path / "nan.toml"
    path.write_text(text)
    status = main(["run", str(path), "-q", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status == 0 and err == "", err
    names = {p.name for p in (tmp_path / "out" / "inf").iterdir()}
    assert {"Inf_ride.csv", "leg_path_alpha_12.5.csv", "nan.ngc", "nan.inp", "nan_ascii.stl", "nan.msh", "nan.obj"} <= names


# --------------------------------------------------------------------------------------------
# A NaN planted where a number stands, in the output of every text writer, is refused
# --------------------------------------------------------------------------------------------
def _plant(content: str | bytes, pattern: str) -> tuple[str | bytes, int]:
    """``content`` with the number captured by ``pattern``'s first match replaced by "nan", and
    the line number (1-based) of the plant."""
    is_bytes = isinstance(content, bytes)
    text = content.decode("latin-1") if is_bytes else content
    match = re.search(pattern, text, re.MULTILINE)
    assert match is not None, pattern
    planted = text[: match.start(1)] + "nan" + text[match.end(1):]
    line = text.count("\n", 0, match.start(1)) + 1
    return (planted.encode("latin-1") if is_bytes else planted), line


#: (format, file of the cam "nan", the writer function (of camgen.writers, or "module:function"),
#: a regular expression whose group 1 is a number)
PLANTS = [
    ("dxf", "nan.dxf", "dxf", r"^ 10\n([-0-9.e]+)$"),
    ("points", "nan_points.csv", "points", r"^([-0-9.]+),[-0-9.]+$"),
    ("lift", "nan_lift.csv", "lift", r"^[-0-9.]+,([-0-9.]+),"),
    ("follower", "nan_follower.csv", "follower", r"^[-0-9.]+,[-0-9.e]+,([-0-9.e]+),"),
    ("ngc", "nan.ngc", "gcode", r"^G1 X([-0-9.]+) "),
    ("stl_ascii", "nan_ascii.stl", "mesh", r"vertex ([-0-9.e+]+) "),
    ("obj", "nan.obj", "mesh", r"^v ([-0-9.e+]+) "),
    ("msh", "nan.msh", "camgen.export.fea:writer", r"\$Nodes\n\d+\n\d+ ([-0-9.e+]+) "),
    ("inp", "nan.inp", "camgen.export.fea:writer", r"^\*NODE.*\n\d+, ([-0-9.e+]+),"),
] + ([("step", "nan.step", "step", r"CARTESIAN_POINT\('',\(([-0-9.E+]+),")] if _STEP else [])


@pytest.mark.parametrize("fmt, file, writer, pattern", PLANTS)
def test_a_nan_planted_in_each_writer_is_refused(fmt, file, writer, pattern, tmp_path, capsys, monkeypatch):
    import importlib

    module, writer = writer.split(":") if ":" in writer else ("camgen.writers", writer)
    writers = importlib.import_module(module)
    original = getattr(writers, writer)
    planted_at = []

    def planting(cam, run, name):
        content = original(cam, run, name)
        if name != fmt:
            return content
        content, line = _plant(content, pattern)
        planted_at.append(line)
        return content

    monkeypatch.setattr(writers, writer, planting)
    path = tmp_path / "scene.toml"  # names spelt like non-finite numbers beside the planted one
    path.write_text(f'name = "inf"\n[output]\nformats = ["{fmt}"]\n[cams.nan]\n' + _CAM + 'source = "nan"\n')
    status = main(["run", str(path), "-q", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert planted_at, "the writer ran"
    assert status == 2 and err.count("\n") == 1, err
    assert f"{file} would hold the non-finite number 'nan' at line {planted_at[0]}:" in err, err
    assert not (tmp_path / "out").exists()
