"""The cam-steered gravity-driven tricycle of paper 004 (Jiang et al. 2022).

Device model (Section 2, Table 2), as reconstructed here — the paper's Figures and eq. (1)
are missing, so each decision is stated with its evidence:

* **Eq. (1)** is the bicycle steering relation of the rear-axle centre O_AB:
  ``R = L / tan(alpha)`` (front wheel C at distance L ahead of the rear shaft, steered by
  ``alpha``).  Evidence: with ``Delta r = d tan(alpha)`` (Section 2.2) it turns eq. (2) into
  eq. (3), ``rho = d L / R + r_b``, exactly.
* **The path f is followed by the drive wheel A**, the rear wheel at lateral offset ``+D``
  (left, eq. 5), not by O_AB: substituting ``R = 1/k`` into eq. (3) would give
  ``rho = d L k + r_b``, but eq. (13) has ``d L k / (1 + D k)``, i.e. ``R = 1/k + D``: the
  turning centre is ``1/k`` from the tracked point and ``1/k + D`` from O_AB, so the tracked
  point sits ``D`` to the left of O_AB.  The drive wheel is also the wheel whose rolling
  distance per cam turn is the arc length S used for the wheel diameter ``d_AB``.
* **d = 30 mm, not Table 2's 3 mm**: eq. (14) is printed with ``77 x 30``, i.e.
  ``d L = 77 * 30``.  With d = 3 mm the cam radius would change by only +-0.5 mm for this
  path (a 0.01 mm cam error would then be a 0.2 deg steering error); we take Table 2's "3"
  as a dropped zero and keep d configurable.
* **Z2 = 120 for the wheel diameter**: Table 2 gives Z1 = Z2 = 20 but the text computes
  ``d_AB = 2189.0270 * 20 / (120 pi)``; the printed 116.19 mm results with pi = 3.14
  (``2189.0270 * 20 / (120 * 3.14) = 116.19``; with pi itself it is 116.13 mm).  With
  Z2 = 20 the drive wheel would be 696.8 mm across, which does not fit a 77 mm wheelbase.
* ``r_b = L - r_d`` (Table 2, row 6): straight ahead, the rod centre is L from the camshaft.

The steering rod (radius ``r_d``) is the follower: it translates along the radial line of
the camshaft (the +x axis of the fixed frame) and its centre sits at ``L + Delta r``;
``tan(alpha) = Delta r / d``.  The paper uses ``rho`` as the cam's polar radius; the true
cam is the inward offset by ``r_d`` of the rod-centre path ``rho + r_d``
(:func:`tricycle_cam`), which differs from ``rho`` where the profile slopes.

The cam turns counter-clockwise by ``theta`` while the vehicle advances ``S theta / 2 pi``;
the rod then touches the cam at cam-frame polar angle ``-theta``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from camgen.contour import Contour, Spline
from camgen.errors import GeometryError, ParameterError, UndercutError, require_positive
from camgen.geometry import outward_normal, signed_curvature
from camgen.synthesis.trajectory import CamSynthesis, PathError, Trajectory, steerable_paths, synthesize_rho

__all__ = [
    "CURVATURE_PEAK_TOL", "DEFAULT_FIT_TOL", "ErrorModel", "GrooveWalls", "MEASURED_TABLES", "MeasuredTable", "NOISE_FACTOR", "PolarCurves", "RHO_DEGREES",
    "Ride", "RideGeometry", "SPLINE_FORMS", "Tricycle", "TricycleCam", "UNDERCUT_GRID", "contact_vs_rho",
    "design_start", "fine_tuning_step", "groove_walls", "lateral_error", "load_measured_table", "ride", "ride_geometry",
    "ride_max_lateral_error", "simulate_cam", "steering_curvature", "tricycle_cam", "worm_teeth_for",
]


@dataclass(frozen=True)
class Tricycle:
    """Device parameters (paper 004, Table 2), mm.

    Attributes
    ----------
    wheelbase : L, rear shaft to steering wheel C (77).
    half_track : D, lateral distance of each rear wheel from the centre line (50).
    lever : d, active length of the steering rod (30; Table 2 prints 3, eq. 14 uses 30).
    rod_radius : r_d, radius of the steering rod (1.5).
    z_rear, z_cam : teeth of the rear-shaft and camshaft gears (20 and 120, see module doc).
    worm_teeth : Z3, teeth of the worm wheel of the fine-tuning mechanism (50, eq. 17).
    """

    wheelbase: float = 77.0
    half_track: float = 50.0
    lever: float = 30.0
    rod_radius: float = 1.5
    z_rear: int = 20
    z_cam: int = 120
    worm_teeth: int = 50

    def __post_init__(self) -> None:
        for name in ("wheelbase", "half_track", "lever", "rod_radius"):
            require_positive(name, getattr(self, name))
        for name in ("z_rear", "z_cam", "worm_teeth"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ParameterError(name, value, "a whole number of teeth >= 1")
        if self.rod_radius >= self.wheelbase:
            raise ParameterError("rod_radius", self.rod_radius, f"0 < r_d < L = {self.wheelbase:g} mm (wheelbase_mm)", "r_b = L - r_d must be > 0")

    @property
    def base_radius(self) -> float:
        """r_b = L - r_d, mm (Table 2, row 6)."""
        return self.wheelbase - self.rod_radius

    def drive_wheel_diameter(self, arc_length: float) -> float:
        """d_AB = S Z1 / (pi Z2), mm: the drive wheel rolls S while the cam turns once."""
        return arc_length * self.z_rear / (math.pi * self.z_cam)


# --------------------------------------------------------------------------------------------
# The cam
# --------------------------------------------------------------------------------------------
#: Spline forms of :func:`tricycle_cam`.
SPLINE_FORMS = ("polar", "cartesian")
#: Degrees of the polar interpolant rho(phi) (odd: knots at the samples).
RHO_DEGREES = (3, 5)
#: Default largest distance (mm) of the cam's cubic pieces from the exact polar curves.
DEFAULT_FIT_TOL = 1e-9
#: The polar form's fit tolerance is at least this many times the rounding noise of the finite-
#: difference curvature schemes (``forward``/``central`` at large N; :func:`_difference_noise`).
NOISE_FACTOR = 10.0
#: Points per sample interval at which the undercut condition 1 - r_d kappa > 0 is checked.
UNDERCUT_GRID = 16
#: Polar-angle bracket (rad) to which a groove's sharpest turns are polished between grid points.
CURVATURE_PEAK_TOL = 1e-10


@dataclass(frozen=True)
class PolarCurves:
    """The exact cam curves of the polar form, as functions of the polar angle ``phi`` (rad).

    The rod-centre path is ``Q(phi) = R(phi) u(phi)`` with ``u = (cos phi, sin phi)`` and
    ``R = rho + r_d`` a periodic interpolating spline of odd degree ``k`` through the samples
    ``(phi_j, rho_j + r_d)`` (knots at the samples); the profile is ``Q - r_d n`` with ``n`` the
    outward unit normal of ``Q``:

        n = (R u - R' u_perp) / W,  W = sqrt(R^2 + R'^2),  u_perp = (-sin phi, cos phi).

    Attributes
    ----------
    coeffs : array (k + 1, N)
        Polynomial coefficients of ``R`` on the N uniform intervals of ``[0, 2 pi)``, lowest
        power first, in ``phi - phi_j`` (rad), mm.
    rod_radius : float
        ``r_d``, mm.
    """

    coeffs: np.ndarray
    rod_radius: float

    @classmethod
    def interpolate(cls, radius: np.ndarray, degree: int, rod_radius: float) -> PolarCurves:
        """``R`` through ``radius`` (N + 1,) at ``phi_j = 2 pi j / N`` (``radius[N] == radius[0]``)."""
        n = radius.size - 1
        h = 2.0 * math.pi / n
        k = degree
        # the cardinal B-spline of degree k on [0, k + 1], on its unit interval i as a polynomial in
        # s = x - i (truncated powers: N(x) = sum_j (-1)^j C(k+1, j) (x - j)_+^k / k!, de Boor ch. IX)
        poly = np.zeros((k + 1, k + 1))  # poly[i, p]: coefficient of s^p on interval i
        for i in range(k + 1):
            for j in range(i + 1):
                for p in range(k + 1):
                    poly[i, p] += (-1) ** j * math.comb(k + 1, j) * math.comb(k, p) * float(i - j) ** (k - p)
        poly /= math.factorial(k)
        # the B-spline centred on sample m covers interval j as its interval i = j - m + (k + 1) / 2;
        # interpolation at the samples is a circulant system: solved by FFT (de Boor, ch. XIII)
        centre = (k + 1) // 2
        column = np.zeros(n)
        column[(np.arange(k + 1) - centre) % n] += poly[:, 0]
        controls = np.real(np.fft.ifft(np.fft.fft(radius[:-1]) / np.fft.fft(column)))
        sample = np.arange(n)
        gathered = controls[(sample[None, :] + centre - np.arange(k + 1)[:, None]) % n]  # (k + 1, N)
        in_s = poly.T @ gathered  # (k + 1, N): powers of s
        return cls(in_s / h ** np.arange(k + 1)[:, None], rod_radius)

    def derivatives(self, phi: np.ndarray, orders: int = 2) -> list[np.ndarray]:
        """``R, R', ..., R^(orders)`` at polar angles ``phi`` (rad), mm and mm/rad^k (Horner)."""
        c = self.coeffs
        n = c.shape[1]
        h = 2.0 * math.pi / n
        x = np.mod(np.asarray(phi, dtype=float), 2.0 * math.pi)
        j = np.minimum((x / h).astype(np.int64), n - 1)
        tau = x - j * h
        rows = c.T[j]  # (M, k + 1): one gather
        deg = c.shape[0] - 1
        out = []
        for nu in range(orders + 1):
            value = rows[:, deg] * (math.factorial(deg) / math.factorial(deg - nu))
            for p in range(deg - 1, nu - 1, -1):  # d^nu/dtau^nu of sum c_p tau^p
                value = value * tau + rows[:, p] * (math.factorial(p) / math.factorial(p - nu))
            out.append(value)
        return out

    def pitch_point(self, phi: np.ndarray) -> np.ndarray:
        """Points (n, 2) of the rod-centre path ``Q(phi)``, mm."""
        return self.both(phi)[:, :2]

    def profile_point(self, phi: np.ndarray) -> np.ndarray:
        """Points (n, 2) of the profile ``Q - r_d n`` (the rod touches it where its centre is at ``Q(phi)``), mm."""
        return self.both(phi)[:, 2:]

    def both(self, phi: np.ndarray) -> np.ndarray:
        """Pitch and profile points side by side (n, 4), mm (one fit for both, shared knots)."""
        return self.offsets(phi, (0.0, self.rod_radius))

    def offsets(self, phi: np.ndarray, distances: tuple[float, ...]) -> np.ndarray:
        """Points (n, 2 k) of the curves ``Q - d n`` for each of the k ``distances`` d (mm; > 0
        inward, 0 the rod-centre path itself), side by side: a groove's walls are ``d = +-w``."""
        r, dr = self.derivatives(phi, 1)
        phi = np.asarray(phi, dtype=float)
        w = np.hypot(r, dr)
        d = np.asarray(distances, dtype=float)[:, None]
        a = r - d * r / w  # along u
        b = d * dr / w  # along u_perp
        c, s = np.cos(phi), np.sin(phi)
        return np.stack([a * c - b * s, a * s + b * c], axis=-1).transpose(1, 0, 2).reshape(phi.size, 2 * d.shape[0])

    def pitch_curvature(self, phi: np.ndarray) -> np.ndarray:
        """Signed curvature of ``Q`` (1/mm, > 0 convex): ``(R^2 + 2 R'^2 - R R'') / W^3``."""
        r, dr, d2r = self.derivatives(phi, 2)
        return (r * r + 2.0 * dr * dr - r * d2r) / np.hypot(r, dr) ** 3


