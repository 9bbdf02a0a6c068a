"""FEA volume meshes of a cam body (VTU, Gmsh MSH 2.2, Abaqus/CalculiX INP): quality elements
meshed by gmsh, graded from the profile's curvature, within the chord tolerance.

What is meshed: the section between the profile polygon (``contour.flatten(chord_tol)``: the
same vertices as the point list and the surface meshes, so within ``output.chord_tol_mm`` of
the exact profile) and the hole (bore polygon plus keyway, :func:`camgen.export.solid.bore_polygon`),
extruded to the body's thickness.  Every polygon vertex is a node; where a chord is longer than
the local element size gmsh adds nodes on it (the boundary stays the polygon).  A body with
pockets (a groove, a slot) has each pocket cut from the top face down its depth, its walls'
polygons at the same tolerance: :mod:`camgen.export.fea_pockets`.

Sizes (mm): the element size ``h`` (``output.fea_element_size_mm``; default
:func:`default_element_size`, about :data:`DEFAULT_SECTION_ELEMENTS` elements over the section)
is the largest; at a boundary vertex the size is the least of ``h``, the two chords that meet
there, and ``2 pi rho / PER_CIRCLE`` (``rho`` the profile's radius of curvature there, the bore's
radius on the hole); along each loop these sizes are limited to grow by at most
:data:`GRADING` per mm of arc (a Lipschitz envelope, so a short chord does not sit beside a
long element), and inwards gmsh's ``Extend`` field grows them by :data:`GRADING` per mm of
distance to the boundary up to ``h``.

Elements (``output.fea_elements``):

* ``"wedge"`` (default): gmsh's Frontal-Delaunay triangulation of the section (least angle
  >= 20 deg: 26-32 deg measured on the templates and the 10 m cam; a corner of the section
  sharper than that, a keyway almost as wide as the bore, limits it; the least angle is
  reported) extruded into
  ``layers = max(2, ceil(thickness / h))`` equal layers of 6-node wedges (C3D6, Gmsh prism 6,
  VTK_WEDGE 13): the wedges' angles are the triangles' and 90 deg.
* ``"tetra"``: gmsh's 3-D Delaunay (HXT) mesh of the extruded body, 4-node tetrahedra (C3D4,
  Gmsh 4, VTK_TETRA 10), the same sizes graded from every face.  No tetrahedral mesher bounds
  the dihedral angles (slivers): the least face and dihedral angles are measured and reported
  (report.json ``fea_mesh``), about 5 to 12 deg for gmsh's meshes.  Near the profile the
  tetrahedra are as small as its chords (isotropic), so they grow in number as
  ``chord_tol_mm^-1/2`` times the thickness: a coarser chord tolerance keeps them few.

Why gmsh: a maintained mesher with quality 2-D and 3-D algorithms, size fields and a Python API
(PyPI ``gmsh`` 4.11+, its own libgmsh inside; measured 4.15.2: Frontal-Delaunay sections of the
bundled templates have least angles 29-32 deg).  It is GPL-2+ while camgen is MIT, so it is an
optional extra (``pip install "camgen[fea]"``), imported only when an FEA format is written;
without it the run stops with one line naming the format and the extra.  The wheel's libgmsh
links X11/OpenGL libraries even headless (Debian: libglu1-mesa libxcursor1 libxft2 libxinerama1
libgl1; a desktop has them).  Rejected: Shewchuk's ``triangle`` (and ``meshpy``, which wraps
it and TetGen) is free only for non-commercial use; TetGen (``tetgen``) is AGPL; scipy's
Delaunay has no quality refinement; the earlier ring fill (:mod:`camgen.export.section_fill`,
still the surface meshes' section) makes long cells, not quality elements.

gmsh's state is global: each mesh runs in its own initialize/finalize, one thread, no
configuration files read, no terminal output, SIGINT left to camgen (``interruptible=False``).
Nothing is written to disk: the files are built in memory (:func:`vtu_bytes` writes the VTK XML
itself, zlib-compressed and base64-encoded).

Sizes are bounded before anything is meshed (:func:`check_caps`): the element counts are
estimated from the boundary's vertex count and sizes and the section's area (:func:`estimate`:
an upper bound, 1.7-2.3 times the meshes of the templates, checked in the tests), the file bytes
from the counts and the widest line each format prints (:func:`file_bytes`), the mesher's memory
from the counts (:data:`MESHER_BYTES`).

gmsh does not return to Python while it meshes: a Ctrl-C is acted on when it does (up to about
a minute for the largest mesh the caps allow).
"""
from __future__ import annotations

import base64
import math
import zlib
from dataclasses import dataclass, field
from types import TracebackType
from typing import TYPE_CHECKING, Any, Iterable, Literal, Sequence

import numpy as np

from camgen.body import BodySpec
from camgen.contour import Contour
from camgen.errors import CamgenError, ExportError, GeometryError, ParameterError
from camgen.export.tables import format_rows

if TYPE_CHECKING:
    from camgen.kinds.base import Pocket

__all__ = [
    "DEFAULT_SECTION_ELEMENTS", "ESTIMATE_MARGIN", "FEA_ELEMENTS", "FEA_FORMATS", "GRADING", "MAX_BOUNDARY",
    "MAX_ELEMENT_SIZE", "MAX_FILE_BYTES", "MAX_MESHER_BYTES", "MESHER_BYTES", "MIN_LAYERS", "PER_CIRCLE", "GmshSession",
    "add_polygon_loops", "tetra_figures", "tidy_tetrahedra",
    "MeshEstimate", "Section", "VolumeMesh", "check_caps", "default_element_size", "edge_range", "estimate", "fea_bytes",
    "file_bytes", "inp_text", "layer_count", "layer_levels", "loop_sizes", "mesher_memory", "msh_text", "node_table",
    "planned_load", "require_gmsh", "section_outline", "section_triangles", "size_field", "tetra_dihedral_angles",
    "tetra_mesh", "triangle_angles", "volume_mesh", "vtu_bytes", "wedge_mesh", "writer",
]

