"""Groove (track, face) plate cams: a roller running in a groove cut into a plate.

The groove is form-closed: its two walls hold the roller both ways, so no spring is needed and
the follower cannot jump.  The walls are the exact envelopes of a roller of radius ``w = r + c
/ 2`` (``r`` the roller radius, ``c`` the groove clearance, ``groove_clearance_mm``) on both
sides of the pitch curve (the roller-centre path): the inner wall ``P - w n`` (the open plate
cam's profile for a roller of radius ``w``) and the outer wall ``P + w n``
(:func:`camgen.synthesis.followers.pitch_offsets`), each within ``fit_tol_mm``.  A roller of
radius ``r`` in the groove then has ``c`` of play across it: touching the inner wall its centre
lies ``c / 2`` inside the pitch curve, touching the outer wall ``c / 2`` outside.

Conventions are those of the plate cam (:mod:`camgen.synthesis.followers`); the body is a disk
of radius ``rim_radius_mm`` and the plate's thickness, with the groove cut from the top face
(z = thickness, the face seen in the DXF) down ``groove_depth_mm``; the DXF layers GROOVE_INNER
(the wall nearer the axis) and GROOVE_OUTER.

Checks (closed forms on the law's dense grid): both walls can be made (|radius of curvature of
the pitch curve| > w wherever it bends towards a wall: stricter than an open cam's rho > r), the
pressure angle, the continuity of both walls, the walls to the bore, the rim and the floor, the
tool against the groove, and where the roller changes walls (its inertia force changes sign:
a crossover shock at speed).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Mapping, Protocol

import numpy as np

from camgen.errors import ParameterError
from camgen.kinds.base import CamSpec, Pocket, Wall, with_cam
from camgen.kinds.disk import DiskCam, DiskParams, build_disk, follower_keys, pressure_limit
from camgen.schema import Key, Length

if TYPE_CHECKING:
    from camgen.body import BodySpec
    from camgen.checks import CamEvaluation, CheckResult, Motion
    from camgen.contour import Contour

__all__ = ["DEFAULT_CLEARANCE", "acceleration_zeros", "GrooveBody", "INNER", "OUTER", "GrooveCam", "GrooveParams", "build_groove", "evaluate_groove", "groove_keys", "groove_kinematics",
           "groove_tool_check", "groove_wall_checks", "max_radius", "read_groove_depth", "rim_circle", "rim_radius_for", "roller_keys", "groove_spec"]

#: Default ``groove_clearance_mm``: the groove's width less the roller's diameter (mm); a running
#: fit for a track roller (a few hundredths of a millimetre).
DEFAULT_CLEARANCE = 0.05
#: The groove's layers (DXF, point list): the wall nearer the axis, the wall farther from it.
INNER, OUTER = "GROOVE_INNER", "GROOVE_OUTER"
#: The rim radius the form chooses is rounded up to this step (mm).
RIM_STEP = 0.5
#: Radius of curvature (mm) of a wall below which its joints' tangent directions are not
#: resolved (the wall is within that of a cusp): such a joint is taken as the law's and named.
NEAR_CUSP = 0.01
#: Bisection steps locating a wall crossover (a zero of the law's s'') between two samples 0.1 deg
#: apart: 2^-40 of 0.1 deg, 1.6e-15 rad.
CROSSOVER_BISECTIONS = 40
#: Chord tolerance (mm) of the polygons on which the walls' extreme radii are measured (the
#: result is corrected by it to stay on the safe side).
RADIUS_CHORD_TOL = 1e-4


def groove_keys(radius_key: str = "roller_radius_mm", roller: str = "roller") -> tuple[Key, ...]:
    """The groove's own keys (the follower's are the plate cam's, rollers only; a steering cam's
    rod is its ``radius_key``, ``rod_radius_mm``)."""
    return (
        Key("groove_clearance_mm", Length(0.0, 100.0, low_open=False), f"Groove width less the {roller} diameter: the walls are "
            f"the envelopes of a {roller} of radius {radius_key} + clearance / 2 on both sides of the pitch curve.",
            ("profile",), default=DEFAULT_CLEARANCE, example=0.1),
        Key("groove_depth_mm", Length(high=1e4), "Depth of the groove below the plate's top face (< thickness_mm; default: "
            "half the thickness; the DXF states it).", ("thickness", "dxf"), example=4.0),
        Key("rim_radius_mm", Length(high=1e5), "Radius of the plate's rim (default: the outer wall's largest radius plus "
            "min_wall_mm, rounded up to 0.5 mm).", ("profile",), example=120.0),
    )


def roller_keys() -> tuple[Key, ...]:
    """The plate cam's follower keys for a roller: the ``follower`` choice holds the registered
    followers with a radius, keys only other followers take are left out; sizing holds both walls
    (:func:`build_groove`)."""
    from camgen.followers import follower_names, get_follower
    from camgen.schema import Choice

    rollers = tuple(n for n in follower_names(("point",)) if get_follower(n).has_radius)
    out = []
    for key in follower_keys():
        if key.name == "sizing":
            key = replace(key, doc="Let camgen find the smallest base radius (base_radius), or base radius and offset "
                          "(base_radius_and_offset: translating roller) whose groove meets the pressure-angle limit and can be made "
                          "(both walls: |radius of the pitch curve| > roller radius + clearance / 2) and, when a tool is named, "
                          "whose walls' concave radii the tool reaches; base_radius_mm (and follower_offset_mm) are then refused "
                          "and the result is in the report's figures.")
        owners = key.requires.get("follower")
        if owners is not None and not set(owners) & set(rollers):
            continue
        if key.name == "follower":
            key = replace(key, type=Choice(rollers), doc="Follower (camgen.followers): a follower with a roller running in the "
                          "groove: " + "; ".join(f"{n}, {get_follower(n).summary}" for n in rollers) + ".")
        elif owners is not None:
            key = replace(key, requires={**key.requires, "follower": tuple(o for o in owners if o in rollers)})
        out.append(key)
    return tuple(out)


@dataclass(frozen=True)
class GrooveParams(DiskParams):
    """A groove cam: the plate cam's law and roller, the clearance (mm), the groove depth and the
    rim radius (mm; None: chosen, see :func:`groove_keys`)."""

    clearance: float = DEFAULT_CLEARANCE
    depth: float | None = None
    rim_radius: float | None = None

    @property
    def half_width(self) -> float:
        """w = r + c / 2 (mm): the distance of each wall from the pitch curve."""
        return self.follower.roller_radius + 0.5 * self.clearance


@dataclass(frozen=True, kw_only=True)
class GrooveCam(DiskCam):
    """A built groove cam: a :class:`DiskCam` whose envelope is the inner wall's (a roller of
    radius ``half_width``), ``contour`` the rim circle, and the groove: its walls (None where
    they cannot be made), width, depth and rim radius (mm)."""

    inner_wall: "Contour | None"
    outer_wall: "Contour | None"
    half_width: float
    depth: float
    rim_radius: float
    roller: Any  # the FollowerSpec of the real roller (radius r): drawings, dynamics


def read_groove_depth(where: str, parsed: Mapping[str, Any], thickness: float) -> float | None:
    """``groove_depth_mm`` (mm; None: the default, half the plate), refused unless below the
    plate's ``thickness`` mm."""
    depth: float | None = parsed.get("groove_depth")
    if depth is not None and not depth < thickness:
        raise ParameterError(f"{where}.groove_depth_mm", depth, f"0 < groove_depth_mm < thickness_mm = {thickness:g} mm",
                             "the groove is cut into the plate, not through it")
    return depth


