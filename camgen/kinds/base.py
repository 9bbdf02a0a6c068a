"""What every cam kind shares: the built cam, the cam spec, the kind object and the key groups.

A cam kind is one module in :mod:`camgen.kinds` exposing ``KIND``, a :class:`CamKind`: its
scene keys, how to read them into a typed spec, how to build the cam (synthesis, and the
analysis stages it feeds), and which report section draws it.  The pipeline knows nothing
about any kind beyond this interface.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from functools import lru_cache
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Callable, ClassVar, Mapping

from camgen.errors import CamgenError, ParameterError
from camgen.schema import Angle, Key, Length, Number, Text

if TYPE_CHECKING:  # the heavy modules stay unimported until a cam is built
    from camgen.body import BodySpec
    from camgen.checks import CamEvaluation, Follower
    from camgen.contour import Arc, Contour, Spline
    from camgen.errors import UndercutError
    from camgen.report.model import SectionData

#: Analysis stages a kind may feed (the pipeline plans them from the requested outputs).
#: ``analysis``: figures and files beyond the design checks (ride simulations, fits, sweeps);
#: ``plots``: the data report.html draws.
STAGES = ("analysis", "plots", "mesh", "fea")

#: Least cam speed a scene may give, rev/min: one turn in 1000 min (16.7 h), slower than any
#: machine cam.  Every number derived from it stays a normal float: omega = 2 pi rpm / 60 =
#: 1.05e-4 rad/s, omega^3 = 1.15e-12 (jerk), one turn 6e4 s; a positive rpm near the float's
#: least (5e-324) once made omega underflow to 0 and the follower table's time infinite.
MIN_RPM = 1e-3


def field_default(cls: type, name: str) -> Any:
    """The default of dataclass field ``name`` of ``cls``: one owner for every default."""
    return {f.name: f.default for f in dataclasses.fields(cls)}[name]


@dataclass(frozen=True)
class CheckSettings:
    """Limits and conditions of the design checks (rad, rev/min, mm), final when the scene is read.

    ``tool_radius``: the cutting tool's radius when it is a limit: the scene names a tool or the
    run writes G-code (the scene reader sets it; a kind that sizes its cam holds the concave radii
    to it, the machinability check fails below it); None: the tool is information only.
    """

    pressure_angle_limit: float | None = None
    rpm: float | None = None
    tool_radius: float | None = None
    jerk_limit: float | None = None  # VDI: the follower's jerk limit at rpm (m/s^3 or rad/s^3; camgen/kinds/jerk_limit.py)

    @property
    def tool_is_limit(self) -> bool:
        """The concave radii are held to the tool (``tool_radius`` is set)."""
        return self.tool_radius is not None


@dataclass(frozen=True)
class ZeroMark:
    """Where cam angle 0 is on the part and which way the cam turns (the DXF ZERO layer, the report).

    ``point``: the point of the profile the follower touches at cam angle 0 (cam frame, mm); the
    mark is the line from the rotation axis to it.  ``sigma``: +1 the cam turns counter-clockwise
    (seen from +z, as the DXF is drawn), -1 clockwise.
    """

    point: tuple[float, float]
    sigma: float


@dataclass(frozen=True)
class CamSpec:
    """One cam of a scene: name, motion (``kind``), the typed parameters, body, follower and check
    settings, and the cam form realising the motion (``form``; the scene reader sets it).
    """

    name: str
    kind: str
    params: Any  # the kind's own frozen dataclass (see its module)
    body: "BodySpec"
    checks: CheckSettings
    follower: "Follower | None" = None
    dynamics: Any = None  # camgen.kinds.dynamics.DynamicsSpec: the follower train, when the scene gives one
    form: str = "plate"  # the cam form (camgen.forms) realising the motion


@dataclass(frozen=True)
class Wall:
    """A closed wall of a pocket: its contour (cam frame, mm, counter-clockwise) and its name,
    which is the DXF layer it is drawn on and the ``wall`` column of the point list
    (``GROOVE_INNER``, ``GROOVE_OUTER``, ...)."""

    layer: str
    contour: "Contour"


@dataclass(frozen=True)
class Pocket:
    """A region cut into the body from its top face (z = thickness) down ``depth`` mm: inside
    ``walls[0]`` and outside every other wall (a groove: its outer wall, then its inner wall).

    The body is the cam's outline (:attr:`BuiltCam.contour`) extruded by the body's thickness,
    minus bore and keyway, minus its pockets.  ``width``: the distance between the walls (a
    groove), or for a pocket of one wall twice the largest distance of a point inside from it (a
    slot: its width); ``clearance``: what the pocket's width exceeds the follower's by (mm,
    information for the files' notes); ``centre``: the closed curve midway between the walls at
    ``width / 2`` from each (a groove's pitch curve: the path of a tool as wide as the groove),
    None when the pocket has none; ``centre_path``: an open centre instead, the segments (arcs,
    splines) of a chain at ``width / 2`` from the one wall whose tool disc of that width sweeps
    exactly the pocket (a slot closed by half circles about its ends: the pitch curve between
    them), None when the pocket has none; ``note``: one line for the files.
    """

    name: str
    walls: tuple[Wall, ...]
    depth: float
    width: float | None = None
    centre: "Contour | None" = None
    clearance: float = 0.0
    note: str = ""
    centre_path: "tuple[Arc | Spline, ...] | None" = None


@dataclass(frozen=True)
class BuiltCam:
    """A synthesised cam (the synthesis stage's result, frozen): its contour, figures (report
    numbers) and the kind's own files.

    ``contour`` is None when the profile cannot be made (an undercut, ``undercut`` says why): the
    checks say so, the report shows it, and no manufacturing file is written.  Kinds extend this
    class with their own typed data (frozen too).  The later stages' results are composed with it
    in :class:`camgen.results.CamResult`.
    """

    name: str
    kind: str
    contour: "Contour | None"
    figures: Mapping[str, Any]
    body: "BodySpec"
    follower: "Follower | None" = None
    pitch: "Contour | None" = None  # follower-centre path the cam was made for (roller followers)
    breadth: float | None = None  # constant breadth (yoke followers)
    files: Mapping[str, str] = field(default_factory=dict)
    undercut: "UndercutError | None" = None  # why the profile could not be made (contour None)
    zero_mark: ZeroMark | None = None  # cam angle 0 and the rotation sense (kinds that know them)
    section: "SectionData | None" = None  # the data of the kind's own report section (the plots stage made it)
    pockets: tuple[Pocket, ...] = ()  # regions cut into the top face (a groove cam's groove); contour is then the outline (rim)
    #: The body is a plate (``contour`` extruded, less its pockets): the generic plan view, meshes and
    #: checks of a contour apply.  A form whose body is not (a barrel cam) says False, writes its own
    #: files (:attr:`camgen.forms.base.CamForm.writers`) and has no ``contour``, yet can be made.
    planar: ClassVar[bool] = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "figures", MappingProxyType(dict(self.figures)))  # read-only: no later stage writes into them
        object.__setattr__(self, "files", MappingProxyType(dict(self.files)))


@dataclass(frozen=True)
class CamKind:
    """A cam type: one motion realised by one cam form (:func:`camgen.kinds.get_kind` composes it
    from the motion and form registries, or a motion realises a form by its own synthesis).

    Attributes
    ----------
    name : the ``kind`` value in scene files (the motion).
    summary : one line for ``camgen keys`` and the template list.
    keys : every key ``[cams.<name>]`` accepts besides ``kind``.
    read : ``(where, name, parsed, base_dir) -> CamSpec``: the parsed keys (fields in internal
        units) into the typed spec; cross-key validation here, errors naming scene keys under
        ``where``; ``base_dir`` is where relative file names in the scene point.
    build : ``(spec, stages) -> BuiltCam``: synthesis, plus the analysis stages in ``stages``.
    report_section : ``"module:function"`` drawing the kind's own part of report.html, or "".
    evaluate : ``(cam, spec, tool_radius, tool_is_limit) -> CamEvaluation``: the kind's own design
        checks (e.g. closed-form kinematics of its follower); None: the generic checks of the
        contour with ``spec.follower`` (:func:`camgen.checks.evaluate_cam`).
    follower_dynamics : ``(cam, spec) -> (camgen.dynamics.Kinematics, arm_length_mm)``: the
        follower's kinematics and contact geometry for the dynamics stage
        (:mod:`camgen.kinds.dynamics`); None: the kind has no dynamics keys.
    """

    name: str
    summary: str
    keys: tuple[Key, ...]
    read: Callable[..., CamSpec]
    build: Callable[[CamSpec, frozenset[str]], BuiltCam]
    report_section: str = ""
    evaluate: "Callable[[BuiltCam, CamSpec, float, bool], CamEvaluation] | None" = None
    follower_dynamics: "Callable[[BuiltCam, CamSpec], tuple[Any, float]] | None" = None


# --------------------------------------------------------------------------------------------
# Key groups shared by the kinds
# --------------------------------------------------------------------------------------------
def _solid_default(name: str) -> Any:
    from camgen.body import BodySpec

    return field_default(BodySpec, name)


@lru_cache(maxsize=None)  # constants only: made once
def body_keys() -> tuple[Key, ...]:
    """Keys of the cam body (every kind): thickness, bore, keyway, minimum wall."""
    return (
        Key("thickness_mm", Length(high=1e4), "Thickness of the cam plate.", ("thickness",), default=_solid_default("thickness")),
        Key("bore_diameter_mm", Length(0.0, 1e4, low_open=False), "Diameter of the shaft bore; 0: no bore.", ("body",),
            default=_solid_default("bore_diameter")),
        Key("keyway_width_mm", Length(0.0, 1e4, low_open=False), "Width of the keyway in the bore (< bore_diameter_mm); 0: no keyway.", ("body",),
            default=_solid_default("keyway_width")),
        Key("keyway_depth_mm", Length(0.0, 1e4, low_open=False), "Depth of the keyway beyond the bore radius.", ("body",),
            default=_solid_default("keyway_depth")),
        Key("keyway_angle_deg", Angle(), "Direction of the keyway's centre line in the cam frame (counter-clockwise from +x).",
            ("body",), default=math.degrees(_solid_default("keyway_angle"))),
        Key("min_wall_mm", Length(0.0, 1e4, low_open=False), "Smallest wall allowed between bore/keyway and profile (the wall check's limit).",
            ("report",), default=_solid_default("min_wall")),
    )


#: Smallest pressure-angle limit a scene may set, deg (a limit is an engineering angle; below
#: this its radians would underflow, 5e-324 deg is 0 rad).
MIN_PRESSURE_ANGLE_LIMIT_DEG = 0.01


def check_keys(oscillating: bool = True) -> tuple[Key, ...]:
    """Keys of the design checks (every kind); ``oscillating`` False leaves out the keys of an
    oscillating arm (a kind whose follower only translates)."""
    return (
        Key("pressure_angle_limit_deg", Angle(MIN_PRESSURE_ANGLE_LIMIT_DEG, 90.0, high_open=True),
            "Largest pressure angle allowed (default: 30 deg translating followers, 45 deg oscillating ones and yokes); disk cams "
            "with sizing are sized to it.", ("report",)),
        Key("rpm", Number("rev/min", MIN_RPM, 1e6), "Cam speed: the follower's velocity, acceleration and jerk at speed in "
            "the report, and the follower table (<cam>_follower.csv, which needs it).", ("report", "motion")),
        *_jerk_limit_keys(oscillating),  # VDI: issue 26 item 5
    )


def _jerk_limit_keys(oscillating: bool) -> tuple[Key, ...]:
    from camgen.kinds.jerk_limit import jerk_limit_keys

    return jerk_limit_keys(oscillating)


def source_key() -> Key:
    return Key("source", Text(), "Where the numbers come from (a note copied into the report).", ("report",))


def read_body(where: str, parsed: Mapping[str, Any]) -> "BodySpec":
    """The :class:`~camgen.export.solid.BodySpec` of a cam table, errors naming the scene key."""
    from camgen.body import BodySpec

    keys = body_keys()
    return rename_errors(where, lambda: BodySpec(**{k.field: parsed[k.field] for k in keys if k.field in parsed}), keys)


def read_checks(parsed: Mapping[str, Any]) -> CheckSettings:
    """The check settings of a cam table: its limits, and the tool radius the scene reader set as
    a limit (:attr:`camgen.schema.Parsed.tool_limit`)."""
    return CheckSettings(parsed.get("pressure_angle_limit"), parsed.get("rpm"), getattr(parsed, "tool_limit", None),
                         parsed.get("jerk_limit", parsed.get("jerk_limit_angular")))  # VDI: the jerk limit


def rename_errors(where: str, make: Callable[[], Any], keys: tuple[Key, ...]) -> Any:
    """Call ``make``; a :class:`ParameterError` naming an internal parameter (``bore_diameter``)
    is re-raised naming its scene key (``cams.x.bore_diameter_mm``) so the user finds the line
    (:func:`camgen.keynames.renamed`)."""
    from camgen.keynames import renamed

    return renamed(where, keys, make)


def with_cam(where: str, make: Callable[[], Any]) -> Any:
    """Call ``make``; any other :class:`CamgenError` is prefixed with the cam's scene path (its
    attributes, e.g. an undercut's pitch curve, are kept)."""
    import copy

    try:
        return make()
    except ParameterError:
        raise
    except CamgenError as exc:
        text = str(exc)
        if text.startswith(f"{where}"):
            raise
        renamed = copy.copy(exc)
        renamed.args = (f"{where}: {text}",)
        raise renamed from None
