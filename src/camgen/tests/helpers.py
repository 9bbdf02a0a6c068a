"""Independent reference computations for the tests (brute force, closed forms)."""
from __future__ import annotations

import math
import os
import shutil

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


def rs274_toolpath(program: str, workdir) -> tuple[int, str, list[tuple[float, np.ndarray]]]:
    """Run LinuxCNC's ``rs274 -g`` on ``program``; return (exit status, stderr, feed moves).

    Feed moves are rebuilt from the canonical calls: ``STRAIGHT_FEED`` as its end point and
    ``ARC_FEED`` sampled every 0.2 deg, as (z, points (n, 2)) per move.
    """
    import re
    import subprocess
    from pathlib import Path

    path = Path(workdir) / "program.ngc"
    path.write_text(program)
    proc = subprocess.run(["rs274", "-g", str(path)], stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=120)
    number = r"(-?\d+(?:\.\d+)?)"
    moves = []
    current = np.zeros(3)
    for line in proc.stdout.splitlines():
        m = re.search(rf"STRAIGHT_(FEED|TRAVERSE)\({number}, {number}, {number}", line)
        if m:
            end = np.array([float(m.group(i)) for i in (2, 3, 4)])
            if m.group(1) == "FEED":
                moves.append((end[2], np.vstack([current[:2], end[:2]])))
            current = end
            continue
        m = re.search(rf"ARC_FEED\({number}, {number}, {number}, {number}, (-?\d+), {number}", line)
        if m:
            x1, y1, cx, cy = (float(m.group(i)) for i in (1, 2, 3, 4))
            rot, z1 = int(m.group(5)), float(m.group(6))
            a0 = math.atan2(current[1] - cy, current[0] - cx)
            a1 = math.atan2(y1 - cy, x1 - cx)
            sweep = (a1 - a0) % (2 * math.pi) if rot > 0 else -((a0 - a1) % (2 * math.pi))
            radius = math.hypot(current[0] - cx, current[1] - cy)
            n = max(2, int(abs(math.degrees(sweep)) / 0.2) + 2)
            ang = a0 + sweep * np.linspace(0, 1, n)
            moves.append((z1, np.stack([cx + radius * np.cos(ang), cy + radius * np.sin(ang)], axis=1)))
            current = np.array([x1, y1, z1])
    return proc.returncode, proc.stderr + proc.stdout[-2000:] if proc.returncode else proc.stderr, moves