def groove_spec(where: str, spec: CamSpec, parsed: Mapping[str, Any]) -> CamSpec:
    """The plate cam's ``spec`` with the groove's keys (errors naming them)."""
    p = spec.params
    depth = read_groove_depth(where, parsed, spec.body.thickness)
    half = 0.5 * parsed["groove_clearance"]
    if not p.follower.base_radius - half > 0.0:  # the inner wall's base circle lies c / 2 inside the base radius
        if p.sizing == "none":
            raise ParameterError(f"{where}.base_radius_mm", p.follower.base_radius, f"> groove_clearance_mm / 2 = {half:g} mm",
                                 "the groove's inner wall lies half the clearance inside the base circle")
        p = replace(p, follower=replace(p.follower, base_radius=half + 1.0))  # sizing's starting placeholder, clear of it
    params = GrooveParams(**{f: getattr(p, f) for f in p.__dataclass_fields__}, clearance=parsed["groove_clearance"],
                          depth=depth, rim_radius=parsed.get("rim_radius"))
    return replace(spec, params=params)


def max_radius(contour: "Contour") -> float:
    """The largest distance of ``contour`` from the axis (mm), from above (a polygon within
    :data:`RADIUS_CHORD_TOL` of it, plus that tolerance)."""
    pts = contour.flatten(RADIUS_CHORD_TOL)
    return float(np.max(np.hypot(pts[:, 0], pts[:, 1]))) + RADIUS_CHORD_TOL


