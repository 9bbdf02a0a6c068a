"""Design checks on a contour: each returns a :class:`CheckResult` a person and a program can read."""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from camgen.contour import Contour

_ORDER = ["none", "G0", "G1", "G2"]


@dataclass(frozen=True)
class CheckResult:
    """One design check.

    Attributes
    ----------
    name : str
        What is checked (snake_case).
    value : float or str
        The measured value, in ``unit``.
    limit : float or str
        The limit it is held against, in ``unit``.
    unit : str
        Unit of ``value`` and ``limit`` (``mm``, ``deg``, ``1/mm``, or ``""``).
    passed : bool
        Whether ``value`` satisfies ``limit``.
    where_deg : list of float
        Cam angles (deg, polar angle in the cam frame) where the check is worst or fails.
    note : str
        One sentence a designer reads.
    """

    name: str
    value: Any
    limit: Any
    unit: str
    passed: bool
    where_deg: list[float] = field(default_factory=list)
    note: str = ""

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def _polar_deg(points: np.ndarray) -> list[float]:
    return [round(math.degrees(math.atan2(y, x)) % 360.0, 6) for x, y in np.atleast_2d(points)]


def breadth_error(contour: Contour, breadth: float, n_directions: int = 3600) -> tuple[float, float]:
    """Largest ``|h(psi) + h(psi + pi) - breadth|`` (mm) over ``n_directions`` face directions, and where (rad)."""
    psi = np.linspace(0.0, math.pi, n_directions, endpoint=False)
    err = np.abs(contour.support(psi) + contour.support(psi + math.pi) - breadth)
    worst = int(np.argmax(err))
    return float(err[worst]), float(psi[worst])


def constant_breadth_check(contour: Contour, breadth: float, tol: float = 1e-6) -> CheckResult:
    """Constant breadth for a yoke (double flat-faced) follower: error against ``tol`` mm."""
    err, psi = breadth_error(contour, breadth)
    return CheckResult(
        "constant_breadth",
        err,
        tol,
        "mm",
        err <= tol,
        [round(math.degrees(psi) % 360.0, 6)],
        f"distance between the parallel yoke faces stays {breadth:g} mm within {err:.3g} mm over 3600 directions",
    )


def continuity_check(contour: Contour, required: str = "G1") -> CheckResult:
    """Lowest joint continuity against ``required``; ``where_deg`` lists joints with curvature jumps."""
    joints = contour.joints()
    level = min((j.continuity for j in joints), key=_ORDER.index)
    jumps = [j for j in joints if j.continuity != "G2"]
    where = _polar_deg(np.array([j.point for j in jumps])) if jumps else []
    note = f"lowest continuity {level} over {len(joints)} joints"
    if level == "G1":
        biggest = max(abs(j.curvature_jump_per_mm) for j in jumps)
        note += (
            f"; curvature jumps at {len(jumps)} joints (largest {biggest:.6g} 1/mm): the follower "
            "acceleration jumps there, i.e. infinite jerk"
        )
    return CheckResult("continuity", level, required, "", _ORDER.index(level) >= _ORDER.index(required), where, note)


def convexity_check(contour: Contour, samples_per_segment: int = 64) -> CheckResult:
    """Flat-faced and yoke followers need a convex cam: smallest signed curvature must be > 0 (1/mm)."""
    u = (np.arange(samples_per_segment) + 0.5) / samples_per_segment
    t = (np.arange(contour.n_segments)[:, None] + u[None, :]).ravel()
    kappa = contour.curvature(t)
    worst = int(np.argmin(kappa))
    bad = kappa <= 0
    where = _polar_deg(contour.evaluate(t[bad])) if bad.any() else _polar_deg(contour.evaluate(t[worst : worst + 1]))
    return CheckResult(
        "convexity",
        float(kappa[worst]),
        0.0,
        "1/mm",
        bool(not bad.any()),
        where[:20],
        "a flat face touches a convex cam at one point in every direction" if not bad.any()
        else "concave parts: a flat face would bridge them (undercut of the flat follower)",
    )
