"""A barrel cam's part of report.html: the developed pitch curve and walls (a rib: its faces), the
pressure angle at the root, mean and rim radius, a 3-D view (an orthographic SVG projection of the
cylinder with its groove or rib) and the developed track moving past the follower (SMIL animation,
no script): a groove under its roller, a rib between its two rollers.

The data (:func:`section_class`) is made by the plots stage (:mod:`camgen.kinds.barrel`); this
module only draws it.
"""
from __future__ import annotations

import functools
import html
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["VIEW_AZIMUTH_DEG", "VIEW_ELEVATION_DEG", "barrel_section", "project", "section_class"]

#: The 3-D view's direction (towards the viewer): azimuth from +x about +z, elevation above the
#: x-y plane, deg.
VIEW_AZIMUTH_DEG = -30.0
VIEW_ELEVATION_DEG = 20.0
#: Seconds one cam turn takes in the report's animation.
ANIMATION_SECONDS = 6.0


@functools.cache
def section_class() -> type:
    """The frozen data of a barrel cam's section (made on first use: the report model is imported
    only by runs that draw)."""
    from camgen.report.model import SectionData

    @dataclass(frozen=True)
    class BarrelSection(SectionData):
        """Against the cam angle (deg): the pressure angles (deg) at root, mean and rim; the
        developed drawing at the mean radius (x = R_m phi, mm; z mm): pitch curve and both walls
        (a rib: its upper and lower face); the 3-D polylines (label, (n, 3) mm) of the cylinder and
        its track; the animation's frames: per roller (a groove's one, a rib's lower and upper),
        its axis' tangential offset and height per frame (mm); the track (``"groove"`` or
        ``"rib"``); the radii (mm), the cylinder's length (mm), the roller radius (mm), sigma and
        the pressure-angle limit (deg)."""

        theta_deg: np.ndarray
        pressure: tuple[tuple[str, float, np.ndarray], ...]
        developed_x: np.ndarray
        pitch_x: np.ndarray
        pitch_z: np.ndarray
        upper: np.ndarray
        lower: np.ndarray
        lines: tuple[tuple[str, np.ndarray], ...]
        rollers: tuple[tuple[np.ndarray, np.ndarray], ...]
        track: str
        mean_radius: float
        length: float
        roller_radius: float
        sigma: int
        limit: float

    return BarrelSection


def project(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Orthographic projection of ``points`` (n, 3) seen from the view direction
    (:data:`VIEW_AZIMUTH_DEG`, :data:`VIEW_ELEVATION_DEG`): screen x, screen y (mm) and the depth
    towards the viewer (mm)."""
    az, el = math.radians(VIEW_AZIMUTH_DEG), math.radians(VIEW_ELEVATION_DEG)
    d = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
    right = np.array([-math.sin(az), math.cos(az), 0.0])
    up = np.cross(d, right)
    return points @ right, points @ up, points @ d


def _facing(points: np.ndarray) -> np.ndarray:
    """Whether each point of the cylinder's surface (its outward normal radial) faces the viewer."""
    az = math.radians(VIEW_AZIMUTH_DEG)
    return points[:, 0] * math.cos(az) + points[:, 1] * math.sin(az) > 0.0


def _runs(mask: np.ndarray) -> list[slice]:
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return [slice(int(a), int(b)) for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1))]


def _view(Figure: Any, d: Any) -> str:
    """The cylinder and its groove projected: the lines on the near side solid, the far side's
    faint (the rim circles of the end faces in full: the top face is seen)."""
    fig = Figure(figsize=(5.2, 5.2))
    ax = fig.add_subplot()
    colours = {"top face": "k", "bottom face": "k", "silhouette": "k", "bore": "tab:orange"}
    seen: set[str] = set()
    for label, pts in d.lines:
        u, v, _ = project(pts)
        # the top face is seen whole (the view is from above); the bottom face's far half and the far walls are hidden
        front = np.ones(len(pts), dtype=bool) if label in ("top face", "silhouette", "bore") else _facing(pts)
        colour = colours.get(label, "tab:blue" if label.endswith("at the rim") else "tab:green")
        for part in _runs(front):
            ax.plot(u[part], v[part], color=colour, width=1.0, label=None if label in seen else label)
            seen.add(label)
        for part in _runs(~front):
            ax.plot(u[part], v[part], color=colour, width=0.5, dash=":")
    ax.equal_aspect()
    ax.xlabel("mm")
    ax.ylabel("mm")
    ax.title(f"3-D view (orthographic, from azimuth {VIEW_AZIMUTH_DEG:g} deg, elevation {VIEW_ELEVATION_DEG:g} deg)", font_size=8)
    ax.legend("upper right", font_size=7)
    return fig.to_svg()