def _pieces(contour: "Contour") -> int:
    """Spline pieces of a wall (the envelopes are quintic splines)."""
    from camgen.contour import Spline

    return int(sum(seg.n_pieces for seg in contour.segments if isinstance(seg, Spline)))


def rim_circle(radius: float) -> "Contour":
    """The body's outline: the rim circle of ``radius`` mm about the axis."""
    from camgen.contour import Arc, Contour

    return Contour([Arc((0.0, 0.0), radius, 0.0, 2.0 * math.pi)])


def rim_radius_for(reach: float, min_wall: float) -> float:
    """The rim radius the form chooses (mm): the outer wall's largest radius ``reach`` plus
    ``min_wall``, rounded up to :data:`RIM_STEP`."""
    return math.ceil((reach + min_wall) / RIM_STEP - 1e-9) * RIM_STEP


def build_groove(spec: CamSpec, stages: frozenset[str]) -> GrooveCam:
    """The groove's walls (exact envelopes of a roller of radius w on both sides of the pitch
    curve), the rim and the pocket; the plate cam's envelope for the inner wall gives the checks."""
    from camgen.synthesis.followers import pitch_offset_failures, pitch_offsets

    p: GrooveParams = spec.params
    where = f"cams.{spec.name}"
    w = p.half_width
    roller = p.follower
    # the roller of radius w on the same pitch curve (prime radius base + r): its base circle lies c / 2 inside the roller's
    wall_follower = with_cam(where, lambda: replace(roller, roller_radius=w, base_radius=roller.base_radius - 0.5 * p.clearance))
    # the inner wall is the open cam's profile for a roller of radius w; its concave radius is |rho| + w where the pitch
    # curve is concave, so sizing it with concave radii >= 2 w holds the outer wall's |rho| > w too (and the tool's)
    tool = spec.checks.tool_radius
    sizing_checks = replace(spec.checks, tool_radius=max(tool or 0.0, 2.0 * w)) if p.sizing != "none" else spec.checks
    inner_spec = replace(spec, params=replace(p, follower=wall_follower), checks=sizing_checks)
    disk = build_disk(inner_spec, stages)
    if disk.sizing is not None:  # the sized roller: the wall roller's base radius + c / 2
        wall_follower = disk.sizing.follower
        roller = replace(wall_follower, roller_radius=roller.roller_radius, base_radius=wall_follower.base_radius + 0.5 * p.clearance)
    k = disk.envelope.data
    depth = p.depth if p.depth is not None else 0.5 * spec.body.thickness
    inner = outer = None
    fit_error = float(disk.figures.get("fit_error_mm", float("nan")))
    can_make = disk.contour is not None and not pitch_offset_failures(k, -w).any()
    if can_make:
        inner = disk.contour
        (outer,), (error,) = with_cam(where, lambda: pitch_offsets(roller, disk.law, (-w,), fit_tol=p.fit_tol))
        fit_error = max(fit_error, error)
    rim = p.rim_radius
    if rim is None:
        reach = max_radius(outer) if outer is not None else max_radius(disk.envelope.pitch) + w if disk.envelope.pitch is not None else w
        rim = rim_radius_for(reach, spec.body.min_wall)
    figures = dict(disk.figures)
    for name in ("profile_pieces", "area_mm2", "perimeter_mm", "bounds_mm"):
        figures.pop(name, None)
    figures["follower"] = {**figures["follower"], "roller_radius_mm": roller.roller_radius,
                           "prime_radius_mm": roller.prime_radius}
    figures["base_radius_mm"] = roller.base_radius
    if disk.sizing is not None:
        figures["sizing"] = {**figures["sizing"], "base_radius_mm": roller.base_radius, "offset_mm": roller.offset,
                             "min_concave_radius_mm": tool or 0.0,
                             "walls": "both walls can be made: |radius of the pitch curve| > roller radius + clearance / 2"}
        if p.sizing != "base_radius_and_offset":
            figures["sizing"].pop("offset_mm")
    figures["groove"] = {"clearance_mm": p.clearance, "width_mm": 2.0 * w, "depth_mm": depth, "rim_radius_mm": rim,
                         "wall_offset_mm": w,
                         "walls": "exact envelopes of a roller of radius roller_radius_mm + clearance / 2 on both sides of the pitch curve"}
    contour = pockets = None
    if inner is not None and outer is not None:
        figures["fit_error_mm"] = fit_error
        figures["groove"].update(inner_wall_pieces=_pieces(inner), outer_wall_pieces=_pieces(outer), groove_area_mm2=outer.area - inner.area)
        contour = rim_circle(rim)
        figures["area_mm2"] = contour.area
        pockets = (Pocket("groove", (Wall(OUTER, outer), Wall(INNER, inner)), depth, width=2.0 * w, centre=disk.envelope.pitch,
                          clearance=p.clearance, note=f"groove {2.0 * w:g} mm wide (roller {2.0 * roller.roller_radius:g} mm "
                          f"+ clearance {p.clearance:g} mm), {depth:g} mm deep"),)
    drawing, animation = disk.drawing, disk.animation
    if "plots" in stages:
        from camgen.kinds.disk import ride_animation, follower_shapes

        size = roller.prime_radius + (disk.law.s_bounds[1] - disk.law.s_bounds[0] if roller.lift_unit == "mm" else 0.0)
        s0 = float(disk.law(np.zeros(1))[0][0])
        drawing = follower_shapes(roller, s0, size)
        walls = tuple(c.flatten(max(1e-3, 2e-4 * size)) for c in (outer, inner) if c is not None)
        assert disk.zero_mark is not None  # a disk cam knows its cam angle 0
        animation = ride_animation(contour if contour is not None else disk.envelope.pitch, disk.zero_mark, roller, disk.law, size, None)
        if animation is not None:
            animation = replace(animation, walls=walls)
    return GrooveCam(spec.name, spec.kind, contour, figures, spec.body, None, pitch=disk.envelope.pitch, zero_mark=disk.zero_mark,
                     envelope=disk.envelope, law=disk.law, spec_follower=wall_follower, sizing=disk.sizing, motion=disk.motion,
                     drawing=drawing, animation=animation, pockets=pockets or (), inner_wall=inner, outer_wall=outer, half_width=w,
                     depth=depth, rim_radius=rim, roller=roller)