#: Largest ``output.fea_element_size_mm`` (mm).
MAX_ELEMENT_SIZE = 1e5
#: FEA element choices (``output.fea_elements``).
FEA_ELEMENTS = ("wedge", "tetra")
#: Formats written as FEA volume meshes.
FEA_FORMATS = ("vtu", "msh", "inp")
#: Element size growth per mm of distance (along a loop and inwards from the boundary).
GRADING = 0.3
#: Elements per full turn of a boundary's radius of curvature (24: 15 deg per element).
PER_CIRCLE = 24
#: About this many elements of the default size fit in the section (the boundary adds more).
DEFAULT_SECTION_ELEMENTS = 1000
#: Fewest element layers through the thickness (wedges).
MIN_LAYERS = 2

# element type per format: (Abaqus/CalculiX, Gmsh MSH type, VTK cell type, nodes)
_TYPES = {"wedge": ("C3D6", 6, 13, 6), "tetra": ("C3D4", 4, 10, 4)}


def _gmsh(fmt: str = "vtu"):
    """The gmsh module, or a one-line error naming the format and the extra."""
    try:
        import gmsh
    except (ImportError, OSError) as exc:  # OSError: libgmsh or a library it links is missing
        detail = "" if isinstance(exc, ImportError) else f"; libgmsh did not load: {exc}"
        raise ExportError(f'the "{fmt}" output (FEA volume mesh) needs gmsh: pip install "camgen[fea]" '
                          f"(gmsh, GPL-2+){detail}") from None
    return gmsh


def require_gmsh(formats) -> None:
    """Refuse, before anything is meshed, FEA formats in ``formats`` without gmsh installed."""
    wanted = [f for f in formats if f in FEA_FORMATS]
    if wanted:
        _gmsh(wanted[0])


# --------------------------------------------------------------------------------------------
# Sizes
# --------------------------------------------------------------------------------------------
def default_element_size(section_area: float) -> float:
    """Default element size (mm): ``sqrt(area / DEFAULT_SECTION_ELEMENTS)`` to 2 significant digits."""
    h = math.sqrt(max(section_area, 1e-300) / DEFAULT_SECTION_ELEMENTS)
    return float(f"{h:.2g}")


def _lipschitz_loop(sizes: np.ndarray, arc: np.ndarray, period: float, slope: float) -> np.ndarray:
    """min over j of ``sizes[j] + slope * distance(i, j)`` along a closed loop (arc length ``arc``
    of each vertex, loop length ``period``): two running minima over three laps."""
    n = sizes.size
    x = np.concatenate([arc - period, arc, arc + period])
    s = np.tile(sizes, 3)
    ahead = np.minimum.accumulate(s - slope * x) + slope * x
    behind = np.minimum.accumulate((s + slope * x)[::-1])[::-1] - slope * x
    return np.minimum(ahead, behind)[n : 2 * n]


def loop_sizes(loop: np.ndarray, h: float, curvature: np.ndarray | None = None) -> np.ndarray:
    """Element size (mm) at each vertex of a closed ``loop`` (n, 2): the least of ``h``, the two
    chords meeting there and ``2 pi / (PER_CIRCLE |curvature|)``, limited to grow by GRADING per
    mm along the loop."""
    chord = np.hypot(*(np.roll(loop, -1, axis=0) - loop).T)
    sizes = np.minimum(np.minimum(chord, np.roll(chord, 1)), h)
    if curvature is not None:
        with np.errstate(divide="ignore"):
            sizes = np.minimum(sizes, 2.0 * math.pi / (PER_CIRCLE * np.abs(curvature)))
    arc = np.concatenate([[0.0], np.cumsum(chord)[:-1]])
    return _lipschitz_loop(sizes, arc, float(chord.sum()), GRADING)


