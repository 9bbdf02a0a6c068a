"""Independent reference computations for the tests (brute force, closed forms)."""
from __future__ import annotations

import json
import math
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

#: Debian packages of the independent validators (command -> package); .ci/run installs them.
VALIDATOR_PACKAGES = {
    "rs274": "linuxcnc-uspace",
    "admesh": "admesh",
    "ogrinfo": "gdal-bin",
    "chromium": "chromium",
    "ccx": "calculix-ccx",
    "gmsh": "gmsh",
    "openscad": "openscad",
    "librecad": "librecad",
    "prusa-slicer": "prusa-slicer",
    "freecadcmd": "freecad-python3",
    "pdftoppm": "poppler-utils",
    "soffice": "libreoffice-calc",
}


def require_tool(name: str) -> str:
    """Path of the validator ``name``; skip the test where it is missing, but fail instead when
    ``CAMGEN_REQUIRE_VALIDATORS=1`` (set by .ci/run once apt installed them all)."""
    path = shutil.which(name)
    if path is None:
        why = f"{name} not installed (Debian package {VALIDATOR_PACKAGES.get(name, name)}; .ci/run installs it)"
        if os.environ.get("CAMGEN_REQUIRE_VALIDATORS") == "1":
            pytest.fail(why + ", but CAMGEN_REQUIRE_VALIDATORS=1: the validators must run")
        pytest.skip(why)
    return path


def brute_support(points: np.ndarray, psi: np.ndarray, chunk: int = 128) -> np.ndarray:
    """max over ``points`` of p . (cos psi, sin psi), by brute force."""
    out = np.empty(psi.size)
    for lo in range(0, psi.size, chunk):
        u = np.stack([np.cos(psi[lo : lo + chunk]), np.sin(psi[lo : lo + chunk])])
        out[lo : lo + chunk] = (points @ u).max(axis=0)
    return out


def chord_deviation(contour, chord_tol: float, samples: int = 65) -> float:
    """Largest distance from the true curve to the chord polygon, measured at ``samples``
    points inside every chord's parameter interval (midpoint included)."""
    params = contour.flatten_params(chord_tol)
    t0 = params
    t1 = np.append(params[1:], contour.n_segments)
    frac = np.linspace(0.0, 1.0, samples)[1:-1]
    t = t0[:, None] + frac[None, :] * (t1 - t0)[:, None]
    curve = contour.evaluate(t)  # (N, S, 2)
    a = contour.evaluate(t0)[:, None, :]
    b = contour.evaluate(np.mod(t1, contour.n_segments))[:, None, :]
    ab = b - a
    w = np.clip(np.sum((curve - a) * ab, axis=-1) / np.sum(ab * ab, axis=-1), 0.0, 1.0)
    foot = a + w[..., None] * ab
    return float(np.max(np.linalg.norm(curve - foot, axis=-1)))