# --------------------------------------------------------------------------------------------
# Checks
# --------------------------------------------------------------------------------------------
def _undercut(cam: GrooveCam) -> "CheckResult":
    """Both walls: the pitch curve's radius against w where it bends towards each wall."""
    from camgen.checks import CheckResult
    from camgen.kinds.disk import mask_where
    from camgen.synthesis.followers import pitch_offset_failures

    k, w = cam.envelope.data, cam.half_width
    theta = k.theta
    rho = k.pitch_radius
    assert rho is not None
    inner_bad, outer_bad = pitch_offset_failures(k, w), pitch_offset_failures(k, -w)
    bad = inner_bad | outer_bad
    magnitude = np.abs(rho)
    i = int(np.argmin(magnitude))
    value = float(magnitude[i])
    parts = []
    for what, mask, side in (("inner wall (GROOVE_INNER)", inner_bad, "convex"), ("outer wall (GROOVE_OUTER)", outer_bad, "concave")):
        if mask.any():
            parts.append(f"{what}: the pitch curve's {side} radius is at most {w:g} mm between the listed pairs of cam angles")
    convex = np.where(rho > 0, rho, np.inf)
    concave = np.where(rho < 0, -rho, np.inf)
    note = (f"smallest |radius of curvature| of the pitch curve against the walls' offset w = roller radius + clearance / 2 = "
            f"{w:g} mm (stricter than an open cam's convex radius > roller radius: the outer wall needs the concave radius above "
            f"w too); smallest convex radius {float(convex.min()):.6g} mm (inner wall), smallest concave radius "
            f"{float(concave.min()):.6g} mm (outer wall)" if np.isfinite(concave.min()) else
            f"smallest |radius of curvature| of the pitch curve against the walls' offset w = roller radius + clearance / 2 = "
            f"{w:g} mm; the pitch curve is convex everywhere (the outer wall cannot undercut)")
    if parts:
        note += "; " + "; ".join(parts) + ": the groove cannot be made"
    if bad.any():
        i = int(np.argmax(bad))
    return CheckResult("undercut", value, w, ">", "mm", not bad.any(), mask_where(bad, theta, i), note, blocks_manufacture=True)


