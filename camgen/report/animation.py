"""The follower riding the cam: an inline SVG animated with SMIL (no script, no external file).

The cam (its profile polygon and the cam-angle-0 mark) turns about the axis with
``<animateTransform type="rotate">``; the follower moves with one ``<animateTransform>`` whose
values are its lift (translate, mm) or swing (rotate about the pivot, deg) at uniformly spaced
cam angles: both start at cam angle 0 and last one turn, so they stay in step.  Drawing
coordinates are the cam's (mm, y up): one group flips them to SVG's y-down.  Numbers are
printed with fixed decimals: the same data give the same bytes.
"""
from __future__ import annotations

import math

import numpy as np

from camgen.report.model import RideAnimation

__all__ = ["RideAnimation", "animation_svg"]


def _path(points: np.ndarray, closed: bool = False) -> str:
    text = " ".join(f"{x:.3f},{y:.3f}" for x, y in points)
    return f"M {text}{' Z' if closed else ''}"


_COLOURS = {"roller": "#c0392b", "knife": "#c0392b", "follower face": "#c0392b", "follower stem": "#7f8c8d", "arm": "#7f8c8d",
            "pivot": "#2c3e50"}


def animation_svg(anim: RideAnimation, title: str, width_px: int = 420) -> str:
    """The inline SVG (text) of ``anim``: the cam turning, the follower riding it, in a loop."""
    radius = float(np.max(np.hypot(*anim.profile.T)))
    pts = [anim.profile, *[p for _, p in anim.follower]]
    if anim.motion == "translating":
        lifted = [p + np.array([0.0, float(np.max(anim.moves))]) for _, p in anim.follower]
        pts.extend(lifted)
    else:
        pts.append(np.array([anim.pivot]))
        pts.extend(_turned(p, anim.pivot, float(a)) for _, p in anim.follower for a in (np.min(anim.moves), np.max(anim.moves)))
    allp = np.concatenate(pts + [np.array([[radius, radius], [-radius, -radius]])])
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    pad = 0.06 * float(np.max(hi - lo))
    lo, hi = lo - pad, hi + pad
    w, h = hi - lo
    height_px = int(round(width_px * h / w))
    stroke = 0.004 * float(max(w, h))
    dur = f"{anim.seconds:g}s"
    turn = 360.0 * anim.sigma
    parts = [f"<svg xmlns='http://www.w3.org/2000/svg' width='{width_px}' height='{height_px}' "
             f"viewBox='{lo[0]:.3f} {-hi[1]:.3f} {w:.3f} {h:.3f}' role='img' aria-label='{title}'>",
             f"<title>{title}</title>",
             "<g transform='scale(1,-1)'>",
             f"<circle cx='0' cy='0' r='{0.015 * radius:.3f}' fill='#000'/>",
             "<g>",
             f"<animateTransform attributeName='transform' type='rotate' from='0 0 0' to='{turn:g} 0 0' dur='{dur}' "
             "repeatCount='indefinite'/>",
             f"<path d='{_path(anim.profile, True)}' fill='#d6e4f0' stroke='#1f3a5f' stroke-width='{stroke:.3f}'/>"]
    # a pocket's walls (a groove): the outer wall filled as the pocket's floor, the inner wall's island as the face
    for wall, fill in zip(anim.walls, ("#9fb7cf", "#d6e4f0")):
        parts.append(f"<path d='{_path(wall, True)}' fill='{fill}' stroke='#1f3a5f' stroke-width='{stroke:.3f}'/>")
    if anim.zero_mark is not None:
        p = np.array(anim.zero_mark.point)
        parts.append(f"<path d='M 0,0 {p[0]:.3f},{p[1]:.3f}' stroke='#8e44ad' stroke-width='{1.5 * stroke:.3f}' fill='none'/>")
        parts.append(f"<circle cx='{p[0]:.3f}' cy='{p[1]:.3f}' r='{3 * stroke:.3f}' fill='#8e44ad'/>")
    parts.append("</g>")
    if anim.motion == "translating":
        values = ";".join(f"0,{v:.4f}" for v in np.append(anim.moves, anim.moves[0]))
        motion = (f"<animateTransform attributeName='transform' type='translate' values='{values}' dur='{dur}' "
                  "repeatCount='indefinite' calcMode='linear'/>")
    else:
        assert anim.pivot is not None  # an oscillating follower's animation has its pivot (RideAnimation)
        px, py = anim.pivot
        values = ";".join(f"{v:.4f} {px:.3f} {py:.3f}" for v in np.append(anim.moves, anim.moves[0]))
        motion = (f"<animateTransform attributeName='transform' type='rotate' values='{values}' dur='{dur}' "
                  "repeatCount='indefinite' calcMode='linear'/>")
        parts.append(f"<circle cx='{px:.3f}' cy='{py:.3f}' r='{4 * stroke:.3f}' fill='#2c3e50'/>")
    parts.append("<g>" + motion)
    for label, poly in anim.follower:
        closed = label in ("roller", "pivot")
        parts.append(f"<path d='{_path(poly, closed)}' fill='none' stroke='{_COLOURS.get(label, '#c0392b')}' "
                     f"stroke-width='{2 * stroke:.3f}'/>")
    parts.append("</g></g></svg>")
    return "".join(parts)


def _turned(points: np.ndarray, pivot: tuple[float, float] | None, degrees: float) -> np.ndarray:
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    d = points - np.asarray(pivot)
    return np.asarray(pivot) + np.stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]], axis=1)
