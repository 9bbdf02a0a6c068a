"""What the report draws: the typed, frozen input of report.json and report.html.

The report never sees a run: :mod:`camgen.report_data` maps a run's results to a
:class:`ReportInput` (the run's settings, one :class:`CamReport` per cam, one
:class:`MechanismReport` per mechanism), and :mod:`camgen.report.document` (report.json) and
:mod:`camgen.report.html` (report.html) draw only that.  The JSON parts (``figures``,
``tables``) are report.json's trees as they are written; the curves are numpy arrays, read-only,
mm and rad unless a name says otherwise.

A kind or mechanism with a part of its own on the page (``report_section``) gets its data as a
:class:`SectionData` (each section defines its own: :mod:`camgen.report.sections`).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal, Protocol, TypeAlias

import numpy as np
import numpy.typing as npt

__all__ = ["CamBody", "CamPlots", "CamReport", "CheckRow", "CompliantCurves", "DynamicsCurves", "FloatArray", "FollowerFaces", "JsonValue",
           "FrictionCurves", "MechanismReport", "MotionAtSpeed", "MotionCurves", "ReportInput", "RideAnimation", "RollerAtZero", "SectionData",
           "ZeroMark", "json_number", "json_numbers", "json_object", "json_objects"]

#: A value of report.json: what :func:`json.dumps` writes (mappings and sequences read-only).
JsonValue: TypeAlias = "None | bool | int | float | str | Sequence[JsonValue] | Mapping[str, JsonValue]"
#: An array of floats (a curve's samples, a polyline's (n, 2) points).
FloatArray: TypeAlias = npt.NDArray[np.float64]
#: A curve against cam angle: (cam angles rad, values).
Curve: TypeAlias = "tuple[FloatArray, FloatArray]"


def json_object(value: JsonValue) -> Mapping[str, JsonValue]:
    """``value`` as a JSON object; anything else (a figure left out: None) as an empty one."""
    return value if isinstance(value, Mapping) else {}


def json_objects(value: JsonValue) -> tuple[Mapping[str, JsonValue], ...]:
    """The JSON objects of the list ``value`` (a motion program's segments); none if it is no list."""
    if isinstance(value, (str, Mapping)) or not isinstance(value, Sequence):
        return ()
    return tuple(json_object(v) for v in value)


def json_number(value: JsonValue) -> float:
    """``value``, a number of report.json (the report's own figures: a bug if it is not one)."""
    if isinstance(value, (int, float)):
        return value
    raise TypeError(f"a number was expected in the report's figures, not {value!r}")


def json_numbers(value: JsonValue) -> tuple[float, ...]:
    """``value``, a list of numbers of report.json."""
    if isinstance(value, (str, Mapping)) or not isinstance(value, Sequence):
        raise TypeError(f"a list of numbers was expected in the report's figures, not {value!r}")
    return tuple(json_number(v) for v in value)


class ZeroMark(Protocol):
    """Cam angle 0 on the part: the point of the profile the follower touches then (cam frame,
    mm) and the rotation sense (``sigma`` +1 counter-clockwise, -1 clockwise)."""

    @property
    def point(self) -> tuple[float, float]: ...

    @property
    def sigma(self) -> float: ...


@dataclass(frozen=True)
class RideAnimation:
    """What the animation of the follower riding the cam draws (mm, deg, s;
    :mod:`camgen.report.animation`).

    Attributes
    ----------
    profile : (n, 2) the cam's outline at cam angle 0 (cam frame = fixed frame then).
    sigma : +1 the cam turns counter-clockwise, -1 clockwise.
    follower : (label, polyline (m, 2)) of the follower at zero lift or swing, fixed frame.
    motion : ``"translating"`` (moves along +y) or ``"oscillating"`` (turns about ``pivot``).
    pivot : the pivot (x, y) of an oscillating follower, else None.
    moves : per frame (uniform cam angles over one turn, from 0): the lift (mm) of a translating
        follower, or its arm's turn about the pivot (deg, counter-clockwise positive).
    seconds : duration of one turn on screen.
    zero_mark : the contact point at cam angle 0 (:class:`ZeroMark`) or None.
    walls : polylines (n, 2) of the walls of a pocket cut into the cam (a groove: its outer wall,
        then its inner wall), turning with it; () for a plain outline.
    """

    profile: FloatArray
    sigma: float
    follower: Sequence[tuple[str, FloatArray]]
    motion: str
    pivot: tuple[float, float] | None
    moves: FloatArray
    seconds: float
    zero_mark: ZeroMark | None = None
    walls: tuple[FloatArray, ...] = ()


@dataclass(frozen=True)
class CheckRow:
    """One design check as the report shows it (:class:`camgen.checks.CheckResult`'s fields):
    ``status`` "pass", "fail" or "info"; ``value`` and ``limit`` in ``unit``; ``limit`` None
    and ``comparison`` "" for information; ``where_deg`` the cam angles concerned (a linear
    cam's plate travel in mm: ``where_unit``)."""

    name: str
    status: Literal["pass", "fail", "info"]
    value: float | str
    limit: float | str | None
    comparison: str
    unit: str
    where_deg: tuple[float, ...]
    note: str
    blocks_manufacture: bool
    where_unit: str = "deg"

    @property
    def failed(self) -> bool:
        return self.status == "fail"

    def as_json(self) -> dict[str, JsonValue]:
        """The check's object in report.json."""
        return {"name": self.name, "status": self.status, "value": self.value, "limit": self.limit, "comparison": self.comparison,
                "unit": self.unit, f"where_{self.where_unit}": self.where_deg, "note": self.note,
                "blocks_manufacture": self.blocks_manufacture}


@dataclass(frozen=True)
class CamBody:
    """The cam plate (mm, rad): thickness, bore (diameter 0: none), keyway (width 0: none) and
    its four corners (cam frame) when there is one, the least wall allowed."""

    thickness: float
    bore_diameter: float
    keyway_width: float
    keyway_depth: float
    keyway_angle: float
    min_wall: float
    keyway_corners: FloatArray | None


@dataclass(frozen=True)
class FollowerFaces:
    """A flat follower's face lines at cam angle 0 (a yoke: both faces): normal to ``direction``
    (rad, fixed frame), ``distances`` (mm) from the cam axis along it."""

    direction: float
    distances: tuple[float, ...]


@dataclass(frozen=True)
class RollerAtZero:
    """A translating roller at cam angle 0: its centre (mm, fixed frame) and radius (mm)."""

    centre: tuple[float, float]
    radius: float


@dataclass(frozen=True)
class MotionAtSpeed:
    """The follower's velocity, acceleration and jerk at ``rpm`` against cam angle, in the units
    named (mm/s, m/s^2, m/s^3; an oscillating arm rad/s, rad/s^2, rad/s^3)."""

    rpm: float
    velocity: FloatArray
    acceleration: FloatArray
    jerk: FloatArray
    velocity_unit: str
    acceleration_unit: str
    jerk_unit: str


@dataclass(frozen=True)
class MotionCurves:
    """The follower's motion per unit cam speed on a uniform cam-angle grid (rad): ``lift`` from
    zero lift in ``unit`` (mm, or rad for an oscillating arm), its derivatives per rad of cam
    angle (jerk: its finite part; the acceleration's jumps at ``jerk_impulses_deg``), and the
    same at the cam's speed when the scene gives one."""

    cam_angle: FloatArray
    lift: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    jerk: FloatArray
    unit: str
    jerk_impulses_deg: tuple[float, ...]
    at_speed: MotionAtSpeed | None


@dataclass(frozen=True)
class CamPlots:
    """What report.html draws of a cam's checks (cam angles rad, mm).

    ``profile`` and ``pitch``: the outline (n, 2) and the roller-centre path, flattened (None:
    not made); ``outline_bounds``: (x min, y min, x max, y max) of the profile, else of the pitch
    curve; the follower at cam angle 0 as the kind drew it (``follower_drawing``: (label,
    polyline)), else its ``faces`` or ``roller``; ``pressure_angle`` against cam angle with its
    label and the follower's limit (deg); ``curvature`` (angle, signed radius mm) with its labels
    and the radius it must stay above (None: the tool radius either way); ``motion``;
    ``animation``: the follower riding the cam; ``walls``: the walls of the pockets cut into the
    cam (a groove's two walls), each (its layer name, polyline).
    """

    profile: FloatArray | None
    pitch: FloatArray | None
    outline_bounds: tuple[float, float, float, float] | None
    zero_mark: ZeroMark | None
    follower_drawing: tuple[tuple[str, FloatArray], ...] | None
    faces: FollowerFaces | None
    roller: RollerAtZero | None
    pressure_angle: Curve | None
    pressure_angle_label: str
    follower_limit_deg: float | None
    curvature: Curve | None
    curvature_label: str
    curvature_angle_label: str
    curvature_limit: float | None
    motion: MotionCurves | None
    animation: RideAnimation | None
    walls: tuple[tuple[str, FloatArray], ...] = ()  # (layer, polyline) of every pocket wall (a groove's)


@dataclass(frozen=True)
class DynamicsCurves:
    """The follower dynamics at ``rpm`` (:class:`camgen.dynamics.DynamicsResult`), against cam
    angle ``theta`` (rad): contact forces N (``contact_force_2``: a yoke's second face), the
    pressure angle rad, camshaft torque N*m, power W, Hertz stress MPa (None: not computed), the
    force along and across the follower's motion N; the scalars of the plots' titles; the limits
    given (None: not given); the smallest contact force against cam speed (rpm, N; force-closed
    trains with the plots stage)."""

    rpm: float
    closure: Literal["force", "form"]
    motion: str
    theta: FloatArray
    contact_force: FloatArray
    contact_force_2: FloatArray | None
    pressure_angle: FloatArray
    torque: FloatArray
    power: FloatArray
    hertz_stress: FloatArray | None
    hertz_stress_2: FloatArray | None
    follower_force: FloatArray
    side_force: FloatArray
    jump_margin: float
    jump_rpm: float
    torque_peak: float
    torque_rms: float
    power_peak: float
    power_rms: float
    mean_power: float
    hertz_peak: float | None
    torque_limit: float | None
    allowable_stress: float | None
    speed_rpm: FloatArray | None
    speed_min_force: FloatArray | None
    compliant: "CompliantCurves | None" = None  # a compliant train's response (issue 25 item 2)
    friction: "FrictionCurves | None" = None  # friction, loads and contact life (issue 25 items 3, 4)


# ---- compliant follower train (issue 25 item 2) --------------------------------------------
@dataclass(frozen=True)
class CompliantCurves:
    """A compliant follower train's periodic response (:class:`camgen.compliant.CompliantResult`)
    against cam angle ``theta`` (rad): the dynamic and rigid contact forces N, the dynamic error
    (mm; an arm rad, ``error_unit``); the law's acceleration amplitudes by harmonic 1 .. H
    (``spectrum_unit``), the natural and turn frequencies Hz, the dwell starts (rad) and the
    residual amplitudes there (mm) with their limit (None: not given)."""

    theta: FloatArray
    contact_force: FloatArray
    rigid_force: FloatArray
    error: FloatArray
    error_unit: str
    spectrum: FloatArray
    spectrum_unit: str
    natural_frequency: float
    turn_frequency: float
    damping_ratio: float
    dwell_theta: FloatArray
    residual: FloatArray
    residual_limit: float | None
    natural_frequencies: tuple[float, float] | None = None  # a two-mass train's modes (Hz); then error is the tool's
    cam_side_error: FloatArray | None = None  # a two-mass train's cam-side mass error (mm)
# ---- end compliant -------------------------------------------------------------------------


# ---- friction, loads and contact life (issue 25 items 3, 4) ---------------------------------
@dataclass(frozen=True)
class FrictionCurves:
    """Friction, loads and contact fatigue over a turn (:class:`camgen.friction.FrictionResult`,
    :class:`camgen.contact_life.ContactLife`) against cam angle ``theta`` (rad); None: that part
    is not computed for this follower or these keys.

    Attributes
    ----------
    torque, torque_with_friction, friction_torque : N*m, the camshaft torque without friction,
        with it, and their difference (None with the other two when no friction torque is asked for).
    side_load : N, the force across a translating follower's motion (its guide load).
    guide_near, guide_far : N, the magnitudes of the near and far bushing reactions.
    binding : the binding ratio ``mu_g (|R1| + |R2|) / F_axial`` (0 where the cam does not push
        the stem): the guide binds where it reaches 1 (None: no guide).
    guide_friction : the bushings' coefficient mu_g (None: no guide).
    pin_torque, roller_drive_torque, traction_limit : N*mm on the roller: its pin's friction
        torque, the torque that turns it (pin friction and inertia), the traction the contact holds
        ``mu_c F R`` (the roller skids where the drive torque passes it).
    slip_peak : the largest slip ratio drive / traction (report.json's ``roller_slip_ratio_peak``).
    half_width : mm, the Hertz line-contact half-width b.
    shear, shear_depth : MPa and mm, the sub-surface maximum shear stress (0.30 p_max) and its
        depth (0.78 b); case_depth : mm, the case depth asked for (None: no contact life).
    """

    theta: FloatArray
    torque: FloatArray | None = None
    torque_with_friction: FloatArray | None = None
    friction_torque: FloatArray | None = None
    side_load: FloatArray | None = None
    guide_near: FloatArray | None = None
    guide_far: FloatArray | None = None
    binding: FloatArray | None = None
    guide_friction: float | None = None
    pin_torque: FloatArray | None = None
    roller_drive_torque: FloatArray | None = None
    traction_limit: FloatArray | None = None
    slip_peak: float | None = None
    half_width: FloatArray | None = None
    shear: FloatArray | None = None
    shear_depth: FloatArray | None = None
    case_depth: float | None = None
# ---- end friction -------------------------------------------------------------------------


class SectionData:
    """Base of the data a kind's or mechanism's own report section draws: frozen dataclasses
    defined beside their section (:mod:`camgen.report.sections`), made by the ``plots`` stage.
    A kind puts its data on its built cam's ``section`` (:attr:`camgen.kinds.base.BuiltCam.section`), a mechanism job
    on :attr:`camgen.jobs.base.JobResult.plots`; the function its ``report_section`` names is
    called with the page's figure maker and the :class:`CamReport` (:class:`MechanismReport`),
    and reads the data as its ``section``."""

    __slots__ = ()


@dataclass(frozen=True)
class CamReport:
    """One cam: report.json's ``cams.<name>`` (kind: the motion, form: the cam form realising it,
    manufacturable, withheld files, figures, checks) and what report.html draws besides (``rpm``, ``body``; ``plots``: None when the cam
    has no evaluation or the run writes no report.html; ``dynamics``; the kind's own part of the
    page: ``report_section``, the ``"module:function"`` drawing it ("": none), and its data,
    ``section``)."""

    name: str
    kind: str
    form: str
    manufacturable: bool
    withheld_files: tuple[str, ...]
    figures: Mapping[str, JsonValue]
    checks: tuple[CheckRow, ...]
    rpm: float | None
    body: CamBody | None
    plots: CamPlots | None
    dynamics: DynamicsCurves | None
    report_section: str
    section: SectionData | None

    @property
    def failed(self) -> bool:
        return any(c.failed for c in self.checks)


@dataclass(frozen=True)
class MechanismReport:
    """One mechanism: its report.json object (``mechanisms.<name>``), the ``"module:function"``
    drawing its part of report.html ("": none) and that part's data (None: the plots stage did
    not run)."""

    name: str
    figures: Mapping[str, JsonValue]
    report_section: str
    section: SectionData | None


@dataclass(frozen=True)
class ReportInput:
    """A run as the report shows it: the scene's name and file, camgen's version, the chord
    tolerance and tool radius (mm), the stages run, every file written, the cams, the
    mechanisms, and report.json's ``tables`` (what each CSV holds)."""

    scene: str
    camgen_version: str
    source_file: str
    chord_tol_mm: float
    tool_radius_mm: float
    stages: tuple[str, ...]
    files: tuple[str, ...]
    cams: tuple[CamReport, ...]
    mechanisms: tuple[MechanismReport, ...]
    tables: Mapping[str, JsonValue]

    @property
    def failed(self) -> bool:
        return any(cam.failed for cam in self.cams)