def _continuity(cam: GrooveCam) -> "CheckResult":
    """The walls' joints against the law: G2 where s'' is continuous, G1 with the exact
    curvature jump where it jumps (the walls' curvature kappa / (1 -+ w kappa) from the pitch
    curve's, kappa, one-sided at each joint)."""
    from camgen.checks import CheckResult, where_degrees
    from camgen.synthesis.followers import kinematics

    f, w = cam.roller, cam.half_width
    levels, expected, deviation, angles_all = [], [], 0.0, []
    near_cusp: list[float] = []
    for contour, d in ((cam.inner_wall, w), (cam.outer_wall, -w)):
        assert contour is not None
        joints = contour.joints(curvature_tol=1e-6)
        ends = np.array([float(seg.breaks[-1]) for seg in contour.segments])  # type: ignore[union-attr]
        angles = np.mod(-f.sigma * ends, 2.0 * math.pi)
        eps = 1e-9
        kb = kinematics(f, cam.law, angles + f.sigma * eps).pitch_curvature
        ka = kinematics(f, cam.law, angles - f.sigma * eps).pitch_curvature
        assert kb is not None and ka is not None
        before, after = kb / (1.0 - d * kb), ka / (1.0 - d * ka)  # the wall's curvature (paper-free: an offset curve's)
        exp = np.where(np.abs(after - before) > 1e-6, "G1", "G2")
        lev = np.array([j.continuity for j in joints])
        # where the wall's radius on either side is below NEAR_CUSP (the pitch curve's |radius| within that of w) the
        # wall's tangent is 1 - d kappa ~ 0 times the pitch curve's: its direction at the joint is not resolved
        sharp = np.minimum(np.abs(1.0 / np.where(before != 0, before, 1e-300)), np.abs(1.0 / np.where(after != 0, after, 1e-300))) < NEAR_CUSP
        lev = np.where(sharp, exp, lev)
        near_cusp += [float(a) for a in angles[sharp]]
        devs = [abs(j.curvature_jump_per_mm - (a - b)) for j, a, b, e in zip(joints, after, before, sharp) if not e]
        deviation = max([deviation] + devs)
        levels.append(lev)
        expected.append(exp)
        angles_all.append(angles)
    lev, exp, ang = np.concatenate(levels), np.concatenate(expected), np.concatenate(angles_all)
    passed = bool(np.all(lev == exp)) and deviation <= 1e-6
    order = ["none", "G0", "G1", "G2"]
    lowest = min(lev, key=order.index)
    jumps = lev != "G2"
    note = (f"{lev.size} joints on the two walls at the law's breaks; lowest continuity {lowest}; each joint's curvature jump "
            f"is the closed form's within {deviation:.2g} 1/mm")
    if near_cusp:
        note += (f"; at cam angles {', '.join(f'{math.degrees(a):.3f}' for a in near_cusp)} deg a wall's radius of curvature is below "
                 f"{NEAR_CUSP:g} mm (the pitch curve's |radius| there is barely above the walls' offset): a sharp edge the roller "
                 "rides over; its joint is taken as the law's")
    if not passed:
        note += "; joints not as continuous as the law"
    return CheckResult("continuity", str(lowest), "G1", "at least", "", passed, where_degrees(np.unique(ang[jumps])), note)


