"""Cam-follower dynamics at scene level: the keys, reading them, and the stage that runs them.

The keys (:func:`dynamics_keys`, shared by the disk kinds and ``three_arc``) describe the
follower train in SI-friendly units: a translating follower in kg, N/mm, N, N*s/m; an
oscillating arm in kg*m^2, N*mm/rad, N*mm, N*m*s/rad (about its pivot); the contact's materials
in GPa; the limits in N, MPa, N*m.  The dynamics run when the cam gives its speed (``rpm``) and
the moving mass (``mass_kg``, translating) or the arm's moment of inertia (``inertia_kg_m2``,
oscillating); any other dynamics key without them is refused naming the missing key, and a key
that does not apply to the follower (a torsional spring on a translating follower, a spring on
a form-closed yoke, a contact stress on a knife edge) is refused saying why.

The stage (:func:`run_dynamics`) takes the follower's kinematics from the kind's own closed
forms (:attr:`camgen.kinds.base.CamKind.follower_dynamics`: :func:`disk_kinematics`,
:func:`three_arc_kinematics`), runs :func:`camgen.dynamics.analyse` (the physics) at the
scene's speed and turns its results into checks (:func:`dynamics_checks`: "jump", or
"contact_force" for a yoke; "hertz_stress"; "camshaft_torque") on the cam: a failed one fails
the run (exit 1) like every design check, none withholds a file.
Its figures go to report.json (``figures.dynamics``), its curves to report.html.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from camgen.errors import GeometryError, ParameterError
from camgen.keynames import renamed, scene_key
from camgen.schema import Angle, Choice, Flag, Key, Length, Number, Text, given_keys

if TYPE_CHECKING:
    from camgen.checks import CheckResult
    from camgen.dynamics import ContactMaterial, DynamicsResult, FollowerTrain, Kinematics
    from camgen.checks import CheckResult
    from camgen.kinds.base import BuiltCam, CamSpec

_T = {"follower_motion": ("translating",)}
_O = {"follower_motion": ("oscillating",)}
_R = ("report",)

#: Samples per turn of a three-arc cam's follower kinematics (0.05 deg, the disk cams' check grid).
THREE_ARC_SAMPLES = 7200
#: Points of the report's curve of the smallest contact force against cam speed.
SPEED_SAMPLES = 241
#: The speed curve runs to this multiple of the scene's rpm (or a little past the jump speed).
SPEED_SPAN = 2.0
#: ... but never beyond this multiple of the scene's rpm (a jump speed far above it is stated in figures).
SPEED_SPAN_MAX = 20.0

#: Spring keys (refused on a form-closed yoke).
SPRING_KEYS = ("spring_rate_n_per_mm", "spring_preload_n", "spring_free_length_mm", "spring_installed_length_mm",
               "spring_rate_n_mm_per_rad", "spring_preload_n_mm")
#: Contact-stress keys (refused on a knife edge).
CONTACT_KEYS = ("contact_width_mm", "cam_modulus_gpa", "cam_poisson", "follower_modulus_gpa", "follower_poisson",
                "allowable_contact_stress_mpa")


@lru_cache(maxsize=None)
def dynamics_keys(oscillating: bool = True) -> tuple[Key, ...]:
    """The keys of the follower train, the contact materials and the dynamic limits;
    ``oscillating`` False leaves out the keys of an oscillating arm (for kinds whose dynamics
    are for translating followers only).

    Each is stored under its own name (``spring_rate_n_per_mm``: no unit suffix is stripped,
    they are part of the name), ``gravity_deg`` in radians under ``gravity_angle``.  Made once per
    argument (constants only: no registry is read)."""
    # FATIGUE: the friction and life keys on the kinds with the plate's follower envelope (those that take
    # oscillating followers; a translating-only kind's, three_arc's, has neither a roller nor its geometry)
    extra = friction_life_keys() if oscillating else ()
    return tuple(k if k.attr is not None else replace(k, attr=k.name) for k in (*_keys(), *_compliant_keys(), *extra)
                 if oscillating or k.requires.get("follower_motion") != ("oscillating",))


def _keys() -> tuple[Key, ...]:
    return (
        Key("mass_kg", Number("kg", 0.0, 1e5), "Translating follower: its effective moving mass (follower, roller and about a "
            "third of the spring), for its inertia and weight; with rpm it turns the dynamics on (contact force, jump, camshaft "
            "torque, Hertz stress). Oscillating follower: the arm's mass, for its weight only (with cg_distance_mm).", _R,
            example=0.5, feeds=("mass",)),
        Key("inertia_kg_m2", Number("kg*m^2", 0.0, 1e4), "Oscillating follower: moment of inertia of the arm with its roller "
            "about the pivot; with rpm it turns the dynamics on.", _R, example=1e-3, requires=_O, feeds=("inertia",)),
        Key("cg_distance_mm", Length(-1e5, 1e5, low_open=False), "Oscillating follower with mass_kg: distance from the pivot to "
            "the arm's centre of mass, along the arm towards the roller (a flat face: perpendicular to the face, from the pivot "
            "towards the cam; < 0 beyond the pivot), for its weight.", _R, example=30.0, requires=_O, feeds=("cg_distance",)),
        Key("spring_rate_n_per_mm", Number("N/mm", 0.0, 1e7), "Translating follower: rate of the spring pressing it onto the "
            "cam (default 0).", _R, example=2.0, requires=_T, feeds=("spring_rate",)),
        Key("spring_preload_n", Number("N", 0.0, 1e8), "Translating follower: the spring force with the follower at its lowest "
            "position (default 0); or give spring_free_length_mm and spring_installed_length_mm.", _R, example=50.0, requires=_T,
            feeds=("preload",)),
        Key("spring_free_length_mm", Length(), "Translating follower: the spring's free length; with spring_installed_length_mm "
            "it sets the preload, rate x (free - installed).", _R, example=60.0, requires=_T, feeds=("spring_free_length",)),
        Key("spring_installed_length_mm", Length(), "Translating follower: the spring's length with the follower at its lowest "
            "position (<= spring_free_length_mm).", _R, example=50.0, requires=_T, feeds=("spring_installed_length",)),
        Key("spring_rate_n_mm_per_rad", Number("N*mm/rad", 0.0, 1e10), "Oscillating follower: rate of the torsional spring "
            "about the pivot (default 0).", _R, example=5000.0, requires=_O, feeds=("spring_rate",)),
        Key("spring_preload_n_mm", Number("N*mm", 0.0, 1e10), "Oscillating follower: the spring torque about the pivot with the "
            "arm at its lowest position (default 0).", _R, example=2000.0, requires=_O, feeds=("preload",)),
        Key("damping_n_s_per_m", Number("N*s/m", 0.0, 1e7), "Translating follower: viscous damping of its motion (default 0).",
            _R, example=20.0, requires=_T, feeds=("damping",)),
        Key("damping_n_m_s_per_rad", Number("N*m*s/rad", 0.0, 1e7), "Oscillating follower: viscous damping of the arm's "
            "rotation (default 0).", _R, example=0.05, requires=_O, feeds=("damping",)),
        Key("external_load_n", Number("N", -1e8, 1e8), "Translating follower: a constant external load pressing it onto the cam "
            "(< 0 pulls it off; default 0); or external_load_csv.", _R, example=20.0, requires=_T, feeds=("load",)),
        Key("external_load_n_mm", Number("N*mm", -1e10, 1e10), "Oscillating follower: a constant external torque about the pivot "
            "pressing the arm onto the cam (< 0 pulls it off; default 0); or external_load_csv.", _R, example=500.0, requires=_O,
            feeds=("load",)),
        Key("external_load_csv", Text(), "CSV file of rows 'cam_angle_deg, load' relative to the scene file: the external load "
            "pressing the follower onto the cam against cam angle (N; oscillating: N*mm about the pivot), interpolated linearly "
            "and periodically; cam angles increasing in [0, 360); loads within the range of external_load_n (external_load_n_mm); '#' "
            "comments and a header row allowed.", _R),
        Key("gravity", Flag(), "The follower's weight acts in the plane of the cam, along gravity_deg (false: the cam plane is "
            "horizontal and the weight does not load the contact).", _R, default=True),
        Key("gravity_deg", Angle(), "Direction of gravity in the fixed frame, counter-clockwise from +x (-90: down the drawing, "
            "-y).", _R, default=-90.0, requires={"gravity": (True,)}, attr="gravity_angle"),
        Key("contact_width_mm", Length(), "Length of the contact line for the Hertz stress: the smaller of the cam's thickness and "
            "the roller's (or face's) width; default: thickness_mm.", _R, example=8.0, feeds=("width",)),
        Key("cam_modulus_gpa", Number("GPa", 0.0, 1e4, low_open=True), "Young's modulus of the cam material (steel: 210).", _R,
            default=210.0, feeds=("cam_modulus",)),
        Key("cam_poisson", Number("", -1.0, 0.5, low_open=True, high_open=True), "Poisson's ratio of the cam material (steel: "
            "0.3).", _R, default=0.3),
        Key("follower_modulus_gpa", Number("GPa", 0.0, 1e4, low_open=True), "Young's modulus of the follower (roller or face) "
            "material (steel: 210).", _R, default=210.0, feeds=("follower_modulus",)),
        Key("follower_poisson", Number("", -1.0, 0.5, low_open=True, high_open=True), "Poisson's ratio of the follower material "
            "(steel: 0.3).", _R, default=0.3),
        Key("allowable_contact_stress_mpa", Number("MPa", 0.0, 1e6, low_open=True), "Allowable Hertz contact stress: the "
            "hertz_stress check fails above it (left out: the stress is information).", _R, example=1200.0, feeds=("allowable_stress",)),
        Key("jump_margin_n", Number("N", 0.0, 1e8), "Smallest contact force the jump check requires at every cam angle (0: the "
            "follower must only stay on the cam).", _R, default=0.0),
        Key("torque_limit_n_m", Number("N*m", 0.0, 1e8, low_open=True), "Largest camshaft torque allowed: the camshaft_torque "
            "check fails above it (left out: the torque is information).", _R, example=5.0),
    )


# ---- compliant follower train (issue 25 item 2: camgen/kinds/compliant.py) ----------------
def _compliant_keys() -> tuple[Key, ...]:
    from camgen.kinds.compliant import compliant_keys

    return compliant_keys()
# ---- end compliant -------------------------------------------------------------------------


@dataclass(frozen=True)
class DynamicsSpec:
    """The dynamics a scene asks for: the follower train (an oscillating one's arm length is
    filled in by the stage from the follower geometry), the contact material (None for a knife
    edge), the jump margin (N), the torque limit (N*m or None) and the keys given."""

    train: "FollowerTrain"
    material: "ContactMaterial | None"
    jump_margin: float
    torque_limit: float | None
    given: tuple[str, ...]
    compliance: Any = None  # camgen.compliant.TrainCompliance: the train's stiffness (None: rigid)
    friction_life: "FrictionLifeSpec | None" = None  # FATIGUE: friction, loads, contact life (None: no such key)


def read_dynamics(where: str, parsed: Mapping[str, Any], *, motion: str, follower: str, rpm: float | None, thickness: float,
                  base_dir: Path | None = None, unavailable: str | None = None, form_closed: bool = False) -> DynamicsSpec | None:
    """The dynamics of a cam table, or None when it gives no dynamics key.

    Parameters
    ----------
    where : the cam's scene path (``cams.<name>``), for errors.
    parsed : the parsed table (:class:`camgen.schema.Parsed`: it knows which keys were given).
    motion : ``"translating"`` or ``"oscillating"``.
    follower : ``"roller"``, ``"flat"``, ``"knife"`` or ``"yoke"`` (form closure: no spring, no jump).
    rpm : the cam speed (rev/min) or None.
    thickness : mm, the cam thickness (the default contact width).
    base_dir : where ``external_load_csv`` is relative to.
    unavailable : why this follower has no dynamics (every dynamics key is then refused), or None.
    form_closed : the cam form holds the follower both ways (a groove's two walls), as a yoke's
        two faces do: no spring, no jump, both contacts checked.

    Raises
    ------
    ParameterError
        Naming the scene key: a dynamics key without ``rpm`` and the mass (inertia), a key that
        does not apply to the follower, an inconsistent spring or load.
    """
    keys = dynamics_keys()
    by_name = {k.name: k for k in keys}
    given_set = given_keys(parsed, keys)
    given = tuple(k.name for k in keys if k.name in given_set)
    if not given:
        return None

    def shown(name: str) -> Any:
        key = by_name[name]
        return key.type.to_scene(parsed.get(key.field))

    def refuse(name: str, valid: str, why: str) -> None:
        raise ParameterError(f"{where}.{name}", shown(name), valid, why)

    if unavailable:
        refuse(given[0], "no dynamics keys for this follower", unavailable)
    translating = motion == "translating"
    trigger = "mass_kg" if translating else "inertia_kg_m2"
    if trigger not in given:
        what = "moving mass in kg (>= 0)" if translating else "moment of inertia about the pivot in kg*m^2 (>= 0)"
        raise ParameterError(f"{where}.{trigger}", None, f"the follower's {what}",
                             f"the dynamics keys given ({', '.join(given)}) need the {'follower' if translating else 'arm'}'s "
                             f"{'mass' if translating else 'moment of inertia'} (and rpm)")
    if rpm is None:
        raise ParameterError(f"{where}.rpm", None, "a cam speed in rev/min (> 0)",
                             f"the follower dynamics ({trigger} given) are computed at the cam speed")
    from camgen.followers import get_follower

    model = get_follower(follower)
    form_closed = form_closed or model.contact == "faces"
    if form_closed:
        what = "a yoke is form-closed: its second face" if model.contact == "faces" else "a groove is form-closed: its second wall"
        for name in (*SPRING_KEYS, "jump_margin_n"):
            if name in given:
                refuse(name, f"left out for a {follower} follower" if model.contact == "faces" else "left out for a groove cam",
                       f"{what} holds the follower on the cam, so it has no spring and cannot jump (both contacts are checked instead)")
    edge = model.contact == "point" and not model.has_radius
    if edge:
        for name in CONTACT_KEYS:
            if name in given:
                refuse(name, f"left out for a {follower} follower", "a sharp knife edge touches the cam along a line of zero radius: "
                       "its Hertz contact stress is unbounded (use a roller to have it checked)")
    lengths = ("spring_free_length_mm", "spring_installed_length_mm")
    if (lengths[0] in given) != (lengths[1] in given):
        missing = lengths[1] if lengths[0] in given else lengths[0]
        raise ParameterError(f"{where}.{missing}", None, "a length in mm",
                             f"{lengths[0]} and {lengths[1]} are given together (they set the spring preload)")
    if lengths[0] in given and "spring_preload_n" in given:
        refuse("spring_preload_n", "left out when the spring lengths are given",
               "spring_free_length_mm and spring_installed_length_mm set the preload, rate x (free - installed)")
    if not translating and ("mass_kg" in given) != ("cg_distance_mm" in given):
        missing = "cg_distance_mm" if "mass_kg" in given else "mass_kg"
        raise ParameterError(f"{where}.{missing}", None, "a length in mm" if missing == "cg_distance_mm" else "a mass in kg",
                             "an oscillating arm's weight needs its mass_kg and where its centre of mass is, cg_distance_mm")
    constant = "external_load_n" if translating else "external_load_n_mm"
    if constant in given and "external_load_csv" in given:
        refuse("external_load_csv", f"left out when {constant} is given", f"give one external load: {constant} (constant) or "
               "external_load_csv (a table over cam angle)")

    from camgen import dynamics as dy

    load: Any = parsed.get(constant, 0.0)
    if "external_load_csv" in given:
        bound = by_name[constant].type
        assert isinstance(bound, Number)  # external_load_n and external_load_n_mm are numbers
        load = read_load_table(f"{where}.external_load_csv", parsed["external_load_csv"], base_dir, bound)
    # the keys of this follower motion: an error of the train or the material names the key that gave the value
    keys = tuple(k for k in keys if motion in k.requires.get("follower_motion", (motion,)))
    spring_rate, preload, damping = (scene_key(keys, name) for name in ("spring_rate", "preload", "damping"))
    get = parsed.get
    train = renamed(where, keys, lambda: dy.FollowerTrain(
        motion=motion, closure="form" if form_closed else "force", mass=get("mass_kg", 0.0), inertia=get("inertia_kg_m2", 0.0),
        arm_length=0.0 if translating else 1.0,  # placeholder: the stage sets the arm from the follower geometry
        cg_distance=get("cg_distance_mm", 0.0), spring_rate=get(spring_rate, 0.0), preload=get(preload),
        spring_free_length=get("spring_free_length_mm"), spring_installed_length=get("spring_installed_length_mm"),
        damping=get(damping, 0.0), load=load, gravity=dy.STANDARD_GRAVITY if parsed.get("gravity", True) else 0.0,
        gravity_angle=get("gravity_angle", -math.pi / 2)))
    material = None
    if not edge:
        material = renamed(where, keys, lambda: dy.ContactMaterial(
            width=get("contact_width_mm", thickness), cam_modulus=get("cam_modulus_gpa", 210.0), cam_poisson=get("cam_poisson", 0.3),
            follower_modulus=get("follower_modulus_gpa", 210.0), follower_poisson=get("follower_poisson", 0.3),
            allowable_stress=get("allowable_contact_stress_mpa")))
    from camgen.kinds.compliant import read_compliance  # compliant follower train (issue 25 item 2)

    compliance = read_compliance(where, parsed, given, translating=translating, form_closed=form_closed)
    life = read_friction_life(where, parsed, given, motion=motion, follower=follower, form_closed=form_closed)  # FATIGUE
    return DynamicsSpec(train, material, get("jump_margin_n", 0.0), get("torque_limit_n_m"), given, compliance, life)


def read_load_table(key: str, name: str, base_dir: Path | None, bound: Number) -> tuple[list[float], list[float]]:
    """The external-load table of ``name`` (CSV rows 'cam_angle_deg, load'): (angles rad, loads).

    Every load must lie in ``bound``, the range of the constant load's key (``external_load_n``
    or ``external_load_n_mm``): the forces, torques and stresses computed from it stay finite.

    Raises :class:`ParameterError` naming ``key`` (the scene path), the file and the line (never
    the file's text: it may not be a table at all)."""
    from camgen.synthesis.lift_table import MAX_BYTES, MAX_ROWS, parse_two_column_table
    from camgen.textfile import TextFileError, read_text_file

    path = Path(name)
    path = path if path.is_absolute() or base_dir is None else base_dir / path
    try:
        text = read_text_file(path, MAX_BYTES)
    except TextFileError as exc:
        raise ParameterError(key, str(path), f"a readable regular UTF-8 file of at most {MAX_BYTES} bytes", str(exc)) from None
    if "\x00" in text:
        raise ParameterError(key, str(path), "text without NUL characters")
    angles, loads, labels = _renamed_table(key, lambda: parse_two_column_table(text, str(path), key, ("cam_angle_deg", "load"),
                                                                               MAX_ROWS))
    if angles.size == 0:
        raise ParameterError(key, str(path), "at least one row 'cam_angle_deg, load'")
    bad = np.flatnonzero((angles < 0) | (angles >= 360.0) | np.append(False, np.diff(angles) <= 0))
    if bad.size:
        raise ParameterError(key, labels[int(bad[0])], "cam angles strictly increasing in [0, 360) deg")
    bad = np.flatnonzero((loads < bound.low) | (loads > bound.high))
    if bad.size:
        i = int(bad[0])
        raise ParameterError(key, labels[i], f"loads {bound.low:g} <= load <= {bound.high:g} {bound.unit} (the range of a constant "
                             "external load)", f"the load {loads[i]:.6g} {bound.unit} is outside it")
    return np.radians(angles).tolist(), loads.tolist()


def _renamed_table(key: str, parse: Any) -> Any:
    """``parse()``, its ParameterError renamed to the scene path ``key``."""
    try:
        return parse()
    except ParameterError as exc:
        raise ParameterError(key, exc.value, exc.valid, exc.why) from None


# --------------------------------------------------------------------------------------------
# The follower kinematics of the kinds (closed forms)
# --------------------------------------------------------------------------------------------
def disk_kinematics(cam: "BuiltCam", spec: "CamSpec") -> tuple["Kinematics", float]:
    """The dynamics kinematics of a disk cam from its closed-form data (the envelope's dense
    check grid: the law's s, s', s'', the pressure angle, the profile's radius of curvature at
    the contact) and the arm length (mm) of an oscillating follower (0 translating)."""
    from camgen import dynamics as dy

    f = cam.spec_follower  # type: ignore[attr-defined]
    k = cam.envelope.data  # type: ignore[attr-defined]
    radius = f.roller_radius if f.contact == "point" else math.inf  # a point contact's radius (a knife's 0); a face is straight
    lever = None
    if f.motion == "translating":
        direction: Any = math.pi / 2  # the follower moves along fixed +y
        arm = 0.0
    elif f.contact == "face":
        # the face normal w (away from the cam) turns by tau per unit swing: the centre of mass, on
        # the perpendicular from the pivot towards the cam (-w), moves along -tau J w; the pressure angle
        # arctan(f / xi) refers to the contact point, hypot(xi, f) from the pivot
        direction = k.arm_angle - f.tau * math.pi / 2
        lever = np.hypot(k.face_position, f.face_offset)
        arm = float(np.max(lever))
    else:
        direction = k.arm_angle + f.tau * math.pi / 2  # the roller centre moves along tau J u(arm angle)
        arm = f.arm_length
    kin = checked_kinematics(lambda: dy.Kinematics(k.theta, k.s, k.ds, k.d2s, k.pressure_angle, k.profile_radius, radius, direction,
                                            lever=lever))
    return kin, arm


def three_arc_kinematics(cam: "BuiltCam", spec: "CamSpec", samples: int = THREE_ARC_SAMPLES) -> tuple["Kinematics", float]:
    """The dynamics kinematics of a three-arc cam's translating flat face or yoke from the
    contour's support function h (exact on its arcs): with psi = direction - theta the face
    moves s = h(psi), s' = -h'(psi), s'' = h''(psi), and the cam's radius of curvature at the
    face's contact is h + h''; a yoke's second face (normal psi + pi) touches where
    h(psi + pi) + h''(psi + pi) is the radius."""
    from camgen import dynamics as dy

    follower, contour = cam.follower, cam.contour
    assert follower is not None and contour is not None  # the stage runs on a cam that was made, with its follower
    theta = 2.0 * math.pi * np.arange(samples) / samples
    psi = follower.direction - theta
    h, dh, d2h = contour.support_derivatives(psi)
    zero = np.zeros(samples)
    second: dict[str, Any] = {}
    if follower.contact == "faces":
        h2, _, d2h2 = contour.support_derivatives(psi + math.pi)
        second = {"pressure_angle_2": zero, "rho_cam_2": h2 + d2h2, "follower_radius_2": math.inf}
    return checked_kinematics(lambda: dy.Kinematics(theta, h, -dh, d2h, zero, h + d2h, math.inf, follower.direction, **second)), 0.0


class DynamicsNotComputed(GeometryError):
    """Raised by a kind's ``follower_dynamics`` when a body the dynamics need cannot be made (a
    conjugate pair's other cam): :func:`run_dynamics` then states the dynamics as not computed,
    saying why, as it does for a profile that cannot be made."""


def checked_kinematics(make: Any) -> "Kinematics":
    """``make()``: a :class:`camgen.dynamics.Kinematics`, its refusal of the geometry (valid
    parameters the contact cannot drive) turned into a :class:`GeometryError` saying so."""
    try:
        return make()
    except ParameterError as exc:  # valid parameters, geometry the contact cannot drive
        raise GeometryError(f"the follower dynamics cannot be computed: {exc} (the contact normal passes through the pivot or "
                            "the contact has a cusp there; change the follower's geometry)") from None


# --------------------------------------------------------------------------------------------
# The stage
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class DynamicsOutcome:
    """What the stage computed for one cam: the result at the scene's speed, the kinematics it
    used, the limits it was checked against (N*m, MPa; None: not given), and (plots stage) the
    smallest contact force against cam speed (rpm, N)."""

    result: "DynamicsResult"
    kinematics: "Kinematics"
    torque_limit: float | None = None
    allowable_stress: float | None = None
    speed_rpm: np.ndarray | None = None
    speed_min_force: np.ndarray | None = None
    compliant: Any = None  # camgen.compliant.CompliantResult of a compliant train, else None
    friction_life: "FrictionLifeOutcome | None" = None  # FATIGUE: friction, loads, contact life


@dataclass(frozen=True)
class DynamicsStage:
    """The dynamics stage's result for one cam: the ``outcome`` the report draws (None when the
    profile cannot be made), its ``checks`` and report.json's ``figures.dynamics``."""

    outcome: DynamicsOutcome | None
    checks: "tuple[CheckResult, ...]"
    figures: Mapping[str, Any] = field(default_factory=dict)


def run_dynamics(cam: "BuiltCam", spec: "CamSpec", stages: frozenset[str], report_figures: bool = True) -> DynamicsStage | None:
    """The dynamics of ``spec`` on the built ``cam``: checks, figures and (``plots`` in ``stages``)
    the report's curves; None when the scene gives no follower train.  ``report_figures`` False
    (a design evaluation's plan: :attr:`camgen.planning.Plan.report_figures`): ``figures.dynamics``
    holds only what a design's row reads (:meth:`camgen.dynamics.DynamicsResult.row_figures`)."""
    from camgen import dynamics as dy
    from camgen.checks import information

    dyn: DynamicsSpec | None = getattr(spec, "dynamics", None)
    if dyn is None:
        return None
    if cam.contour is None and cam.planar:  # a body that is no plate (a barrel) has no outline to lack
        return DynamicsStage(None, (information("dynamics", "not computed", "", [], "the profile cannot be made (see the undercut "
                                                "check): the contact forces, jump and contact stress are computed for a cam that "
                                                "can be made"),))
    from camgen.kinds import get_kind

    rpm, follower_dynamics = spec.checks.rpm, get_kind(spec.kind, spec.form).follower_dynamics
    assert rpm is not None and follower_dynamics is not None  # read_dynamics refuses dynamics without them
    try:
        kin, arm = follower_dynamics(cam, spec)
    except DynamicsNotComputed as exc:
        return DynamicsStage(None, (information("dynamics", "not computed", "", [], str(exc)),))
    train = replace(dyn.train, arm_length=arm) if dyn.train.motion == "oscillating" else dyn.train
    result = dy.analyse(kin, train, rpm, dyn.material, jump_margin=dyn.jump_margin)
    checks = dynamics_checks(result, kin, dyn.material, dyn.torque_limit)
    # SMOOTH (issue 26 item 3): a smoothed lift table's stress and jump against the raw readings'
    from camgen.kinds.lift_noise import dynamics_noise_notes

    def recheck(other: Any) -> tuple[Any, Any]:
        other_kin = follower_dynamics(other, spec)[0]
        other_result = dy.analyse(other_kin, train, rpm, dyn.material, jump_margin=dyn.jump_margin)
        return other_result, dynamics_checks(other_result, other_kin, dyn.material, dyn.torque_limit)

    checks = dynamics_noise_notes(cam, result, checks, recheck if spec.form == "plate" else None)
    speed = force = None
    if "plots" in stages and train.closure == "force":
        top = SPEED_SPAN * rpm
        if math.isfinite(result.jump_rpm) and result.jump_rpm > 0:
            top = min(max(top, 1.2 * result.jump_rpm), SPEED_SPAN_MAX * rpm)
        speed = np.linspace(0.0, top, SPEED_SAMPLES)
        force = dy.min_contact_force(kin, train, speed)
    allowable = dyn.material.allowable_stress if dyn.material is not None else None
    figures = dynamics_figures(result, dyn, train) if report_figures else {"closure": train.closure, "follower_motion": train.motion,
                                                                          **result.row_figures()}
    compliant = None
    if dyn.compliance is not None:  # compliant follower train (issue 25 item 2)
        from camgen.kinds.compliant import run_compliant

        compliant, more, figures["compliant"] = run_compliant(kin, train, dyn.compliance, rpm, dyn.jump_margin)
        checks = [*checks, *more]
    life = None
    if dyn.friction_life is not None:  # FATIGUE: friction, loads, contact life (issue 25 items 3, 4)
        life = run_friction_life(cam, result, kin, dyn)
        checks = [*checks, *life.checks]
        figures.update(life.figures)
    return DynamicsStage(DynamicsOutcome(result, kin, dyn.torque_limit, allowable, speed, force, compliant, life), tuple(checks),
                         figures)


def dynamics_figures(result: "DynamicsResult", dyn: DynamicsSpec, train: "FollowerTrain") -> dict[str, Any]:
    """report.json's ``figures.dynamics``: :meth:`DynamicsResult.figures` and where the peaks are,
    the effective spring preload, the contact width, the limits given."""
    out: dict[str, Any] = {"closure": train.closure, "follower_motion": train.motion}
    out.update(result.figures())

    def deg(i: Any) -> float:  # the cam angle of sample i, deg, 6 decimals (only the angles quoted are converted)
        return round(float(np.degrees(result.theta[int(i)])), 6)

    force = result.contact_force if result.contact_force_2 is None else np.maximum(result.contact_force, result.contact_force_2)
    out["max_contact_force_deg"] = deg(np.argmax(force))
    if train.closure == "force":
        out["min_contact_force_deg"] = deg(np.argmin(result.contact_force))
        unit = "N" if train.motion == "translating" else "Nmm"
        out[f"spring_preload_{unit}"] = train.spring_preload
    else:
        out["max_contact_force_1_N"] = float(np.max(result.contact_force))
        assert result.contact_force_2 is not None  # a form-closed train's second contact
        out["max_contact_force_2_N"] = float(np.max(result.contact_force_2))
    out["torque_peak_deg"] = deg(result.torque_peak_index)
    if dyn.torque_limit is not None:
        out["torque_limit_Nm"] = dyn.torque_limit
    if result.hertz_peak is not None:
        stress = result.hertz_stress if result.hertz_stress is not None else np.zeros_like(result.theta)
        if result.hertz_stress_2 is not None:
            stress = np.maximum(stress, result.hertz_stress_2)
        out["hertz_stress_peak_deg"] = deg(np.argmax(stress))
    if dyn.material is not None:
        out["contact_width_mm"] = dyn.material.width
        if dyn.material.allowable_stress is not None:
            out["allowable_contact_stress_MPa"] = dyn.material.allowable_stress
    return out


# --------------------------------------------------------------------------------------------
# The checks of the dynamics
# --------------------------------------------------------------------------------------------
def dynamics_checks(result: "DynamicsResult", kin: "Kinematics", material: "ContactMaterial | None",
                    torque_limit: float | None) -> "list[CheckResult]":
    """The "jump" (or "contact_force" for a form-closed train), "hertz_stress" (with a material)
    and "camshaft_torque" checks of ``result`` (:func:`camgen.dynamics.analyse` of ``kin``):
    the jump check's note quotes the least spring that keeps the margin, each value tried
    (:func:`camgen.dynamics.spring_hints`); ``torque_limit`` N*m, None: the torque is
    information."""
    from camgen.checks import information, limited, run_ends, where_degrees
    from camgen.dynamics import spring_hints
    from camgen.errors import floor_significant, require_finite

    if torque_limit is not None and not require_finite("torque_limit", torque_limit) > 0:
        raise ParameterError("torque_limit", torque_limit, "torque_limit > 0 N*m")
    theta = result.theta
    train = result.train
    unit = train.force_unit
    rate_unit = "N/mm" if train.motion == "translating" else "N*mm/rad"
    checks: "list[CheckResult]" = []
    if train.closure == "force":
        force = result.contact_force
        i = int(np.argmin(force))
        short = force[i] < result.jump_margin  # some force < the margin: the smallest is (finite: dy.Kinematics refuses nan)
        where = run_ends(force < result.jump_margin, theta) if short else where_degrees(theta[i])
        # the jump speed rounded down: below the speed quoted the contact force stays positive
        jump = ("never (the contact force does not fall with speed)" if math.isinf(result.jump_rpm)
                else "at rest (the force is not positive even standing still)" if result.jump_rpm == 0
                else f"at {floor_significant(result.jump_rpm, 6):g} rpm ({result.jump_rpm / result.rpm:.4g} x this speed)")
        preload, installed, rate = spring_hints(result, kin)
        lengths = train.spring_free_length is not None
        note = (f"smallest contact force {force[i]:.6g} N at cam angle {math.degrees(theta[i]):.6g} deg at {result.rpm:g} rpm "
                f"against a margin of {result.jump_margin:g} N; the follower jumps {jump}; to keep the margin at this speed: ")
        if lengths:
            assert result.min_preload is not None  # a force-closed train's
            note += (f"installed length <= {installed:g} mm (preload >= {result.min_preload:.6g} {unit} at rate "
                     f"{train.spring_rate:g} {rate_unit})" if installed is not None
                     else f"preload >= {result.min_preload:.6g} {unit}" if result.min_preload > train.spring_preload
                     else f"the spring as given (preload {train.spring_preload:g} {unit})")
        else:
            note += (f"preload >= {preload:g} {unit} (rate {train.spring_rate:g} {rate_unit})" if preload is not None
                     else "no preload found")
        note += ((f" or rate >= {rate:g} {rate_unit} (" + ("spring lengths given" if lengths else f"preload {train.spring_preload:g} {unit}")
                  + ")") if rate is not None else "; no spring rate alone can (the force falls short at the lowest position)")
        if result.jump_ranges_deg:
            note += "; the follower leaves the cam between the listed pairs of cam angles"
        checks.append(limited("jump", float(force[i]), ">=", result.jump_margin, "N", where, note))
    else:
        f1, f2 = result.contact_force, result.contact_force_2
        assert f2 is not None
        # where the load passes from one contact to the other (zero-force stretches skipped)
        loaded = np.nonzero(result.generalised_force != 0)[0]
        sign = np.sign(result.generalised_force[loaded])
        takes_over = loaded[np.nonzero(sign != np.roll(sign, 1))[0]] if loaded.size > 1 else loaded[:0]
        where = where_degrees(theta[takes_over])
        note = (f"form-closed train (no spring, no jump): contact 1 carries up to {np.max(f1):.6g} N, contact 2 up to "
                f"{np.max(f2):.6g} N; the load crosses from one contact to the other at {len(where)} cam angles (listed): "
                "any backlash there gives a knock")
        checks.append(information("contact_force", float(max(np.max(f1), np.max(f2))), "N", where[:24], note))
    if material is not None:
        peak = result.hertz_peak
        if peak is None:
            checks.append(information("hertz_stress", "unbounded", "MPa", [],
                                      "a sharp knife edge (tip radius 0) has no finite contact stress: give its tip radius"))
        else:
            stress = result.hertz_stress if result.hertz_stress is not None else np.zeros_like(theta)
            if result.hertz_stress_2 is not None:
                stress = np.maximum(stress, result.hertz_stress_2)
            i = int(np.argmax(stress))
            note = (f"largest Hertz line-contact stress {peak:.6g} MPa at cam angle {math.degrees(theta[i]):.6g} deg "
                    f"(contact width {material.width:g} mm; two-cylinder formula, Rothbart eq. 9.11"
                    + (", both contacts" if result.hertz_stress_2 is not None else "") + ")")
            if material.allowable_stress is None:
                checks.append(information("hertz_stress", peak, "MPa", where_degrees(theta[i]),
                                          note + "; give an allowable stress to check it"))
            else:
                over = stress[i] > material.allowable_stress  # some stress > the allowable: the largest is (finite: as the forces)
                where = run_ends(stress > material.allowable_stress, theta) if over else where_degrees(theta[i])
                checks.append(limited("hertz_stress", peak, "<=", material.allowable_stress, "MPa", where, note))
    i = result.torque_peak_index
    note = (f"camshaft torque peak {result.torque_peak:.6g} N*m at cam angle {math.degrees(theta[i]):.6g} deg, "
            f"RMS {result.torque_rms:.6g} N*m; power peak {result.power_peak:.6g} W, RMS {result.power_rms:.6g} W, "
            f"mean {result.mean_power:.6g} W at {result.rpm:g} rpm (frictionless contact, power balance T w = Q v)")
    if torque_limit is None:
        checks.append(information("camshaft_torque", result.torque_peak, "N*m", where_degrees(theta[i]), note + "; no torque limit given"))
    else:
        over = result.torque_peak > torque_limit  # some |torque| > the limit: the peak is (finite: as the forces)
        where = run_ends(np.abs(result.torque) > torque_limit, theta) if over else where_degrees(theta[i])
        checks.append(limited("camshaft_torque", result.torque_peak, "<=", float(torque_limit), "N*m", where, note))
    return checks


# ============================================================================================
# FATIGUE (issue 25, items 3 and 4): friction, loads, contact fatigue and life.
# The physics: camgen/friction.py, camgen/contact_life.py; here their keys, reading, stage,
# figures and checks.  Nothing runs without one of these keys (existing scenes unchanged).
# ============================================================================================
_ROLLER = {"follower": ("roller",)}
#: The guide's keys (translating followers).
GUIDE_KEYS = ("guide_length_mm", "guide_overhang_mm", "guide_friction")
#: The roller's keys (pin, inertia, bearing).
ROLLER_KEYS = ("roller_pin_friction", "roller_pin_radius_mm", "roller_inertia_kg_mm2", "roller_dynamic_load_rating_n",
               "roller_bearing", "min_bearing_life_h")
#: The contact-fatigue keys (a contact with a radius).
FATIGUE_KEYS = ("case_depth_factor", "sn_stress_mpa", "sn_cycles", "sn_exponent", "contact_design_cycles")
#: Every key of this block.
FRICTION_LIFE_KEYS = GUIDE_KEYS + ("contact_friction",) + ROLLER_KEYS + FATIGUE_KEYS


@lru_cache(maxsize=None)
def friction_life_keys() -> tuple[Key, ...]:
    """The keys of friction, loads, contact fatigue and life (appended to :func:`dynamics_keys`):
    any of them turns on the friction and life figures (with the dynamics' mass and rpm); made once."""
    from camgen.contact_life import CASE_DEPTH_FACTOR
    from camgen.friction import DEFAULT_CONTACT_FRICTION, DEFAULT_GUIDE_FRICTION, DEFAULT_PIN_FRICTION

    return (
        Key("guide_length_mm", Length(), "Translating follower: distance between the two bushings of its guide; with "
            "guide_overhang_mm it gives the bushing reactions (statics of the stem), the guide's friction torque and the "
            "guide_binding check.", _R, example=40.0, requires=_T),
        Key("guide_overhang_mm", Number("mm", 0.0, 1e5), "Translating follower: distance along the stem from the contact "
            "(roller centre, knife tip or flat face) to the nearer bushing; given with guide_length_mm.", _R, example=20.0,
            requires=_T),
        Key("guide_friction", Number("", 0.0, 1.0), "Translating follower with guide_length_mm: Coulomb friction "
            f"coefficient of the bushings (default {DEFAULT_GUIDE_FRICTION:g}, lubricated steel in bronze); the guide binds "
            "where mu (|R1| + |R2|) >= the axial force.", _R, example=0.1, requires=_T),
        Key("contact_friction", Number("", 1e-3, 1.0), "Friction coefficient at the cam contact: a translating "
            "flat face's sliding friction (its torque on the camshaft, mu F h, and its drag across the face in the guide "
            "reactions); for a roller the traction limit of the roller_slip check (default there "
            f"{DEFAULT_CONTACT_FRICTION:g}, lubricated steel on steel).", _R, example=0.1),
        Key("roller_pin_friction", Number("", 0.0, 1.0), "Roller follower with roller_pin_radius_mm: friction coefficient of "
            f"the roller on its pin (default {DEFAULT_PIN_FRICTION:g}, a plain bushed roller); torque mu F r_pin.", _R,
            example=0.1, requires=_ROLLER),
        Key("roller_pin_radius_mm", Length(), "Roller follower: radius of the roller's pin; turns on the pin friction torque "
            "(and its share of the camshaft torque) and the roller_slip check.", _R, example=3.0, requires=_ROLLER),
        Key("roller_inertia_kg_mm2", Number("kg*mm^2", 0.0, 1e9), "Roller follower: the roller's moment of inertia about its "
            "pin (default 0), the torque its angular acceleration needs in the roller_slip check.", _R, example=2.0,
            requires=_ROLLER),
        Key("roller_dynamic_load_rating_n", Number("N", 1.0, 1e9), "Roller follower: the roller bearing's basic "
            "dynamic load rating C; turns on its ISO 281 basic rating life L10 = (C / P)^p from the contact force over the "
            "turn (mean-load rule weighted by the roller's revolutions).", _R, example=8000.0, requires=_ROLLER),
        Key("roller_bearing", Choice(("roller", "ball")), "Roller follower with roller_dynamic_load_rating_n: the bearing "
            "type, for the life exponent p (roller 10/3, ball 3; default roller).", _R, example="roller", requires=_ROLLER),
        Key("min_bearing_life_h", Number("h", 0.0, 1e9, low_open=True), "Roller follower with roller_dynamic_load_rating_n: "
            "the least L10 life in hours at rpm: the bearing_life check fails below it (left out: the life is information).",
            _R, example=20000.0, requires=_ROLLER),
        Key("case_depth_factor", Number("", 1.0, 100.0), "The case depth asked for, in depths of the sub-surface maximum "
            f"shear (0.78 b; default {CASE_DEPTH_FACTOR:g}, a rule of thumb: give your heat treater's rule).", _R,
            example=2.0),
        Key("sn_stress_mpa", Number("MPa", 0.0, 1e6, low_open=True), "Contact-fatigue S-N point of the cam material: the "
            "Hertz stress it survives for sn_cycles (give sn_stress_mpa, sn_cycles, sn_exponent and contact_design_cycles "
            "together): the contact_fatigue check's allowable S (N_ref / N)^(1/m).", _R, example=1500.0),
        Key("sn_cycles", Number("cycles", 1.0, 1e15), "Cycles of the S-N point (sn_stress_mpa).", _R,
            example=1e7),
        Key("sn_exponent", Number("", 1.0, 1e3), "Exponent m of the contact-fatigue S-N curve, S^m N = const.",
            _R, example=6.6),
        Key("contact_design_cycles", Number("cycles", 1.0, 1e15), "The cam's design life in cam turns (each "
            "point of the profile is loaded once a turn), for the S-N allowable.", _R, example=1e8),
    )


@dataclass(frozen=True)
class FrictionLifeSpec:
    """The friction and life a cam asks for: the friction settings, the case-depth factor, an
    S-N curve and the cycles to hold (or None), the roller bearing's rating C (N or None), its
    type and the least life (h or None), the follower kind."""

    friction: Any
    case_depth_factor: float
    sn: Any
    design_cycles: float | None
    rating: float | None
    bearing: str
    min_life_h: float | None
    follower: str


def read_friction_life(where: str, parsed: Mapping[str, Any], given: tuple[str, ...], *, motion: str, follower: str,
                       form_closed: bool) -> FrictionLifeSpec | None:
    """The friction and life keys of a cam table (None when none is given); a key that has no
    effect for this follower is refused naming it and saying why."""
    from camgen.contact_life import CASE_DEPTH_FACTOR, SnCurve
    from camgen.followers import get_follower
    from camgen.friction import DEFAULT_GUIDE_FRICTION, DEFAULT_PIN_FRICTION, FrictionSettings

    mine = [name for name in given if name in FRICTION_LIFE_KEYS]
    if not mine:
        return None
    by_name = {k.name: k for k in friction_life_keys()}

    def refuse(name: str, valid: str, why: str) -> None:
        raise ParameterError(f"{where}.{name}", by_name[name].type.to_scene(parsed.get(name)), valid, why)

    model = get_follower(follower)
    if form_closed or model.contact == "faces":
        refuse(mine[0], "left out for a form-closed train", "friction, loads and contact life are computed for a force-closed "
               "plate cam (one contact, a spring)")
    for name in ("guide_overhang_mm", "guide_length_mm"):
        other = "guide_length_mm" if name == "guide_overhang_mm" else "guide_overhang_mm"
        if name in mine and other not in mine:
            raise ParameterError(f"{where}.{other}", None, "a length in mm", f"{name} is given: the guide's bushing reactions "
                                 "need guide_length_mm and guide_overhang_mm together")
    needs = {"guide_friction": "guide_length_mm", "roller_pin_friction": "roller_pin_radius_mm",
             "roller_bearing": "roller_dynamic_load_rating_n", "min_bearing_life_h": "roller_dynamic_load_rating_n"}
    for name, base in needs.items():
        if name in mine and base not in mine:
            refuse(name, f"given with {base}", f"{name} has no effect without {base}")
    edge = model.contact == "point" and not model.has_radius
    if edge:
        for name in (*FATIGUE_KEYS, "contact_friction"):
            if name in mine:
                refuse(name, f"left out for a {follower} follower", "a sharp knife edge has no finite contact stress and "
                       "its friction is not modelled (use a roller or a flat face)")
    if model.contact == "face" and motion != "translating" and "contact_friction" in mine:
        refuse("contact_friction", "left out for an oscillating flat face", "the flat face's friction torque is computed for "
               "a translating face")
    if follower == "roller" and "contact_friction" in mine and not ({"roller_pin_radius_mm", "roller_inertia_kg_mm2"} & set(mine)):
        refuse("contact_friction", "given with roller_pin_radius_mm or roller_inertia_kg_mm2", "on a roller it is the traction "
               "limit of the roller_slip check, which needs the pin's friction or the roller's inertia")
    sn_keys = ("sn_stress_mpa", "sn_cycles", "sn_exponent", "contact_design_cycles")
    sn_given = [name for name in sn_keys if name in mine]
    if sn_given and len(sn_given) < len(sn_keys):
        missing = next(name for name in sn_keys if name not in mine)
        raise ParameterError(f"{where}.{missing}", None, by_name[missing].type.describe(),
                             f"the S-N allowable needs {', '.join(sn_keys)} together ({', '.join(sn_given)} given)")
    get = parsed.get
    friction = renamed(where, friction_life_keys(), lambda: FrictionSettings(
        guide_length=get("guide_length_mm"), guide_overhang=get("guide_overhang_mm"),
        guide_friction=get("guide_friction", DEFAULT_GUIDE_FRICTION), contact_friction=get("contact_friction"),
        pin_friction=get("roller_pin_friction", DEFAULT_PIN_FRICTION), pin_radius=get("roller_pin_radius_mm"),
        roller_inertia=get("roller_inertia_kg_mm2", 0.0)))
    sn = SnCurve(parsed["sn_stress_mpa"], parsed["sn_cycles"], parsed["sn_exponent"]) if sn_given else None
    return FrictionLifeSpec(friction, get("case_depth_factor", CASE_DEPTH_FACTOR), sn, get("contact_design_cycles"),
                            get("roller_dynamic_load_rating_n"), get("roller_bearing", "roller"), get("min_bearing_life_h"),
                            follower)


@dataclass(frozen=True)
class FrictionLifeOutcome:
    """The friction (:class:`camgen.friction.FrictionResult`) and contact life
    (:class:`camgen.contact_life.ContactLife` or None: no contact radius) of a cam, their checks
    and figures (merged into ``figures.dynamics``)."""

    friction: Any
    life: Any
    checks: "tuple[CheckResult, ...]"
    figures: Mapping[str, Any]


def _friction_geometry(cam: "BuiltCam", kin: "Kinematics", motion: str, follower: str) -> Any:
    """The contact geometry the friction needs: from the plate's closed-form envelope data where
    the cam has it (the roller's spin from the pitch curve, a flat face's contact position),
    else (a three_arc flat face, its stem through the cam axis) the face position ``s'``."""
    from camgen.friction import FrictionGeometry, roller_spin

    data = getattr(getattr(cam, "envelope", None), "data", None)
    f = getattr(cam, "spec_follower", None)
    sigma = float(getattr(f, "sigma", 1.0))
    tau = float(getattr(f, "tau", 1.0)) if motion == "oscillating" else 0.0
    radius = float(kin.follower_radius) if math.isfinite(kin.follower_radius) else 0.0
    face = spin = rate = None
    if follower == "flat" and motion == "translating":
        face = data.face_position if data is not None and data.face_position is not None else sigma * kin.ds
    if follower == "roller" and data is not None and data.pitch_d1 is not None and data.pitch_d2 is not None:
        spin, rate = roller_spin(data.pitch_d1, data.pitch_d2, radius, sigma, tau, kin.ds)
    return FrictionGeometry(follower, motion, sigma, tau if motion == "oscillating" else 1.0, radius, face, spin, rate)


def run_friction_life(cam: "BuiltCam", result: "DynamicsResult", kin: "Kinematics", dyn: DynamicsSpec) -> FrictionLifeOutcome:
    """Friction, loads, contact fatigue and the roller bearing's life of a cam at the scene's
    speed, with their checks ("guide_binding", "roller_slip", "contact_fatigue", "bearing_life"
    where their limits apply; "case_depth", "friction_torque" as information) and figures."""
    from camgen.checks import information, limited, run_ends, where_degrees
    from camgen.contact_life import LIFE_EXPONENTS, contact_life
    from camgen.friction import analyse_friction

    spec = dyn.friction_life
    assert spec is not None  # the stage runs this block only when a key of it is given
    theta, motion = result.theta, result.train.motion
    geometry = _friction_geometry(cam, kin, motion, spec.follower)
    fr = analyse_friction(result.contact_force, result.pressure_angle, kin.ds, kin.d2s, kin.rho_cam, result.torque,
                          result.omega, geometry, spec.friction)
    checks: "list[CheckResult]" = []
    fig: dict[str, Any] = {}

    def peak(values: Any) -> tuple[float, int]:
        i = int(np.argmax(np.abs(values)))
        return float(abs(values[i])), i

    if fr.side_load is not None:
        fig["side_load_peak_N"] = peak(fr.side_load)[0]
    if fr.guide_near is not None and fr.guide_far is not None and fr.binding is not None:
        s = spec.friction
        fig.update({"guide_length_mm": s.guide_length, "guide_overhang_mm": s.guide_overhang, "guide_friction": s.guide_friction,
                    "guide_reaction_near_peak_N": peak(fr.guide_near)[0], "guide_reaction_far_peak_N": peak(fr.guide_far)[0]})
        ratio, i = peak(fr.binding)
        fig["guide_binding_ratio_peak"] = ratio
        bad = fr.binding >= 1.0
        note = (f"the guide's bushings (length {s.guide_length:g} mm, overhang {s.guide_overhang:g} mm, friction "
                f"{s.guide_friction:g}) hold up to {ratio:.6g} x the axial force at cam angle {math.degrees(theta[i]):.6g} deg "
                "(reactions from the stem's statics; Coulomb friction at both bushings locks the stem at >= 1)")
        checks.append(limited("guide_binding", ratio, "<", 1.0, "", run_ends(bad, theta) if bad.any() else where_degrees(theta[i]),
                              note))
    if fr.pin_torque is not None and fr.slip is not None:
        fig["roller_pin_torque_peak_Nmm"] = peak(fr.pin_torque)[0]
        fig["roller_pin_friction"] = spec.friction.pin_friction
        if spec.friction.pin_radius is not None:
            fig["roller_pin_radius_mm"] = spec.friction.pin_radius
        fig["roller_inertia_kg_mm2"] = spec.friction.roller_inertia
        ratio, i = peak(fr.slip)
        fig["roller_slip_ratio_peak"] = ratio
        bad = fr.slip > 1.0
        note = (f"the torque to turn the roller (pin friction and its inertia) reaches {ratio:.6g} x the traction the "
                f"contact holds (mu_c F R) at cam angle {math.degrees(theta[i]):.6g} deg; above 1 the roller skids")
        checks.append(limited("roller_slip", ratio, "<=", 1.0, "", run_ends(bad, theta) if bad.any() else where_degrees(theta[i]),
                              note))
    if fr.face_torque is not None:
        fig["face_friction_torque_peak_Nm"] = peak(fr.face_torque)[0]
    if spec.friction.contact_friction is not None:
        fig["contact_friction"] = spec.friction.contact_friction
    assert fr.friction_torque is not None and fr.total_torque is not None  # always set
    weights = result.weights
    if np.any(fr.friction_torque != 0):
        total_peak, i = peak(fr.total_torque)
        rms = float(np.sqrt(np.sum(weights * fr.total_torque**2) / (2.0 * math.pi)))
        energy = float(np.sum(weights * fr.friction_torque))
        fig.update({"friction_torque_peak_Nm": peak(fr.friction_torque)[0], "friction_energy_per_turn_J": energy,
                    "torque_with_friction_peak_Nm": total_peak, "torque_with_friction_rms_Nm": rms})
        checks.append(information("friction_torque", total_peak, "N*m", where_degrees(theta[i]),
                                  f"camshaft torque with friction: peak {total_peak:.6g} N*m, RMS {rms:.6g} N*m; the friction "
                                  f"takes {energy:.6g} J a turn (first order: Coulomb friction of the frictionless contact force)"))
    life = None
    material = dyn.material
    if material is not None and result.hertz_stress is not None:
        curvature = 1.0 / kin.rho_cam + 1.0 / kin.follower_radius
        rating = spec.rating
        exponent = LIFE_EXPONENTS[spec.bearing]
        life = contact_life(result.contact_force, result.hertz_stress, curvature, material.width, material.compliance,
                            case_depth_factor=spec.case_depth_factor, sn=spec.sn, design_cycles=spec.design_cycles,
                            roller_spin=geometry.roller_spin, weights=weights, rating=rating, exponent=exponent, rpm=result.rpm)
        i = int(np.argmax(life.shear))
        deep = int(np.argmax(life.shear_depth))
        fig.update({"hertz_half_width_peak_mm": float(np.max(life.half_width)), "subsurface_shear_peak_MPa": float(life.shear[i]),
                    "subsurface_shear_peak_deg": round(math.degrees(theta[i]), 6),
                    "subsurface_shear_depth_max_mm": float(life.shear_depth[deep]), "case_depth_mm": life.case_depth,
                    "case_depth_factor": life.case_depth_factor})
        checks.append(information("case_depth", life.case_depth, "mm", where_degrees(theta[deep]),
                                  f"sub-surface maximum shear {life.shear[i]:.6g} MPa (0.30 p_max, Johnson §4.2) at most "
                                  f"{life.shear_depth[deep]:.6g} mm deep (0.78 b); case depth asked for {life.case_depth_factor:g} "
                                  "x that depth"))
        if life.allowable is not None:
            peak_stress = float(np.max(result.hertz_stress))
            fig.update({"contact_fatigue_allowable_MPa": life.allowable, "contact_design_cycles": life.design_cycles})
            bad = result.hertz_stress > life.allowable
            j = int(np.argmax(result.hertz_stress))
            assert spec.sn is not None  # the allowable comes from it
            checks.append(limited("contact_fatigue", peak_stress, "<=", life.allowable, "MPa",
                                  run_ends(bad, theta) if bad.any() else where_degrees(theta[j]),
                                  f"allowable {life.allowable:.6g} MPa at {life.design_cycles:g} cam turns from the S-N point "
                                  f"{spec.sn.stress:g} MPa at {spec.sn.cycles:g} cycles, exponent {spec.sn.exponent:g} "
                                  "(S = S_ref (N_ref / N)^(1/m))"))
        if life.roller_revs_per_turn is not None:
            fig["roller_revs_per_turn"] = life.roller_revs_per_turn
        if life.l10_mrev is not None:
            finite = math.isfinite(life.l10_mrev)
            fig.update({"roller_dynamic_load_rating_N": rating, "bearing_life_exponent": exponent,
                        "bearing_equivalent_load_N": life.equivalent_load,
                        "bearing_L10_Mrev": life.l10_mrev if finite else None,
                        "bearing_L10_h": life.l10_hours if finite else None})
            note = (f"ISO 281 L10 = (C / P)^p = {life.l10_mrev:.6g} million revolutions, C {rating:g} N, equivalent load P "
                    f"{life.equivalent_load:.6g} N (mean-load rule over the turn, weighted by the roller's "
                    f"{life.roller_revs_per_turn:.6g} revolutions a turn), p {exponent:.6g}")
            hours = life.l10_hours if life.l10_hours is not None and math.isfinite(life.l10_hours) else None
            if spec.min_life_h is not None:
                fig["min_bearing_life_h"] = spec.min_life_h
            if spec.min_life_h is None or hours is None:  # no limit, or no load on the roller: the life is unbounded
                checks.append(information("bearing_life", hours if hours is not None else "unbounded", "h", [], note))
            else:
                checks.append(limited("bearing_life", hours, ">=", spec.min_life_h, "h", [], note))
    return FrictionLifeOutcome(fr, life, tuple(checks), fig)
