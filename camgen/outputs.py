"""The output registry: one line per format, naming its file, writer and the stages it needs.

Adding a format: a writer function (in :mod:`camgen.writers` or a module of its own:
``(cam, run, fmt) -> content`` per cam, ``(report) -> content`` per run) and one
:class:`OutputFormat` line in :data:`OUTPUTS`.  Everything the planner, the scene reader and the
pipeline need to know about a format is in its line (its stages, scope, whether it is
manufacturing, always written, needs the cam speed or the machining settings, flattens the
profile); none of them names a format.  The per-cam stages the formats need are registered in
:data:`CAM_STAGES`.  The pipeline plans the stages from the requested formats and runs only those.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

from camgen.schema import Angle, Choice, ChoiceList, Count, Flag, Key, Number
from camgen.export.drawing_spec import DrawingSpec, drawing_keys

#: Stages: ``mesh`` (the extruded solid), ``analysis`` (ride simulations, fits, sweeps: report
#: figures beyond the checks), ``plots`` (the data report.html draws).
MESH = frozenset({"mesh"})
#: ``fea``: the FEA volume mesh (gmsh), made once per cam for the vtu, msh and inp files.
FEA = frozenset({"fea"})
ANALYSIS = frozenset({"analysis"})


@dataclass(frozen=True)
class OutputFormat:
    """A registered output.

    Attributes
    ----------
    name : the format's name in ``output.formats`` and ``--only``.
    files : file name pattern (``{cam}`` is the cam's name).
    description : one line for the key reference.
    writer : ``"module:function"``; None for files a kind or mechanism job makes in its stages.
    stages : the stages it needs besides synthesis and checks.
    manufacturing : withheld for a cam that cannot be made as designed (undercut, gouge, wall).
    scope : ``"cam"`` (a file per cam), ``"run"`` (one file per run), ``"kind"`` / ``"job"``
        (files a kind's or a mechanism job's stages made).
    implied : written whenever the scene has something for it, without being listed in
        ``output.formats`` (``--only`` still filters it).
    always : written by every run, ``--only`` or not (the report); the run's other files are
        listed in it, so it is written first.
    needs_rpm : why the format needs the cam speed (``rpm``), or "" (a cam without one is refused).
    machining : the format is G-code: the run then checks the ``[machining]`` settings against
        the chord tolerance and holds the cams' concave radii to the tool.
    flattens : the file holds the whole profile flattened at the chord tolerance (the point-count
        cap of :func:`camgen.planning.check_flat_size` applies; the surface meshes have theirs).
    keys : the ``[output]`` keys that change this format only (with other formats that list
        them): given without one of their formats in ``output.formats``, they are refused.
    """

    name: str
    files: str
    description: str
    writer: str | None
    stages: frozenset[str] = frozenset()
    manufacturing: bool = True
    scope: str = "cam"
    implied: bool = False
    always: bool = False
    needs_rpm: str = ""
    machining: bool = False
    flattens: bool = False
    keys: tuple[str, ...] = ()


#: The FEA meshes' keys (every FEA format takes them).
_FEA_KEYS = ("fea_element_size_mm", "fea_elements")
#: The drawing's keys (its SVG and PDF take them) and the inspection table's (the drawing shows it too).
_INSPECTION_KEYS = ("inspection_step_deg", "inspection_roller_radius_mm")
_DRAWING_KEYS = ("drawing_scale", "drawing_sheet", "drawing_material", "drawing_tolerance_mm") + _INSPECTION_KEYS

_FORMATS = (
    OutputFormat("dxf", "{cam}.dxf", "2-D drawing of what is cut: PROFILE (exact ARCs, B-splines or biarcs), BORE, KEYWAY layers "
                 "(with output.dxf_construction: PITCH, CENTER, ZERO too); R2010, mm (R12: output.dxf_version)", "camgen.writers:dxf",
                 keys=("dxf_splines", "dxf_construction", "dxf_version")),
    OutputFormat("points", "{cam}_points.csv", "XY point list of the profile at the chord tolerance", "camgen.writers:points",
                 flattens=True),
    OutputFormat("lift", "{cam}_lift.csv", "polar lift table of the profile: polar angle on the cam -> radius, lift above the base radius",
                 "camgen.writers:lift", keys=("lift_step_deg",)),
    OutputFormat("follower", "{cam}_follower.csv", "follower inspection table at the cam's rpm: cam angle, time, lift, velocity, "
                 "acceleration, jerk (needs rpm)", "camgen.writers:follower", manufacturing=False,
                 needs_rpm="tabulates the follower motion at the cam speed"),
    OutputFormat("stl", "{cam}.stl", "binary STL of the extruded body", "camgen.writers:mesh", MESH),
    OutputFormat("stl_ascii", "{cam}_ascii.stl", "ASCII STL of the extruded body", "camgen.writers:mesh", MESH),
    OutputFormat("3mf", "{cam}.3mf", "3MF mesh of the body (units mm)", "camgen.writers:mesh", MESH),
    OutputFormat("obj", "{cam}.obj", "Wavefront OBJ mesh of the body", "camgen.writers:mesh", MESH),
    OutputFormat("ply", "{cam}.ply", "binary PLY mesh of the body", "camgen.writers:mesh", MESH),
    OutputFormat("vtu", "{cam}.vtu", "VTK unstructured grid of the body, pockets cut (FEA: wedges or tetrahedra meshed by gmsh); "
                 "needs the fea extra (gmsh)", "camgen.export.fea:writer", FEA, keys=_FEA_KEYS),
    OutputFormat("msh", "{cam}.msh", "Gmsh 2.2 mesh of the body, pockets cut (FEA: wedges or tetrahedra); needs the fea extra (gmsh)",
                 "camgen.export.fea:writer", FEA, keys=_FEA_KEYS),
    OutputFormat("inp", "{cam}.inp", "Abaqus/CalculiX input mesh of the body (FEA: C3D6 or C3D4, node sets PROFILE, BORE with a "
                 "bore, BOTTOM, TOP, and with pockets one per wall named by its layer and one per floor, e.g. GROOVE_FLOOR); needs "
                 "the fea extra (gmsh)", "camgen.export.fea:writer", FEA, keys=_FEA_KEYS),
    OutputFormat("step", "{cam}.step", "exact solid (circles and B-splines), AP214, mm (AP242: output.step_schema); needs the step "
                 "extra (cadquery-ocp-novtk)", "camgen.writers:step", keys=("step_schema",)),
    OutputFormat("ngc", "{cam}.ngc", "RS274/NGC G-code milling the outside profile and pockets (LinuxCNC or GRBL), in mm or inches (machining.units); a barrel cam's groove on a rotary A axis (LinuxCNC)", "camgen.writers:gcode",
                 machining=True),
    OutputFormat("html", "report.html", "the design-check report with plots, one self-contained page",
                 "camgen.writers:html", frozenset({"analysis", "plots"}), manufacturing=False, scope="run"),
    OutputFormat("json", "report.json", "the machine-readable report: figures and checks of every cam and mechanism (always written)",
                 "camgen.writers:json_report", ANALYSIS, manufacturing=False, scope="run", implied=True, always=True),
    OutputFormat("ride", "{cam}_ride.csv", "trajectory cams: the simulated ride on the cam as made", None, ANALYSIS, manufacturing=False,
                 scope="kind", implied=True),
    OutputFormat("legs", "leg_path_alpha_<deg>.csv", "horse leg: the leg end point's path per inclination", None, manufacturing=False,
                 scope="job", implied=True),
    # -- the manufacturing drawing and its inspection table (issue 27 item 4: camgen/export/drawing*.py) --
    OutputFormat("drawing", "{cam}_drawing.svg", "dimensioned manufacturing drawing of a disk cam (plate, groove: both walls, "
                 "conjugate, constant breadth: its breadth), a linear cam's plate or a barrel cam (side view, groove or rib developed at the mean radius) at output.drawing_scale: profile, base circle, bore, keyway, zero mark, "
                 "rotation arrow, inspection table, scale bar, title block; SVG in mm",
                 "camgen.export.drawing_writers:drawing_svg", keys=_DRAWING_KEYS),
    OutputFormat("drawing_pdf", "{cam}_drawing.pdf", "the manufacturing drawing as PDF, one page printing at the stated scale; needs "
                 "the drawing extra (fpdf2)", "camgen.export.drawing_writers:drawing_pdf", keys=_DRAWING_KEYS),
    OutputFormat("inspection", "{cam}_inspection.csv", "inspection table of a disk cam (a groove cam's: a plug of the groove's "
                 "width; a linear cam's: lift against x; a barrel cam's: the groove's or rib's axial position against cam angle): per cam-angle step, the distance from the axis of a checking roller's centre resting on the profile", "camgen.export.drawing_writers:inspection",
                 keys=_INSPECTION_KEYS),
    # --- issue 27 item 5 (formats): SVG for laser cutters, IGES ---
    OutputFormat("svg", "{cam}.svg", "what is cut for laser cutters: profile, bore and keyway, pocket walls as stroked paths of exact "
                 "arcs (A) and lines, mm (width, height and viewBox; y flipped: SVG y = -y)", "camgen.export.svg:writer"),
    OutputFormat("iges", "{cam}.igs", "the STEP file's exact solid as IGES 5.3 (B-rep solid, entity 186), mm; needs the step extra",
                 "camgen.export.iges:writer"),
    # --- end issue 27 item 5 ---
)

#: format name -> OutputFormat
OUTPUTS: dict[str, OutputFormat] = {f.name: f for f in _FORMATS}
#: formats a scene lists in ``output.formats`` (the implied ones are always on)
SELECTABLE = tuple(f.name for f in _FORMATS if not f.implied)
MESH_FORMATS = tuple(f.name for f in _FORMATS if "mesh" in f.stages)
#: formats written by every run (the report)
ALWAYS = tuple(f.name for f in _FORMATS if f.always)
#: the G-code formats (they need the [machining] settings)
MACHINING_FORMATS = tuple(f.name for f in _FORMATS if f.machining)


@dataclass(frozen=True)
class CamStage:
    """A stage run on every cam that can be made, after the checks and the mechanism jobs, when a
    planned output needs it (its name in :attr:`OutputFormat.stages`).

    ``runner``: ``"module:function"``, ``(cam, output spec, progress) -> cam`` (a
    :class:`camgen.results.CamResult` with the stage's result, or the failure that stopped it)."""

    name: str
    runner: str


#: The per-cam stages, in the order they run.
CAM_STAGES = (
    CamStage("mesh", "camgen.pipeline:mesh_stage"),
    CamStage("fea", "camgen.pipeline:fea_stage"),
)


#: Keys removed from ``[output]``: name -> what replaced it (a scene that sets one is refused naming it).
REMOVED_OUTPUT_KEYS = {
    "dxf_pitch": "output.dxf_construction = true (the DXF's PITCH, CENTER and ZERO layers; off by default: the DXF holds only "
                 "what is cut)",
}

#: Smallest ``output.fea_element_size_mm`` (mm): a thousandth of the smallest cam (base radius
#: 1e-3 mm); the size caps refuse a size too small for the cam at hand, naming the least that fits.
MIN_FEA_ELEMENT_SIZE = 1e-6

#: Largest ``output.chord_tol_mm`` (mm).
MAX_CHORD_TOL = 1.0
#: The FEA volume-mesh formats (``output.fea_*`` keys need one of them).
FEA_FORMATS = tuple(f.name for f in _FORMATS if "fea" in f.stages)


@dataclass(frozen=True)
class OutputSpec:
    """What a run writes and how: formats, chord tolerance (mm) of every flattened output, DXF
    spline form, construction layers, lift-table step (rad), FEA element size (mm; None: derived
    from the section, :func:`camgen.export.fea.default_element_size`) and element type."""

    formats: tuple[str, ...] = ("dxf", "points")
    chord_tol: float = 1e-3
    dxf_splines: str = "biarc"
    dxf_construction: bool = False
    lift_step: float = math.radians(1.0)
    fea_element_size: float | None = None
    fea_elements: str = "wedge"
    drawing: DrawingSpec = DrawingSpec()  # the drawing and inspection table (camgen.export.drawing_spec)
    dxf_version: str = "R2010"
    step_schema: str = "AP214"


@lru_cache(maxsize=None)
def output_keys() -> tuple[Key, ...]:
    """Keys of the ``[output]`` table (defaults owned by :class:`OutputSpec`); made once (constants
    only: every scene reads its ``[output]`` table through the same frozen keys)."""
    d = OutputSpec()
    return (
        Key("formats", ChoiceList(SELECTABLE), "Files to write per cam (report.json is always written; ride and leg files whenever "
            "the scene has them).", ("files",), default=list(d.formats)),
        Key("chord_tol_mm", Number("mm", 1e-7, MAX_CHORD_TOL), "Largest distance between a flattened output (point list, DXF biarcs, "
            "meshes, G-code) and the exact profile.", ("tolerance",), default=d.chord_tol),
        Key("dxf_splines", Choice(("biarc", "bspline")), "How the DXF writes spline segments: ARCs and LINEs within chord_tol_mm "
            "(every reader takes them), or exact clamped B-spline SPLINEs (for CAD).", ("dxf",), default=d.dxf_splines),
        Key("dxf_construction", Flag(), "Add construction layers to the DXF: PITCH (the follower-centre path of roller "
            "followers), CENTER (a cross on the rotation axis) and ZERO (disk cams: cam angle 0 and the direction of rotation). "
            "Off: the DXF holds only what is cut (PROFILE, BORE, KEYWAY), so programs that import the whole file cut the part.",
            ("dxf",), default=d.dxf_construction),
        Key("lift_step_deg", Angle(0.01, 10.0), "Polar-angle step of the lift table (<cam>_lift.csv).", ("tables",),
            default=math.degrees(d.lift_step)),
        Key("fea_element_size_mm", Number("mm", MIN_FEA_ELEMENT_SIZE, 1e5), "Largest element size of the FEA meshes (vtu, msh, "
            "inp); near the profile and bore the elements are smaller: at most 1/24 of the local radius of curvature and the "
            "chords at chord_tol_mm, growing by 0.3 mm per mm inwards (default: sqrt(section area / 1000), 2 digits).",
            ("fea",)),
        Key("fea_elements", Choice(("wedge", "tetra")), "Elements of the FEA meshes: 6-node wedges (the section's triangles, "
            "least angle >= 20 deg, in layers of about the element size through the thickness) or 4-node tetrahedra (gmsh's "
            "3-D mesh, sizes graded the same way from every face).", ("fea",), default=d.fea_elements),
        *drawing_keys(),
        # --- issue 27 item 5 (formats) ---
        Key("dxf_version", Choice(("R2010", "R12")), "DXF version of the dxf file: R2010, or R12 (AC1009) for legacy CAM programs: "
            "LINE, ARC, CIRCLE and POLYLINE only, spline segments as ARCs and LINEs within chord_tol_mm (R12 has no SPLINE: "
            'needs dxf_splines = "biarc"), units and spline tolerance stated in comments.', ("dxf",), default=d.dxf_version),
        Key("step_schema", Choice(("AP214", "AP242")), "Schema of the STEP file: AP214 (automotive design) or AP242 (managed "
            "model-based 3-D engineering); the same solid.", ("step",), default=d.step_schema),
    )


@lru_cache(maxsize=None)
def machining_keys() -> tuple[Key, ...]:
    """Keys of the ``[machining]`` table (defaults owned by :class:`camgen.export.gcode.MachiningSpec`);
    made once (constants only)."""
    from camgen.export.entry_settings import ENTRIES, MAX_RAMP_ANGLE_DEG
    from camgen.export.gcode import DIALECTS, DIRECTIONS, SPLINE_MODES, MachiningSpec
    from camgen.export.gcode_spec import LEAD_STYLES, MIN_LEAD_RADIUS, UNITS
    from camgen.export.wire_edm_spec import wire_edm_keys
    from camgen.export.fanuc_settings import DEFAULT_PROGRAM_NUMBER, DEFAULT_TOOL_NUMBER, MAX_PROGRAM_NUMBER, MAX_RADIUS_REGISTER, MAX_TOOL_NUMBER
    from camgen.export.bore_settings import BORE_OPERATIONS, MILLING_DIALECTS as MILLING
    from camgen.export.gcode_bore import MIN_BORE_TOOL
    from camgen.kinds.base import field_default

    def d(name: str):
        return field_default(MachiningSpec, name)

    return (
        Key("tool_diameter_mm", Number("mm", 0.0, 1000.0, low_open=True), "Diameter of the end mill; its radius is also the "
            "machinability check's limit on concave radii. A pocket (a groove cam's groove) is cut in one pass along its pitch curve "
            "by a tool of its width, in two wall passes with the slot cleared by a smaller one; a wider tool is refused. A barrel cam's "
            "groove needs a tool of its width (roller diameter + clearance).", ("gcode", "report"), default=d("tool_diameter")),
        Key("step_down_mm", Number("mm", 0.0, 1000.0, low_open=True), "Largest depth of cut per pass (a pocket: per level, each entered by a ramp along the path).", ("gcode",), default=d("step_down")),
        Key("safe_z_mm", Number("mm", 0.0, 1000.0, low_open=True), "Clearance height above the stock top (Z0) for rapid moves.",
            ("gcode",), default=d("safe_z")),
        Key("feed_mm_per_min", Number("mm/min", 0.0, 1e6, low_open=True), "Cutting feed.", ("gcode",), default=d("feed"), attr="feed"),
        Key("plunge_feed_mm_per_min", Number("mm/min", 0.0, 1e6, low_open=True), "Feed of the way down to each pass depth (the "
            "helix or ramp of entry, or the plunge).", ("gcode",), default=d("plunge_feed"), attr="plunge_feed"),
        # --- the outline's passes (camgen.export.gcode_entry, camgen.export.gcode_passes) ---
        Key("entry", Choice(ENTRIES), "How the tool goes down to each pass depth of the outline, from the floor of the pass "
            "before (Z0 for the first), outside the part: helix (whole turns of radius half the tool radius, its axis outward of the "
            "lead-in's start), ramp (straight ramps to and fro along the lead line, lead_mm long, at least the tool diameter) or "
            "plunge (a straight feed down); the header states it. Default: the helix, or a ramp where the helix of this tool would "
            "need more than 200 turns to descend step_down_mm at ramp_angle_deg (a very small tool), or the plunge where the ramp "
            "would too; a helix or ramp given that needs more is refused.", ("gcode",)),
        Key("ramp_angle_deg", Angle(0.0, MAX_RAMP_ANGLE_DEG, low_open=True), "Steepest descent of the helix or ramp entry "
            "(at the tool centre); refused where the tool would need more than 200 turns (ramps) for one step_down_mm.",
            ("gcode",), default=math.degrees(d("ramp_angle")), attr="ramp_angle"),
        Key("stock_allowance_mm", Number("mm", 0.0, 100.0), "Roughing allowance: the step-down passes cut the profile grown by "
            "it, then one finishing pass at full depth cuts the profile (0: no finishing pass); refused where a concave radius "
            "would close up.", ("gcode",), default=d("stock_allowance"), attr="stock_allowance"),
        Key("holding_tabs", Count(0, 100), "Holding tabs left by the outline's passes below their top (0: none; not with "
            "wire_edm, which has its own tab): evenly spaced along the tool path, the lead midway between two, the tool rising "
            "over each by Z moves only (the XY path unchanged, so with cutter compensation too); the header lists them (cam "
            "angle, width, height) and says to cut them free. As many as fit: each tab's width, a tool radius on both sides and a "
            "tool diameter of full cut between two tabs along the tool path.", ("gcode",), default=d("holding_tabs")),
        Key("holding_tab_width_mm", Number("mm", 0.0, 1000.0, low_open=True), "Narrowest width of each holding tab: the tool "
            "stays at the tab's top along this plus the tool diameter of its path (default: the tool diameter; only with "
            "holding_tabs > 0).", ("gcode",), attr="holding_tab_width"),
        Key("holding_tab_height_mm", Number("mm", 0.0, 1000.0, low_open=True), "Height of the holding tabs above the stock "
            "bottom, below the stock thickness (default: 1 mm, at most half the stock; only with holding_tabs > 0).", ("gcode",),
            attr="holding_tab_height"),
        Key("spindle_rpm", Number("rev/min", 0.0, 2e5, low_open=True), "Spindle speed.", ("gcode",), default=d("spindle_rpm")),
        Key("direction", Choice(DIRECTIONS), "Climb (clockwise round the outside, spindle M3) or conventional milling; in a groove climb "
            "runs the outer wall counter-clockwise and the inner wall clockwise.", ("gcode",),
            default=d("direction")),
        Key("dialect", Choice(DIALECTS), "Controller: LinuxCNC (G64 blending, cutter compensation), GRBL, fanuc: Fanuc/Haas and "
            "the ISO modes of Okuma and Mazak (% framing, O number, T M06 and G43 H, G41/G42 D on the leads' G1 blocks, M30), or wire_edm: "
            "an ISO wire-EDM program of the outline (the wire keys below; the milling keys refused).", ("gcode",),
            default=d("dialect")),
        Key("cutter_compensation", Flag(), "Program the profile itself with G41.1/G42.1 (LinuxCNC) or G41/G42 D, D holding the tool "
            "radius (fanuc) instead of the tool-centre path (fanuc: the tool-centre path with G41/G42 D for the wear only, D "
            "holding 0) (refused for a cam with pockets: their passes are tool-centre paths).",
            ("gcode",), default=d("cutter_compensation")),
        Key("lead_mm", Number("mm", 0.0, 1000.0, low_open=True), "Length of the straight lead-in and lead-out moves (default: tool "
            "radius + 3 mm): the tangent lines themselves with lead_style = \"line\", the straight moves before and after the lead "
            "arcs with \"arc\" (cutter compensation is switched on and off on them).", ("gcode",)),
        Key("lead_style", Choice(LEAD_STYLES), "Lead-in and lead-out: arc = a straight move along the outward normal, then a tangent "
            "quarter arc into the tool path at the start point (the tool centre's arc centred outside the part; with cutter "
            "compensation the programmed arc's radius is lead_radius_mm + tool radius) and the mirror arc and straight move out; "
            "line = straight along the tangent in and out.", ("gcode",), default=d("lead_style")),
        Key("lead_radius_mm", Number("mm", MIN_LEAD_RADIUS, 1000.0), "Radius of the tool centre's lead arcs (default: tool radius "
            "+ 3 mm; at least 0.1 mm, so that no printed lead arc can be read as a full circle). Fanuc: a wear value in the D "
            "register must stay below it (the tool runs inside the lead arcs; the program's header states the wear the leads take).", ("gcode",), requires={"lead_style": ("arc",)}),
        Key("breakthrough_mm", Number("mm", 0.0, 100.0), "How far the last pass goes below the stock bottom (Z = -thickness), so "
            "no skin or burr is left.", ("gcode",), default=d("breakthrough")),
        Key("spline_mode", Choice(SPLINE_MODES), "Spline segments as G2/G3 biarcs or G1 chords, within chord_tol_mm.", ("gcode",),
            default=d("spline_mode")),
        Key("decimals", Count(3, 6), "Decimal places of the coordinates in the program, in its units (mm or inches); their "
            "rounding must stay within a quarter of chord_tol_mm (a coarser value is refused naming the least). Default: 4 in mm; "
            "in inches the least that keeps that budget (6 with the default chord_tol_mm).", ("gcode",)),
        Key("units", Choice(UNITS), 'Units of the program: "mm" (G21) or "inch" (G20: every coordinate, I/J, Z, safe Z and '
            'register value in inches, feeds in in/min with 2 decimals; the header gives the tolerance in both units). The scene '
            'keys stay in mm. Plate cams (milling and wire EDM) and a barrel cam\'s groove or rib (X, Y, Z in inches, A in '
            'degrees, the inverse-time feeds unchanged).', ("gcode",), default=d("units")),
        # --- fanuc dialect (camgen.export.fanuc_settings) ---
        Key("program_number", Count(1, MAX_PROGRAM_NUMBER), f"The Fanuc program's O number (default {DEFAULT_PROGRAM_NUMBER}).",
            ("gcode",), requires={"dialect": ("fanuc",)}),
        Key("tool_number", Count(1, MAX_TOOL_NUMBER), f"The Fanuc program's tool: T<n> M06 and its length offset G43 H<n> "
            f"(default {DEFAULT_TOOL_NUMBER}).", ("gcode",), requires={"dialect": ("fanuc",)}),
        Key("radius_register", Count(1, MAX_RADIUS_REGISTER), "The D register of the Fanuc program's G41/G42, holding a radius: the "
            "tool radius with cutter_compensation, else 0 (the wear only); the header says which (default: tool_number).", ("gcode",),
            requires={"dialect": ("fanuc",)}),
        # --- the bore and keyway (camgen.export.gcode_bore) ---
        Key("bore_operation", Choice(BORE_OPERATIONS), "The cam's shaft bore: helix (milling dialects) = milled first, while the "
            "stock holds the part, by helical interpolation (tool-centre circles stepped out by <= half the tool so no core is left, "
            "helix pitch <= step_down_mm, a full circle at the bottom) and the keyway slotted with the same tool where it fits (its "
            "inner corners left at the tool radius); drill (linuxcnc, fanuc) = G98 G83 peck drilling at the axis, pecks of step_down_mm, with a "
            "drill of the bore's diameter (118 deg point, through: its full diameter reaches the last pass's depth; its own tool, "
            "bore_tool_number), the keyway left to another operation; wire (wire_edm) = bore and keyway cut first as an inner contour with the outline's "
            "cuts and registers, from a start hole at the axis, the slug held by a tab of tab_width_mm until the last cut's stop; none = a "
            "header note that bore and keyway are left to another operation (default: wire for wire_edm; helix when "
            "bore_tool_diameter_mm is given, else none).", ("gcode",)),
        Key("bore_tool_diameter_mm", Number("mm", MIN_BORE_TOOL, 1000.0), "End mill of the bore and keyway, helix only (default: the "
            "outline's tool, no tool change); at most the bore diameter - 0.2 mm; a tool wider than the keyway leaves it to another "
            "operation (the header says so).", ("gcode",), requires={"dialect": MILLING}),
        Key("bore_tool_number", Count(1, MAX_TOOL_NUMBER), "Tool number of the bore tool (T<n> M6 and G43 H<n>, then the outline's "
            f"tool T<tool_number> again; default: tool_number + 1, tool_number being {DEFAULT_TOOL_NUMBER} unless a fanuc program "
            "sets it); needs bore_tool_diameter_mm or bore_operation = \"drill\" (GRBL: M0 stops to change the tool).", ("gcode",),
            requires={"dialect": ("linuxcnc", "fanuc")}),
    ) + wire_edm_keys()  # wire EDM (camgen.export.wire_edm_spec)