class GrooveBody(Protocol):
    """What the groove's material checks read: the walls (mm contours about the axis), their
    offset from the groove's centre line, its depth, the rim and the body (a groove cam's, or a
    steering cam's groove: :mod:`camgen.motions.trajectory`)."""

    @property
    def inner_wall(self) -> "Contour | None": ...
    @property
    def outer_wall(self) -> "Contour | None": ...
    @property
    def half_width(self) -> float: ...
    @property
    def depth(self) -> float: ...
    @property
    def rim_radius(self) -> float: ...
    @property
    def body(self) -> "BodySpec": ...


def groove_wall_checks(cam: GrooveBody) -> list["CheckResult"]:
    """The material left: bore/keyway to the inner wall, outer wall to the rim, the floor."""
    from camgen.body import wall_left
    from camgen.checks import limited

    body = cam.body
    out = []
    assert cam.inner_wall is not None and cam.outer_wall is not None
    if body.bore_diameter > 0:
        wall, where = wall_left(cam.inner_wall, body)
        what = ("the bore/keyway breaks into the groove" if wall <= 0 else
                f"thinnest wall between the bore/keyway and the groove's inner wall, {wall:.3f} mm")
        out.append(limited("wall_thickness", wall, ">=", body.min_wall, "mm", [round(where, 6)], what, blocks_manufacture=True))
    pts = cam.outer_wall.flatten(1e-4)
    radius = np.hypot(pts[:, 0], pts[:, 1])
    i = int(np.argmax(radius))
    rim_wall = cam.rim_radius - float(radius[i]) - 1e-4
    out.append(limited("rim_wall", rim_wall, ">=", body.min_wall, "mm",
                       [round(math.degrees(math.atan2(pts[i, 1], pts[i, 0])) % 360.0, 6)],
                       f"thinnest wall between the groove's outer wall and the rim (radius {cam.rim_radius:g} mm), at the polar angle "
                       "listed", blocks_manufacture=True))
    floor = body.thickness - cam.depth
    out.append(limited("groove_floor", floor, ">=", body.min_wall, "mm", [],
                       f"plate left under the groove: thickness {body.thickness:g} mm less depth {cam.depth:g} mm",
                       blocks_manufacture=True))
    return out


def groove_tool_check(cam: GrooveBody, tool_radius: float, tool_is_limit: bool) -> "CheckResult":
    """The end mill against the groove: it must enter the groove (diameter <= width) and reach
    the walls' concave parts (as the tool sees them: the outer wall where the pitch curve is
    convex, radius rho + w; the inner wall where it is concave, |rho| + w: both >= w)."""
    from camgen.checks import information, limited

    width = 2.0 * cam.half_width
    note = (f"groove width {width:g} mm against the tool diameter {2.0 * tool_radius:g} mm: the walls' concave radii (as the tool "
            f"sees them) are at least the walls' offset {cam.half_width:g} mm, so a tool that enters the groove reaches them; a tool as "
            "wide as the groove cuts it in one pass along the pitch curve, a narrower one in two wall passes with the slot cleared")
    if not tool_is_limit:
        return information("groove_tool", width, "mm", [], note + "; no tool is named (machining.tool_diameter_mm)")
    return limited("groove_tool", width, ">=", 2.0 * tool_radius, "mm", [], note, blocks_manufacture=True)