@dataclass(frozen=True)
class TricycleCam:
    """A synthesised tricycle cam.

    Attributes
    ----------
    synthesis : the eq. (9)-(13) samples (theta, x, k, rho).
    pitch : Contour of the rod-centre path, polar radius ``rho + r_d`` (periodic C2 spline).
    profile : Contour of the cam itself: ``pitch`` offset inward by ``r_d`` (what is made).
    form : ``"polar"`` (default) or ``"cartesian"`` (the earlier form), see :func:`tricycle_cam`.
    curves : the exact polar curves the contours are fitted to (``"polar"`` form), else None.
    fit_tol : the stated tolerance of the contours' cubic pieces, mm (the requested one, or for
        eq. (12)'s finite differences at large N ten times their rounding noise where larger).
    fit_error : the largest distance of the contours from the exact curves measured at the probe
        points of every piece, mm (``"polar"``; NaN for ``"cartesian"``).
    """

    synthesis: CamSynthesis
    pitch: Contour
    profile: Contour
    device: Tricycle
    trajectory: Trajectory = field(repr=False)
    form: str = "cartesian"
    curves: PolarCurves | None = field(default=None, repr=False)
    fit_tol: float = DEFAULT_FIT_TOL
    fit_error: float = float("nan")


def tricycle_cam(
    trajectory: Trajectory,
    device: Tricycle = Tricycle(),
    n_samples: int = 720,
    scheme: str = "exact",
    offset_tol: float = 1e-9,
    form: str = "polar",
    rho_degree: int = 5,
    fit_tol: float = DEFAULT_FIT_TOL,
) -> TricycleCam:
    """Synthesise the steering cam for ``trajectory`` (paper 004, Section 3).

    ``form="polar"`` (default): the rod-centre distance ``R = rho + r_d`` is a periodic
    interpolating spline of degree ``rho_degree`` (5: quintic, error O(h^6); 3: cubic, O(h^4))
    in the polar angle ``phi`` through the samples (the rod at polar angle ``phi_j = -theta_j``
    sits at ``rho_j + r_d``), so the curve has no one-signed radial bias between the samples.
    The exact rod-centre path ``R(phi) u(phi)`` and the profile (its inward offset by ``r_d``,
    closed form in ``R, R'``: :class:`PolarCurves`) are represented by one periodic C2 cubic
    spline each, least-squares fits on shared knots placed by the tolerance (not by ``N``):
    within ``fit_tol`` mm of the exact curves at the probe points of every piece
    (:func:`camgen.numerics.splinefit.fit_periodic`).  Their spline parameter is ``phi``.

    ``form="cartesian"``: the earlier form, kept for comparison: a periodic C2 *parametric*
    cubic through the points at polar angles ``phi_j`` with radius ``rho_j + r_d`` (its radial
    error is one-signed where the curve is convex, so the ride's heading drifts), offset inward
    by ``r_d`` and refitted within ``offset_tol`` mm (C1 cubic Hermite pieces).

    Raises :class:`UndercutError` (with the rod-centre path) where the rod cannot follow the
    profile: the rod-centre path is convex with a radius of curvature <= ``r_d``; and
    :class:`~camgen.synthesis.trajectory.PathError` (saying which paths are valid) for a path the
    device cannot steer: a right turn of radius <= ``D + d L / r_b`` (eq. 13 needs ``1 + D k > 0``
    and ``rho > 0``), or one the arc-length quadrature does not resolve.
    """
    from camgen.errors import require_positive as _positive

    if form not in SPLINE_FORMS:
        raise ParameterError("form", form, f"one of {', '.join(SPLINE_FORMS)}")
    if rho_degree not in RHO_DEGREES:
        raise ParameterError("rho_degree", rho_degree, f"one of {RHO_DEGREES}")
    _positive("fit_tol", fit_tol, "mm")
    synth = synthesize_rho(trajectory, n_samples, device.lever, device.wheelbase, device.half_track, device.base_radius, scheme)
    n = synth.theta.size
    if np.min(synth.rho) <= 0.0:
        raise PathError(f"cam radius rho reaches {np.min(synth.rho):.6g} mm <= 0: the path turns too sharply for r_b = {device.base_radius:g} mm",
                        steerable_paths(device.lever, device.wheelbase, device.half_track, device.base_radius))
    # polar angle phi_j = 2 pi j / N (counter-clockwise) carries the sample of theta = -phi_j
    order = (-np.arange(n)) % n
    phi = 2.0 * math.pi * np.arange(n + 1) / n
    radius = np.append(synth.rho[order], synth.rho[0]) + device.rod_radius
    if form == "cartesian":
        points = np.stack([radius * np.cos(phi), radius * np.sin(phi)], axis=1)
        points[-1] = points[0]
        pitch = Contour([Spline.interpolate(phi, points, periodic=True)])
        try:
            profile = pitch.offset(-device.rod_radius, spline_tol=offset_tol)
        except GeometryError as exc:
            raise UndercutError(f"the steering rod (r_d = {device.rod_radius:g} mm) cannot follow this cam: {exc}", pitch=pitch,
                                limit=device.rod_radius) from None
        return TricycleCam(synth, pitch, profile, device, trajectory, "cartesian", None, offset_tol)
    return _polar_cam(synth, phi, radius, device, trajectory, rho_degree, fit_tol)


