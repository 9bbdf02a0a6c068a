"""STEP (AP214, mm) of a barrel (cylindrical) cam through OpenCASCADE (OCP): the cylinder less the
bore, less the groove, one solid.

* **The walls** are bicubic B-spline surfaces ``S(psi, r)`` over the cam angle's turn
  (``theta = -sigma psi``, so that the polar angle grows with ``psi``; closed in ``psi``) and the
  radius, from slightly inside the root to slightly outside the rim
  (:data:`OVERLAP` of the depth, at most 1 mm, so that the booleans below cut across them): the
  tensor-product cubic spline interpolating the exact contact points
  (:meth:`BarrelGroove.wall`) on a grid uniform in both, periodic in ``psi`` (written as a clamped
  B-spline: the same polynomial pieces) and not-a-knot in ``r``.  The grid is doubled until, at
  the middle of every grid edge and cell, the surface is within half the stated tolerance of the
  exact wall, measured axially (:func:`camgen.export.barrel_solid.axial_deviation`: the point's own
  radius and polar angle, the cam angle there solved by Newton's method).  The tolerance is the
  groove's ``fit_tol`` (``fit_tol_mm``), stated in the file's FILE_DESCRIPTION.
* **The groove** is the tube between the two wall surfaces, each cut into patches of at most
  :data:`FACE_SPANS` knot spans along the turn (one face each: OCCT's default volume integration,
  FreeCAD's, is then exact), closed at its inner and outer radius by ruled B-spline surfaces (the
  straight lines between the walls' edge curves, outside the body), sewn into one solid; the part of it inside the root radius is cut away by the exact root
  cylinder (so the floor is the cylinder ``r = R_i``), then the rest is cut from the cylinder of
  the rim radius less the bore (exact cylinders and planes).
* OCCT's checker (BRepCheck_Analyzer) must find the result valid and one solid; anything OCCT
  refuses is a :class:`GeometryError` naming the cam (a failed export check), never an OCCT
  exception.

Writing, units, schema and the fixed header (time stamp, names) are
:mod:`camgen.export.step`'s.  A rib's solid (:mod:`camgen.export.barrel_rib_step`) is made by
the same steps: its faces' tube (:func:`tube_solid`), checked (:func:`inside_ends`,
:func:`one_valid_solid`) and written (:func:`solid_step_bytes`) by this module.
"""
from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any

import numpy as np

from camgen.errors import ExportError, GeometryError

__all__ = ["FACE_SPANS", "MAX_GRID", "MAX_ROWS", "OVERLAP", "SEW_TOL", "barrel_step_bytes", "build_solid", "cut_shape", "groove_solid",
           "inside_ends", "one_valid_solid", "solid_step_bytes", "tube_solid", "wall_surface"]

#: How far (as a fraction of the groove depth, at most 1 mm) the wall surfaces reach inside the
#: root and outside the rim: the booleans then cut across them, never along an edge.
OVERLAP = 0.1
#: Most grid points along the turn and across the radius of a wall surface (each doubling of the
#: grid is checked against them first: a bound on the work and the file).
MAX_GRID = 8192
MAX_ROWS = 257
#: Most knot spans along the turn of one wall face (each face its own B-spline patch): OCCT's
#: default mass properties (FreeCAD's volume) integrate a face with one Gauss rule over its
#: parameter range, so the template's walls of 500 spans in one face came out 1e-2 off in volume;
#: faces of 64, 16 and 4 spans gave 5e-6, 2.5e-7 and 1e-9 (the test holds it to 1e-8).
FACE_SPANS = 4
#: Tolerance (mm) for sewing the groove's four faces: their shared edges are the same curves (the
#: same poles), so anything above rounding does.
SEW_TOL = 1e-6


def _ocp() -> None:
    """ExportError unless the OpenCASCADE bindings load (the ``step`` extra)."""
    try:
        import OCP  # noqa: F401
    except ModuleNotFoundError as exc:  # pragma: no cover - depends on the install
        if (exc.name or "OCP").split(".")[0] != "OCP":
            raise ExportError(f"the OpenCASCADE bindings (OCP) are installed but did not load: {exc}") from None
        raise ExportError('STEP export needs OpenCASCADE bindings: pip install ".[step]" (cadquery-ocp-novtk)') from None
    except (ImportError, OSError) as exc:  # a library they link did not load
        raise ExportError(f"the OpenCASCADE bindings (OCP) are installed but did not load: {exc}") from None