def acceleration_zeros(law: Any, motion: "Motion") -> tuple[np.ndarray, np.ndarray] | None:
    """Where the follower's acceleration changes sign (a form-closed follower's crossovers): the
    cam angles (rad) of the law's own zeros of s'', each bisected (:data:`CROSSOVER_BISECTIONS`)
    between the two samples of ``motion``'s grid around it, and the index of the sample before
    each; None when the acceleration never changes sign."""
    sign = np.sign(motion.acceleration)
    nz = np.flatnonzero(sign != 0)
    if nz.size < 2:
        return None
    s = sign[nz]
    change = np.flatnonzero(s != np.roll(s, -1))  # from nz[i] to the next non-zero sample
    if change.size == 0:
        return None
    theta = motion.cam_angle
    lo, hi = theta[nz[change]], theta[nz[(change + 1) % nz.size]]
    hi = np.where(hi > lo, hi, hi + 2.0 * math.pi)
    a_lo = law(np.mod(lo, 2.0 * math.pi))[2]
    for _ in range(CROSSOVER_BISECTIONS):  # the law's own zero of s'' between the two samples
        mid = 0.5 * (lo + hi)
        a_mid = law(np.mod(mid, 2.0 * math.pi))[2]
        left = np.sign(a_mid) == np.sign(a_lo)
        lo, a_lo = np.where(left, mid, lo), np.where(left, a_mid, a_lo)
        hi = np.where(left, hi, mid)
    return np.mod(0.5 * (lo + hi), 2.0 * math.pi), nz[change]


def _crossovers(cam: GrooveCam, rpm: float | None) -> "CheckResult":
    """Where the roller changes walls: the follower's inertia force (mass times acceleration)
    changes sign, so the contact moves across the clearance from one wall to the other."""
    from camgen.checks import information, where_degrees

    m = cam.motion
    zeros = acceleration_zeros(cam.law, m)
    if zeros is None:
        return information("wall_crossover", 0, "", [], "the acceleration never changes sign: the roller stays on one wall")
    angles, here = zeros
    note = (f"{angles.size} cam angles where the follower's acceleration changes sign: with inertia the only load, the contact "
            f"force changes sign there and the roller crosses the {cam.figures['groove']['clearance_mm']:g} mm clearance to the "
            "other wall (crossover shock; an external load on the follower moves these angles)")
    if rpm:
        omega = 2.0 * math.pi * rpm / 60.0
        jerk = np.abs(m.jerk[here]) * omega**3 * 1e-3 if m.unit == "mm" else np.abs(m.jerk[here]) * omega**3
        speed = np.abs(m.velocity[here]) * omega * 1e-3 if m.unit == "mm" else np.abs(m.velocity[here]) * omega
        unit = ("m/s", "m/s^3") if m.unit == "mm" else ("rad/s", "rad/s^3")
        note += (f"; at {rpm:g} rpm the follower moves at up to {float(speed.max()):.6g} {unit[0]} there, the acceleration "
                 f"passing zero at up to {float(jerk.max()):.6g} {unit[1]}")
    return information("wall_crossover", int(angles.size), "", where_degrees(np.sort(angles)), note)