def _difference_noise(synth: CamSynthesis, trajectory: Trajectory, device: Tricycle) -> float:
    """Rounding noise (mm) of the cam radius from eq. (12)'s finite differences (0 for the exact
    scheme): second differences of coordinates up to ``c`` mm over steps ``h`` carry rounding
    ``4 eps c / h^2`` in the curvature, times ``d L`` in rho (eq. 13, with ``1 + D k`` at its
    smallest).  A fit tolerance below it would make the spline follow the noise."""
    if synth.scheme == "exact":
        return 0.0
    x = synth.x
    h = float(np.min(np.diff(x))) if x.size > 1 else trajectory.period
    size = max(float(np.max(np.abs(x))) + trajectory.period, float(np.max(np.abs(trajectory.f(x)))))
    gain = device.lever * device.wheelbase / float(np.min(1.0 + device.half_track * synth.curvature)) ** 2
    return 4.0 * np.finfo(float).eps * size / h**2 * gain


def _polar_cam(synth: CamSynthesis, phi: np.ndarray, radius: np.ndarray, device: Tricycle, trajectory: Trajectory,
               degree: int, fit_tol: float) -> TricycleCam:
    """The ``"polar"`` form of :func:`tricycle_cam`."""
    from camgen.numerics.splinefit import RELATIVE_FLOOR, fit_periodic

    n = phi.size - 1
    radius = radius.copy()
    radius[-1] = radius[0]
    curves = PolarCurves.interpolate(radius, degree, device.rod_radius)
    # above the rounding noise of the curvature's differences and the fit's floor for a curve of
    # this size (a 1e5 mm device cannot be fitted to 1e-9 mm: rounding would decide the fit)
    size = float(np.max(np.abs(curves.both(np.array([0.0, 2.0 * math.pi / 3, 4.0 * math.pi / 3])))))
    fit_tol = max(fit_tol, NOISE_FACTOR * _difference_noise(synth, trajectory, device), RELATIVE_FLOOR * max(1.0, size))
    rd = device.rod_radius
    dense = np.linspace(0.0, 2.0 * math.pi, UNDERCUT_GRID * n, endpoint=False)
    factor = 1.0 - rd * curves.pitch_curvature(dense)  # |Q'| (1 - r_d kappa) is the profile's speed
    if np.any(factor <= 0.0):
        worst = int(np.argmin(factor))
        pitch_fit = fit_periodic(curves.pitch_point, 0.0, 2.0 * math.pi, fit_tol, initial_pieces=max(16, n // 8),
                                 what="rod-centre path")
        pitch = Contour([Spline(pitch_fit.breaks, pitch_fit.coeffs)])
        kappa = float(curves.pitch_curvature(dense[worst : worst + 1])[0])
        raise UndercutError(
            f"the steering rod (r_d = {rd:g} mm) cannot follow this cam: the rod-centre path turns with radius "
            f"{1.0 / kappa:.6g} mm <= r_d at cam angle {math.degrees(2.0 * math.pi - dense[worst]) % 360.0:.3f} deg "
            "(undercut: the profile would have a cusp there)", pitch=pitch, limit=rd)
    fit = fit_periodic(curves.both, 0.0, 2.0 * math.pi, fit_tol, initial_pieces=max(16, n // 8),
                       what="tricycle cam (rod-centre path and profile)")
    pitch = Contour([Spline(fit.breaks, fit.coeffs[..., :2])])
    profile = Contour([Spline(fit.breaks, fit.coeffs[..., 2:])])
    if not pitch.is_convex():
        crossing = profile.self_intersection()
        if crossing is not None:
            polar = math.degrees(math.atan2(crossing[1], crossing[0])) % 360.0
            raise UndercutError(
                f"the steering rod (r_d = {rd:g} mm) cannot follow this cam: the profile crosses itself near polar angle "
                f"{polar:.3f} deg: a neck of the rod-centre path is narrower than 2 r_d", pitch=pitch, limit=rd)
    return TricycleCam(synth, pitch, profile, device, trajectory, "polar", curves, fit_tol, fit.error)


@dataclass(frozen=True)
class GrooveWalls:
    """The walls of a groove the steering rod runs in (the groove form of the trajectory motion).

    Attributes
    ----------
    inner, outer : Contours ``Q - w n`` and ``Q + w n`` of the rod-centre path ``Q`` (``n`` its
        outward normal), each one periodic cubic spline in the polar angle on shared knots,
        within ``fit_tol`` mm of the exact curves; None where the groove cannot be made.
    cam_angle : the dense cam angles (rad) at which the conditions below were evaluated.
    pitch_curvature : the signed curvature (1/mm, > 0 convex) of ``Q`` there.
    inner_fails, outer_fails : where ``1 - w kappa <= 0`` (the inner wall would have a cusp: the
        rod-centre path's convex radius <= w) and ``1 + w kappa <= 0`` (the outer wall: its
        concave radius <= w).
    crossing : the polar angle (rad) where a wall crosses itself (a neck of ``Q`` narrower than
        2 w), or None.
    fit_error : the walls' largest distance from the exact curves at the fit's probe points, mm.
    """

    inner: Contour | None
    outer: Contour | None
    cam_angle: np.ndarray
    pitch_curvature: np.ndarray
    inner_fails: np.ndarray
    outer_fails: np.ndarray
    crossing: float | None = None
    fit_error: float = 0.0


def groove_walls(cam: TricycleCam, half_width: float) -> GrooveWalls:
    """The groove's walls for a rod whose centre follows ``cam.pitch`` with ``half_width`` w of
    room each side (rod radius plus half the clearance): the exact offsets ``Q -+ w n`` of the
    polar form's rod-centre path (:meth:`PolarCurves.offsets`), fitted on shared knots within
    ``cam.fit_tol`` when both can be made (``1 -+ w kappa > 0`` on the dense grid of the undercut
    condition, and neither wall crosses itself)."""
    from camgen.numerics.splinefit import fit_periodic

    if cam.curves is None:
        raise GeometryError("a groove needs the polar form's exact rod-centre path (form='polar')")
    from camgen.numerics.minimise import golden_section

    n = cam.synthesis.theta.size
    curves = cam.curves
    phi = np.linspace(0.0, 2.0 * math.pi, UNDERCUT_GRID * n, endpoint=False)
    kappa = curves.pitch_curvature(phi)
    # the sharpest convex and concave turns, polished between the grid's neighbours (a narrow
    # peak of the curvature falls between grid points): the conditions hold there too
    step = float(phi[1] - phi[0])
    sharpest = []
    for sign in (1.0, -1.0):
        i = int(np.argmax(sign * kappa))
        (at, _), _ = golden_section(lambda t: -sign * float(curves.pitch_curvature(np.array([t]))[0]), float(phi[i]) - step,
                                    float(phi[i]) + step, tol=CURVATURE_PEAK_TOL)
        sharpest.append(at)
    phi = np.concatenate([phi, np.mod(sharpest, 2.0 * math.pi)])
    kappa = np.concatenate([kappa, curves.pitch_curvature(phi[-2:])])
    w = half_width
    inner_fails, outer_fails = 1.0 - w * kappa <= 0.0, 1.0 + w * kappa <= 0.0
    cam_angle = np.mod(-phi, 2.0 * math.pi)  # the rod at polar angle phi is there at cam angle -phi
    if inner_fails.any() or outer_fails.any():
        return GrooveWalls(None, None, cam_angle, kappa, inner_fails, outer_fails)
    fit = fit_periodic(lambda p: curves.offsets(p, (w, -w)), 0.0, 2.0 * math.pi, cam.fit_tol, initial_pieces=max(16, n // 8),
                       what="groove walls of the tricycle cam")
    inner, outer = Contour([Spline(fit.breaks, fit.coeffs[..., :2])]), Contour([Spline(fit.breaks, fit.coeffs[..., 2:])])
    crossing = None
    if not cam.pitch.is_convex():
        for wall in (inner, outer):
            hit = wall.self_intersection()
            if hit is not None:
                crossing = math.atan2(hit[1], hit[0]) % (2.0 * math.pi)
                break
    if crossing is not None:
        return GrooveWalls(None, None, cam_angle, kappa, inner_fails, outer_fails, crossing)
    return GrooveWalls(inner, outer, cam_angle, kappa, inner_fails, outer_fails, None, fit.error)


def contact_vs_rho(cam: TricycleCam) -> float:
    """Largest |polar radius of the true contact contour - rho| at the sample angles, mm.

    The paper takes ``rho`` as the cam's polar radius; the contour that really touches the
    rod is the inward offset of the rod-centre path, whose polar radius differs where the
    profile slopes.
    """
    theta = cam.synthesis.theta
    radius = cam.profile.polar_radius(-theta)
    return float(np.max(np.abs(radius - cam.synthesis.rho)))


# --------------------------------------------------------------------------------------------
# Ride simulation
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ErrorModel:
    """Assembly and drive errors of the tricycle (paper 004, Section 4.2).

    Attributes
    ----------
    steering_offset : delta, rad: type I error, added to the steering angle (left > 0).
    steering_gain : g: type II error, ``tan(alpha) = g Delta r / d`` (g = d_design / d_actual).
    drive_scale : sigma: actual distance per cam turn / designed S (wheel diameter, slip).
    start_phase : cam angle at the start, rad.
    start_heading : heading offset from the designed heading at the start, rad.
    """

    steering_offset: float = 0.0
    steering_gain: float = 1.0
    drive_scale: float = 1.0
    start_phase: float = 0.0
    start_heading: float = 0.0


def _gauss_integration_matrix(m: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes, weights and the matrix I with I[j, l] = integral_{-1}^{tau_j} l_l."""
    nodes, weights = np.polynomial.legendre.leggauss(m)
    vander = np.vander(nodes, m, increasing=True)
    powers = np.arange(1, m + 1)
    antider = (nodes[:, None] ** powers - (-1.0) ** powers) / powers
    return nodes, weights, antider @ np.linalg.inv(vander)


@dataclass(frozen=True)
class RideGeometry:
    """What the rod sees of a cam as made, at Gauss nodes in increasing cam angle.

    Attributes
    ----------
    theta : array (K, m)
        Cam angle at the nodes, rad, increasing, within (0, 2 pi).
    rod : array (K, m)
        Distance of the rod centre from the camshaft axis, mm.
    scale : array (K, m)
        d(theta)/d(sigma) at the nodes, sigma in [-1, 1] on every node interval.
    weights, integration : Gauss weights (m,) and cumulative integration matrix (m, m).
    theta_end, rod_end : array (K,)
        Cam angle and rod-centre distance at the end of every node interval (theta_end[-1] = 2 pi).
    """

    theta: np.ndarray
    rod: np.ndarray
    scale: np.ndarray
    weights: np.ndarray
    integration: np.ndarray
    theta_end: np.ndarray
    rod_end: np.ndarray


def ride_geometry(profile: Contour, rod_radius: float, nodes: int = 6) -> RideGeometry:
    """Rod-centre distance along the cam turn, from the profile contour (exact offset, no refit).

    The rod centre is the point ``Q = C + r_d n`` of the profile ``C``; ``Q`` must be
    star-shaped and its polar angle is ``-theta``.  The integration nodes are Gauss points in
    the spline parameter of every piece of ``C``, where the integrand is smooth.
    """
    (seg,) = profile.segments
    assert isinstance(seg, Spline)  # a tricycle cam's profile is one closed spline (tricycle_cam)
    tau, weights, integ = _gauss_integration_matrix(nodes)
    h = np.diff(seg.breaks)
    t = seg.breaks[:-1, None] + 0.5 * h[:, None] * (tau[None, :] + 1.0)  # (K, m)
    piece = np.repeat(np.arange(h.size), nodes)
    tau_flat = (t - seg.breaks[:-1, None]).ravel()
    c0, c1, c2 = (seg.eval_piece(piece, tau_flat, order) for order in (0, 1, 2))
    normal = _outward(c1)
    stretch = 1.0 + rod_radius * signed_curvature(c1, c2)
    if np.any(stretch <= 0):
        raise GeometryError("the rod-centre path of this profile has a cusp: the rod radius exceeds a concave radius of the cam")
    q = c0 + rod_radius * normal
    dq = c1 * stretch[:, None]
    rod = np.hypot(q[:, 0], q[:, 1])
    dphi_dt = (q[:, 0] * dq[:, 1] - q[:, 1] * dq[:, 0]) / rod**2
    if np.any(dphi_dt <= 0):
        raise GeometryError("the rod-centre path is not star-shaped about the camshaft")
    phi = np.unwrap(np.arctan2(q[:, 1], q[:, 0]))
    phi -= 2.0 * math.pi * math.floor((phi[0] + 1e-9) / (2.0 * math.pi))
    theta = (2.0 * math.pi - phi).reshape(t.shape)
    scale = 0.5 * h[:, None] * dphi_dt.reshape(t.shape)
    # interval ends: the break points, theta = 2 pi - phi (the first break is at phi = 0)
    q_break = seg.eval_t(seg.breaks) + rod_radius * _outward(seg.eval_t(seg.breaks, 1))
    phi_break = np.unwrap(np.arctan2(q_break[:, 1], q_break[:, 0]))
    phi_break -= phi_break[0]
    # increasing theta = decreasing parameter: reverse pieces and nodes (Gauss nodes are symmetric)
    rev = (slice(None, None, -1), slice(None, None, -1))
    theta_end = (2.0 * math.pi - phi_break[:-1])[::-1]
    theta_end[-1] = 2.0 * math.pi
    rod_end = np.hypot(q_break[:-1, 0], q_break[:-1, 1])[::-1]
    return RideGeometry(theta[rev], rod.reshape(t.shape)[rev], scale[rev], weights, integ, theta_end, rod_end)


_outward = outward_normal


def _cumulative(values: np.ndarray, geom: RideGeometry, start: float | None = None) -> np.ndarray:
    """Integral over theta of ``values`` (P, K, m) from theta = 0 to every node and to the end
    of every node interval: flattened (P K (m + 1),), the interval end after its nodes.

    ``start``: the integral before theta = 0 (a previous cam turn's end value); the running sum
    is continued from it exactly as one cumulative sum over all the turns would (bit for bit)."""
    weighted = values * geom.scale
    per_interval = (weighted @ geom.weights).ravel()
    ends = np.cumsum(per_interval) if start is None else np.cumsum(np.concatenate([[start], per_interval]))[1:]
    inner = np.einsum("jl,...l->...j", geom.integration, weighted).reshape(per_interval.size, -1)
    return np.concatenate([(ends - per_interval)[:, None] + inner, ends[:, None]], axis=1).ravel()


def _with_ends(node_values: np.ndarray, end_values: np.ndarray) -> np.ndarray:
    """Interleave node values (P, K, m) with interval-end values (P, K) as _cumulative orders them."""
    return np.concatenate([node_values, end_values[..., None]], axis=-1).ravel()


@dataclass(frozen=True)
class Ride:
    """Simulated path of the tracked point (drive wheel A) at the integration nodes, in order.

    ``theta`` cam angle from the start (rad), ``x``, ``y`` (mm), ``heading`` (rad),
    ``curvature`` of the path (1/mm) and ``speed`` the distance per unit cam angle (mm/rad).
    """

    theta: np.ndarray
    x: np.ndarray
    y: np.ndarray
    heading: np.ndarray
    curvature: np.ndarray
    speed: float

    def at(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """x, y (mm) and heading (rad) at cam angles ``theta`` by cubic Hermite interpolation."""
        theta = np.asarray(theta, dtype=float)
        k = np.clip(np.searchsorted(self.theta, theta, side="right") - 1, 0, self.theta.size - 2)
        h = self.theta[k + 1] - self.theta[k]
        s = (theta - self.theta[k]) / h
        h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
        out = []
        slopes = (np.cos(self.heading), np.sin(self.heading), self.curvature)
        for values, slope in zip((self.x, self.y, self.heading), slopes):
            d = self.speed * slope
            out.append(h00 * values[k] + h10 * h * d[k] + h01 * values[k + 1] + h11 * h * d[k + 1])
        return out[0], out[1], out[2]

    def moved(self, dx: float, dy: float, turn: float) -> "Ride":
        """The path rotated by ``turn`` (rad) about the origin, then shifted by (dx, dy) mm."""
        c, s = math.cos(turn), math.sin(turn)
        return replace(self, x=c * self.x - s * self.y + dx, y=s * self.x + c * self.y + dy, heading=self.heading + turn)


def steering_curvature(rod: np.ndarray, device: Tricycle, errors: ErrorModel) -> np.ndarray:
    """Path curvature of the drive wheel A (1/mm) for rod-centre distances ``rod`` (mm).

    ``tan(alpha) = g (q - L) / d`` (+ offset delta on alpha), ``kappa_O = tan(alpha) / L``
    (eq. 1), ``kappa_A = kappa_O / (1 - D kappa_O)`` (A is D to the left of O_AB).
    """
    tan_alpha = np.tan(np.arctan(errors.steering_gain * (rod - device.wheelbase) / device.lever) + errors.steering_offset)
    kappa_o = tan_alpha / device.wheelbase
    denom = 1.0 - device.half_track * kappa_o
    if np.any(denom <= 0.0):
        raise GeometryError("the steering turns the rear-axle centre about the drive wheel (1 - D kappa_O <= 0)")
    return kappa_o / denom


def ride(geom: RideGeometry, device: Tricycle, arc_length: float, errors: ErrorModel = ErrorModel(), periods: int = 1) -> Ride:
    """Integrate the vehicle kinematics over ``periods`` cam turns from ``theta = start_phase``.

    Per unit cam angle the drive wheel rolls ``sigma S / 2 pi``; its heading changes by that
    times :func:`steering_curvature`.  Heading and position are integrated with the
    Gauss-Legendre cumulative matrix of every node interval (spectral accuracy inside the
    pieces of the cam spline).  The path starts at the origin with heading
    ``errors.start_heading``.
    """
    if isinstance(periods, bool) or not isinstance(periods, int) or not 1 <= periods <= 1000:
        raise ParameterError("periods", periods, "an integer 1 <= periods <= 1000")
    speed = errors.drive_scale * arc_length / (2.0 * math.pi)
    theta0 = errors.start_phase % (2.0 * math.pi)
    reps = periods + (1 if theta0 > 0.0 else 0)
    shape = (reps,) + geom.rod.shape
    kappa = np.broadcast_to(steering_curvature(geom.rod, device, errors), shape)
    heading_all = _cumulative(speed * kappa, geom)
    nodes = np.ones(shape[:-1] + (shape[-1] + 1,), dtype=bool)
    nodes[..., -1] = False
    nodes = nodes.ravel()
    heading_nodes = heading_all[nodes].reshape(shape)
    x = np.concatenate([[0.0], _cumulative(speed * np.cos(heading_nodes), geom)])
    y = np.concatenate([[0.0], _cumulative(speed * np.sin(heading_nodes), geom)])
    heading = np.concatenate([[0.0], heading_all])
    turns = 2.0 * math.pi * np.arange(reps)[:, None]
    theta = np.concatenate([[0.0], _with_ends(geom.theta[None] + turns[..., None], geom.theta_end[None] + turns)])
    kappa_end = np.broadcast_to(steering_curvature(geom.rod_end, device, errors), shape[:-1])
    kappa_start = steering_curvature(geom.rod_end[-1:], device, errors)  # theta = 0 is theta = 2 pi
    curvature = np.concatenate([kappa_start, _with_ends(kappa, kappa_end)])
    path = Ride(theta, x, y, heading, curvature, speed)
    if theta0 > 0.0:
        x0, y0, h0 = path.at(np.array([theta0]))
        keep = (theta > theta0) & (theta <= theta0 + 2.0 * math.pi * periods)
        path = Ride(
            np.concatenate([[theta0], theta[keep]]) - theta0,
            np.concatenate([x0, x[keep]]) - x0[0],
            np.concatenate([y0, y[keep]]) - y0[0],
            np.concatenate([h0, heading[keep]]),
            np.concatenate([[float(np.interp(theta0, theta, curvature))], curvature[keep]]),
            speed,
        ).moved(0.0, 0.0, -float(h0[0]))
    return path.moved(0.0, 0.0, errors.start_heading)


def ride_max_lateral_error(cam: TricycleCam, periods: int = 1, errors: ErrorModel = ErrorModel(), nodes: int = 6) -> float:
    """Largest |lateral error| (mm) from the target path of the ride of ``cam`` over ``periods``
    cam turns, started at cam angle 0 on the designed path.

    The same number, bit for bit, as ``max |lateral_error(simulate_cam(cam, errors, periods))|``,
    but integrated one cam turn at a time (the heading and the position carry over as the
    running sums of the one-shot integration; :func:`_cumulative`), keeping only the running
    maximum: memory O(K m) for K node intervals of m nodes, whatever ``periods`` (the one-shot
    ride holds periods K (m + 1) values of six arrays: 11 GB at 20000 samples x 1000 turns).

    ``errors.start_phase`` must be 0 (the ride of the report); other starts: :func:`simulate_cam`.
    """
    if isinstance(periods, bool) or not isinstance(periods, int) or not 1 <= periods <= 1000:
        raise ParameterError("periods", periods, "an integer 1 <= periods <= 1000")
    if errors.start_phase % (2.0 * math.pi) != 0.0:
        raise ParameterError("start_phase", errors.start_phase, "0 rad (a ride started at theta = 0)", "use simulate_cam")
    geom = ride_geometry(cam.profile, cam.device.rod_radius, nodes)
    x0, y0, h0 = design_start(cam, errors.start_phase)
    speed = errors.drive_scale * cam.synthesis.arc_length / (2.0 * math.pi)
    rate = speed * steering_curvature(geom.rod, cam.device, errors)[None]  # (1, K, m): d heading / d theta
    shape = rate.shape
    at_nodes: np.ndarray = np.ones(shape[:-1] + (shape[-1] + 1,), dtype=bool)
    at_nodes[..., -1] = False
    at_nodes = at_nodes.ravel()
    # the two rigid moves of simulate_cam: ride() turns by the start-heading error, then onto the design
    moves = [(math.cos(errors.start_heading), math.sin(errors.start_heading), 0.0, 0.0), (math.cos(h0), math.sin(h0), x0, y0)]

    def worst(x: np.ndarray, y: np.ndarray) -> float:
        for c, s, dx, dy in moves:  # as Ride.moved
            x, y = c * x - s * y + dx, s * x + c * y + dy
        return float(np.max(np.abs(lateral_error(cam.trajectory, x, y))))

    largest = worst(np.zeros(1), np.zeros(1))
    heading_end = x_end = y_end = 0.0
    for _ in range(periods):
        heading = _cumulative(rate, geom, heading_end)
        heading_nodes = heading[at_nodes].reshape(shape)
        x = _cumulative(speed * np.cos(heading_nodes), geom, x_end)
        y = _cumulative(speed * np.sin(heading_nodes), geom, y_end)
        heading_end, x_end, y_end = float(heading[-1]), float(x[-1]), float(y[-1])
        largest = max(largest, worst(x, y))
    return largest


def lateral_error(trajectory: Trajectory, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Signed distance (mm) of points from the periodic path ``y = f(x)``, along its normal
    (first order in the deviation: ``(y - f(x)) / sqrt(1 + f'(x)^2)``)."""
    xm = np.mod(x, trajectory.period)
    slope = trajectory.df(xm)
    return (y - trajectory.f(xm)) / np.sqrt(1.0 + slope * slope)


def design_start(cam: TricycleCam, start_phase: float) -> tuple[float, float, float]:
    """Designed position (x, y, mm) and heading (rad) of the tracked point at a cam angle."""
    theta0 = start_phase % (2.0 * math.pi)
    x0 = cam.synthesis.length.inverse(np.array([cam.synthesis.arc_length * theta0 / (2.0 * math.pi)]))
    return float(x0[0]), float(cam.trajectory.f(x0)[0]), float(np.arctan(cam.trajectory.df(x0))[0])


def simulate_cam(cam: TricycleCam, errors: ErrorModel = ErrorModel(), periods: int = 1, nodes: int = 6) -> Ride:
    """Ride of ``cam`` as made (its profile contour), started on the designed path.

    The drive wheel starts where the design puts it at ``errors.start_phase``, with the
    designed heading there plus ``errors.start_heading``.
    """
    geom = ride_geometry(cam.profile, cam.device.rod_radius, nodes)
    x0, y0, h0 = design_start(cam, errors.start_phase)
    return ride(geom, cam.device, cam.synthesis.arc_length, errors, periods).moved(x0, y0, h0)


# --------------------------------------------------------------------------------------------
# Fine-tuning mechanism (paper 004, Section 4.2, eqs. 16-17)
# --------------------------------------------------------------------------------------------
def fine_tuning_step(permissible_deviation_deg: float) -> float:
    """Eq. (16): a correction step ``e`` brings any excess back within ``+-delta`` iff ``e <= 2 delta`` (deg)."""
    delta = require_positive("permissible_deviation_deg", permissible_deviation_deg, "deg")
    return 2.0 * delta


def worm_teeth_for(step_deg: float, knob_step_deg: float = 1.0) -> int:
    """Eq. (17): one knob step of ``knob_step_deg`` turns the worm wheel (and the steering) by
    ``knob_step_deg / Z3``; the smallest whole ``Z3`` with ``knob_step / Z3 <= step``."""
    step = require_positive("step_deg", step_deg, "deg")
    knob = require_positive("knob_step_deg", knob_step_deg, "deg")
    return math.ceil(knob / step - 1e-9)


# --------------------------------------------------------------------------------------------
# Measured trajectories (paper 004, Appendix A)
# --------------------------------------------------------------------------------------------
MEASURED_TABLES = {"A1": "tricycle_table_a1.csv", "A2": "tricycle_table_a2.csv"}


@dataclass(frozen=True)
class MeasuredTable:
    """A measured trajectory: ``x``, ``measured`` and the paper's ``ideal`` and ``error`` columns (mm)."""

    name: str
    x: np.ndarray
    measured: np.ndarray
    ideal: np.ndarray
    error: np.ndarray


def load_measured_table(name: str) -> MeasuredTable:
    """Load Table A1 or A2 of paper 004 from ``camgen/data`` (see the CSV headers for the
    reconstruction and the swapped column labels)."""
    import csv
    from importlib.resources import files

    if name not in MEASURED_TABLES:
        raise ParameterError("table", name, f"one of {sorted(MEASURED_TABLES)}")
    text = files("camgen.data").joinpath(MEASURED_TABLES[name]).read_text(encoding="utf-8")
    lines = [line for line in text.splitlines() if line and not line.startswith("#")]
    rows = list(csv.DictReader(lines))
    col = {key: np.array([float(r[key]) for r in rows]) for key in ("x_mm", "measured_y_mm", "ideal_y_mm", "error_mm")}
    return MeasuredTable(name, col["x_mm"], col["measured_y_mm"], col["ideal_y_mm"], col["error_mm"])