def _clamped_periodic(psi: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The periodic cubic spline interpolating ``values`` (N, ...) at ``psi`` (N, uniform over one
    turn, rad) as a clamped B-spline on ``[0, 2 pi]``: knots and poles (N + 3, ...)."""
    from scipy.interpolate import make_interp_spline, make_lsq_spline

    nodes = np.append(psi, 2.0 * math.pi)
    data = np.concatenate([values, values[:1]])
    periodic = make_interp_spline(nodes, data, k=3, bc_type="periodic", axis=0)
    knots = np.concatenate([[0.0] * 3, nodes, [2.0 * math.pi] * 3])
    # the same pieces on the clamped knots: a least-squares fit to samples of the spline reproduces
    # it (it lies in the clamped space), to rounding
    sample = np.linspace(0.0, 2.0 * math.pi, 4 * len(nodes) + 1)
    clamped = make_lsq_spline(sample, periodic(sample), knots, k=3, axis=0)
    poles = np.array(clamped.c)
    poles[-1] = poles[0]  # the seam: both ends are the value at psi = 0
    return knots, poles


def wall_surface(groove: Any, side: int, count: int, r_lo: float, r_hi: float, rows: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Knots along the turn, knots along the radius and poles (nu, nv, 3) of the bicubic B-spline
    interpolating wall ``side`` on ``count`` cam angles x ``rows`` radii in ``[r_lo, r_hi]``."""
    from scipy.interpolate import make_interp_spline

    psi = 2.0 * math.pi * np.arange(count) / count
    r = np.linspace(r_lo, r_hi, rows)
    pp, rr = np.meshgrid(psi, r, indexing="ij")
    phi, z = groove.wall(side, rr, -groove.layout.sigma * pp)
    points = np.stack([rr * np.cos(phi), rr * np.sin(phi), np.asarray(z, dtype=np.float64)], axis=-1)  # (count, rows, 3)
    u_knots, along_u = _clamped_periodic(psi, points)
    across = make_interp_spline(r, along_u, k=3, axis=1)  # not-a-knot in r
    return u_knots, np.asarray(across.t), np.moveaxis(np.asarray(across.c), 0, 1)


def _evaluate(u_knots: np.ndarray, v_knots: np.ndarray, poles: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The B-spline surface at parameters ``u`` (a), ``v`` (b): points (a, b, 3)."""
    from scipy.interpolate import BSpline

    along_v = BSpline(v_knots, np.moveaxis(poles, 1, 0), 3)(v)  # (b, nu, 3)
    return BSpline(u_knots, np.moveaxis(along_v, 1, 0), 3)(u)  # (a, b, 3)


def _fit(groove: Any, tol: float, r_lo: float, r_hi: float, cam: str) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Both walls' B-splines (:func:`wall_surface`, upper then lower) on the coarsest common doubled
    grid whose edge and cell midpoints lie within ``tol / 2`` of the exact walls, axially (module
    notes)."""
    from camgen.export.barrel_solid import axial_deviation

    rim = float(groove.rim_radius)
    count = max(64, 2 ** math.ceil(math.log2(2.0 * math.pi * rim / 2.0)))  # a point per 2 mm on the rim to start
    rows = 5
    while count <= MAX_GRID and rows <= MAX_ROWS:
        walls = [wall_surface(groove, side, count, r_lo, r_hi, rows) for side in (1, -1)]
        psi = 2.0 * math.pi * np.arange(count) / count
        r = np.linspace(r_lo, r_hi, rows)
        psi_mid, r_mid = psi + math.pi / count, 0.5 * (r[:-1] + r[1:])
        # the deviation at the middle of the edges along the turn, across it, and of the cells
        along, across, cells = (max(float(np.max(axial_deviation(groove, side, _evaluate(*wall, u, v),
                                                                 np.broadcast_to(u[:, None], (len(u), len(v))))))
                                    for side, wall in zip((1, -1), walls))
                                for u, v in ((psi_mid, r), (psi, r_mid), (psi_mid, r_mid)))
        if max(along, across, cells) <= 0.5 * tol:
            return walls
        if along > 0.5 * tol or (cells > 0.5 * tol and along >= across):
            count *= 2
        if across > 0.5 * tol or (cells > 0.5 * tol and across > along):
            rows = 2 * rows - 1
    raise GeometryError(f"cam '{cam}': the barrel's walls need more than {MAX_GRID} points per turn or {MAX_ROWS} across the "
                        f"groove to come within fit_tol_mm = {tol:g}: use a larger fit_tol_mm")


def _surface(u_knots: np.ndarray, v_knots: np.ndarray, poles: np.ndarray, v_degree: int = 3) -> Any:
    """OCCT's Geom_BSplineSurface (degree 3 along the turn, ``v_degree`` across) of clamped knot
    vectors and poles (nu, nv, 3)."""
    from OCP.collections import Array1_double, Array1_int, Array2_gp_Pnt
    from OCP.Geom import Geom_BSplineSurface
    from OCP.gp import gp_Pnt

    def knots(flat: np.ndarray) -> tuple[Any, Any]:
        values, counts = np.unique(flat, return_counts=True)
        kn, mu = Array1_double(1, len(values)), Array1_int(1, len(values))
        for i, (k, m) in enumerate(zip(values, counts), 1):
            kn.SetValue(i, float(k))
            mu.SetValue(i, int(m))
        return kn, mu

    nu, nv = poles.shape[:2]
    net = Array2_gp_Pnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            x, y, z = poles[i, j]
            net.SetValue(i + 1, j + 1, gp_Pnt(float(x), float(y), float(z)))
    uk, um = knots(u_knots)
    vk, vm = knots(v_knots)
    return Geom_BSplineSurface(net, uk, vk, um, vm, 3, v_degree)


def tube_solid(groove: Any, tol: float, cam: str) -> Any:
    """The tube between the surfaces ``groove.wall(+1, ...)`` above and ``groove.wall(-1, ...)``
    below (module notes: a groove's walls, or a rib's faces, :class:`~camgen.synthesis.barrel.BarrelRib`)
    over the radii from :data:`OVERLAP` inside the root to as far outside the rim, the surfaces
    within ``tol`` mm of the exact ones, closed by ruled surfaces at both ends, sewn and made a
    solid."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeSolid, BRepBuilderAPI_Sewing
    from OCP.BRepLib import BRepLib
    from OCP.GeomConvert import GeomConvert
    from OCP.TopAbs import TopAbs_SHELL
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    root, rim = float(groove.root_radius), float(groove.rim_radius)
    reach = min(1.0, OVERLAP * (rim - root))
    upper, lower = _fit(groove, tol, root - reach, rim + reach, cam)
    sewing = BRepBuilderAPI_Sewing(SEW_TOL)
    lin = np.array([0.0, 0.0, 1.0, 1.0])
    # both walls share the turn's knots and the radial grid; the poles of the edge rows are the
    # edge curves' poles, so a ruled surface joins them exactly
    surfaces = [_surface(*upper), _surface(*lower)]
    for edge in (0, -1):
        poles = np.stack([lower[2][:, edge], upper[2][:, edge]], axis=1)
        surfaces.append(_surface(upper[0], lin, poles, v_degree=1))
    knots = np.unique(upper[0])  # the turn's knots: wall faces of at most FACE_SPANS spans each (module notes)
    cuts = knots[np.unique(np.append(np.arange(0, len(knots) - 1, FACE_SPANS), len(knots) - 1))]
    patches = [GeomConvert.SplitBSplineSurface_s(wall, float(u0), float(u1), True, 1e-12)
               for wall in surfaces[:2] for u0, u1 in zip(cuts[:-1], cuts[1:])]
    for surface in patches + surfaces[2:]:
        face = BRepBuilderAPI_MakeFace(surface, SEW_TOL)
        if not face.IsDone():
            raise GeometryError(f"cam '{cam}': OpenCASCADE cannot make a face of the barrel's groove ({face.Error()})")
        sewing.Add(face.Face())
    sewing.Perform()
    explorer = TopExp_Explorer(sewing.SewedShape(), TopAbs_SHELL)
    if not explorer.More():
        raise GeometryError(f"cam '{cam}': the barrel's groove faces do not sew into a closed shell")
    made = BRepBuilderAPI_MakeSolid(TopoDS.Shell(explorer.Current()))
    solid = made.Solid()
    BRepLib.OrientClosedSolid_s(solid)
    return solid


def cut_shape(shape: Any, tool: Any, what: str, cam: str) -> Any:
    """``shape`` less ``tool`` (OCCT's boolean); GeometryError naming ``what`` and the cam if it fails."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut

    cut = BRepAlgoAPI_Cut(shape, tool)
    if not cut.IsDone():
        raise GeometryError(f"cam '{cam}': OpenCASCADE cannot cut {what}")
    return cut.Shape()


def inside_ends(groove: Any, cam: str, what: str = "groove") -> None:
    """GeometryError where the groove (``what``: or a rib's faces) reaches an end face: its walls
    sampled at root, mean and rim radius every 0.1 deg of the cam angle (the mesh,
    :mod:`camgen.export.barrel_solid`, checks every vertex)."""
    theta = np.radians(np.arange(3600) / 10.0)
    r = np.array([groove.root_radius, 0.5 * (groove.root_radius + groove.rim_radius), groove.rim_radius])[:, None]
    low = float(np.min(groove.wall(-1, r, theta)[1]))
    high = float(np.max(groove.wall(1, r, theta)[1]))
    if not (low > 0.0 and high < groove.length):
        raise GeometryError(f"cam '{cam}': the {what} runs from z = {low:.4g} mm to z = {high:.4g} mm, through an end face of the "
                            f"cylinder (length {groove.length:g} mm)")


def _body(groove: Any, tol: float, cam: str) -> Any:
    """The barrel's OCCT solid: the cylinder of the rim radius less the bore, less the groove."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    rim, root, length, bore = (float(groove.rim_radius), float(groove.root_radius), float(groove.length), float(groove.bore_radius))
    inside_ends(groove, cam)
    axis = gp_Ax2(gp_Pnt(0.0, 0.0, 0.0), gp_Dir(0.0, 0.0, 1.0))
    below = gp_Ax2(gp_Pnt(0.0, 0.0, -1.0), gp_Dir(0.0, 0.0, 1.0))
    body = BRepPrimAPI_MakeCylinder(axis, rim, length).Shape()
    if bore > 0.0:
        body = cut_shape(body, BRepPrimAPI_MakeCylinder(below, bore, length + 2.0).Shape(), "the bore", cam)
    tube = tube_solid(groove, tol, cam)
    groove_cut = cut_shape(tube, BRepPrimAPI_MakeCylinder(below, root, length + 2.0).Shape(), "the groove at the root radius", cam)
    body = cut_shape(body, groove_cut, "the groove from the cylinder", cam)
    return one_valid_solid(body, cam)


def one_valid_solid(body: Any, cam: str) -> Any:
    """``body``, unless OCCT's checker (BRepCheck_Analyzer) finds it invalid or it is not one solid
    (a GeometryError naming the cam)."""
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    solids = 0
    explorer = TopExp_Explorer(body, TopAbs_SOLID)
    while explorer.More():
        solids += 1
        explorer.Next()
    if solids != 1 or not BRepCheck_Analyzer(body).IsValid():
        raise GeometryError(f"cam '{cam}': OpenCASCADE finds the barrel {'invalid' if solids == 1 else f'in {solids} solids'} "
                            "(BRepCheck_Analyzer)")
    return body


def barrel_step_bytes(groove: Any, name: str = "cam", schema: str = "AP214") -> bytes:
    """STEP file content (``schema`` AP214 or AP242) of the barrel cam of ``groove`` (module notes):
    walls within ``groove.fit_tol`` mm of the exact ones, stated in the header."""
    tol = float(groove.fit_tol)
    return solid_step_bytes(lambda: _body(groove, tol, name), name,
                            f"B-spline groove walls within {tol!r} mm (axially) of the exact walls; cylinders and planes exact", schema)


def groove_solid(groove: Any, name: str = "cam") -> Any:
    """The OCCT solid of the STEP file of the barrel cam of ``groove`` (:func:`barrel_step_bytes`:
    walls within ``groove.fit_tol`` mm), for the other writers of that solid (IGES)."""
    return build_solid(lambda: _body(groove, float(groove.fit_tol), name), name)


def build_solid(build: Callable[[], Any], name: str) -> Any:
    """``build()``, the barrel cam ``name``'s OCCT solid: an ExportError without OCP, OCCT's
    exceptions while building a GeometryError naming the cam."""
    _ocp()
    try:
        return build()
    except GeometryError:
        raise
    except Exception as exc:  # OCCT's exceptions share no Python base
        if not type(exc).__module__.startswith("OCP"):
            raise
        raise GeometryError(f"cam '{name}': OpenCASCADE cannot build the barrel's STEP solid ({type(exc).__name__}: {exc})") from None


def solid_step_bytes(build: Callable[[], Any], name: str, what: str, schema: str = "AP214") -> bytes:
    """STEP file content of the barrel cam ``name``'s solid made by ``build()`` (OCCT's exceptions
    while building a GeometryError naming the cam), written by
    :func:`camgen.export.step.step_text` with ``what`` (the surfaces and their tolerance) in the
    header's FILE_DESCRIPTION and a fixed time stamp, under ``schema`` (AP214 or AP242)."""
    body = build_solid(build, name)
    from camgen.export.step import step_text

    text = step_text(body, name, schema)
    text = re.sub(r"FILE_DESCRIPTION\(\('[^']*'\)", f"FILE_DESCRIPTION(('camgen barrel cam {name}: {what}')", text, count=1)
    text = re.sub(r"FILE_NAME\('[^']*','[^']*'", f"FILE_NAME('{name}.step','2000-01-01T00:00:00'", text, count=1)
    text = re.sub(r"PRODUCT\('[^']*',\s*'[^']*'", f"PRODUCT('{name}','{name}'", text, count=1)
    return text.encode("ascii")