def evaluate_groove(cam: Any, spec: CamSpec, tool_radius: float, tool_is_limit: bool) -> "CamEvaluation":
    """The design checks of a groove cam (built by :func:`build_groove`)."""
    from camgen.checks import CamEvaluation, motion_check, pressure_angle_check
    from camgen.kinds.disk import law_joins_check

    assert isinstance(cam, GrooveCam), f"a groove cam's checks on a {type(cam).__name__}"
    f, k = cam.roller, cam.envelope.data
    theta = k.theta
    checks: list[CheckResult] = []
    made = cam.inner_wall is not None and cam.outer_wall is not None
    if made:
        checks.append(_continuity(cam))
    checks.append(_undercut(cam))
    what = f"{f.motion} {f.kind} follower in a groove" + (f" (offset {f.offset:g} mm)" if f.motion == "translating" and f.offset else "")
    pressure = pressure_angle_check(k.pressure_angle, theta, pressure_limit(spec), what)
    checks.append(replace(pressure, limit=round(pressure.limit, 9)))
    checks.append(motion_check(cam.motion, spec.checks.rpm))
    checks.append(law_joins_check(cam, spec.checks.rpm))
    checks.append(_crossovers(cam, spec.checks.rpm))
    if made:
        checks.extend(groove_wall_checks(cam))
        checks.append(groove_tool_check(cam, tool_radius, tool_is_limit))
    if cam.sizing is not None:
        from camgen.checks import information

        method = spec.params.sizing
        offset = f", offset {f.offset:.6g} mm" if method == "base_radius_and_offset" else ""
        tool = f" and concave radii the tool (radius {spec.checks.tool_radius:g} mm) reaches" if spec.checks.tool_is_limit else ""
        checks.append(information("sizing", f.base_radius, "mm", [],
                                  f"sizing = {method!r}: the smallest base radius{offset} (the wall roller's rounded up to 0.001 mm, plus "
                                  f"clearance / 2) meeting the pressure-angle limit {math.degrees(pressure_limit(spec)):g} deg with both "
                                  f"walls made (|radius of the pitch curve| > {cam.half_width:g} mm){tool}"))
    rho = k.pitch_radius
    assert rho is not None
    return CamEvaluation(tuple(checks), None, cam.motion, (theta, k.pressure_angle), (theta, rho), cam.pitch,
                         pressure_angle_label=f"{f.motion} {f.kind} in a groove, closed form",
                         curvature_label="radius of curvature of the pitch curve (mm, < 0 concave); the walls need |radius| > w",
                         curvature_limit=cam.half_width, curvature_angle_label="cam angle (deg)", follower_drawing=cam.drawing,
                         animation=cam.animation)


def groove_kinematics(cam: Any, spec: CamSpec) -> tuple[Any, float]:
    """The dynamics kinematics of a groove cam: a form-closed train whose contact 1 is the inner
    wall (radius of curvature rho - w, rho the pitch curve's, signed > 0 convex) and contact 2
    the outer wall (seen from the roller inside the groove: radius -(rho + w), concave where the
    pitch curve is convex), both along the one normal through the roller centre (the same
    pressure angle), each against the roller of radius r (:func:`camgen.kinds.dynamics.disk_kinematics`)."""
    from camgen import dynamics as dy
    from camgen.kinds.dynamics import checked_kinematics

    assert isinstance(cam, GrooveCam), f"a groove cam's dynamics on a {type(cam).__name__}"
    f, k, w = cam.roller, cam.envelope.data, cam.half_width
    rho = k.pitch_radius
    assert rho is not None
    if f.motion == "translating":
        direction: Any = math.pi / 2
        arm = 0.0
    else:
        direction = k.arm_angle + f.tau * math.pi / 2  # the roller centre moves along tau J u(arm angle)
        arm = f.arm_length
    with np.errstate(invalid="ignore"):
        inner, outer = rho - w, -(rho + w)  # inf where the pitch curve is straight: inf - w = inf
    kin = checked_kinematics(lambda: dy.Kinematics(k.theta, k.s, k.ds, k.d2s, k.pressure_angle, inner, f.roller_radius, direction,
                                            pressure_angle_2=k.pressure_angle, rho_cam_2=outer, follower_radius_2=f.roller_radius))
    return kin, arm