def _animation_svg(d: Any, title: str, width_px: int = 720) -> str:
    """The developed track (at the mean radius) sliding past the follower at x = 0 over one turn:
    the track translates by sigma 2 pi R_m (two copies cover the view), each roller follows its
    axis (tangential offset, height) per frame.  The cam's material at the mean radius is shaded: a
    groove's outside its walls, a rib's between its faces (the root cylinder lies beside it)."""
    span = 2.0 * math.pi * d.mean_radius
    lo = np.array([-0.5 * span, -5.0])
    hi = np.array([0.5 * span, d.length + 5.0])
    w, h = hi - lo
    height = int(round(width_px * h / w))

    def path(x: np.ndarray, z: np.ndarray) -> str:
        return "M " + " ".join(f"{a:.3f},{b:.3f}" for a, b in zip(x, z))

    dur = f"{ANIMATION_SECONDS:g}s"
    shift = d.sigma * span
    strip = []
    for copy in (-span, 0.0, span):
        x = d.developed_x + copy - 0.5 * span
        if d.track == "rib":
            strip.append(f"<path d='{path(x, d.upper)} L " + " ".join(f"{a:.3f},{b:.3f}" for a, b in zip(x[::-1], d.lower[::-1]))
                         + " Z' fill='#d6e4f0'/>")
        else:
            strip.append(f"<path d='{path(x, d.upper)} L {x[-1]:.3f},{d.length:.3f} L {x[0]:.3f},{d.length:.3f} Z' fill='#d6e4f0'/>")
            strip.append(f"<path d='{path(x, d.lower)} L {x[-1]:.3f},0 L {x[0]:.3f},0 Z' fill='#d6e4f0'/>")
        for wall in (d.upper, d.lower):
            strip.append(f"<path d='{path(x, wall)}' fill='none' stroke='#1f4e79' stroke-width='0.5'/>")
    body = [f"<g><animateTransform attributeName='transform' type='translate' from='{0.5 * span:.3f} 0' to='{0.5 * span + shift:.3f} 0' "
            f"dur='{dur}' repeatCount='indefinite'/>" + "".join(strip) + "</g>"]
    a = np.linspace(0.0, 2.0 * math.pi, 49)
    circle = path(d.roller_radius * np.cos(a), d.roller_radius * np.sin(a))
    for frames_e, frames_z in d.rollers:
        values = ";".join(f"{e:.4f} {z:.4f}" for e, z in zip(frames_e, frames_z))
        body.append(f"<g><animateTransform attributeName='transform' type='translate' values='{values}' dur='{dur}' "
                    f"repeatCount='indefinite'/><path d='{circle}' fill='none' stroke='#c0392b' stroke-width='0.8'/></g>")
    body.append(f"<line x1='0' y1='{lo[1]:.3f}' x2='0' y2='{hi[1]:.3f}' stroke='#888' stroke-dasharray='2,2' stroke-width='0.4'/>")
    inner = "".join(body)
    return (f"<svg xmlns='http://www.w3.org/2000/svg' width='{width_px}' height='{height}' viewBox='0 0 {w:.3f} {h:.3f}' "
            f"role='img' aria-label='{title}'><g transform='translate({-lo[0]:.3f} {hi[1]:.3f}) scale(1 -1)'>{inner}</g></svg>")


def barrel_section(Figure: Any, cam: Any) -> str:
    """A barrel cam's part of report.html (see the module notes)."""
    d = cam.section
    if d is None:
        return ""
    name = html.escape(cam.name)
    rib = d.track == "rib"
    surface = "face of the rib" if rib else "wall"
    parts = [f"<h3>{name}: barrel cam{' with a rib between two rollers' if rib else ''}, developed at the mean radius "
             f"R_m = {d.mean_radius:g} mm</h3>"]
    fig = Figure(figsize=(10, 3.6))
    ax = fig.add_subplot()
    ax.plot(d.developed_x, d.upper, color="#1f3a5f", width=1.0, label=f"upper {surface} at R_m")
    ax.plot(d.developed_x, d.lower, color="#1f3a5f", width=1.0, dash="-.", label=f"lower {surface} at R_m")
    pitch = "pitch line (midway between the roller axes)" if rib else "pitch curve (roller axis)"
    ax.plot(d.pitch_x, d.pitch_z, color="tab:blue", width=0.8, dash="--", label=pitch)
    span = 2.0 * math.pi * d.mean_radius
    for z in (0.0, d.length):
        ax.plot(np.array([0.0, span]), np.array([z, z]), color="k", width=1.0)
    ax.plot(np.array([0.0, 0.0]), np.array([0.0, d.length]), color="k", width=1.0)
    ax.plot(np.array([span, span]), np.array([0.0, d.length]), color="k", width=1.0, label="cylinder developed")
    ax.equal_aspect()
    ax.xlabel("x = R_m * polar angle on the cam (mm)")
    ax.ylabel("z along the axis (mm)")
    ax.legend(font_size=7)
    ax.title("developed drawing at the mean radius (the cam's polar angle from 0 to 360 deg)", font_size=9)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    fig = Figure(figsize=(10, 3.4))
    ax = fig.add_subplot()
    for (label, radius, values), colour in zip(d.pressure, ("tab:red", "tab:blue", "tab:green")):
        ax.plot(d.theta_deg, values, color=colour, width=1.0, label=f"{label}, radius {radius:g} mm")
    ax.hline(d.limit, color="tab:red", dash="--")
    ax.hline(-d.limit, color="tab:red", dash="--")
    ax.xlabel("cam angle (deg)")
    ax.ylabel("pressure angle (deg)")
    ax.legend(font_size=7)
    ax.title(f"pressure angle at the root, mean and rim radius (limit {d.limit:g} deg, dashed)", font_size=9)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    parts.append(f"<div class='tables'><div class='fig'>{_view(Figure, d)}</div>"
                 f"<div class='fig'>{_animation_svg(d, name + (': the developed rib moving between the rollers' if rib else ': the developed groove moving past the roller'))}"
                 + ("<p class='note'>The rib developed at the mean radius moving between the follower's two rollers over one "
                    "turn (the rollers' axes at x = 0, dashed; the rib shaded).</p></div></div>" if rib else
                    "<p class='note'>The groove developed at the mean radius moving past the roller over one turn "
                    "(the roller's axis at x = 0, dashed).</p></div></div>"))
    return "".join(parts)