def segmentwise(contour, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The contour at global parameters ``t`` from each segment's own methods, one segment at a
    time: points (n, 2), derivatives d/du (n, 2), curvatures (n,), and every parameter's segment
    index and local parameter u (the reference of Contour's vectorised evaluation)."""
    n = contour.n_segments
    flat = np.mod(t, n)
    idx = np.minimum(np.floor(flat).astype(int), n - 1)
    u = flat - idx
    point, deriv, kappa = np.empty((t.size, 2)), np.empty((t.size, 2)), np.empty(t.size)
    for i, seg in enumerate(contour.segments):
        at = idx == i
        point[at], deriv[at], kappa[at] = seg.point(u[at]), seg.derivative(u[at]), seg.curvature(u[at])
    return point, deriv, kappa, idx, u


def shoelace(points: np.ndarray) -> float:
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def distance_to_arcs(points: np.ndarray, arcs) -> np.ndarray:
    """Distance of each point (n, 2) to the nearest of ``arcs`` (objects with center, radius,
    start_angle, sweep), from the circle equation alone."""
    best = np.full(len(points), np.inf)
    for arc in arcs:
        c = np.asarray(arc.center)
        d = points - c
        ang = np.arctan2(d[:, 1], d[:, 0])
        lo = arc.start_angle if arc.sweep > 0 else arc.start_angle + arc.sweep
        inside = np.mod(ang - lo, 2 * math.pi) <= abs(arc.sweep) + 1e-12
        radial = np.abs(np.hypot(d[:, 0], d[:, 1]) - arc.radius)
        ends = [c + arc.radius * np.array([math.cos(a), math.sin(a)]) for a in (arc.start_angle, arc.start_angle + arc.sweep)]
        end_dist = np.minimum(*(np.hypot(*(points - e).T) for e in ends))
        best = np.minimum(best, np.where(inside, radial, end_dist))
    return best


def table1_paper(a: float, b: float, c: float, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Table 1 of paper 000 typed literally (sine-rule form of R), for |phi| off the region ends."""
    tx = 2 * math.asin(b / (2 * a))
    ap = np.abs(phi)
    b1 = math.asin(b / (2 * a))
    b2 = math.pi / 2 + math.atan(math.sqrt(a * a - b * b / 4) / (a + c - b / 2))
    b3 = math.pi - math.asin(b / (2 * a))
    beta = np.zeros_like(phi)
    radius = np.empty_like(phi)
    r1 = ap <= b1
    r2 = (ap > b1) & (ap <= b2)
    r3 = (ap > b2) & (ap <= b3)
    r4 = ap > b3
    radius[r1] = c
    beta[r2] = np.arcsin(a / (a + c) * np.sin(ap[r2] - tx / 2))
    radius[r2] = a * np.sin(ap[r2] - beta[r2] - tx / 2) / np.sin(beta[r2])
    beta[r3] = np.arcsin(a / (a + c - b) * np.sin(ap[r3] + tx / 2))
    radius[r3] = a * np.sin(ap[r3] - beta[r3] + tx / 2) / np.sin(beta[r3])
    radius[r4] = 2 * a + c - b
    return beta, radius


def rs274_command(path, workdir, tool_table: str | None = None) -> list[str]:
    """``rs274 -g path``, with ``-t`` and the tool table written into ``workdir`` when one is given."""
    from pathlib import Path

    if tool_table is None:
        return ["rs274", "-g", str(path)]
    table = Path(workdir) / "tools.tbl"
    table.write_text(tool_table)
    return ["rs274", "-t", str(table), "-g", str(path)]


def rs274_env(workdir, tool_table: str | None = None) -> dict[str, str]:
    """rs274's environment: HOME is ``workdir``.  LinuxCNC keeps the loaded tool table (its
    default one too) in ``$HOME/.tool.mmap``, shared by every rs274 running at the same time: one
    truncating it under another's mapping ends that one by SIGBUS (seen under xdist: status -7)."""
    import os

    return {**os.environ, "HOME": str(workdir)}


def rs274_canon(program: str, workdir, tool_table: str | None = None) -> tuple[int, str, list[dict]]:
    """Run LinuxCNC's ``rs274 -g`` on ``program``; return (exit status, message, canonical moves).

    Every ``STRAIGHT_TRAVERSE``, ``STRAIGHT_FEED`` and ``ARC_FEED`` call becomes a dict with
    ``kind`` ("traverse", "line" or "arc"), ``start`` and ``end`` (3,) in mm, and for arcs
    ``centre`` (2,) and ``turn`` (rs274's rotation: > 0 counter-clockwise, |turn| - 1 extra
    full turns).  rs274 prints 4 decimals, so every number is within 5e-5 mm of its value.
    ``tool_table``: the text of a LinuxCNC tool table (``T1 P1 Z0 D6 ;``) rs274 reads (``-t``).
    """
    import re
    import subprocess
    from pathlib import Path

    path = Path(workdir) / "program.ngc"
    path.write_text(program)
    proc = subprocess.run(rs274_command(path, workdir, tool_table), stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=120,
                          env=rs274_env(workdir, tool_table))
    number = r"(-?\d+(?:\.\d+)?)"
    straight = re.compile(rf"STRAIGHT_(FEED|TRAVERSE)\({number}, {number}, {number}")
    arc = re.compile(rf"ARC_FEED\({number}, {number}, {number}, {number}, (-?\d+), {number}")
    moves: list[dict] = []
    current = np.zeros(3)
    for line in proc.stdout.splitlines():
        m = straight.search(line)
        if m:
            end = np.array([float(m.group(i)) for i in (2, 3, 4)])
            moves.append({"kind": "line" if m.group(1) == "FEED" else "traverse", "start": current, "end": end})
            current = end
            continue
        m = arc.search(line)
        if m:
            end = np.array([float(m.group(1)), float(m.group(2)), float(m.group(6))])
            centre = np.array([float(m.group(3)), float(m.group(4))])
            moves.append({"kind": "arc", "start": current, "end": end, "centre": centre, "turn": int(m.group(5))})
            current = end
    message = proc.stderr + proc.stdout[-2000:] if proc.returncode else proc.stderr
    return proc.returncode, message, moves


def arc_sweep(start: np.ndarray, end: np.ndarray, centre: np.ndarray, turn: int) -> float:
    """Signed sweep (rad) of a canonical arc as LinuxCNC runs it: counter-clockwise for turn > 0,
    in (0, 2 pi] plus (|turn| - 1) full turns; an arc that ends where it starts is a full circle."""
    a0 = math.atan2(start[1] - centre[1], start[0] - centre[0])
    a1 = math.atan2(end[1] - centre[1], end[0] - centre[0])
    ccw = (a1 - a0) % (2 * math.pi) if turn > 0 else (a0 - a1) % (2 * math.pi)
    if ccw == 0.0 or math.hypot(end[0] - start[0], end[1] - start[1]) == 0.0:
        ccw = 2 * math.pi
    ccw += (abs(turn) - 1) * 2 * math.pi
    return ccw if turn > 0 else -ccw


def rs274_toolpath(program: str, workdir) -> tuple[int, str, list[tuple[float, np.ndarray]]]:
    """Run LinuxCNC's ``rs274 -g`` on ``program``; return (exit status, stderr, feed moves).

    Feed moves are rebuilt from the canonical calls (:func:`rs274_canon`): ``STRAIGHT_FEED`` as
    its two end points and ``ARC_FEED`` sampled every 0.2 deg, as (z, points (n, 2)) per move.
    """
    status, message, canon = rs274_canon(program, workdir)
    moves = []
    for move in canon:
        start, end = move["start"], move["end"]
        if move["kind"] == "line":
            moves.append((end[2], np.vstack([start[:2], end[:2]])))
        elif move["kind"] == "arc":
            cx, cy = move["centre"]
            sweep = arc_sweep(start, end, move["centre"], move["turn"])
            a0 = math.atan2(start[1] - cy, start[0] - cx)
            r0, r1 = math.hypot(start[0] - cx, start[1] - cy), math.hypot(end[0] - cx, end[1] - cy)
            n = max(2, int(abs(math.degrees(sweep)) / 0.2) + 2)
            w = np.linspace(0, 1, n)
            radius = r0 + (r1 - r0) * w
            ang = a0 + sweep * w
            moves.append((end[2], np.stack([cx + radius * np.cos(ang), cy + radius * np.sin(ang)], axis=1)))
    return status, message, moves


#: The checkout the tests live in (README.md, benchmarks/, templates/ beside them).
CHECKOUT = Path(__file__).resolve().parent.parent


@pytest.fixture
def tree() -> Path:
    """The checkout: README.md and benchmarks/ are not part of the installed package."""
    return CHECKOUT


def scene_toml(scene: dict) -> str:
    """A scene dict (``output`` with ``formats``, ``cams`` with optional ``segments``) as TOML text."""
    def value(v):
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    lines = ["[output]", f"formats = {value(scene['output']['formats'])}"]
    for name, cam in scene["cams"].items():
        lines.append(f"[cams.{name}]")
        lines += [f"{k} = {value(v)}" for k, v in cam.items() if k != "segments"]
        for seg in cam.get("segments", []):
            lines.append(f"[[cams.{name}.segments]]")
            lines += [f"{k} = {value(v)}" for k, v in seg.items()]
    return "\n".join(lines) + "\n"


def occt_shape(data: bytes, path: Path):
    """OCCT's reading of the STEP or IGES file ``data`` (written to ``path``; its suffix .igs
    picks the IGES reader): the transferred shape, OCCT's statistics kept off stdout."""
    from OCP.IGESControl import IGESControl_Reader
    from OCP.STEPControl import STEPControl_Reader

    path.write_bytes(data)
    reader = IGESControl_Reader() if path.suffix == ".igs" else STEPControl_Reader()
    saved = os.dup(1)  # OCCT prints its statistics on stdout
    with open(os.devnull, "w") as devnull:
        os.dup2(devnull.fileno(), 1)
        try:
            assert int(reader.ReadFile(str(path))) == 1  # IFSelect_RetDone
            reader.TransferRoots()
        finally:
            os.dup2(saved, 1)
            os.close(saved)
    return reader.OneShape()