@dataclass(frozen=True)
class Section:
    """The meshed section's outline: the profile polygon and the hole polygon (or None), the
    element size at each of their vertices, the largest size ``h`` and the section's area (mm)."""

    outer: np.ndarray
    hole: np.ndarray | None
    outer_sizes: np.ndarray
    hole_sizes: np.ndarray | None
    h: float
    area: float
    walls: tuple = ()  # (layer, polygon (n, 2), sizes (n,)) of each pocket wall, in the pockets' order
    floors: tuple = ()  # the height (mm) of each pocket's floor, 0 for a pocket through the body

    def loops(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """(polygon, sizes at its vertices) of the profile, then of the hole when there is one."""
        loops = [(self.outer, self.outer_sizes)]
        if self.hole is not None:
            assert self.hole_sizes is not None  # given with the hole (section_outline)
            loops.append((self.hole, self.hole_sizes))
        return loops


def _shoelace(loop: np.ndarray) -> float:
    x, y = loop[:, 0], loop[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _contour_sizes(contour: Contour, chord_tol: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    """The polygon of ``contour`` at ``chord_tol`` and the element size at each of its vertices
    (:func:`loop_sizes`, the curvature the largest of the vertex's and its two chords' middles)."""
    params = contour.flatten_params(chord_tol)
    polygon = contour.flatten(chord_tol)
    ends = np.append(params[1:], contour.n_segments)
    middle = np.mod(0.5 * (params + ends), contour.n_segments)
    at_middle = np.abs(contour.curvature(middle))
    kappa = np.maximum(np.abs(contour.curvature(params)), np.maximum(at_middle, np.roll(at_middle, 1)))
    return polygon, loop_sizes(polygon, h, kappa)


def section_outline(contour: Contour, body: BodySpec, chord_tol: float, element_size: float | None = None,
                    pockets: "Sequence[Pocket]" = ()) -> Section:
    """The polygons and boundary sizes of the section (see the module notes), with the walls of
    ``pockets`` (each sized as the profile) and their floors' heights."""
    from camgen.export.solid import bore_polygon

    outer = contour.flatten(chord_tol)
    hole = bore_polygon(body, chord_tol)
    area = _shoelace(outer) - (_shoelace(hole) if hole is not None else 0.0)
    h = default_element_size(area) if element_size is None else float(element_size)
    outer, outer_sizes = _contour_sizes(contour, chord_tol, h)
    hole_sizes = None
    if hole is not None:
        hole_sizes = loop_sizes(hole, h, np.full(len(hole), 2.0 / body.bore_diameter))
    walls = tuple((wall.layer, *_contour_sizes(wall.contour, chord_tol, h)) for pocket in pockets for wall in pocket.walls)
    floors = tuple(max(0.0, float(body.thickness - pocket.depth)) for pocket in pockets)
    return Section(outer, hole, outer_sizes, hole_sizes, h, area, walls, floors)


# --------------------------------------------------------------------------------------------
# Estimates before meshing (the caps)
# --------------------------------------------------------------------------------------------
#: Safety factor of the element-count estimates over the integral of the size field (the tests
#: compare estimate and mesh on every template and on random cams).
ESTIMATE_MARGIN = 1.5


@dataclass(frozen=True)
class MeshEstimate:
    """Upper estimates of a volume mesh: nodes, elements, layers (wedges; 0 for tetrahedra), the
    mesher's largest element count (section triangles or tetrahedra) and the boundary nodes."""

    nodes: int
    elements: int
    layers: int
    mesher_elements: int
    boundary_nodes: int
    node_sets: int = 4  # PROFILE, BORE, BOTTOM, TOP and one per pocket wall and floor


def layer_count(thickness: float, h: float) -> int:
    """Element layers through ``thickness``: ``max(MIN_LAYERS, ceil(thickness / h))``."""
    return max(MIN_LAYERS, math.ceil(thickness / h - 1e-9))


def layer_levels(thickness: float, h: float, floors: Sequence[float] = ()) -> np.ndarray:
    """Heights (mm, ascending, 0 first and ``thickness`` last) of the layer boundaries of the
    wedges: without floors ``layer_count(thickness, h)`` equal layers; with pockets' floors
    (heights in (0, thickness); 0 for a pocket through the body adds none) every floor is a
    boundary and each interval between two neighbouring boundaries has ``ceil(length / h)``
    equal layers (at least one; the longest more until there are MIN_LAYERS)."""
    if not floors:
        layers = layer_count(thickness, h)
        return thickness * np.arange(layers + 1) / layers
    breaks = np.unique(np.concatenate([[0.0, thickness], [f for f in floors if 0.0 < f < thickness]]))
    lengths = np.diff(breaks)
    counts = np.maximum(1, np.ceil(lengths / h - 1e-9)).astype(int)
    while counts.sum() < MIN_LAYERS:
        counts[int(np.argmax(lengths / counts))] += 1
    parts = [a + (b - a) * np.arange(n) / n for a, b, n in zip(breaks[:-1], breaks[1:], counts)]
    return np.concatenate(parts + [[thickness]])


def estimate(section: Section, thickness: float, elements: str) -> MeshEstimate:
    """Upper estimates of the mesh of ``section`` (see :class:`MeshEstimate`).

    Size field ``s = min(h, s_b + g d)`` (``d`` the distance to the boundary, ``s_b`` the boundary
    size): triangles about ``int dA / (sqrt(3)/4 s^2)``, which over the band along a boundary
    chord of length ``l`` is ``l / (sqrt(3)/4 g s_b)``, plus the bulk ``A / (sqrt(3)/4 h^2)``;
    tetrahedra ``int dV / (s^3 / (6 sqrt 2))`` likewise (the size does not change through the
    thickness: top and bottom take the section's sizes): ``l T / (2 g s_b^2)`` per side-wall
    chord plus ``V / h^3``.
    """
    h, g = section.h, GRADING
    # a pocket wall lies inside the section: its band is on both sides of it (twice a boundary's)
    loops = [(loop, sizes, 1.0) for loop, sizes in section.loops()] + [(loop, sizes, 2.0) for _, loop, sizes in section.walls]
    boundary = 0.0
    band2 = 0.0  # sum of l / s_b
    band3 = 0.0  # sum of l / s_b^2
    for loop, sizes, sides in loops:
        chord = np.hypot(*(np.roll(loop, -1, axis=0) - loop).T)
        s = np.minimum(sizes, np.roll(sizes, -1))
        boundary += float(np.sum(np.maximum(1.0, np.ceil(chord / s))))
        band2 += sides * float(np.sum(chord / s))
        band3 += float(np.sum(chord / s**2))
    sets = 4 + len(section.walls) + len(section.floors)
    tri_area = math.sqrt(3.0) / 4.0
    triangles = ESTIMATE_MARGIN * (band2 / (tri_area * g) + section.area / (tri_area * h * h)) + 2.0 * boundary
    section_nodes = 0.5 * triangles + boundary
    if elements == "wedge":
        layers = len(layer_levels(thickness, h, section.floors)) - 1
        return MeshEstimate(math.ceil(section_nodes * (layers + 1)), math.ceil(triangles * layers), layers, math.ceil(triangles),
                            math.ceil(boundary), sets)
    tet_volume = 1.0 / (6.0 * math.sqrt(2.0))
    # a pocket wall's band counted over the whole thickness, as a side face's: its face (the
    # pocket's depth) and the material graded from its foot under the floor (the tests compare)
    tets = ESTIMATE_MARGIN * thickness * (band3 / (2.0 * g) + section.area / h**3) / tet_volume
    nodes = tets / 4.0 + section_nodes
    return MeshEstimate(math.ceil(nodes), math.ceil(tets), 0, math.ceil(tets), math.ceil(boundary), sets)


def _digits(count: int) -> int:
    return len(str(max(int(count), 1)))


def _coordinate_chars(significant: int) -> int:
    """Widest ``%.<significant>g`` print of a number: sign, digits, point, exponent (e-308)."""
    return significant + 7


def file_bytes(fmt: str, est: MeshEstimate, elements: str, boundary_nodes_per_set: int | None = None) -> int:
    """Upper estimate of the bytes of FEA format ``fmt`` holding ``est``'s nodes and elements."""
    k = _TYPES[elements][3]
    idn, ide = _digits(est.nodes), _digits(est.elements)
    if fmt == "inp":  # "%d, %.14g, %.14g, %.14g"; "id, n1, ..., nk"; node sets 8 ids to a line
        node_line = idn + 3 * (2 + _coordinate_chars(14)) + 1
        element_line = ide + k * (2 + idn) + 1
        # a node is in at most two sets (one face of z: BOTTOM, TOP or a floor; one side: PROFILE,
        # BORE or a wall): 3 x the nodes; each set's header line and note at most 256 characters
        sets = 3 * est.nodes * (idn + 2)
        return est.nodes * node_line + est.elements * element_line + sets + 4096 + 256 * max(0, est.node_sets - 4)
    if fmt == "msh":  # "%d %.17g %.17g %.17g"; "id type 2 1 1 n1 ... nk"
        node_line = idn + 3 * (1 + _coordinate_chars(17)) + 1
        element_line = ide + 8 + k * (1 + idn) + 1
        return est.nodes * node_line + est.elements * element_line + 4096
    if fmt == "vtu":  # float64 points, int64 connectivity and offsets, uint8 types; zlib then base64
        raw = 24 * est.nodes + 8 * k * est.elements + 8 * est.elements + est.elements
        return math.ceil(4 * (raw * 1.001 + 64) / 3) + 8192
    raise ParameterError("format", fmt, f"one of {', '.join(FEA_FORMATS)}")


def mesher_memory(est: MeshEstimate, elements: str) -> int:
    """Upper estimate (bytes) of gmsh's memory for the mesh of ``est`` (measured per element:
    :data:`MESHER_BYTES`)."""
    return MESHER_BYTES[elements] * est.mesher_elements


#: Resident memory per element of the mesher's count (bytes): measured 2.0 kB per section
#: triangle of a wedge mesh (gmsh and the extrusion; default template at 1e-5 mm) and 1.6 kB per
#: tetrahedron (motion_law template at 1e-3 mm), with a margin; applied to the estimated counts.
MESHER_BYTES = {"wedge": 2500, "tetra": 2000}


# --------------------------------------------------------------------------------------------
# Meshing
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class VolumeMesh:
    """A volume mesh (mm).

    Attributes
    ----------
    nodes : array (n, 3)
        Node coordinates.
    cells : array (m, 4 or 6)
        0-based node indices, positive Jacobian in all three formats: a wedge's bottom triangle
        counter-clockwise seen from +z, then the nodes above them; a tetrahedron's first three
        nodes counter-clockwise seen from the fourth.
    elements : str
        "wedge" or "tetra".
    node_sets : dict of str to array
        0-based node indices: ``PROFILE`` (on the profile), ``BORE`` (on the bore and keyway;
        only with a bore), ``BOTTOM`` (z = 0) and ``TOP`` (z = thickness); a body with pockets
        also one per wall (named by its layer: the nodes on the wall's face, from the floor to
        the top) and one per pocket floor (``<POCKET>_FLOOR``, the nodes on the floor; none for
        a pocket through the body).
    thickness : float
        Extrusion height, mm.
    layers : int
        Element layers through the thickness (wedges); 0 for tetrahedra.
    element_size : float
        The largest element size asked for, mm.
    """

    nodes: np.ndarray
    cells: np.ndarray
    elements: str
    node_sets: dict
    thickness: float
    layers: int
    element_size: float
    figures: dict = field(default_factory=dict)
    set_notes: dict = field(default_factory=dict)  # what a pocket's node set holds (the .inp's header)


class GmshSession:
    """One gmsh session: initialized quiet, single-threaded, without configuration files, SIGINT
    left alone; finalized on exit.  gmsh's errors become :class:`GeometryError`."""

    def __init__(self, what: str) -> None:
        self.what = what

    def __enter__(self):
        gmsh = _gmsh()
        gmsh.initialize(readConfigFiles=False, interruptible=False)
        self.gmsh = gmsh
        for name, value in (("General.Terminal", 0), ("General.NumThreads", 1), ("General.SaveSession", 0),
                            ("Mesh.RandomSeed", 1), ("Mesh.MeshSizeExtendFromBoundary", 0),
                            ("Mesh.MeshSizeFromCurvature", 0)):
            gmsh.option.setNumber(name, value)
        gmsh.option.setString("General.ErrorFileName", "")
        gmsh.model.add("camgen")
        return gmsh

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> Literal[False]:
        self.gmsh.finalize()
        if exc is not None and isinstance(exc, Exception) and not isinstance(exc, CamgenError):
            raise GeometryError(f"{self.what}: gmsh could not mesh it ({' '.join(str(exc).split())})") from None
        return False


def _outline_geometry(gmsh, section: Section) -> tuple[int, list[int], list[int]]:
    """Points (one per polygon vertex, with its size), lines, curve loops and the plane surface
    of the section in gmsh's built-in kernel: the surface tag, the profile's and the hole's
    line tags.  gmsh's API adds one point or line per call: a loop over the vertices."""
    geo = gmsh.model.geo
    loops, lines = add_polygon_loops(geo, section.loops())
    if section.hole is None:
        lines.append([])
    surface = geo.addPlaneSurface(loops)
    return surface, lines[0], lines[1]


def add_polygon_loops(geo: Any, polygons: "Iterable[tuple[np.ndarray, np.ndarray]]") -> tuple[list[int], list[list[int]]]:
    """Each (polygon (n, 2) mm, sizes (n,) mm) in gmsh's built-in kernel ``geo``: a point per
    vertex with its size, a line per edge, a curve loop; the point and line tags run from 1
    in polygon order.  Returns the curve loops' tags and each polygon's line tags.  gmsh's API
    adds one point or line per call: a loop over the vertices."""
    loops: list[int] = []
    lines: list[list[int]] = []
    first = 1
    for loop, sizes in polygons:
        n = len(loop)
        tags = list(range(first, first + n))
        for tag, (x, y), size in zip(tags, loop.tolist(), sizes.tolist()):
            geo.addPoint(x, y, 0.0, size, tag)
        for i, tag in enumerate(tags):
            geo.addLine(tag, tags[(i + 1) % n], tag)
        loops.append(geo.addCurveLoop(tags))
        lines.append(tags)
        first += n
    return loops, lines


def size_field(gmsh, section: Section, curves: list[int], surfaces: list[int]) -> None:
    """Background size: gmsh's Extend field (the boundary mesh's sizes grown by GRADING per mm
    up to h)."""
    field = gmsh.model.mesh.field
    tag = field.add("Extend")
    if curves:
        field.setNumbers(tag, "CurvesList", curves)
    if surfaces:
        field.setNumbers(tag, "SurfacesList", surfaces)
    field.setNumber(tag, "DistMax", section.h / GRADING)
    field.setNumber(tag, "SizeMax", section.h)
    field.setNumber(tag, "Power", 1)
    field.setAsBackgroundMesh(tag)
    gmsh.option.setNumber("Mesh.MeshSizeMax", section.h)


def node_table(gmsh) -> tuple[np.ndarray, np.ndarray]:
    """All nodes: tags (n,) and coordinates (n, 3); and a tag -> row lookup array."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    tags = np.asarray(tags, dtype=np.int64)
    lookup = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    lookup[tags] = np.arange(tags.size)
    return np.asarray(coords, dtype=float).reshape(-1, 3), lookup


def section_triangles(section: Section) -> tuple[np.ndarray, np.ndarray]:
    """gmsh's Frontal-Delaunay triangulation of ``section``: points (k, 2) (the profile polygon's
    vertices first, then the hole's, both as given, then the others) and counter-clockwise
    triangles (t, 3)."""
    with GmshSession("the section") as gmsh:
        surface, outer_lines, hole_lines = _outline_geometry(gmsh, section)
        gmsh.model.geo.synchronize()
        size_field(gmsh, section, outer_lines + hole_lines, [])
        gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay
        gmsh.model.mesh.generate(2)
        coords, lookup = node_table(gmsh)
        _, node_tags = gmsh.model.mesh.getElementsByType(2)  # 3-node triangles
        triangles = lookup[np.asarray(node_tags, dtype=np.int64).reshape(-1, 3)]
    polygon = section.outer if section.hole is None else np.concatenate([section.outer, section.hole])
    k = len(polygon)
    # the polygon's vertices are gmsh's points 1..k, whose nodes gmsh numbers first
    if len(coords) < k or not np.array_equal(coords[:k, :2], polygon):
        raise GeometryError("gmsh did not keep the profile polygon's vertices as its first nodes")
    points = coords[:, :2].copy()
    p = points[triangles]
    twice = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])
    if np.all(twice < 0):
        triangles = triangles[:, ::-1]
    elif not np.all(twice > 0):
        raise GeometryError("gmsh's section triangulation has triangles of both orientations or none of any area")
    return points, np.ascontiguousarray(triangles)


def triangle_angles(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Angles (t, 3), deg, of triangles (t, 3) over ``points`` (n, 2 or 3)."""
    p = points[triangles]
    out = []
    for i in range(3):
        u, v = p[:, (i + 1) % 3] - p[:, i], p[:, (i + 2) % 3] - p[:, i]
        if u.shape[1] == 2:
            sine = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        else:
            sine = np.linalg.norm(np.cross(u, v), axis=1)
        out.append(np.degrees(np.arctan2(sine, np.einsum("ij,ij->i", u, v))))
    return np.stack(out, axis=1)


def tetra_dihedral_angles(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """The six dihedral angles (m, 6), deg, of tetrahedra (m, 4) over ``points`` (n, 3)."""
    p = points[tets]
    normals = []
    for a, b, c, d in ((0, 1, 2, 3), (0, 1, 3, 2), (0, 2, 3, 1), (1, 2, 3, 0)):  # face abc, opposite d
        n = np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a])
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        n *= -np.sign(np.einsum("ij,ij->i", n, p[:, d] - p[:, a]))[:, None]  # outward
        normals.append(n)
    pairs = [(i, j) for i in range(4) for j in range(i + 1, 4)]
    return np.stack([180.0 - np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", normals[i], normals[j]), -1.0, 1.0)))
                     for i, j in pairs], axis=1)


def _boundary_loops(points: np.ndarray, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (indices) of the outer boundary loop and of the hole loops of a triangulation."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    edges = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    key = np.sort(edges, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    boundary = edges[counts[inverse.ravel()] == 1]  # directed: the outer loop runs CCW, holes CW
    n = len(points)
    graph = coo_matrix((np.ones(len(boundary)), (boundary[:, 0], boundary[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    a, b = points[boundary[:, 0]], points[boundary[:, 1]]
    loop_area = np.bincount(label[boundary[:, 0]], weights=0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]), minlength=label.max() + 1)
    on_boundary = np.unique(boundary)
    outer = loop_area[label[on_boundary]] > 0
    return on_boundary[outer], on_boundary[~outer]


def edge_range(points: np.ndarray, cells: np.ndarray) -> tuple[float, float]:
    """The shortest and the longest edge (mm) of ``cells`` (m, k) over ``points`` (n, 3)."""
    p = points[cells]
    k = cells.shape[1]
    pairs = [(i, j) for i in range(k) for j in range(i + 1, k)]
    lengths = np.stack([np.linalg.norm(p[:, i] - p[:, j], axis=1) for i, j in pairs], axis=1)
    return float(lengths.min()), float(lengths.max())


def wedge_mesh(section: Section, thickness: float) -> VolumeMesh:
    """The section's triangles (:func:`section_triangles`) extruded into
    ``layer_count(thickness, h)`` layers of wedges."""
    points, triangles = section_triangles(section)
    least = float(triangle_angles(points, triangles).min())
    layers = layer_count(thickness, section.h)
    k = len(points)
    z = thickness * np.arange(layers + 1) / layers
    nodes = np.concatenate([np.repeat(points[None], layers + 1, axis=0), np.broadcast_to(z[:, None, None], (layers + 1, k, 1))],
                           axis=2).reshape(-1, 3)
    base = (np.arange(layers) * k)[:, None, None] + triangles[None]
    cells = np.concatenate([base, base + k], axis=2).reshape(-1, 6).astype(np.int64)
    outer, holes = _boundary_loops(points, triangles)
    column = (np.arange(layers + 1) * k)[:, None]
    sets = {"PROFILE": (column + outer[None]).ravel()}
    if section.hole is not None:
        sets["BORE"] = (column + holes[None]).ravel()
    sets["BOTTOM"] = np.arange(k)
    sets["TOP"] = layers * k + np.arange(k)
    shortest, longest = edge_range(points, triangles)
    figures = {"elements": "wedge", "element_count": int(len(cells)), "node_count": int(len(nodes)), "layers": layers,
               "element_size_mm": section.h, "least_triangle_angle_deg": least,
               "shortest_edge_mm": min(shortest, thickness / layers), "longest_edge_mm": max(longest, thickness / layers),
               "layer_height_mm": thickness / layers}
    return VolumeMesh(nodes, cells, "wedge", sets, thickness, layers, section.h, figures)


def tetra_mesh(section: Section, thickness: float) -> VolumeMesh:
    """gmsh's tetrahedral mesh (HXT) of the section extruded to ``thickness``, sizes graded
    from every face."""
    with GmshSession("the body") as gmsh:
        surface, outer_lines, hole_lines = _outline_geometry(gmsh, section)
        out = gmsh.model.geo.extrude([(2, surface)], 0.0, 0.0, thickness)
        gmsh.model.geo.synchronize()
        # extrude returns the top face, the volume, then one side face per line of the
        # surface's boundary, in the order of its loops
        sides = [tag for dim, tag in out[2:]]
        if len(sides) != len(outer_lines) + len(hole_lines) or out[1][0] != 3:
            raise GeometryError("gmsh's extrusion of the section has not one side face per outline edge")
        profile_faces, bore_faces = sides[: len(outer_lines)], sides[len(outer_lines) :]
        groups = {"PROFILE": gmsh.model.addPhysicalGroup(2, profile_faces)}
        if bore_faces:
            groups["BORE"] = gmsh.model.addPhysicalGroup(2, bore_faces)
        gmsh.model.addPhysicalGroup(3, [out[1][1]])
        size_field(gmsh, section, outer_lines + hole_lines, [surface, out[0][1]] + sides)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.Algorithm3D", 10)  # HXT
        gmsh.option.setNumber("Mesh.Optimize", 1)
        gmsh.model.mesh.generate(3)
        coords, lookup = node_table(gmsh)
        _, node_tags = gmsh.model.mesh.getElementsByType(4)  # 4-node tetrahedra
        tets = lookup[np.asarray(node_tags, dtype=np.int64).reshape(-1, 4)]
        sets = {}
        for name, group in groups.items():
            tags, _ = gmsh.model.mesh.getNodesForPhysicalGroup(2, group)
            sets[name] = np.unique(lookup[np.asarray(tags, dtype=np.int64)])
    coords, tets, sets = tidy_tetrahedra(coords, tets, sets)
    z = coords[:, 2]
    sets["BOTTOM"] = np.flatnonzero(z == 0.0)
    sets["TOP"] = np.flatnonzero(z == thickness)
    sets = {name: sets[name] for name in ("PROFILE", "BORE", "BOTTOM", "TOP") if name in sets}
    return VolumeMesh(coords, np.ascontiguousarray(tets, dtype=np.int64), "tetra", sets, thickness, 0, section.h,
                      tetra_figures(coords, tets, section.h))


def tidy_tetrahedra(coords: np.ndarray, tets: np.ndarray, sets: dict[str, np.ndarray]
                    ) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """gmsh's tetrahedra (t, 4) over nodes ``coords`` (n, 3) and node ``sets``: the nodes of no
    tetrahedron dropped (none expected) and every tetrahedron turned to a positive volume;
    :class:`GeometryError` for one of no volume."""
    used = np.unique(tets)
    if used.size != len(coords):
        remap = np.full(len(coords), -1, dtype=np.int64)
        remap[used] = np.arange(used.size)
        coords, tets = coords[used], remap[tets]
        sets = {name: remap[members][remap[members] >= 0] for name, members in sets.items()}
    p = coords[tets]
    volume = np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))
    if np.any(volume == 0):
        raise GeometryError("gmsh's tetrahedral mesh has a tetrahedron of no volume")
    return coords, np.where((volume < 0)[:, None], tets[:, [1, 0, 2, 3]], tets), sets


def tetra_figures(coords: np.ndarray, tets: np.ndarray, h: float) -> dict[str, Any]:
    """report.json's figures of a tetrahedral mesh: counts, element size ``h`` (mm), least
    face and dihedral angles (deg), shortest and longest edge (mm)."""
    faces = np.concatenate([tets[:, [0, 1, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 3]], tets[:, [1, 2, 3]]])
    shortest, longest = edge_range(coords, tets)
    return {"elements": "tetra", "element_count": int(len(tets)), "node_count": int(len(coords)), "layers": 0,
            "element_size_mm": h, "least_triangle_angle_deg": float(triangle_angles(coords, faces).min()),
            "least_dihedral_angle_deg": float(tetra_dihedral_angles(coords, tets).min()),
            "shortest_edge_mm": shortest, "longest_edge_mm": longest}


def volume_mesh(contour: Contour, body: BodySpec, chord_tol: float, element_size: float | None = None,
                elements: str = "wedge") -> VolumeMesh:
    """The FEA mesh of the cam body (see the module notes); a body with pockets:
    :func:`camgen.export.fea_pockets.body_volume_mesh`."""
    if elements not in FEA_ELEMENTS:
        raise ParameterError("fea_elements", elements, f"one of {', '.join(FEA_ELEMENTS)}")
    section = section_outline(contour, body, chord_tol, element_size)
    if elements == "wedge":
        return wedge_mesh(section, body.thickness)
    return tetra_mesh(section, body.thickness)


# --------------------------------------------------------------------------------------------
# Writers (in memory)
# --------------------------------------------------------------------------------------------
def _numbers(values: np.ndarray) -> np.ndarray:
    """Coordinates cleaned for printing: sub-picometre values (and -0.0) become 0.0."""
    return np.where(np.abs(values) < 1e-9, 0.0, values) + 0.0


def _id_lines(ids: np.ndarray, per_line: int = 8) -> str:
    """1-based ids, ``per_line`` to a line, comma separated (Abaqus data lines)."""
    ids = np.asarray(ids, dtype=np.int64) + 1
    full = len(ids) // per_line * per_line
    text = format_rows(ids[:full].reshape(-1, per_line), ", ".join(["%d"] * per_line)) if full else ""
    if full < len(ids):
        text += ", ".join(map(str, ids[full:].tolist())) + "\n"
    return text


_SET_NOTES = {"PROFILE": "PROFILE (on the profile)", "BORE": "BORE (bore and keyway)", "BOTTOM": "BOTTOM (z = 0)",
              "TOP": "TOP (z = thickness)"}


def _describe(mesh: VolumeMesh) -> str:
    name = _TYPES[mesh.elements][0]
    through = f"in {mesh.layers} layers through" if mesh.elements == "wedge" else "through"
    return f"{len(mesh.cells)} {name} {'wedges' if mesh.elements == 'wedge' else 'tetrahedra'} {through} {mesh.thickness:g} mm"


def inp_text(mesh: VolumeMesh, name: str = "camgen") -> str:
    """Abaqus/CalculiX input (mesh part): ``*NODE`` (set NALL), ``*ELEMENT`` (C3D6 or C3D4, set
    CAM) and the node sets of ``mesh.node_sets`` (BORE only with a bore); units mm.

    Coordinates are printed with 14 significant digits ("%.14g"): at most 20 characters, the
    field width CalculiX reads a coordinate with.  Add material, section, steps and loads in
    the analysis deck (``*INCLUDE, INPUT=<cam>.inp``).
    """
    element = _TYPES[mesh.elements][0]
    ids = np.arange(1, len(mesh.nodes) + 1)
    nodes = format_rows(np.column_stack([ids, _numbers(mesh.nodes)]), "%d, %.14g, %.14g, %.14g")
    k = mesh.cells.shape[1]
    elements = format_rows(np.column_stack([np.arange(1, len(mesh.cells) + 1), mesh.cells + 1]), ", ".join(["%d"] * (k + 1)))
    notes = {**_SET_NOTES, **mesh.set_notes}
    sets = ", ".join(["NALL"] + [notes[s] for s in mesh.node_sets])
    parts = [
        "*HEADING\n",
        f"camgen cam '{name}': {_describe(mesh)}; element size {mesh.element_size:g} mm; units mm\n",
        f"** node sets: {sets}\n",
        "** element set: CAM; add *MATERIAL, *SOLID SECTION, ELSET=CAM and the steps in the analysis deck\n",
        "*NODE, NSET=NALL\n", nodes,
        f"*ELEMENT, TYPE={element}, ELSET=CAM\n", elements,
    ]
    for set_name, members in mesh.node_sets.items():
        parts += [f"*NSET, NSET={set_name}\n", _id_lines(np.sort(members))]
    return "".join(parts)


def msh_text(mesh: VolumeMesh, name: str = "camgen") -> str:
    """Gmsh MSH 2.2 (ASCII) of the elements (type 6: 6-node prism, or 4: 4-node tetrahedron),
    physical volume 1 named after the cam; coordinates with 17 significant digits (exact round
    trip)."""
    kind = _TYPES[mesh.elements][1]
    nodes = format_rows(np.column_stack([np.arange(1, len(mesh.nodes) + 1), _numbers(mesh.nodes)]), "%d %.17g %.17g %.17g")
    m = len(mesh.cells)
    # id, type, 2 tags (physical 1, elementary 1), the nodes
    rows = np.column_stack([np.arange(1, m + 1), np.full(m, kind), np.full(m, 2), np.ones(m, int), np.ones(m, int), mesh.cells + 1])
    elements = format_rows(rows, " ".join(["%d"] * rows.shape[1]))
    label = name.replace('"', "'")
    return (
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
        f'$PhysicalNames\n1\n3 1 "{label}"\n$EndPhysicalNames\n'
        f"$Nodes\n{len(mesh.nodes)}\n{nodes}$EndNodes\n"
        f"$Elements\n{m}\n{elements}$EndElements\n"
    )


def _vtk_array(values: np.ndarray, vtk_type: str, name: str, components: int = 1) -> str:
    """One inline binary DataArray: a zlib block (header: UInt64 block count 1, block size,
    last block size, compressed size), header and data base64-encoded separately (VTK XML
    "binary" format with vtkZLibDataCompressor)."""
    raw = np.ascontiguousarray(values).tobytes()
    packed = zlib.compress(raw, 6)
    header = np.array([1, len(raw), len(raw), len(packed)], dtype="<u8").tobytes()
    data = base64.b64encode(header).decode("ascii") + base64.b64encode(packed).decode("ascii")
    extra = f' NumberOfComponents="{components}"' if components > 1 else ""
    return f'<DataArray type="{vtk_type}" Name="{name}"{extra} format="binary">\n{data}\n</DataArray>\n'


def vtu_bytes(mesh: VolumeMesh, name: str = "camgen") -> bytes:
    """VTK XML unstructured grid (VTK_WEDGE or VTK_TETRA cells; little-endian, zlib-compressed,
    base64 inline), written in memory; coordinates as the other formats print them (sub-picometre
    values 0)."""
    from xml.sax.saxutils import escape

    cell_type = _TYPES[mesh.elements][2]
    k = mesh.cells.shape[1]
    m = len(mesh.cells)
    # VTK_WEDGE takes Gmsh's prism order: VTK's own volume and Jacobian (Verdict) are positive
    # with the base counter-clockwise seen from the top (vtkWedge: the normal of (0, 2, 1) points
    # away from (3, 4, 5)); meshio reverses the base on reading, after an older vtkWedge text
    cells = mesh.cells
    text = (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64" '
        'compressor="vtkZLibDataCompressor">\n'
        f"<!-- camgen cam '{escape(name).replace('--', '- -')}': {_describe(mesh)}; units mm -->\n"
        "<UnstructuredGrid>\n"
        f'<Piece NumberOfPoints="{len(mesh.nodes)}" NumberOfCells="{m}">\n'
        "<Points>\n" + _vtk_array(_numbers(mesh.nodes).astype("<f8"), "Float64", "Points", 3) + "</Points>\n"
        "<Cells>\n"
        + _vtk_array(cells.astype("<i8"), "Int64", "connectivity")
        + _vtk_array((k * np.arange(1, m + 1)).astype("<i8"), "Int64", "offsets")
        + _vtk_array(np.full(m, cell_type, dtype="u1"), "UInt8", "types")
        + "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n"
    )
    return text.encode("ascii")


def fea_bytes(mesh: VolumeMesh, fmt: str, name: str = "camgen") -> bytes:
    """File content of ``mesh`` in FEA format ``fmt`` (vtu, msh, inp)."""
    if fmt == "inp":
        return inp_text(mesh, name).encode("ascii")
    if fmt == "msh":
        return msh_text(mesh, name).encode("ascii")
    if fmt == "vtu":
        return vtu_bytes(mesh, name)
    raise ParameterError("format", fmt, f"one of {', '.join(FEA_FORMATS)}")


# --------------------------------------------------------------------------------------------
# Caps, checked before anything is meshed
# --------------------------------------------------------------------------------------------
#: Largest FEA file (bytes), each of vtu, msh, inp, as estimated from the counts (:func:`file_bytes`).
MAX_FILE_BYTES = 100_000_000
#: Largest memory (bytes) gmsh may take for one mesh, as estimated from the counts
#: (:func:`mesher_memory`).
MAX_MESHER_BYTES = 1_000_000_000
#: Most boundary vertices looked at: beyond it no FEA mesh fits the caps (every boundary vertex
#: is a node of at least MIN_LAYERS + 1 layers, 40 bytes or more each).
MAX_BOUNDARY = MAX_FILE_BYTES // (40 * (MIN_LAYERS + 1))


def _boundary_count(contour: Contour, body: BodySpec, chord_tol: float, pockets: "Sequence[Pocket]" = ()) -> int:
    """Vertices of the profile polygon, the pockets' walls and the bore circle at ``chord_tol``
    (no points made)."""
    count = sum(int(seg.flatten_params(chord_tol).size) for seg in contour.segments)
    if pockets:
        from camgen.export.pocket import wall_flat_count

        count += wall_flat_count(pockets, chord_tol)
    if body.bore_diameter > 0:
        r = body.bore_diameter / 2.0
        count += max(8, math.ceil(2.0 * math.pi / (2.0 * math.acos(max(-1.0, 1.0 - chord_tol / r)))))
    return count


def planned_load(contour: Contour, body: BodySpec, formats, chord_tol: float, element_size: float | None,
                 elements: str, pockets: "Sequence[Pocket]" = ()) -> tuple[dict[str, int], int] | None:
    """Estimated bytes of each planned FEA file and gmsh's memory (bytes); None where the
    boundary (the pockets' walls counted) alone has more than :data:`MAX_BOUNDARY` vertices."""
    if _boundary_count(contour, body, chord_tol, pockets) > MAX_BOUNDARY:
        return None
    section = section_outline(contour, body, chord_tol, element_size, pockets)
    est = estimate(section, body.thickness, elements)
    return {f: file_bytes(f, est, elements) for f in formats if f in FEA_FORMATS}, mesher_memory(est, elements)


def _fits(contour: Contour, body: BodySpec, formats, chord_tol: float, element_size: float | None, elements: str,
          pockets: "Sequence[Pocket]" = ()) -> bool:
    load = planned_load(contour, body, formats, chord_tol, element_size, elements, pockets)
    return load is not None and max(load[0].values(), default=0) <= MAX_FILE_BYTES and load[1] <= MAX_MESHER_BYTES


def _least(fits, low: float, high: float) -> float | None:
    """The least value in (``low``, ``high``] with 2 significant digits for which ``fits`` holds
    (``fits(low)`` is false); None if not even ``high`` fits.  ``fits`` is monotone (a larger
    value gives fewer elements): bisection in log scale to 1 %, rounded up
    (:func:`camgen.errors.ceil_significant`) and checked."""
    from camgen.errors import ceil_significant

    if not fits(high):
        return None
    while high > 1.01 * low:
        middle = math.sqrt(low * high)
        if fits(middle):
            high = middle
        else:
            low = middle
    value = ceil_significant(high, 2)
    while not fits(value):  # not expected (fits is monotone): step on
        value = ceil_significant(value * 1.05, 2)
    return value


def check_caps(contour: Contour, body: BodySpec, formats, chord_tol: float, element_size: float | None, elements: str,
               cam: str, max_chord_tol: float, pockets: "Sequence[Pocket]" = ()) -> None:
    """Refuse FEA formats whose files could exceed :data:`MAX_FILE_BYTES` or whose meshing could
    take more than :data:`MAX_MESHER_BYTES` (the walls of ``pockets`` counted with the profile),
    naming the least ``output.chord_tol_mm`` that fits (or, where none does, the least
    ``output.fea_element_size_mm``)."""
    if not any(f in FEA_FORMATS for f in formats):
        return
    if _fits(contour, body, formats, chord_tol, element_size, elements, pockets):
        return
    load = planned_load(contour, body, formats, chord_tol, element_size, elements, pockets)
    if load is None:
        why = (f"its boundary would have {_boundary_count(contour, body, chord_tol, pockets)} vertices, more than the "
               f"{MAX_BOUNDARY} an FEA file may hold")
    else:
        sizes, memory = load
        worst = max(sizes, key=lambda name: sizes[name])
        why = (f"its {worst} file could reach {sizes[worst] / 1e6:.4g} MB (at most {MAX_FILE_BYTES / 1e6:g} MB) and meshing "
               f"{memory / 1e6:.4g} MB of memory (at most {MAX_MESHER_BYTES / 1e6:g} MB)")
    least = _least(lambda tol: _fits(contour, body, formats, tol, element_size, elements, pockets), chord_tol, max_chord_tol)
    if least is not None:
        raise ParameterError("output.chord_tol_mm", chord_tol, f">= {least:.2g} mm for cam '{cam}' with {', '.join(f for f in formats if f in FEA_FORMATS)}",
                             f"at {chord_tol:g} mm {why}")
    h = element_size if element_size is not None else default_element_size(contour.area)
    size = _least(lambda value: _fits(contour, body, formats, chord_tol, value, elements, pockets), h, MAX_ELEMENT_SIZE)
    if size is not None:
        raise ParameterError("output.fea_element_size_mm", element_size, f">= {size:.2g} mm for cam '{cam}' at chord_tol_mm = {chord_tol:g}",
                             f"at element size {h:g} mm {why}, at any chord_tol_mm up to {max_chord_tol:g} mm")
    # neither key alone: the least size at the largest tolerance (then the error names the tolerance)
    size = _least(lambda value: _fits(contour, body, formats, max_chord_tol, value, elements, pockets), h, MAX_ELEMENT_SIZE)
    planned = [f for f in formats if f in FEA_FORMATS]
    if size is not None:
        raise ParameterError("output.fea_element_size_mm", element_size, f">= {size:.2g} mm for cam '{cam}', with a larger chord_tol_mm",
                             f"at element size {h:g} mm {why}; no element size fits at chord_tol_mm = {chord_tol:g}")
    raise ParameterError("output.formats", planned, f"formats without {', '.join(FEA_FORMATS)} for cam '{cam}'", why)


# --------------------------------------------------------------------------------------------
# The registered writer (camgen.outputs: vtu, msh, inp)
# --------------------------------------------------------------------------------------------
def writer(cam, run, fmt: str) -> bytes:
    """File content of FEA format ``fmt`` of ``cam`` (a :class:`camgen.results.CamResult`): its
    FEA mesh, made once by the pipeline's ``fea`` stage for every FEA format of the cam (its
    figures are report.json's ``cams.<cam>.figures.fea_mesh``)."""
    if cam.fea is None:
        raise GeometryError(f"the FEA mesh of cam '{cam.name}' was not made")
    return fea_bytes(cam.fea, fmt, cam.name)
