"""Barrel (cylindrical) cams: keys, reading, building and the checks.

A cylinder turning about its axis (z) carries a groove that drives a roller along the axis
(translating) or swinging it about an axis perpendicular to the cam's (oscillating).  The
conventions are those of :mod:`camgen.synthesis.barrel` (the exact geometry); in short:

- cam frame: z along the cam axis, z = 0 the cylinder's bottom face, z = ``cylinder_length_mm``
  its top face; the cam turns about +z, ``rotation = "ccw"`` (sigma = +1, counter-clockwise
  seen from +z) or ``"cw"`` (sigma = -1);
- the follower stands at world polar angle 0 (the +x side): at cam angle theta its station is at
  cam polar angle phi_r = -sigma theta;
- radii: rim R_o (``cylinder_radius_mm``), groove depth d, root R_i = R_o - d, mean (pitch) radius
  R_m = (R_o + R_i) / 2: the pressure angle and the developed drawing "at the mean radius" use it;
- the roller's axis is radial; a cylindrical roller of radius Rr, or a conical one (apex on the
  cam axis at the roller centre's height, radius Rr at R_m, translating only: it rolls without slip
  at every radius in a dwell, :mod:`camgen.synthesis.barrel`); the walls are the exact envelopes of the roller widened by
  half the clearance, w = Rr + c / 2;
- translating: the roller axis at height z_c = z0 + s(theta) (``pitch_z_mm`` = z0, default
  centred: (length - (s_max + s_min)) / 2); oscillating: the arm of length L
  (``arm_length_mm``) swings about a pivot axis parallel to x at (y, z) = (-L, z_p)
  (``pivot_z_mm``, default length / 2), arm angle psi = psi0 + phi(theta) (``rest_angle_deg``,
  default -(phi_max + phi_min) / 2), so the roller axis is at height z_p + L sin psi and
  tangential offset L (cos psi - 1).

The body is the cylinder less the bore, less the groove; ``BuiltCam.contour`` is None (there is
no planar outline: :attr:`BarrelCam.planar` is False) and the form writes its own drawing, point
list, solid and program (:mod:`camgen.forms.barrel`).  The checks come from the closed forms on
a dense cam-angle grid: the pressure angle at root, mean and rim radius, the undercut of both
walls at radii from root to rim, the walls' reach against the cylinder's end faces, the wall to
the bore, and the law's joins.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar, Mapping

import numpy as np

from camgen.errors import ParameterError
from camgen.kinds.base import BuiltCam, CamSpec, CheckSettings, field_default, with_cam
from camgen.kinds.jerk_limit import jerk_limit_keys
from camgen.schema import REQUIRED, Angle, Choice, Key, Length, Number, Text

if TYPE_CHECKING:
    from camgen.checks import CamEvaluation, CheckResult, Motion
    from camgen.synthesis.barrel import BarrelGroove, BarrelRib

__all__ = ["BarrelCam", "BarrelFollower", "BarrelParams", "barrel_keys", "build_barrel", "evaluate_barrel", "read_barrel"]

#: Default ``groove_clearance_mm``: the groove's width less the roller's diameter (mm), a running
#: fit for a track roller (the groove cam's).
DEFAULT_CLEARANCE = 0.05
#: Default ``fit_tol_mm`` (mm): the stated tolerance of the walls' representation (STEP surfaces).
DEFAULT_FIT_TOL = 1e-4
#: Default pressure-angle limits, rad: translating and oscillating followers.
DEFAULT_LIMITS = {"translating": math.radians(30.0), "oscillating": math.radians(45.0)}
#: Samples of the cam-angle grid of the checks and the report (0.1 deg: the law's segment ends at
#: whole tenths of a degree are on it).
CHECK_SAMPLES = 3600
#: Radii (from root to rim, evenly spaced) at which the undercut of both walls is checked.
UNDERCUT_RADII = 9
ROLLER_SHAPES = ("cylindrical", "conical")
_OSC = {"follower_motion": ("oscillating",)}
_TRANS = {"follower_motion": ("translating",)}
_RIB = {"track": ("rib",)}
#: The tracks a barrel cam carries.
TRACKS = ("groove", "rib")
#: Outputs a rib cam does not have yet (refused naming output.formats, :attr:`BarrelParams.formats_refused`).
RIB_FORMATS_REFUSED: dict[str, str] = {}
#: Outputs an oscillating follower's rib does not have yet (none: its STEP and its program are built, ORIB).
OSCILLATING_RIB_FORMATS_REFUSED: dict[str, str] = {}


def _body_default(name: str) -> Any:
    from camgen.body import BodySpec

    return field_default(BodySpec, name)


def barrel_keys() -> tuple[Key, ...]:
    """The keys of a barrel cam: follower, cylinder, groove, checks (after the motion's)."""
    return (
        Key("follower_motion", Choice(("translating", "oscillating")), "Translating: the roller moves along the cam axis, its "
            "height z0 + s(theta) (s the law's lift, mm); oscillating: it swings on an arm about an axis perpendicular to the cam "
            "axis (the law's swing, deg).", ("profile",), default="translating", feeds=("motion",)),
        Key("roller_shape", Choice(ROLLER_SHAPES), "cylindrical: a roller of radius roller_radius_mm, its axis radial; conical "
            "(translating only): a cone whose apex lies on the cam axis at the roller centre's height, of radius roller_radius_mm "
            "at the mean radius (it rolls without slip at every radius where the follower dwells; during a rise its contact is a "
            "curve, as the cylinder's).", ("profile",), default="cylindrical"),
        Key("roller_radius_mm", Length(high=1e4), "Radius of the roller (conical: at the mean radius); < the root radius "
            "(cylinder_radius_mm - groove_depth_mm).", ("profile",), default=REQUIRED),
        Key("cylinder_radius_mm", Length(high=1e5), "Outer (rim) radius R_o of the cylinder.", ("profile",), default=REQUIRED),
        Key("cylinder_length_mm", Length(high=1e5), "Length of the cylinder along its axis: z = 0 its bottom face, "
            "z = cylinder_length_mm its top face.", ("profile",), default=REQUIRED),
        Key("track", Choice(TRACKS), "groove: a groove cut into the cylinder guides one roller between its walls; rib: a rib stands on "
            "the root cylinder up to the rim, straddled by two rollers of the follower whose axes ride rib_width_mm / 2 + w below "
            "and above the pitch line (w = roller_radius_mm + groove_clearance_mm / 2; oscillating: both on the arm's end, spaced "
            "along the arm's normal in the plane tangent to the cylinder, turning with the arm); the rib's faces are the exact "
            "envelopes of the two rollers (the lower roller's is the lower face). Its STEP and 4th-axis program (oscillating too: "
            "each face cut along its roller's axis, off the radial line by the roller's tangential offset) are built.",
            ("profile",), default="groove"),
        Key("rib_width_mm", Length(high=1e5), "Rib (required with track = \"rib\"): the rib's width along the cam axis where the "
            "follower dwells (the rollers' axes are rib_width_mm + 2 w apart; oscillating: apart along the arm's normal, so where "
            "the arm dwells at angle psi the rib is (rib_width_mm + 2 w) cos(psi) - 2 w wide); during a rise the rib is thinner "
            "along the axis, checked at every radius and cam angle (rib_thickness).", ("profile",), requires=_RIB),
        Key("groove_depth_mm", Length(high=1e5), "Depth d of the groove below the rim (track = \"rib\": the rib's height above the root cylinder) (< cylinder_radius_mm): the root radius is "
            "R_i = R_o - d, the mean (pitch) radius R_m = R_o - d / 2.", ("profile",), default=REQUIRED),
        Key("groove_clearance_mm", Length(0.0, 100.0, low_open=False), "Groove width less the roller diameter: the walls are the "
            "envelopes of the roller widened by half of it (w = roller_radius_mm + clearance / 2).", ("profile",),
            default=DEFAULT_CLEARANCE),
        Key("pitch_z_mm", Length(-1e5, 1e5, low_open=False), "Translating follower: the roller axis' height at zero lift, z0 "
            "(default: the travel centred on the cylinder, (cylinder_length_mm - (s_max + s_min)) / 2).", ("profile",),
            requires=_TRANS),
        Key("arm_length_mm", Length(high=1e5), "Oscillating follower (required): the arm's length L from its pivot axis to the "
            "roller axis; the pivot lies at y = -L, in the plane tangent to the cylinder at the follower's station.", ("profile",),
            requires=_OSC),
        Key("rest_angle_deg", Angle(-90.0, 90.0, low_open=True, high_open=True), "Oscillating follower: the arm's angle psi0 at "
            "zero swing, from the y axis towards +z (default: the swing symmetric about the y axis, -(phi_max + phi_min) / 2).",
            ("profile",), requires=_OSC),
        Key("pivot_z_mm", Length(-1e5, 1e5, low_open=False), "Oscillating follower: height z_p of the arm's pivot axis (default: "
            "half the cylinder's length).", ("profile",), requires=_OSC),
        Key("rotation", Choice(("ccw", "cw")), "Direction the cam turns, seen from +z (from the top face); the cam angle is measured "
            "in this direction.", ("profile",), default="ccw"),
        Key("bore_diameter_mm", Length(0.0, 1e5, low_open=False), "Diameter of the shaft bore along the axis; 0: no bore.",
            ("profile",), default=_body_default("bore_diameter")),
        Key("min_wall_mm", Length(0.0, 1e4, low_open=False), "Least material allowed between the groove and the bore (the floor "
            "an end mill of the groove's width cuts, its flat tip just below the root radius, less the bore radius) and between the groove's walls and each end face (the checks' limit); "
            "track = \"rib\": the least width of the rib along the axis and the root cylinder's wall over the bore (to the floor an end mill of the rollers' diameter cuts beside the faces, "
            "sqrt(R_i^2 - w^2)).", ("report",),
            default=_body_default("min_wall")),
        Key("pressure_angle_limit_deg", Angle(0.01, 90.0, high_open=True), "Largest pressure angle allowed at the root radius, "
            "where it is largest (default: 30 deg translating followers, 45 deg oscillating ones).", ("report",)),
        Key("fit_tol_mm", Number("mm", 1e-8, 1e-2), "Stated tolerance of the walls' representation: the STEP's B-spline wall "
            "surfaces lie within it of the exact envelope; the drawing and point list state it.", ("profile",),
            default=DEFAULT_FIT_TOL),
        Key("rpm", Number("rev/min", 1e-3, 1e6), "Cam speed: the follower's velocity, acceleration and jerk at speed in the report, "
            "and the follower table (<cam>_follower.csv, which needs it).", ("report", "motion")),
        *jerk_limit_keys(oscillating=True),  # issue 26 item 5: the follower's jerk at rpm against a limit
        Key("source", Text(), "Where the numbers come from (a note copied into the report).", ("report",)),
    )


@dataclass(frozen=True)
class BarrelFollower:
    """What the motion asks of the follower it drives (:attr:`camgen.motions.base.Motion.read_law`):
    ``motion`` (a lift in mm or a swing in rad), ``kind`` and ``edge`` (a roller never follows a
    velocity jump); ``lift_unit`` the law's unit."""

    motion: str
    kind: str = "roller"
    edge: bool = False

    @property
    def lift_unit(self) -> str:
        return "mm" if self.motion == "translating" else "rad"


@dataclass(frozen=True)
class BarrelParams:
    """A barrel cam: its law, follower, roller, cylinder and groove (mm, rad), the follower's
    placement (z0 or the pivot's height, arm length, rest angle; None: defaults, see
    :func:`barrel_keys`), the fit tolerance, the law's figures and a source note."""

    law: Any
    follower: BarrelFollower
    roller_shape: str
    roller_radius: float
    rim_radius: float
    length: float
    depth: float
    clearance: float
    sigma: int
    bore_radius: float
    fit_tol: float
    z0: float
    arm_length: float = 0.0
    rest_angle: float = 0.0
    law_figures: Mapping[str, Any] = field(default_factory=dict)
    source: str | None = None
    track: str = "groove"
    rib_width: float = 0.0

    @property
    def formats_refused(self) -> Mapping[str, str]:
        """Outputs this cam cannot have yet (format -> why; :func:`camgen.planning` refuses them)."""
        if self.track == "rib" and self.follower.motion == "oscillating":  # ROSC; ORIB lifted its STEP and program (none left)
            return {**RIB_FORMATS_REFUSED, **OSCILLATING_RIB_FORMATS_REFUSED}
        return RIB_FORMATS_REFUSED if self.track == "rib" else {}

    @property
    def root_radius(self) -> float:
        return self.rim_radius - self.depth

    @property
    def mean_radius(self) -> float:
        return self.rim_radius - 0.5 * self.depth


def read_barrel(where: str, name: str, parsed: Mapping[str, Any], motion: Any, base_dir: Path | None = None) -> CamSpec:
    """The typed spec of a barrel cam table; errors name the scene keys."""
    from camgen.body import BodySpec

    moves = parsed["follower_motion"]
    shape = parsed["roller_shape"]
    if shape == "conical" and moves != "translating":
        raise ParameterError(f"{where}.roller_shape", shape, '"cylindrical" with follower_motion = "oscillating"',
                             "a conical roller rolls without slip only when its apex stays on the cam axis (a translating follower)")
    rim, depth, length = parsed["cylinder_radius"], parsed["groove_depth"], parsed["cylinder_length"]
    if not depth < rim:
        raise ParameterError(f"{where}.groove_depth_mm", depth, f"< cylinder_radius_mm = {rim:g} mm", "the groove's root radius "
                             "cylinder_radius_mm - groove_depth_mm must be > 0")
    root = rim - depth
    radius = parsed["roller_radius"]
    if not radius < root:
        raise ParameterError(f"{where}.roller_radius_mm", radius, f"< the root radius cylinder_radius_mm - groove_depth_mm = {root:g} mm",
                             "a roller as wide as the cylinder's core leaves no groove")
    bore = parsed["bore_diameter"]
    if not 0.5 * bore < root:
        raise ParameterError(f"{where}.bore_diameter_mm", bore, f"< twice the root radius, {2.0 * root:g} mm",
                             "the bore would cut through the groove's root")
    track = parsed.get("track", "groove")
    if track == "rib":
        if "rib_width" not in parsed:
            raise ParameterError(f"{where}.rib_width_mm", None, "a width in mm", 'required with track = "rib"')
    if moves == "oscillating" and "arm_length" not in parsed:
        raise ParameterError(f"{where}.arm_length_mm", None, "a length in mm", 'required with follower_motion = "oscillating"')
    follower = BarrelFollower(moves)
    reading = motion.read_law(where, parsed, follower, base_dir)
    law = reading.law
    s_min, s_max = law.s_bounds
    arm = rest = 0.0
    if moves == "translating":
        z0 = parsed.get("pitch_z", 0.5 * (length - (s_max + s_min)))
    else:
        arm = parsed["arm_length"]
        rest = parsed.get("rest_angle", -0.5 * (s_max + s_min))
        z0 = parsed.get("pivot_z", 0.5 * length)
        lo, hi = rest + s_min, rest + s_max
        if not (-0.5 * math.pi < lo and hi < 0.5 * math.pi):
            raise ParameterError(f"{where}.rest_angle_deg", round(math.degrees(rest), 9),
                                 f"an angle keeping the arm within +-90 deg of the y axis over the swing ({math.degrees(s_min):.6g} to "
                                 f"{math.degrees(s_max):.6g} deg): between {-90.0 - math.degrees(s_min):.6g} and "
                                 f"{90.0 - math.degrees(s_max):.6g} deg", "the arm would turn past the cylinder's axis")
    params = BarrelParams(law, follower, shape, radius, rim, length, depth, parsed["groove_clearance"],
                          1 if parsed["rotation"] == "ccw" else -1, 0.5 * bore, parsed["fit_tol"], float(z0), arm, rest,
                          dict(reading.figures), parsed.get("source"), track, float(parsed.get("rib_width", 0.0)))
    body = BodySpec(thickness=length, bore_diameter=bore, min_wall=parsed["min_wall"])
    checks = CheckSettings(parsed.get("pressure_angle_limit"), parsed.get("rpm"), getattr(parsed, "tool_limit", None),
                           parsed.get("jerk_limit", parsed.get("jerk_limit_angular")))
    from camgen.kinds.barrel_dynamics import read_barrel_dynamics

    dynamics = read_barrel_dynamics(where, parsed, motion=moves, roller_shape=shape, depth=depth, rpm=checks.rpm, base_dir=base_dir)
    return CamSpec(name, motion.name, params, body, checks, None, dynamics, form="barrel")


# --------------------------------------------------------------------------------------------
# Building
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class BarrelCam(BuiltCam):
    """A built barrel cam: the exact groove (:class:`camgen.synthesis.barrel.BarrelGroove`, which
    every writer reads as ``cam.built.groove``), its spec, the law and the follower's motion on the
    check grid; ``contour`` is None (no planar outline)."""

    planar: ClassVar[bool] = False
    groove: "BarrelGroove"
    params: BarrelParams
    law: Any
    spec_follower: BarrelFollower
    motion: "Motion"
    #: wall side (+1 upper, -1 lower) -> (UNDERCUT_RADII, check grid) bool: where its section folds
    #: (a rib: its faces, +1 the upper face)
    folds: Mapping[int, np.ndarray]
    #: track = "rib": the rib (:class:`camgen.synthesis.barrel.BarrelRib`; ``groove`` is then its pitch
    #: line's groove, whose pressure angle and law it shares); None for a groove
    rib: "BarrelRib | None" = None

    @property
    def folded(self) -> bool:
        """A wall folds somewhere: the groove cannot be made (the undercut check fails)."""
        return any(bool(mask.any()) for mask in self.folds.values())


def check_grid() -> np.ndarray:
    """The cam angles (rad) of the checks: 0 .. 2 pi every 0.1 deg (the end excluded)."""
    return 2.0 * math.pi * np.arange(CHECK_SAMPLES) / CHECK_SAMPLES


def make_groove(p: BarrelParams) -> "BarrelGroove":
    """The exact groove of ``p`` (:mod:`camgen.synthesis.barrel`)."""
    from camgen.synthesis.barrel import BarrelGroove, BarrelLayout

    layout = BarrelLayout(p.follower.motion, p.sigma, p.roller_radius, p.roller_shape, p.mean_radius, p.z0, p.arm_length, p.rest_angle)
    return BarrelGroove(layout, p.law, p.rim_radius, p.root_radius, p.length, p.bore_radius, p.clearance, p.fit_tol)


def _motion(follower: BarrelFollower, law: Any) -> "Motion":
    """The follower's SVAJ per unit cam speed on the check grid, exactly from the law."""
    from camgen.checks import Motion, where_degrees

    theta = check_grid()
    s, ds, d2s, d3s = law(theta)
    peaks = law.peak_values()
    jumps = np.asarray(law.breaks)[np.asarray(law.break_continuity) < 2]
    return Motion(theta, s, ds, d2s, d3s, follower.lift_unit, where_degrees(jumps), lift_zero=0.0,
                  peaks=(peaks.velocity, peaks.acceleration, peaks.jerk))


def make_rib(p: BarrelParams) -> "BarrelRib":
    """The rib of ``p`` (track = "rib"; :class:`camgen.synthesis.barrel.BarrelRib`)."""
    from camgen.synthesis.barrel import BarrelRib

    return BarrelRib(make_groove(p), p.rib_width)


def rollers_reach(rib: "BarrelRib", theta: np.ndarray) -> tuple[float, float]:
    """The lowest and highest z (mm) a rib's two rollers reach: the pitch line's extremes less and
    plus the roller offset o and the roller's largest half width (:func:`axis_reach`); oscillating:
    each roller axis' own extremes (they turn with the arm) less and plus the half width."""
    if rib.layout.motion == "oscillating":  # ROSC: the rollers ride on the arm's normal, not at a fixed z offset
        heights = [rib.roller(side).axis(theta)[0] for side in (1, -1)]
        return float(min(np.min(z) for z in heights)) - rib.half_width, float(max(np.max(z) for z in heights)) + rib.half_width
    low, high = axis_reach(rib.groove, theta)
    return low - rib.roller_offset, high + rib.roller_offset


def axis_reach(groove: "BarrelGroove", theta: np.ndarray) -> tuple[float, float]:
    """The lowest and highest z (mm) the groove's walls reach: the roller axis' extreme heights
    less and plus the roller's largest half width over the groove's depth (w; a conical roller's
    grows with the radius, w R_o / R_m at the rim).  The walls touch these heights where the
    roller axis is at its extremes (the wall section through the roller's axis)."""
    z_c, _ = groove.axis(theta)
    p = groove.layout
    reach = groove.half_width * (groove.rim_radius / p.mean_radius if p.roller_shape == "conical" else 1.0)
    return float(np.min(z_c)) - reach, float(np.max(z_c)) + reach


def build_barrel(spec: CamSpec, stages: frozenset[str]) -> BuiltCam:
    """Build a barrel cam: the exact groove and its figures (the plots stage adds the report's
    section data)."""
    return with_cam(f"cams.{spec.name}", lambda: _build(spec, stages))


def _build(spec: CamSpec, stages: frozenset[str]) -> BarrelCam:
    p: BarrelParams = spec.params
    groove = make_groove(p)
    theta = check_grid()
    z_c, _ = groove.axis(theta)
    low, high = axis_reach(groove, theta)
    f = p.follower
    follower: dict[str, Any] = {"kind": "roller", "motion": f.motion, "roller_shape": p.roller_shape, "roller_radius_mm": p.roller_radius,
                                "rotation": "ccw" if p.sigma > 0 else "cw"}
    if f.motion == "translating":
        follower["pitch_z_mm"] = p.z0
    else:
        follower.update(arm_length_mm=p.arm_length, rest_angle_deg=math.degrees(p.rest_angle), pivot_z_mm=p.z0)
    if p.roller_shape == "conical":
        follower["cone_half_angle_deg"] = math.degrees(math.atan(p.roller_radius / p.mean_radius))
    s_min, s_max = p.law.s_bounds
    pressures = {name: float(np.degrees(np.max(np.abs(groove.pressure_angle(np.asarray(r), theta))))) for name, r in _radii(p)}
    figures: dict[str, Any] = {
        "follower": follower,
        "cylinder": {"rim_radius_mm": p.rim_radius, "root_radius_mm": p.root_radius, "mean_radius_mm": p.mean_radius,
                     "length_mm": p.length, "bore_diameter_mm": 2.0 * p.bore_radius, "min_wall_mm": spec.body.min_wall},
        "groove": {"depth_mm": p.depth, "clearance_mm": p.clearance, "width_mm": 2.0 * groove.half_width,
                   "walls": "exact envelopes of the roller widened by half the clearance, at every radius from root to rim",
                   "z_reach_mm": [low, high]},
        "roller_axis_z_mm": [float(np.min(z_c)), float(np.max(z_c))],
        ("stroke_mm" if f.motion == "translating" else "swing_deg"): (s_max - s_min) if f.motion == "translating"
        else math.degrees(s_max - s_min),
        **{f"pressure_angle_{name}_deg": value for name, value in pressures.items()},
        "fit_tol_mm": p.fit_tol,
        "conventions": "z along the cam axis from its bottom face; the follower at polar angle 0 (+x); at cam angle theta it "
                       "meets the cam's polar angle -sigma theta (sigma +1 ccw, -1 cw, seen from +z)",
        **dict(p.law_figures),
    }
    folds = _folds(groove, p, theta)
    folded = any(bool(mask.any()) for mask in folds.values())
    # a folded wall is no function of the polar angle (wall_height has no meaning there): the undercut check says where
    figures["groove"]["wrapped_groove_error"] = ({"note": "not computed: a wall folds (the undercut check lists where)"} if folded
                                                 else _wrapped_errors(groove))
    if p.source is not None:
        figures["source"] = p.source
    section = None
    rib = None
    if p.track == "rib":
        rib = make_rib(p)
        folds = _folds(rib, p, theta)
        folded = any(bool(mask.any()) for mask in folds.values())
        del figures["groove"]
        lo_r, hi_r = rollers_reach(rib, theta)
        figures["rib"] = {"height_mm": p.depth, "width_mm": p.rib_width, "clearance_mm": p.clearance,
                          "roller_axis_offset_mm": rib.roller_offset,
                          "faces": "exact envelopes of the two rollers (widened by half the clearance) on the rib's side, their axes "
                                   "rib width / 2 + roller radius + clearance / 2 below and above the pitch line, at every radius "
                                   "from root to rim",
                          "rollers_z_reach_mm": [lo_r, hi_r]}
        if f.motion == "oscillating":  # ROSC: the rollers on the arm's normal, each with its own pressure angle
            figures["rib"]["rollers"] = ("both on the arm's end, their axes parallel to x, rib width / 2 + roller radius + clearance "
                                         "/ 2 either side of it along the arm's normal (in the plane tangent to the cylinder), turning "
                                         "with the arm; each rides an arm of length hypot(L, offset) about the pivot")
            figures["rib"]["roller_arm_length_mm"] = math.hypot(p.arm_length, rib.roller_offset)
            figures.update({f"pressure_angle_{name}_deg": float(np.degrees(np.max(np.abs(rib.pressure_angle(np.asarray(r), theta)))))
                            for name, r in _radii(p)})
    if "plots" in stages and not folded:
        section = _section(rib if rib is not None else groove, p, theta, pressure_limit_deg(spec))
    return BarrelCam(spec.name, spec.kind, None, figures, spec.body, None, section=section, groove=groove, params=p, law=p.law,
                     spec_follower=f, motion=_motion(f, p.law), folds=folds, rib=rib)


def _folds(groove: Any, p: BarrelParams, theta: np.ndarray) -> dict[int, np.ndarray]:
    """Where each wall's section folds at :data:`UNDERCUT_RADII` radii from root to rim (rows) on
    the check grid ``theta`` (columns)."""
    radii = np.linspace(p.root_radius, p.rim_radius, UNDERCUT_RADII)
    return {side: np.stack([np.asarray(groove.undercut(side, r, theta), dtype=bool) for r in radii]) for side in (1, -1)}


def _radii(p: BarrelParams) -> tuple[tuple[str, float], ...]:
    return (("root", p.root_radius), ("mean", p.mean_radius), ("rim", p.rim_radius))


#: Samples of the cam's polar angle on which the wrapped groove is compared with the exact one.
WRAPPED_SAMPLES = 1440


def _wrapped_errors(groove: "BarrelGroove") -> dict[str, Any]:
    """How far the shortcut of wrapping the groove drawn flat at the mean radius onto the cylinder
    (:meth:`camgen.synthesis.barrel.BarrelGroove.wrapped_wall_height`) misses the exact walls at
    the root and the rim (mm, wrapped less exact, the extreme of each sign on a grid of
    :data:`WRAPPED_SAMPLES` polar angles), and how much narrower the wrapped groove is."""
    phi = 2.0 * math.pi * np.arange(WRAPPED_SAMPLES) / WRAPPED_SAMPLES
    out: dict[str, Any] = {"note": f"the groove drawn flat at the mean radius and wrapped onto the cylinder, less the exact walls, "
                                   f"on {WRAPPED_SAMPLES} polar angles: what the wrapped shortcut would get wrong"}
    for name, r in (("root", groove.root_radius), ("rim", groove.rim_radius)):
        radius = np.asarray(r)
        diff = {side: groove.wrapped_wall_height(side, radius, phi) - groove.wall_height(side, radius, phi) for side in (1, -1)}
        narrower = diff[-1] - diff[1]
        out[name] = {"upper_wall_mm": [float(diff[1].min()), float(diff[1].max())],
                     "lower_wall_mm": [float(diff[-1].min()), float(diff[-1].max())],
                     "narrower_by_mm": float(narrower.max())}
    return out


def pressure_limit(spec: CamSpec) -> float:
    limit = spec.checks.pressure_angle_limit
    return limit if limit is not None else DEFAULT_LIMITS[spec.params.follower.motion]


def pressure_limit_deg(spec: CamSpec) -> float:
    return round(math.degrees(pressure_limit(spec)), 9)


# --------------------------------------------------------------------------------------------
# Checks
# --------------------------------------------------------------------------------------------
def _pressure(cam: BarrelCam, spec: CamSpec) -> "CheckResult":
    """The largest pressure angle at the root radius (where it is largest) against the limit; the
    note gives the mean's and the rim's."""
    from camgen.checks import CheckResult, run_ends, where_degrees

    p, g = cam.params, (cam.rib if cam.rib is not None else cam.groove)  # a rib: its rollers' (oscillating: each its own)
    theta = check_grid()
    limit = pressure_limit(spec)
    alpha = {name: np.abs(g.pressure_angle(np.asarray(r), theta)) for name, r in _radii(p)}
    root = alpha["root"]
    i = int(np.argmax(root))
    bad = root > limit
    at = ", ".join(f"{name} (radius {r:g} mm) {math.degrees(float(np.max(alpha[name]))):.6g} deg" for name, r in _radii(p))
    track = "on the barrel's rib" if cam.rib is not None else "in the barrel groove"
    if cam.rib is not None and p.follower.motion == "oscillating":
        track += " (of either roller: each moves about the pivot along its own direction)"
    note = (f"largest pressure angle of the {p.follower.motion} roller {track} at the root radius, where it is largest "
            f"(closed form); at {at}" + ("; above the limit between the listed pairs of cam angles" if bad.any() else ""))
    return CheckResult("pressure_angle", float(np.degrees(root[i])), pressure_limit_deg(spec), "<=", "deg", not bool(bad.any()),
                       run_ends(bad, theta) if bad.any() else where_degrees(theta[i]), note)


def _undercut(cam: BarrelCam) -> "CheckResult":
    """Both walls at :data:`UNDERCUT_RADII` radii from root to rim: where a wall's section folds
    (the roller cuts away what it rides on) the groove cannot be made."""
    from camgen.checks import limited, run_ends

    p = cam.params
    theta = check_grid()
    radii = np.linspace(p.root_radius, p.rim_radius, UNDERCUT_RADII)
    folds = cam.folds
    any_fold: np.ndarray = np.asarray(folds[1].any(axis=0) | folds[-1].any(axis=0))
    count = int(any_fold.sum())
    parts = []
    what = "rib's face" if cam.rib is not None else "wall"
    for side, name in ((1, "upper"), (-1, "lower")):
        at = radii[folds[side].any(axis=1)]
        if at.size:
            parts.append(f"the {name} {what} folds at radii {', '.join(f'{r:g}' for r in at)} mm")
    note = (f"cam angles (of {theta.size}, every {360.0 / theta.size:g} deg) where either {what}'s section folds, at {UNDERCUT_RADII} "
            f"radii from the root {p.root_radius:g} mm to the rim {p.rim_radius:g} mm")
    track = "rib" if cam.rib is not None else "groove"
    note += ("; " + "; ".join(parts) + f": the {track} cannot be made (a larger radius or a smaller roller)") if parts else \
        f"; neither {what} folds"
    return limited("undercut", count, "<=", 0, "", run_ends(any_fold, theta), note, blocks_manufacture=True)


def _length(cam: BarrelCam, min_wall: float) -> "CheckResult":
    """The groove's walls inside both end faces with ``min_wall`` to spare."""
    from camgen.checks import limited

    p = cam.params
    low, high = axis_reach(cam.groove, check_grid())
    bottom, top = low, p.length - high
    room = min(bottom, top)
    note = (f"least material between the groove's walls (z from {low:.6g} to {high:.6g} mm: the roller axis' travel plus the "
            f"roller's half width {cam.groove.half_width:g} mm"
            + (" at the rim" if p.roller_shape == "conical" else "") + f") and the end faces z = 0 and z = {p.length:g} mm "
            f"(below {bottom:.6g} mm, above {top:.6g} mm)")
    if room < min_wall:
        need = high - low + 2.0 * min_wall
        note += f"; a cylinder_length_mm of {need:.6g} mm with the travel centred holds it"
    return limited("cylinder_length", room, ">=", min_wall, "mm", [], note, blocks_manufacture=True)


def _bore(cam: BarrelCam, min_wall: float) -> "CheckResult":
    from camgen.checks import limited

    from camgen.synthesis.barrel import floor_radius

    p = cam.params
    # an end mill of the groove's width cuts the walls to the root: its flat tip dips below the root
    # radius between them, deepest where the roller axis' tangential offset |e| is largest
    from camgen.errors import GeometryError

    e = cam.groove.axis(cam.motion.cam_angle)[1]
    try:
        deepest = float(np.min(floor_radius(p.root_radius, np.atleast_1d(np.max(np.abs(e))), cam.groove.half_width)))
    except GeometryError as exc:  # the cutter reaches the axis' side of the root: nothing is left to the bore
        return limited("wall_thickness", -p.bore_radius, ">=", min_wall, "mm", [], str(exc), blocks_manufacture=True)
    wall = deepest - p.bore_radius
    return limited("wall_thickness", wall, ">=", min_wall, "mm", [],
                   f"material between the bore (radius {p.bore_radius:g} mm) and the groove's floor as an end mill of the groove's "
                   f"width cuts it: its flat tip reaches radius {deepest:.6g} mm at the groove's centre line (the walls meet the root "
                   f"radius {p.root_radius:g} mm at its rim)", blocks_manufacture=True)


#: Polar angles (over a turn) at which the rib's thickness is checked at each of the UNDERCUT_RADII radii.
RIB_THICKNESS_SAMPLES = 3600


def rib_thickness_grid(rib: "BarrelRib") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rib's width along z (mm) at :data:`UNDERCUT_RADII` radii from root to rim (rows) and
    :data:`RIB_THICKNESS_SAMPLES` polar angles (columns): radii, polar angles (rad), widths."""
    radii = np.linspace(rib.root_radius, rib.rim_radius, UNDERCUT_RADII)
    phi = 2.0 * math.pi * np.arange(RIB_THICKNESS_SAMPLES) / RIB_THICKNESS_SAMPLES
    return radii, phi, np.asarray(rib.thickness(radii[:, None], phi[None, :]))


def _rib_thickness(cam: BarrelCam, min_wall: float) -> "CheckResult":
    """The rib's least width along z at every radius and polar angle of the grid against ``min_wall``
    (its faces must not cross: a rib too narrow for its rollers' spacing)."""
    from camgen.checks import limited

    rib = cam.rib
    assert rib is not None
    if any(bool(mask.any()) for mask in cam.folds.values()):
        from camgen.checks import CheckResult

        return CheckResult("rib_thickness", "not computed", min_wall, ">=", "mm", False, [],
                           "not computed: a face of the rib folds (the undercut check lists where)", True)
    radii, phi, width = rib_thickness_grid(rib)
    i, j = np.unravel_index(int(np.argmin(width)), width.shape)
    least = float(width[i, j])
    note = (f"least width of the rib along the cam axis (its upper face less its lower; {rib.width:g} mm where the follower dwells) "
            f"at {UNDERCUT_RADII} radii from the root to the rim and {RIB_THICKNESS_SAMPLES} polar angles: {least:.6g} mm at radius "
            f"{radii[i]:g} mm, polar angle {math.degrees(phi[j]):.6g} deg; below 0 the faces cross (the rollers cut the rib away)")
    if least < min_wall and rib.layout.motion == "oscillating":  # ROSC: the width does not grow one to one; solved and verified
        from camgen.kinds.barrel_rib_oscillating import rib_width_hint

        note += rib_width_hint(rib, min_wall, lambda wider: float(np.min(rib_thickness_grid(wider)[2])))
    elif least < min_wall:
        note += f"; a rib_width_mm of {rib.width + min_wall - least:.6g} mm gives {min_wall:g} mm (the width grows with it one to one)"
    return limited("rib_thickness", least, ">=", min_wall, "mm", [], note,
                   blocks_manufacture=True)


def _rib_length(cam: BarrelCam) -> "CheckResult":
    """The rib's two rollers ride on the root cylinder between its end faces."""
    from camgen.checks import limited

    rib, p = cam.rib, cam.params
    assert rib is not None
    low, high = rollers_reach(rib, check_grid())
    room = min(low, p.length - high)
    travel = (f"each roller axis' travel (on the arm's normal, {rib.roller_offset:g} mm from its end)" if p.follower.motion == "oscillating"
              else f"the pitch line's travel plus the roller offset {rib.roller_offset:g} mm")
    note = (f"least room between the rib's rollers (z from {low:.6g} to {high:.6g} mm: {travel} and the roller's half width "
            f"{rib.half_width:g} mm" + (" at the rim" if p.roller_shape == "conical" else "")
            + f") and the end faces z = 0 and z = {p.length:g} mm (the rib lies between the rollers)")
    if room < 0.0:
        note += f"; a cylinder_length_mm of {high - low:.6g} mm with the travel centred holds them"
    return limited("cylinder_length", room, ">=", 0.0, "mm", [], note, blocks_manufacture=True)


def _rib_bore(cam: BarrelCam, min_wall: float) -> "CheckResult":
    from camgen.checks import limited

    from camgen.synthesis.barrel import floor_radius

    p = cam.params
    # the 4th-axis program's faces' passes (camgen.export.gcode_barrel_rib) run an end mill of the rollers' diameter with its flat
    # tip at sqrt(R_i^2 - w^2), cutting the root that far below the root radius along each roller's track
    offset = np.zeros(1)
    if cam.rib is not None and p.follower.motion == "oscillating":  # ORIB: each roller's axis off the radial line by |e_k|
        from camgen.errors import GeometryError

        rib = cam.rib
        offset = np.atleast_1d(max(float(np.max(np.abs(rib.roller(k).axis(cam.motion.cam_angle)[1]))) for k in (-1, 1)))
        try:
            floor_radius(p.root_radius, offset, cam.groove.half_width)
        except GeometryError as exc:
            return limited("wall_thickness", -p.bore_radius, ">=", min_wall, "mm", [], str(exc), blocks_manufacture=True)
    deepest = float(np.min(floor_radius(p.root_radius, offset, cam.groove.half_width)))
    return limited("wall_thickness", deepest - p.bore_radius, ">=", min_wall, "mm", [],
                   f"material between the bore (radius {p.bore_radius:g} mm) and the root cylinder the rib stands on (radius "
                   f"{p.root_radius:g} mm) where an end mill of the rollers' diameter cuts the faces to the root: its flat tip reaches "
                   f"radius {deepest:.6g} mm along each roller's track", blocks_manufacture=True)


def evaluate_barrel(cam: BuiltCam, spec: CamSpec, tool_radius: float, tool_is_limit: bool) -> "CamEvaluation":
    """The design checks of a barrel cam from the closed forms on the check grid."""
    from camgen.checks import CamEvaluation, motion_check
    from camgen.kinds.disk import law_joins_check

    assert isinstance(cam, BarrelCam), f"a barrel cam's checks on a {type(cam).__name__}"
    min_wall = spec.body.min_wall
    if cam.rib is not None:
        checks = [_pressure(cam, spec), _undercut(cam), _rib_thickness(cam, min_wall), _rib_length(cam)]
        if cam.params.bore_radius > 0:
            checks.append(_rib_bore(cam, min_wall))
    else:
        checks = [_pressure(cam, spec), _undercut(cam), _length(cam, min_wall)]
        if cam.params.bore_radius > 0:
            checks.append(_bore(cam, min_wall))
    checks.append(motion_check(cam.motion, spec.checks.rpm))
    joins: Any = cam  # the law and its follower's motion are what law_joins_check reads
    checks.append(law_joins_check(joins, spec.checks.rpm))
    if spec.dynamics is not None:  # where the roller changes walls (a cam without dynamics keys keeps its report as it was)
        from camgen.kinds.barrel_dynamics import barrel_crossovers

        checks.append(barrel_crossovers(cam, spec.checks.rpm))
    return CamEvaluation(tuple(checks), None, cam.motion, None, None, None,
                         pressure_angle_label="roller in a barrel groove at the root radius, closed form")


# --------------------------------------------------------------------------------------------
# The report's section
# --------------------------------------------------------------------------------------------
#: Samples of the report's curves over a turn (every 0.5 deg) and of the 3-D view's lines.
SECTION_SAMPLES = 721
#: Frames of the report's animation over one turn.
ANIMATION_FRAMES = 120


def _section(groove: Any, p: BarrelParams, theta: np.ndarray, limit_deg: float) -> Any:
    """What the report's section draws (:mod:`camgen.report.barrel`)."""
    from camgen.report.barrel import section_class

    t = np.linspace(0.0, 2.0 * math.pi, SECTION_SAMPLES)
    pressure = tuple((name, r, np.degrees(groove.pressure_angle(np.asarray(r), t))) for name, r in _radii(p))
    phi = np.linspace(0.0, 2.0 * math.pi, SECTION_SAMPLES)
    upper, lower = groove.wall_height(1, np.asarray(p.mean_radius), phi), groove.wall_height(-1, np.asarray(p.mean_radius), phi)
    px, pz = groove.pitch_developed(t)
    span = 2.0 * math.pi * p.mean_radius
    px = np.mod(px, span)
    order = np.argsort(px, kind="stable")
    lines: list[tuple[str, np.ndarray]] = []
    circle = np.stack([np.cos(phi), np.sin(phi), np.zeros_like(phi)], axis=1)
    for z, face in ((0.0, "bottom face"), (p.length, "top face")):
        lines.append((face, circle * [p.rim_radius, p.rim_radius, 0.0] + [0.0, 0.0, z]))
    if p.bore_radius > 0:
        lines.append(("bore", circle * [p.bore_radius, p.bore_radius, 0.0] + [0.0, 0.0, p.length]))
    from camgen.report.barrel import VIEW_AZIMUTH_DEG

    for sign in (1.0, -1.0):  # the silhouette: the generators at +-90 deg from the view's azimuth
        a = math.radians(VIEW_AZIMUTH_DEG) + sign * 0.5 * math.pi
        lines.append(("silhouette", np.array([[p.rim_radius * math.cos(a), p.rim_radius * math.sin(a), 0.0],
                                              [p.rim_radius * math.cos(a), p.rim_radius * math.sin(a), p.length]])))
    surface = "face of the rib" if p.track == "rib" else "wall"
    for r, where in ((p.rim_radius, "rim"), (p.root_radius, "root")):
        for side, name in ((1, "upper"), (-1, "lower")):
            height = groove.wall_height(side, np.asarray(r), phi)
            lines.append((f"{name} {surface} at the {where}", np.stack([r * np.cos(phi), r * np.sin(phi), height], axis=1)))
    frames = np.linspace(0.0, 2.0 * math.pi, ANIMATION_FRAMES + 1)
    # each roller's axis per frame (tangential offset e, height z_c): a groove's one roller, a rib's two (lower, upper)
    carriers = (groove.roller(-1), groove.roller(1)) if p.track == "rib" else (groove,)
    rollers = tuple((np.broadcast_to(e, frames.shape).astype(float), np.asarray(z_c, dtype=float))
                    for z_c, e in (carrier.axis(frames) for carrier in carriers))
    return section_class()(np.degrees(t), pressure, phi * p.mean_radius, px[order], pz[order], upper, lower, tuple(lines),
                           rollers, p.track, p.mean_radius, p.length, p.roller_radius, p.sigma, limit_deg)
