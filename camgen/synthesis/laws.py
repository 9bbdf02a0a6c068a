"""Standard cam motion laws, motion segments and motion programs (one cam turn).

A *law* is a normalised rise ``S(tau)`` on ``tau in [0, 1]`` with ``S(0) = 0`` and ``S(1) = 1`` (a
dwell: ``S = 0``), given in closed form with its derivatives ``V = dS/dtau``, ``A = d2S/dtau2``,
``J = d3S/dtau3``.  A *segment* scales a law to a cam-angle span ``beta`` (rad) and a lift ``L``
(mm for a translating follower, rad for an oscillating one): ``s = s_start + L S(tau)``,
``ds/dtheta = L V / beta``, ``d2s/dtheta2 = L A / beta^2``, ``d3s/dtheta3 = L J / beta^3`` with
``tau = (theta - theta_start) / beta``.  A *return* (``L < 0``) runs the rise backwards in time,
``s = s_start + L (1 - S(1 - tau))``: identical to ``L S(tau)`` for the symmetric laws, and the
textbook fall for the one asymmetric law here, the double harmonic.  A :class:`MotionProgram`
chains segments over one turn and implements the :class:`Displacement` interface.

The laws (``LAWS``, keyed by the names scene files use):

=====================  ===================================================================  =====================
name                   displacement S(tau) (rise)                                           source
=====================  ===================================================================  =====================
dwell                  0                                                                    --
constant_velocity      tau; with ``blend = b`` (0 < b <= 1/2): velocity ramps over           Norton ch. 8 (the
                       ``[0, b]`` and ``[1 - b, 1]`` whose acceleration is the pulse         "naive" cam); blends:
                       ``1 - cos(2 pi u / b)``, constant velocity ``1 / (1 - b)`` between   camgen's design (below)
simple_harmonic        (1 - cos(pi tau)) / 2                    (alias: ``harmonic``)       Norton ch. 8, SHM
double_harmonic        (1 - cos(pi tau)) / 2 - (1 - cos(2 pi tau)) / 8                      Norton ch. 8 (single-
                                                                                            dwell rise and fall)
cycloidal              tau - sin(2 pi tau) / (2 pi)                                         Norton ch. 8
modified_trapezoid     A: quarter sines of period 1/2 on [0, 1/8], [3/8, 5/8] (half),       Norton ch. 8 (modified
                       [7/8, 1], constant on [1/8, 3/8] and [5/8, 7/8]                      trapezoidal accel.)
modified_sine          A: quarter sine of period 1/2 on [0, 1/8] and [7/8, 1], half sine     Norton ch. 8 (modified
                       of period 3/2 on [1/8, 7/8]                                          sinusoidal accel.)
modified_cycloidal     tau = t - k sin(2 pi t)/(2 pi), S = t - sin(2 pi t)/(2 pi): the cycloid  Rothbart, Cam Design
                       with its sine laid off along the tilt k = 1 - sqrt(3)/2 (Wildt's)    Handbook, sec. 3
poly345                10 tau^3 - 15 tau^4 + 6 tau^5                                        Norton ch. 8
poly4567               35 tau^4 - 84 tau^5 + 70 tau^6 - 20 tau^7                            Norton ch. 8
polynomial             the polynomial of lowest degree meeting the user's end conditions    Norton ch. 8
                       (s, v, a[, j] at each end; degree = number of conditions - 1)        (polynomial functions)
constant_acceleration  2 tau^2 on [0, 1/2], 1 - 2 (1 - tau)^2 on [1/2, 1] (parabolic)         Norton ch. 8
trapezoidal            A: linear ramps over [0, 1/8], [3/8, 5/8], [7/8, 1], constant        Norton ch. 8 (trapezoidal
                       between (:mod:`camgen.synthesis.laws_scca`)                          acceleration)
scca                   ``scca = [b, c, d]``: sine ramps (b), constants (c), middle cosine   Norton, 2nd ed., sec. 8.3
                       (d); :mod:`camgen.synthesis.laws_scca`                               (eqs. 8.21-8.24)
asymmetric_modified_   the modified sine / trapezoid with its positive acceleration over    Rothbart, Cam Design
sine, asymmetric_      ``accel_fraction`` of the span, the negative over the rest           Handbook, sec. 3, Fig.
modified_trapezoid     (:mod:`camgen.synthesis.laws_scca`)                                  3.7 (skewed curves)
                       and interior conditions (s[, v[, a]] at points inside; SPLINE)       (single-dwell: 3-4-5-6)
bspline                the interpolating B-spline of degree 3, 5 or 7 through the user's    de Boor, A Practical
                       points, (degree - 1)/2 derivatives given at each end (default rest); Guide to Splines; scipy
                       knots at the points, C^(degree - 1) there                            make_interp_spline
velocity_blend         the lowest-degree polynomial meeting the neighbouring segments'      camgen's design
                       velocity, acceleration and jerk at its ends (and the lift if given)  (Norton ch. 8 polys)
=====================  ===================================================================  =====================

Peak coefficients (``Cv = max|V|``, ``Ca = max|A|``, ``Cj = max|J|``) follow Norton's convention
(Design of Machinery, Table 8-3): a rise *between two dwells*, so a law whose velocity (acceleration)
is not zero at an end has ``Ca = inf`` (``Cj = inf``): the acceleration (jerk) is an impulse there.
The peaks inside the segment are always finite and given by :attr:`Law.peaks`.  Closed forms:
cycloidal ``(2, 2 pi, 4 pi^2)``; simple harmonic ``(pi/2, pi^2/2, inf)``; modified trapezoid
``(2, 8 pi/(2 + pi), 32 pi^2/(2 + pi))``; modified sine ``(4 pi/(4 + pi), 4 pi^2/(4 + pi),
16 pi^3/(4 + pi))``; modified cycloidal ``(4/(4 - sqrt(3)), 5.88825, 4 pi^2/(sqrt(3)/2)^3)``
(Cv 1.7637, Cj 60.781; Ca at ``cos E = (sqrt(3) - 1)/2``, see :class:`_TiltedCyclePiece`); 3-4-5
``(15/8, 10/sqrt(3), 60)``; 4-5-6-7 ``(35/16, 7.51319, 52.5)``; double harmonic ``(3 sqrt(3) pi/8,
pi^2, inf)``; blended constant velocity ``(1/(1-b), 2/(b(1-b)), 2 pi/(b^2 (1-b)))``.  camgen
computes them at construction from the closed-form derivatives (root of the next derivative by
bisection: exact to ~1e-13).

Notes on three laws:

* **modified_cycloidal** (Wildt's modified cycloid; Rothbart, Cam Design Handbook, 2004, sec. 3 and
  Fig. 3.12b): the cycloid is the constant-velocity line plus a sine whose amplitude is laid off
  vertically; Wildt lays it off along a tilted direction (the handbook's line from M, the middle of
  the first half of the constant-velocity line, to a point D at 0.57 of beta/2), chosen to minimise
  the peak acceleration.  In units of the span and the lift the tilt is ``k = 2 (0.57 - 0.5)``;
  the exact minimiser of the peak acceleration is ``k = 1 - sqrt(3)/2 = 0.13397`` (D at 0.56699,
  the handbook's 0.57 to its two digits), which camgen uses (:data:`MODIFIED_CYCLOID_TILT`).
  Against the cycloid it lowers Cv from 2 to 1.764 and Ca from 6.283 to 5.888 and raises Cj from
  39.5 to 60.8; like the cycloid it starts and ends at rest with zero acceleration (the jerk jumps
  against a dwell).  Not to be confused with the Japanese "MC" curves or with codes that call the
  modified sine a "modified cycloid".  The displacement is parametric in the cycloid's own angle
  ``E``; ``E(tau)`` solves Kepler's equation ``E - k sin E = 2 pi tau`` (Newton, to rounding).
* **double_harmonic** (Norton, ch. 8, single-dwell design): the rise starts from rest with zero
  acceleration and jerk and arrives with ``A(1) = -pi^2``; the matching return (the time-reversed
  rise, Norton's fall ``(1 + cos(pi tau))/2 - (1 - cos(2 pi tau))/8``) leaves the top with the same
  acceleration, so a rise and a return of equal span join smoothly up to jerk.  Against a dwell at the
  top the acceleration jumps (reported by :meth:`MotionProgram.joins`).
* **constant_velocity with blends** (camgen's design): each end blend is a velocity ramp shaped like
  a cycloidal displacement, ``V = Vc (u - sin(2 pi u)/(2 pi))`` with ``u = tau / b``, so the
  acceleration ``(Vc/b)(1 - cos(2 pi u))`` and the jerk vanish at both ends of each blend: the
  segment starts and ends at rest and is continuous up to jerk everywhere (only the 4th derivative
  steps at ``tau = b, 1 - b``).  ``S(1) = 1`` gives ``Vc = 1/(1 - b)``.

Notes on the SPLINE laws (issue 26): every one is in physical units on tau (a segment's scale is
1, as for the polynomial).  **bspline**'s points are (position, lift above the segment's start);
without points it is the one polynomial of its end conditions (rest to rest, degree 5: the 3-4-5).
**velocity_blend** takes its ends from the segments before and after it (``MotionProgram`` joins
it): so "dwell -> velocity_blend -> constant_velocity -> velocity_blend -> dwell" and "constant
velocity -> velocity_blend -> constant velocity at another speed" are continuous up to the jerk at
every join; without a lift it is the degree-6 polynomial meeting the six derivatives (between two
constant velocities its velocity ramps as the 3-4-5 and its lift is the mean velocity times the span),
with a lift the degree-7 one.  Two blends side by side are refused (each needs its neighbour's ends).

Segment joins are checked: :meth:`MotionProgram.joins` lists for every join which derivative jumps
and by how much (physical units per rad^n), so a report can say "acceleration jumps by X mm/rad^2 at
120 deg".  A displacement jump is an error; a velocity jump (infinite acceleration) is allowed but
reported.
"""
from __future__ import annotations

import functools
import itertools
import math
import operator
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Protocol, runtime_checkable

import numpy as np

from camgen.errors import ParameterError, require_finite, require_positive
from camgen.synthesis import laws_scca
from camgen.synthesis.laws_spline import (
    MIN_SPACING,
    SPLINE_DEGREES,
    Polynomial,
    hermite_polynomial,
    interpolating_spline,
    polynomial_derivative_at,
)

__all__ = [
    "ALIASES", "Displacement", "Join", "KEPLER_MAX_STEPS", "KEPLER_STEP_TOL", "LAWS", "Law", "LawBreak",
    "MODIFIED_CYCLOID_TILT", "MotionProgram", "ORDER_NAMES", "PROGRAM_KEY", "Peaks", "SMOOTH", "Segment", "constant_velocity",
    "polynomial",
    # issue 26 LAWS
    "ACCEL_FRACTION_CATALOGUE", "SCCA_CATALOGUE", "asymmetric_modified_sine", "asymmetric_modified_trapezoid", "scca_law",
    "bspline", "polynomial_through", "velocity_blend",  # SPLINE (issue 26)
]

TWO_PI = 2.0 * math.pi
#: names of the derivative orders 0..3, for messages
ORDER_NAMES = ("displacement", "velocity", "acceleration", "jerk")
#: continuity order meaning "continuous up to and including the jerk"
SMOOTH = 3


@runtime_checkable
class Displacement(Protocol):
    """A follower displacement over one cam turn (period 2 pi), vectorised.

    ``breaks``: cam angles (rad), sorted, in ``[0, 2 pi)``: every segment join and every internal
    break of a law.  ``break_continuity``: int per break, the highest derivative order continuous
    there (0: s' jumps, 1: s'' jumps, 2: s''' jumps, 3: smooth to jerk).  At a break the value is
    the right-hand (following) piece's.
    """

    breaks: np.ndarray
    break_continuity: np.ndarray

    def __call__(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """s, ds/dtheta, d2s/dtheta2, d3s/dtheta3 at cam angles theta (rad, any real; periodic).
        s in the follower's unit: mm (translating) or rad (oscillating swing)."""
        ...


# --------------------------------------------------------------------------------------------
# pieces: S(tau) = offset + sign_out * F(w), w = sign_in * (tau - ref); F a polynomial plus
# sines (_Piece) or the tilted cycloid (_TiltedCyclePiece)
# --------------------------------------------------------------------------------------------
_MAX_ORDER = 5  # derivatives kept: 0..5 (the peak of the jerk needs the 4th)


@dataclass(frozen=True)
class _MappedPiece:
    """A piece of a law on ``[lo, hi]``: ``S(tau) = offset + sign_out F(w)``, ``w = sign_in (tau - ref)``.
    Subclasses give ``F`` and its derivatives in ``w`` (:meth:`_shape`); the mapping gives the
    time-reversed piece (:meth:`reversed`) without touching ``F``."""

    lo: float
    hi: float
    ref: float = field(default=0.0, kw_only=True)
    sign_in: float = field(default=1.0, kw_only=True)
    offset: float = field(default=0.0, kw_only=True)
    sign_out: float = field(default=1.0, kw_only=True)

    def _shape(self, w: np.ndarray, orders: Sequence[int]) -> list[np.ndarray]:
        """d^n F / dw^n for n in ``orders`` at ``w`` (arrays the caller may overwrite)."""
        raise NotImplementedError

    def values(self, tau: np.ndarray, orders: Sequence[int] = (0, 1, 2, 3)) -> list[np.ndarray]:
        """Derivatives d^n S / dtau^n for n in ``orders`` at ``tau`` (array)."""
        tau = np.asarray(tau, dtype=float)
        w = tau - self.ref if self.sign_in > 0 else self.ref - tau
        out = self._shape(w, orders)
        for i, n in enumerate(orders):
            factor = self.sign_out * self.sign_in**n
            if factor != 1.0:
                out[i] = out[i] * factor
            if n == 0 and self.offset:
                out[i] = out[i] + self.offset
        return out

    def derivative(self, tau: np.ndarray, n: int) -> np.ndarray:
        return self.values(tau, (n,))[0]

    def reversed(self, rise: float) -> _MappedPiece:
        """The piece of R(tau) = rise - S(1 - tau)."""
        return replace(self, lo=1.0 - self.hi, hi=1.0 - self.lo, ref=1.0 - self.ref, sign_in=-self.sign_in,
                       offset=rise - self.offset, sign_out=-self.sign_out)


def _basis(w: np.ndarray, degree: int, omegas: Sequence[float], phasors: Sequence[np.ndarray] | None = None) -> np.ndarray:
    """The rows ``1, w, .., w^degree, sin(om_1 w), cos(om_1 w), ..`` at ``w`` (m,): (degree + 1 +
    2 len(omegas), m), the basis of a polynomial-plus-trig piece (:class:`_Piece`).  ``phasors``:
    ``exp(i om w)`` per omega when known (a uniform grid: :func:`_uniform_phasors`), else the sines
    and cosines are computed."""
    basis = np.empty((degree + 1 + 2 * len(omegas), w.size))
    basis[0] = 1.0
    if degree:
        basis[1] = w
        for j in range(2, degree + 1):
            np.multiply(basis[j - 1], w, out=basis[j])
    for j, om in enumerate(omegas):
        row = degree + 1 + 2 * j
        if phasors is None:
            arg = om * w
            np.sin(arg, out=basis[row])
            np.cos(arg, out=basis[row + 1])
        else:
            basis[row] = phasors[j].imag
            basis[row + 1] = phasors[j].real
    return basis


@dataclass(frozen=True)
class _Piece(_MappedPiece):
    """``F(w) = sum_i poly[i] w^i + sum_m (a_m sin(omega_m w) + b_m cos(omega_m w))``."""

    poly: tuple[float, ...]
    trig: tuple[tuple[float, float, float], ...] = ()
    _unit_matrix: np.ndarray = field(init=False, repr=False, compare=False)
    omegas: tuple[float, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "omegas", tuple(om for om, _, _ in self.trig))
        # d^n F / dw^n (n = 0 .. _MAX_ORDER) in the basis of :func:`_basis`, one row per n
        poly = [float(c) for c in self.poly] or [0.0]
        degree = max((j for j, c in enumerate(poly) if c != 0.0), default=0)
        poly = poly[: degree + 1]
        rows = []
        for n in range(_MAX_ORDER + 1):
            row = poly + [0.0] * (degree + 1 - len(poly))
            for om, a, b in self.trig:
                for _ in range(n):  # d/dw (a sin + b cos) = (-b om) sin + (a om) cos
                    a, b = -b * om, a * om
                row += [a, b]
            rows.append(row)
            poly = [j * c for j, c in enumerate(poly)][1:] or [0.0]
        matrix = np.array(rows)
        matrix.flags.writeable = False
        object.__setattr__(self, "_unit_matrix", matrix)

    @property
    def degree(self) -> int:
        """Degree of the polynomial part (the powers 0 .. degree in the basis)."""
        return self._unit_matrix.shape[1] - 1 - 2 * len(self.trig)

    def _shape(self, w: np.ndarray, orders: Sequence[int]) -> list[np.ndarray]:
        flat = np.asarray(w, dtype=float).ravel()
        values = self._unit_matrix[list(orders)] @ _basis(flat, self.degree, self.omegas)
        return [v.reshape(np.shape(w)) for v in values]

    def scaled(self, k: float) -> _Piece:
        return replace(self, poly=tuple(k * c for c in self.poly), trig=tuple((om, k * a, k * b) for om, a, b in self.trig),
                       offset=k * self.offset)


#: Kepler solve of the tilted cycloid: Newton steps at most, and the step that counts as converged (rad)
KEPLER_MAX_STEPS = 12
KEPLER_STEP_TOL = 4e-16


@dataclass(frozen=True)
class _TiltedCyclePiece(_MappedPiece):
    """One piece ``S(tau)`` of a cycloid whose sine is laid off along a tilted direction (Wildt's
    modified cycloid; Rothbart, Cam Design Handbook, 2004, sec. 3, "modified cycloidal curve").

    Parametric in the cycloid's own angle ``E``: ``tau = (E - k sin E) / (2 pi)``,
    ``S = (E - sin E) / (2 pi)`` (``k = tilt``; ``k = 0`` is the plain cycloid).  ``E`` follows from
    ``tau`` by Kepler's equation ``E - k sin E = 2 pi tau`` (Newton, vectorised; ``k < 1`` keeps it
    monotone), then, with ``c = cos E``, ``s = sin E``, ``D = 1 - k c``, ``K = 1 - k``:
    ``V = (1 - c)/D``, ``A = 2 pi K s/D^3``, ``J = 4 pi^2 K (c + 2 k c^2 - 3 k)/D^5``,
    ``J' = -8 pi^3 K s (1 + 8 k c + 6 k^2 c^2 - 15 k^2)/D^7`` (each ``(2 pi / D) d/dE`` of the one
    before).
    """

    tilt: float

    def _eccentric(self, w: np.ndarray) -> np.ndarray:
        """E with E - k sin E = 2 pi w (Kepler's equation; Newton from E = M + k sin M)."""
        k = self.tilt
        mean = TWO_PI * w
        ecc = mean + k * np.sin(mean)
        for _ in range(KEPLER_MAX_STEPS):
            step = (ecc - k * np.sin(ecc) - mean) / (1.0 - k * np.cos(ecc))
            ecc -= step
            if not step.size or float(np.max(np.abs(step))) <= KEPLER_STEP_TOL * max(1.0, float(np.max(np.abs(mean)))):
                break
        return ecc

    def _shape(self, w: np.ndarray, orders: Sequence[int]) -> list[np.ndarray]:
        """n <= 4."""
        k, big_k = self.tilt, 1.0 - self.tilt
        ecc = self._eccentric(w)
        c, s = np.cos(ecc), np.sin(ecc)
        d = 1.0 - k * c
        out = []
        for n in orders:
            if n == 0:
                val = (ecc - s) / TWO_PI
            elif n == 1:
                val = (1.0 - c) / d
            elif n == 2:
                val = TWO_PI * big_k * s / d**3
            elif n == 3:
                val = TWO_PI**2 * big_k * (c + 2.0 * k * c * c - 3.0 * k) / d**5
            elif n == 4:
                val = -(TWO_PI**3) * big_k * s * (1.0 + 8.0 * k * c + 6.0 * k * k * c * c - 15.0 * k * k) / d**7
            else:
                raise ValueError(f"derivative order {n} > 4 of the tilted cycloid")
            out.append(val)
        return out



def _extrema(piece: _MappedPiece, n: int, samples: int = 257, iterations: int = 80) -> tuple[float, float, float, float]:
    """(min, tau_min, max, tau_max) of d^n S/dtau^n over the closed piece: samples, piece ends and the
    sign changes of the next derivative refined by bisection (vectorised)."""
    u = np.linspace(piece.lo, piece.hi, samples)
    g = piece.derivative(u, n + 1)
    sg = np.sign(g)
    k = np.flatnonzero(sg[:-1] * sg[1:] < 0)
    cand = u
    if k.size:
        a, b, ga = u[k].copy(), u[k + 1].copy(), sg[k].copy()
        for _ in range(iterations):
            mid = 0.5 * (a + b)
            same = np.sign(piece.derivative(mid, n + 1)) == ga
            a = np.where(same, mid, a)
            b = np.where(same, b, mid)
        cand = np.concatenate([u, 0.5 * (a + b)])
    f = piece.derivative(cand, n)
    i, j = int(np.argmin(f)), int(np.argmax(f))
    return float(f[i]), float(cand[i]), float(f[j]), float(cand[j])


#: Length of the short table of :func:`_uniform_phasors`.
_PHASOR_BLOCK = 64
#: Fewest uniform angles of one piece for which :meth:`MotionProgram.on_uniform_grid` takes the
#: sines and cosines from :func:`_uniform_phasors` (its fixed cost, ~6 us, is that of a direct sine
#: and cosine of ~500 angles on the machine of benchmarks/RESULTS.md).
_PHASOR_MIN_POINTS = 640
#: Grids whose values :meth:`MotionProgram.on_uniform_grid` keeps on the program (the dense check
#: grid and the coarse screening grid of a cam, a few more for a sizing search): all are dropped
#: when this many are kept.
_GRID_MEMO_SIZE = 4
#: Calls of :meth:`MotionProgram.__call__` whose values the program keeps: at most this many angles
#: (a cam's motion samples, the zero mark, the angles its checks probe), asked for a second time,
#: among the last this many distinct calls.
_CALL_MEMO_ANGLES = 4096
_CALL_MEMO_SIZE = 16
#: The attributes in which a program keeps values (not pickled).
#: The attribute in which camgen.synthesis.advice_cache keeps a program's key (made once per program).
PROGRAM_KEY = "_advice_law_key"
_KEPT_VALUES = ("_call_memo", "_grid_memo", "_order_memo", "_peaks", "_sample_memo", "_places_key", PROGRAM_KEY)


def _uniform_phasors(first: float, step: float, m: int) -> np.ndarray:
    """``exp(i (first + j step))`` for j = 0 .. m - 1 (complex (m,)) as the products
    ``exp(i (first + B r step)) exp(i l step)`` (``j = B r + l``) of two short tables of direct
    cosines and sines (angle addition: one rounding of the product, within a few ulps)."""
    rows = -(-m // _PHASOR_BLOCK)
    a = first + np.arange(rows) * (_PHASOR_BLOCK * step)
    b = np.arange(_PHASOR_BLOCK) * step
    big = np.empty(rows, dtype=complex)
    np.cos(a, out=big.real)
    np.sin(a, out=big.imag)
    small = np.empty(_PHASOR_BLOCK, dtype=complex)
    np.cos(b, out=small.real)
    np.sin(b, out=small.imag)
    return np.multiply.outer(big, small).ravel()[:m]


def _piece_basis(tau: np.ndarray, span: float, ref: float, forward: bool, omegas: tuple[float, ...], degree: int,
                 step: float | None) -> np.ndarray:
    """:func:`_basis` of a plan entry (:meth:`MotionProgram._plan`) at ``tau`` (its segment's
    fraction, (m,)): the piece's own variable ``w`` from ``tau``, the piece's ``ref`` and direction;
    ``step``: the cam angles are uniform with this step (rad), the sines and cosines then come from
    :func:`_uniform_phasors`."""
    w = tau if forward and ref == 0.0 else (tau - ref if forward else ref - tau)
    phasors = None
    if step is not None:  # om w_j = om w_0 + j (+-om step / span)
        phasors = [_uniform_phasors(om * w[0], (om if forward else -om) * step / span, w.size) for om in omegas]
    return _basis(w, degree, omegas, phasors)


#: Bases :func:`_uniform_basis` keeps (a piece on the dense check grid and on the coarse grid of a
#: few programs' places: at most about this many times 7,200 x 10 floats).
_UNIFORM_BASIS_CACHE = 24


@functools.lru_cache(maxsize=_UNIFORM_BASIS_CACHE)
def _uniform_basis(n: int, lo: int, hi: int, start: float, span: float, ref: float, forward: bool,
                   omegas: tuple[float, ...], degree: int) -> np.ndarray:
    """:func:`_piece_basis` at the uniform cam angles ``k 2 pi / n`` (k = lo .. hi - 1, rad) of a
    piece of a segment starting at ``start`` over ``span`` (rad): the same numbers
    :meth:`MotionProgram._fill` makes there, read-only, kept (a pure function of its arguments:
    the designs of a sweep that changes only lifts share them)."""
    step = TWO_PI / n
    tau = np.arange(n)[lo:hi] * step - start
    tau /= span
    basis = _piece_basis(tau, span, ref, forward, omegas, degree, step)
    basis.setflags(write=False)
    return basis


def _sorted_angles(th: np.ndarray, piece_lo: np.ndarray) -> tuple[np.ndarray, np.ndarray | None, list[int]]:
    """The cam angles ``th`` (rad, (m,), finite) brought onto ``[0, 2 pi)`` and sorted, the order
    that sorted them (None: already sorted) and the bounds of the evaluation pieces starting at
    ``piece_lo`` (rad) in them (:meth:`MotionProgram._values`: at a break the right-hand piece)."""
    if th.size:
        low, high = float(th.min()), float(th.max())
        if not (math.isfinite(low) and math.isfinite(high)):
            raise ParameterError("theta", "non-finite cam angles", "finite angles in rad")
        # np.mod(theta, 2 pi) is theta itself on [0, 2 pi) and theta + 2 pi on [-2 pi, 0)
        if low < 0.0 or high >= TWO_PI:
            if low >= -TWO_PI and high < TWO_PI:
                th = np.where(th < 0.0, th + TWO_PI, th)
                th += 0.0  # np.mod gives +0.0 for -0.0
            else:
                th = np.mod(th, TWO_PI)
            th[th >= TWO_PI] -= TWO_PI  # np.mod(-1e-300, 2 pi) == 2 pi
    order = None
    ths = th
    if len(piece_lo) == 1:
        bounds = [0, th.size]
    else:
        if th.size > 1 and not bool((th[1:] >= th[:-1]).all()):  # not sorted (a check grid is): sort
            order = np.argsort(th)  # (the order among equal angles does not matter)
            ths = th[order]
        # the right-hand piece at a break: a piece starts at the first angle >= its start
        bounds = [0] + np.searchsorted(ths, piece_lo[1:], side="left").tolist() + [th.size]
    return ths, order, bounds


@dataclass(frozen=True)
class _Places:
    """Where a motion program's evaluation pieces lie: ``key``, the bytes of their starts and, per
    plan entry, of its segment's start and span, its ``ref``, direction, degree and trig
    frequencies (signed zeros kept); hashed and compared by ``key`` alone.  ``bases``: per plan
    entry ``(start, span, ref, forward, omegas, degree)`` of :func:`_piece_basis`, or None for a
    piece evaluated without a basis (a constant, the tilted cycloid)."""

    key: bytes
    piece_lo: np.ndarray = field(compare=False)
    bases: tuple[tuple[float, float, float, bool, tuple[float, ...], int] | None, ...] = field(compare=False)


#: Angle layouts :func:`_angle_layout` keeps (the angles a design asks its law at: the motion
#: samples, the contour's knots and probes, the joints; at most 4,096 angles each, or a sample grid).
_ANGLE_LAYOUT_CACHE = 16


@functools.lru_cache(maxsize=_ANGLE_LAYOUT_CACHE)
def _angle_layout(angles: bytes | int, places: _Places) -> tuple[np.ndarray, np.ndarray | None, tuple[int, ...],
                                                                   tuple[np.ndarray | None, ...]]:
    """:func:`_sorted_angles` of the cam angles ``angles`` (their float64 bytes, or ``n`` for
    ``2 pi arange(n) / n``) for pieces at ``places``, and per plan entry the basis
    :meth:`MotionProgram._fill` multiplies its matrix by there (None: the entry evaluates itself),
    every array read-only: a pure function of its arguments, the same numbers ``_fill`` makes (the
    programs of a sweep that changes only lifts share them; only their matrices differ)."""
    th = np.frombuffer(angles, dtype=float) if isinstance(angles, bytes) else 2.0 * math.pi * np.arange(angles) / angles
    ths, order, bounds = _sorted_angles(th, places.piece_lo)
    bases: list[np.ndarray | None] = []
    for g, place in enumerate(places.bases):
        lo, hi = bounds[g], bounds[g + 1]
        if place is None or lo >= hi:
            bases.append(None)
            continue
        start, span, ref, forward, omegas, degree = place
        tau = ths[lo:hi] - start
        tau /= span
        basis = _piece_basis(tau, span, ref, forward, omegas, degree, None)
        basis.setflags(write=False)
        bases.append(basis)
    ths.setflags(write=False)
    if order is not None:
        order.setflags(write=False)
    return ths, order, tuple(bounds), tuple(bases)


#: Grid layouts :func:`_grid_layout` keeps (a cam's dense check grid and coarse grid, a few more).
_GRID_LAYOUT_CACHE = 8


@functools.lru_cache(maxsize=_GRID_LAYOUT_CACHE)
def _grid_layout(n: int, extra: bytes, places: _Places) -> tuple[tuple[int, int, int, int, np.ndarray | None, np.ndarray | None], ...]:
    """Per plan entry of a program whose pieces lie at ``places``: its uniform angles ``k 2 pi / n``
    (``lo .. hi - 1``), its columns ``elo .. ehi - 1`` among the added angles ``extra`` (their
    float64 bytes, sorted, on ``[0, 2 pi)``), and the bases :meth:`MotionProgram.on_uniform_grid`
    multiplies its matrix by: the uniform part's (:func:`_uniform_basis`, or the direct one of
    :meth:`MotionProgram._fill` with its step where it does not key) and the added angles' (None:
    none); a piece of fewer than :data:`_PHASOR_MIN_POINTS` uniform angles: None and the basis of
    its uniform and added angles together; a piece evaluated without a basis: None, None.  Every
    array read-only: a pure function of its arguments, the numbers ``on_uniform_grid`` made per
    program (the programs of a sweep that changes only lifts share them)."""
    added = np.frombuffer(extra, dtype=float)
    step = TWO_PI / n
    grid = np.arange(n) * step
    starts = places.piece_lo[1:]
    bounds = [0] + np.searchsorted(grid, starts, side="left").tolist() + [n]
    extra_bounds = [0] + np.searchsorted(added, starts, side="left").tolist() + [added.size]
    out = []
    for g, place in enumerate(places.bases):
        lo, hi = bounds[g], bounds[g + 1]
        elo, ehi = n + extra_bounds[g], n + extra_bounds[g + 1]
        uniform = together = None
        if place is not None:
            start, span, ref, forward, omegas, degree = place
            if hi - lo >= _PHASOR_MIN_POINTS:
                if math.copysign(1.0, ref) < 0.0:  # (a -0.0 ref keys as 0.0: made as _fill makes it)
                    tau = grid[lo:hi] - start
                    tau /= span
                    uniform = _piece_basis(tau, span, ref, forward, omegas, degree, step)
                    uniform.setflags(write=False)
                else:
                    uniform = _uniform_basis(n, lo, hi, start, span, ref, forward, omegas, degree)
                if elo < ehi:
                    tau = added[elo - n: ehi - n] - start
                    tau /= span
                    together = _piece_basis(tau, span, ref, forward, omegas, degree, None)
            else:
                tau = np.concatenate([grid[lo:hi], added[elo - n: ehi - n]]) - start
                tau /= span
                together = _piece_basis(tau, span, ref, forward, omegas, degree, None)
            if together is not None:
                together.setflags(write=False)
        out.append((lo, hi, elo, ehi, uniform, together))
    return tuple(out)


def _grouped(idx: np.ndarray, count: int) -> tuple[np.ndarray | None, np.ndarray]:
    """Group points by piece index: (permutation or None if already grouped, bounds of each group)."""
    idx = idx.astype(np.int16 if count < 32000 else np.int64)
    bounds = np.concatenate([[0], np.cumsum(np.bincount(idx, minlength=count))])
    if idx.size < 2 or bool(np.all(idx[1:] >= idx[:-1])):
        return None, bounds
    return np.argsort(idx, kind="stable"), bounds


def _ungroup(res: list[np.ndarray], order: np.ndarray | None) -> list[np.ndarray]:
    if order is None:
        return res
    out = [np.empty(r.shape) for r in res]
    for o, r in zip(out, res):
        o[order] = r
    return out


# --------------------------------------------------------------------------------------------
# laws
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class LawBreak:
    """An internal break of a law at ``tau``: ``jumps`` is the order of the lowest derivative that
    jumps there (1: V, 2: A, 3: J, 4: only beyond the jerk)."""

    tau: float
    jumps: int

    @property
    def continuity(self) -> int:
        """Highest derivative order continuous at the break (``jumps - 1``, at most 3)."""
        return min(self.jumps - 1, SMOOTH)


@dataclass(frozen=True)
class _LawSummary:
    """What :class:`Law` finds about itself on first use (see its attributes)."""

    s_range: tuple[float, float, float, float]
    peaks: tuple[tuple[float, float], ...]
    start: tuple[float, float, float, float]
    end: tuple[float, float, float, float]
    cv: float
    ca: float
    cj: float


@dataclass(frozen=True, eq=False)
class Law:
    """A motion law on the normalised segment ``tau in [0, 1]``.

    Attributes
    ----------
    name : str
        Canonical name (a key of :data:`LAWS`).
    pieces : tuple
        The closed-form pieces (internal; see :meth:`evaluate`).
    breaks : tuple of LawBreak
        Internal breaks (tau strictly inside (0, 1)) and the derivative order that jumps there.
    source : str
        Where the formula comes from.
    options : dict
        The options this law was configured with (e.g. ``{"blend": 0.2}``).
    start, end : tuple of 4 floats
        Exact (S, V, A, J) at ``tau = 0`` (right limit) and ``tau = 1`` (left limit); entries below
        1e-12 of the law's peak are rounding of ``sin(2 pi)`` and similar and are set to 0.
    peaks : tuple of 3 (value, tau)
        ``max |V|``, ``max |A|``, ``max |J|`` over the segment (one-sided at breaks) and where.
    cv, ca, cj : float
        Norton's peak coefficients for a rise between two dwells: ``inf`` where the next-lower
        derivative jumps at an end or at an internal break (an impulse).
    s_range : (min S, tau, max S, tau)
    """

    name: str
    pieces: tuple[_MappedPiece, ...]
    breaks: tuple[LawBreak, ...] = ()
    source: str = ""
    options: Mapping[str, object] = field(default_factory=dict)
    exact_ends: tuple[tuple[float, ...], tuple[float, ...]] | None = field(default=None, repr=False)
    builder: Callable[..., Law] | None = field(default=None, repr=False)
    _los: np.ndarray = field(init=False, repr=False)  # each piece's lower tau end (n,), for evaluate's search

    def __post_init__(self) -> None:
        object.__setattr__(self, "_los", np.array([p.lo for p in self.pieces]))

    # The extrema, the exact ends and the peak coefficients are found on first use (a search over
    # every piece and derivative: ~3 ms a law), so importing the catalogue costs nothing for the
    # laws a run does not use.
    @property
    def start(self) -> tuple[float, float, float, float]:
        return self._summary.start

    @property
    def end(self) -> tuple[float, float, float, float]:
        return self._summary.end

    @property
    def peaks(self) -> tuple[tuple[float, float], ...]:
        return self._summary.peaks

    @property
    def s_range(self) -> tuple[float, float, float, float]:
        return self._summary.s_range

    @property
    def cv(self) -> float:
        return self._summary.cv

    @property
    def ca(self) -> float:
        return self._summary.ca

    @property
    def cj(self) -> float:
        return self._summary.cj

    @functools.cached_property
    def _summary(self) -> "_LawSummary":
        ext = []
        for n in range(4):
            per_piece = [_extrema(p, n) for p in self.pieces]
            lo = min(per_piece, key=lambda e: e[0])
            hi = max(per_piece, key=lambda e: e[2])
            ext.append((lo[0], lo[1], hi[2], hi[3]))
        peaks = []
        for n in (1, 2, 3):
            mn, tmn, mx, tmx = ext[n]
            peaks.append((abs(mn), tmn) if abs(mn) > abs(mx) else (abs(mx), tmx))
        if self.exact_ends is not None:
            start, end = (tuple(float(x) for x in e) for e in self.exact_ends)
        else:
            zero = np.zeros(1)
            start = tuple(float(v[0]) for v in self.pieces[0].values(zero))
            end = tuple(float(v[0]) for v in self.pieces[-1].values(zero + 1.0))
            scale = (max(1.0, abs(ext[0][0]), abs(ext[0][2])),) + tuple(max(1.0, p[0]) for p in peaks)
            start = tuple(0.0 if abs(x) <= 1e-12 * s else x for x, s in zip(start, scale))
            end = tuple(0.0 if abs(x) <= 1e-12 * s else x for x, s in zip(end, scale))
            if abs(end[0] - round(end[0])) <= 1e-12:  # S(1) = 1 (a rise) or 0 (a dwell) up to rounding
                end = (float(round(end[0])),) + end[1:]
        # Norton's convention: a rise between two dwells
        v_impulse = start[1] != 0 or end[1] != 0 or any(b.jumps <= 1 for b in self.breaks)
        a_impulse = v_impulse or start[2] != 0 or end[2] != 0 or any(b.jumps <= 2 for b in self.breaks)
        s0, v0, a0, j0 = start
        s1, v1, a1, j1 = end
        return _LawSummary(ext[0], tuple(peaks), (s0, v0, a0, j0), (s1, v1, a1, j1), peaks[0][0],
                           math.inf if v_impulse else peaks[1][0], math.inf if a_impulse else peaks[2][0])

    # -- evaluation ---------------------------------------------------------------------------
    def evaluate(self, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(S, V, A, J) at ``tau`` (array, nominally in [0, 1]; at an internal break the right-hand
        piece).  Closed form, vectorised over ``tau``."""
        tau = np.asarray(tau, dtype=float)
        if len(self.pieces) == 1:
            s, v, a, j = self.pieces[0].values(tau)
            return s, v, a, j
        flat = tau.ravel()
        idx = np.clip(np.searchsorted(self._los, flat, side="right") - 1, 0, len(self.pieces) - 1)
        order, bounds = _grouped(idx, len(self.pieces))
        ts = flat if order is None else flat[order]
        res = [np.empty(flat.shape) for _ in range(4)]
        for k, piece in enumerate(self.pieces):
            lo, hi = bounds[k], bounds[k + 1]
            if lo < hi:
                for r, v in zip(res, piece.values(ts[lo:hi])):
                    r[lo:hi] = v
        out = [o.reshape(tau.shape) for o in _ungroup(res, order)]
        return out[0], out[1], out[2], out[3]

    def __call__(self, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return self.evaluate(tau)

    # -- variants -----------------------------------------------------------------------------
    def reversed(self) -> Law:
        """The time-reversed law ``R(tau) = S(1) - S(1 - tau)`` (a return runs the rise backwards);
        made once per law (a law is immutable; its peaks take a few ms to find)."""
        cached = self.__dict__.get("_reversed")
        if cached is not None:
            return cached
        rise = self.end[0]
        s, e = self.start, self.end
        sign = (0, 1, -1, 1)  # R^(n)(0) = -(-1)^n S^(n)(1) for n >= 1
        start = (0.0,) + tuple(sign[n] * e[n] for n in (1, 2, 3))
        end = (rise,) + tuple(sign[n] * s[n] for n in (1, 2, 3))
        out = Law(self.name, tuple(p.reversed(rise) for p in reversed(self.pieces)),
                  tuple(LawBreak(1.0 - b.tau, b.jumps) for b in reversed(self.breaks)), self.source,
                  dict(self.options, reversed=True), (start, end), None)
        object.__setattr__(self, "_reversed", out)
        return out

    def configure(self, **options: object) -> Law:
        """This law with ``options`` (e.g. ``blend`` for constant_velocity; ``start``/``end`` for
        polynomial, in tau units); a law without options refuses any."""
        if not options:
            return self
        if self.builder is None:
            key = min(options)
            raise ParameterError(key, options[key], f"no option for the {self.name} law")
        return self.builder(**options)


def _integrate(edges: Sequence[float], accel: Sequence[tuple[tuple[float, ...], tuple[tuple[float, float, float], ...]]]) -> list[_Piece]:
    """Pieces of S from a piecewise acceleration (poly in the local u = tau - lo plus sin/cos terms),
    integrated in closed form with S(0) = V(0) = 0 and S, V continuous, then scaled to S(1) = 1."""
    s0 = v0 = 0.0
    pieces = []
    for k, (poly_a, trig_a) in enumerate(accel):
        lo, hi = edges[k], edges[k + 1]
        poly = [0.0, 0.0] + [c / ((i + 1) * (i + 2)) for i, c in enumerate(poly_a)]
        trig = tuple((om, -a / om**2, -b / om**2) for om, a, b in trig_a)
        poly[0] = s0 - sum(b for _, _, b in trig)  # S(0) = s0
        poly[1] = v0 - sum(a * om for om, a, _ in trig)  # V(0) = v0
        piece = _Piece(lo, hi, tuple(poly), trig, ref=lo)
        end = piece.values(np.array([hi]), (0, 1))
        s0, v0 = float(end[0][0]), float(end[1][0])
        pieces.append(piece)
    return [p.scaled(1.0 / s0) for p in pieces]


def constant_velocity(blend: object = 0.0) -> Law:
    """Constant velocity, plain (``blend = 0``: ``S = tau``, velocity 1 at both ends) or with end
    blends over the fraction ``blend`` (0 < blend <= 1/2) of the span each (see the module notes)."""
    b = require_finite("blend", blend)
    if not 0.0 <= b <= 0.5:
        raise ParameterError("blend", blend, "0 <= blend <= 0.5 (fraction of the span in each end blend)")
    if b == 0.0:
        return Law("constant_velocity", (_Piece(0.0, 1.0, (0.0, 1.0)),), (),
                   "Norton, Design of Machinery, ch. 8 (constant velocity: infinite acceleration at the ends)",
                   {"blend": 0.0}, builder=constant_velocity)
    w = TWO_PI / b
    # acceleration per piece (u = tau - lo): (1 - cos(w u)); 0; -(1 - cos(w u))
    edges = [0.0, b, 1.0 - b, 1.0] if b < 0.5 else [0.0, 0.5, 1.0]
    accel = [((1.0,), ((w, 0.0, -1.0),))] + ([((0.0,), ())] if b < 0.5 else []) + [((-1.0,), ((w, 0.0, 1.0),))]
    pieces = _integrate(edges, accel)
    return Law("constant_velocity", tuple(pieces), tuple(LawBreak(t, 4) for t in edges[1:-1]),
               "camgen: cycloidal-velocity blends (acceleration 1 - cos pulses), see module notes",
               {"blend": b}, builder=constant_velocity)


def _falling(i: int, k: int) -> int:
    """i! / (i - k)! (0 for k > i): the k-th derivative factor of tau^i at tau = 1."""
    return math.perm(i, k) if k <= i else 0


def polynomial(start: Sequence[float], end: Sequence[float]) -> Law:
    """The polynomial of lowest degree with ``d^k S/dtau^k (0) = start[k]`` and ``(1) = end[k]``.

    ``start``/``end``: 1..4 values each (S, V, A, J in tau units; ``start[0]`` is normally 0);
    degree ``len(start) + len(end) - 1``.  The coefficients come from the Hermite conditions solved
    exactly in rational arithmetic (the floats are converted exactly), then rounded once.
    """
    start_q = [Fraction(require_finite("start", x)) for x in start]
    end_q = [Fraction(require_finite("end", x)) for x in end]
    m0, m1 = len(start_q), len(end_q)
    if not (1 <= m0 <= 4 and 1 <= m1 <= 4):
        raise ParameterError("polynomial conditions", (m0, m1), "1 to 4 values (s, v, a, j) at each end")
    n = m0 + m1
    c = [Fraction(0)] * n
    for k in range(m0):
        c[k] = start_q[k] / math.factorial(k)
    # end conditions: sum_i c_i i!/(i-k)! = end[k]; unknowns c[m0:] (Gaussian elimination, exact)
    rows = [[Fraction(_falling(m0 + j, k)) for j in range(m1)] + [end_q[k] - sum(c[i] * _falling(i, k) for i in range(m0))]
            for k in range(m1)]
    for col in range(m1):
        piv = next(r for r in range(col, m1) if rows[r][col] != 0)  # the Hermite system is regular
        rows[col], rows[piv] = rows[piv], rows[col]
        for r in range(m1):
            if r != col and rows[r][col] != 0:
                f = rows[r][col] / rows[col][col]
                rows[r] = [x - f * y for x, y in zip(rows[r], rows[col])]
    for j in range(m1):
        c[m0 + j] = rows[j][m1] / rows[j][j]
    at0 = tuple(float(c[k] * math.factorial(k)) if k < n else 0.0 for k in range(4))
    at1 = tuple(float(sum(c[i] * _falling(i, k) for i in range(k, n))) for k in range(4))
    ends = (at0, at1)
    return Law("polynomial", (_Piece(0.0, 1.0, tuple(float(x) for x in c)),), (),
               "Norton, Design of Machinery, ch. 8 (polynomial functions from boundary conditions)",
               {"start": tuple(float(x) for x in start_q), "end": tuple(float(x) for x in end_q), "degree": n - 1},
               ends, polynomial)


def _mod_trapezoid() -> Law:
    # Norton, Design of Machinery, ch. 8, modified trapezoidal acceleration: quarter sines of period
    # 1/2 joined by constant acceleration; the half sine over [3/8, 5/8] is one piece (analytic there)
    w = 4.0 * math.pi
    edges = [0.0, 1 / 8, 3 / 8, 5 / 8, 7 / 8, 1.0]
    accel = [((0.0,), ((w, 1.0, 0.0),)), ((1.0,), ()), ((0.0,), ((w, 0.0, 1.0),)), ((-1.0,), ()), ((0.0,), ((w, 0.0, -1.0),))]
    return Law("modified_trapezoid", tuple(_integrate(edges, accel)), tuple(LawBreak(t, 4) for t in edges[1:-1]),
               "Norton, Design of Machinery, ch. 8 (modified trapezoidal acceleration; Table 8-3)")


def _mod_sine() -> Law:
    # Norton, Design of Machinery, ch. 8, modified sinusoidal acceleration: a quarter sine of period
    # 1/2 at each end and a half sine of period 3/2 over [1/8, 7/8]
    w1, w2 = 4.0 * math.pi, 4.0 * math.pi / 3.0
    edges = [0.0, 1 / 8, 7 / 8, 1.0]
    accel = [((0.0,), ((w1, 1.0, 0.0),)), ((0.0,), ((w2, 0.0, 1.0),)), ((0.0,), ((w1, 0.0, -1.0),))]
    return Law("modified_sine", tuple(_integrate(edges, accel)), tuple(LawBreak(t, 4) for t in edges[1:-1]),
               "Norton, Design of Machinery, ch. 8 (modified sinusoidal acceleration; Table 8-3)")


#: Wildt's modified cycloid: tilt ``k`` of the direction along which the cycloid's sine is laid off
#: (``tau = t - k sin(2 pi t)/(2 pi)``): the tilt that minimises the peak acceleration, 1 - sqrt(3)/2.
#: Rothbart's construction (Cam Design Handbook, sec. 3, Fig. 3.12b; its text here ends at "the base
#: of the sine curve is then constructed") joins M (the middle of the first half of the
#: constant-velocity line) to a point D at "0.57 of beta/2".  Our reading: the sine is laid off
#: along DM with D at mid-stroke, which makes ``0.5 + k/2 = 0.567`` the handbook's 0.57 to two
#: digits (the opposite tilt would raise Ca to 7.7, above the plain cycloid's 6.28).
MODIFIED_CYCLOID_TILT = 1.0 - math.sqrt(3.0) / 2.0


def _mod_cycloid() -> Law:
    return Law("modified_cycloidal", (_TiltedCyclePiece(0.0, 1.0, MODIFIED_CYCLOID_TILT),), (),
               "Rothbart, Cam Design Handbook (2004), sec. 3: Wildt's modified cycloidal curve (the sine laid off "
               "along the acceleration-minimising tilt 1 - sqrt(3)/2; the handbook's point D at 0.57 beta/2)")


def _single(name: str, poly: tuple[float, ...], trig: tuple[tuple[float, float, float], ...], source: str) -> Law:
    return Law(name, (_Piece(0.0, 1.0, poly, trig),), (), source)


_PI = math.pi
_CANONICAL: dict[str, Law] = {
    "dwell": _single("dwell", (0.0,), (), "a dwell: S = 0"),
    "constant_velocity": constant_velocity(0.0),
    # Norton ch. 8, simple harmonic motion: S = (1 - cos(pi tau)) / 2
    "simple_harmonic": _single("simple_harmonic", (0.5,), ((_PI, 0.0, -0.5),), "Norton, Design of Machinery, ch. 8 (simple harmonic motion)"),
    # Norton ch. 8, single-dwell double harmonic rise: S = (1 - cos(pi tau))/2 - (1 - cos(2 pi tau))/8
    "double_harmonic": _single("double_harmonic", (0.375,), ((_PI, 0.0, -0.5), (2 * _PI, 0.0, 0.125)),
                               "Norton, Design of Machinery, ch. 8 (double harmonic, single-dwell rise and fall)"),
    # Norton ch. 8, cycloidal displacement: S = tau - sin(2 pi tau) / (2 pi)
    "cycloidal": _single("cycloidal", (0.0, 1.0), ((2 * _PI, -1.0 / (2 * _PI), 0.0),), "Norton, Design of Machinery, ch. 8 (cycloidal displacement)"),
    "modified_trapezoid": _mod_trapezoid(),
    "modified_sine": _mod_sine(),
    "modified_cycloidal": _mod_cycloid(),
    # Norton ch. 8, the 3-4-5 and 4-5-6-7 polynomials (rest to rest)
    "poly345": _single("poly345", (0, 0, 0, 10.0, -15.0, 6.0), (), "Norton, Design of Machinery, ch. 8 (3-4-5 polynomial)"),
    "poly4567": _single("poly4567", (0, 0, 0, 0, 35.0, -84.0, 70.0, -20.0), (), "Norton, Design of Machinery, ch. 8 (4-5-6-7 polynomial)"),
    # the default conditions give the rest-to-rest quintic (= poly345); segments pass their own
    "polynomial": polynomial((0.0, 0.0, 0.0), (1.0, 0.0, 0.0)),
}

# ---- issue 26 LAWS: constant acceleration, trapezoidal, SCCA, skewed modified sine / trapezoid ------------
# (their accelerations: camgen.synthesis.laws_scca; here they become laws and join the catalogue)
def _planned(name: str, plan: laws_scca.AccelerationPlan, source: str, options: Mapping[str, object] | None = None,
             builder: Callable[..., Law] | None = None) -> Law:
    """The law whose acceleration is ``plan``'s, integrated in closed form from rest to S(1) = 1."""
    return Law(name, tuple(_integrate(plan.edges, plan.accel)), tuple(LawBreak(t, j) for t, j in plan.breaks), source,
               dict(options or {}), builder=builder)


def scca_law(scca: object) -> Law:
    """The SCCA law of ``scca = (b, c, d)`` (fractions of the span, b + c + d = 1; Norton, Design of
    Machinery, 2nd ed., sec. 8.3): see :mod:`camgen.synthesis.laws_scca`."""
    b, c, d = laws_scca.scca_parameters(scca)
    return _planned("scca", laws_scca.scca_plan(b, c, d),
                    "Norton, Design of Machinery, 2nd ed., sec. 8.3 (SCCA family, eqs. 8.21-8.24)", {"scca": (b, c, d)}, scca_law)


_SKEWED_SOURCE = "Rothbart, Cam Design Handbook (2004), sec. 3 (skewed modified trapezoidal curve, Fig. 3.7, eqs. 3.10-3.13)"


def asymmetric_modified_sine(accel_fraction: object) -> Law:
    """The skewed modified sine: its positive acceleration over ``accel_fraction`` of the span."""
    f = laws_scca.accel_fraction_value(accel_fraction)
    return _planned("asymmetric_modified_sine", laws_scca.asymmetric_modified_sine_plan(f),
                    _SKEWED_SOURCE + ", applied to the modified sine", {"accel_fraction": f}, asymmetric_modified_sine)


def asymmetric_modified_trapezoid(accel_fraction: object) -> Law:
    """The skewed modified trapezoid: its positive acceleration over ``accel_fraction`` of the span."""
    f = laws_scca.accel_fraction_value(accel_fraction)
    return _planned("asymmetric_modified_trapezoid", laws_scca.asymmetric_modified_trapezoid_plan(f), _SKEWED_SOURCE,
                    {"accel_fraction": f}, asymmetric_modified_trapezoid)


#: The catalogue's SCCA member and skewed fraction (a segment gives its own: the keys are required).
SCCA_CATALOGUE = (0.2, 0.3, 0.5)
ACCEL_FRACTION_CATALOGUE = 0.4
_CANONICAL.update({
    # Norton ch. 8, constant (parabolic) acceleration: S = 2 tau^2, then 1 - 2 (1 - tau)^2
    "constant_acceleration": Law("constant_acceleration", (_Piece(0.0, 0.5, (0.0, 0.0, 2.0)),
                                                           _Piece(0.5, 1.0, (0.5, 2.0, -2.0), ref=0.5)),
                                 (LawBreak(0.5, 2),), "Norton, Design of Machinery, ch. 8 (constant acceleration, parabolic)"),
    "trapezoidal": _planned("trapezoidal", laws_scca.trapezoidal_plan(),
                            "Norton, Design of Machinery, ch. 8 (trapezoidal acceleration; linear ramps over 1/8 of the span)"),
    "scca": scca_law(SCCA_CATALOGUE),
    "asymmetric_modified_sine": asymmetric_modified_sine(ACCEL_FRACTION_CATALOGUE),
    "asymmetric_modified_trapezoid": asymmetric_modified_trapezoid(ACCEL_FRACTION_CATALOGUE),
})
# ---- end of issue 26 LAWS ------------------------------------------------------------------------------------
# ---- SPLINE (issue 26, item 1): bspline, polynomial with interior conditions, velocity_blend ------------
# The numbers come from camgen.synthesis.laws_spline; here they become pieces and laws.  Every law
# below is in physical units on tau (like a configured polynomial: S(0) = 0, S(1) = the lift,
# V = dS/dtau, ...); the segment's scale is 1.
def _ordered_inside(name: str, taus: Sequence[float]) -> None:
    """Refuse interior abscissae (tau) not inside (0, 1) or not increasing, each at least
    MIN_SPACING from the ends and from the one before."""
    for k, t in enumerate(taus):
        if not (math.isfinite(t) and MIN_SPACING <= t <= 1.0 - MIN_SPACING):
            raise ParameterError(f"{name}[{k}]", t, f"a point strictly inside the segment's span ({MIN_SPACING:g} <= tau <= 1 - {MIN_SPACING:g})")
        if k and not t - taus[k - 1] >= MIN_SPACING:
            raise ParameterError(f"{name}[{k}]", t, f"at least {MIN_SPACING:g} of the span after {name}[{k - 1}] (at tau = "
                                 f"{taus[k - 1]:.9g}): points in increasing order")


def bspline(points: Sequence[Sequence[float]] = (), degree: int = 5, start: Sequence[float] = (0.0, 0.0, 0.0),
            end: Sequence[float] = (1.0, 0.0, 0.0)) -> Law:
    """The interpolating B-spline of odd ``degree`` (3, 5, 7) through ``points`` ((tau, S), inside
    (0, 1), increasing) with ``start`` / ``end`` = (S, V, ..) at the ends, ``(degree + 1)/2`` values
    each (tau units); knots at the points, C^(degree - 1) there (:func:`~camgen.synthesis.laws_spline.interpolating_spline`:
    scipy's make_interp_spline).  Without points: the one polynomial of that degree (degree 5, rest
    to rest: the 3-4-5)."""
    if isinstance(degree, bool) or not isinstance(degree, int) or degree not in SPLINE_DEGREES:
        raise ParameterError("degree", degree, "3, 5 or 7 (odd: the end conditions split evenly)")
    rows = []
    for k, row in enumerate(points):
        if isinstance(row, (str, bytes)) or not isinstance(row, Sequence) or len(row) != 2:
            raise ParameterError(f"points[{k}]", row, "[position, lift]: two numbers")
        rows.append((require_finite(f"points[{k}]", row[0]), require_finite(f"points[{k}]", row[1])))
    _ordered_inside("points", [t for t, _ in rows])
    conds = [tuple(require_finite(key, x) for x in values) for key, values in (("start", start), ("end", end))]
    made = interpolating_spline(rows, degree, conds[0], conds[1])
    pieces = tuple(_Piece(lo, hi, coeffs, ref=lo) for lo, hi, coeffs in zip(made.edges[:-1], made.edges[1:], made.coefficients))
    m = (degree - 1) // 2
    # exact ends: the conditions; the orders above them (the jerk of a quintic) from the end pieces
    first, last = pieces[0].values(np.zeros(1)), pieces[-1].values(np.ones(1))
    at0 = tuple(conds[0][n] if n <= m else float(first[n][0]) for n in range(4))
    at1 = tuple(conds[1][n] if n <= m else float(last[n][0]) for n in range(4))
    return Law("bspline", pieces, tuple(LawBreak(t, min(degree, 4)) for t in made.knots),
               f"interpolating B-spline of degree {degree} (scipy make_interp_spline, knots at the points; "
               "de Boor, A Practical Guide to Splines)",
               {"points": tuple(rows), "degree": degree, "start": conds[0], "end": conds[1]}, (at0, at1), bspline)


def _exact_law(name: str, poly: Polynomial, source: str, options: Mapping[str, object], builder: Callable[..., Law]) -> Law:
    """A one-piece law from an exact :class:`~camgen.synthesis.laws_spline.Polynomial` (ends exact)."""
    ends = [tuple(float(polynomial_derivative_at(poly, Fraction(t), n)) for n in range(4)) for t in (0, 1)]
    return Law(name, (_Piece(0.0, 1.0, poly.floats()),), (), source, dict(options, degree=poly.degree), (ends[0], ends[1]), builder)


def polynomial_through(start: Sequence[float], end: Sequence[float], interior: Sequence[Sequence[float]] = ()) -> Law:
    """The polynomial of lowest degree meeting ``start`` / ``end`` (S, V, A, J: 1 to 4 values, tau
    units) and the ``interior`` conditions ``(tau, S[, V[, A]])`` (0 < tau < 1, increasing): degree
    = number of conditions - 1 (at most 15).  Norton's single-dwell polynomial (Design of Machinery,
    ch. 8) is ``start = end = (0, 0, 0)``, ``interior = [(0.5, 1)]``: ``64 tau^3 - 192 tau^4 + 192 tau^5
    - 64 tau^6``."""
    conds = [tuple(require_finite(key, x) for x in values) for key, values in (("start", start), ("end", end))]
    for key, values in zip(("start", "end"), conds):
        if not 1 <= len(values) <= 4:
            raise ParameterError(key, list(values), "1 to 4 values (s, v, a, j)")
    rows = []
    for k, row in enumerate(interior):
        if isinstance(row, (str, bytes)) or not isinstance(row, Sequence) or not 2 <= len(row) <= 4:
            raise ParameterError(f"interior[{k}]", row, "[position, s] and optionally v, a: 2 to 4 numbers")
        rows.append(tuple(require_finite(f"interior[{k}]", x) for x in row))
    _ordered_inside("interior", [r[0] for r in rows])
    poly = hermite_polynomial([(0.0, conds[0]), (1.0, conds[1])] + [(r[0], r[1:]) for r in rows], "interior")
    return _exact_law("polynomial", poly, "Norton, Design of Machinery, ch. 8 (polynomial functions from boundary and interior "
                      "conditions)", {"start": conds[0], "end": conds[1], "interior": tuple(rows)}, polynomial_through)


def velocity_blend(start: Sequence[float] = (0.0, 0.0, 0.0), end: Sequence[float] = (0.0, 0.0, 0.0),
                   lift: float | None = 1.0) -> Law:
    """A blend from ``start`` = (V, A, J) at tau = 0 to ``end`` = (V, A, J) at tau = 1 (tau units):
    with ``lift``, the degree-7 polynomial with S(0) = 0, S(1) = lift; without (None), the
    lowest-degree one meeting only the six derivatives (its V the degree-5 Hermite polynomial, S its
    integral, degree 6): between two constant velocities V0, V1 its velocity ramps as the 3-4-5
    polynomial, ``V = V0 + (V1 - V0) (10 tau^3 - 15 tau^4 + 6 tau^5)``, and its lift is
    ``(V0 + V1)/2``.  Continuous up to the jerk against neighbours whose ends these are."""
    conds = []
    for key, values in (("start", start), ("end", end)):
        if isinstance(values, (str, bytes)) or not isinstance(values, Sequence) or len(values) != 3:
            raise ParameterError(key, values, "(velocity, acceleration, jerk): 3 numbers")
        conds.append(tuple(require_finite(key, x) for x in values))
    if lift is None:
        vel = hermite_polynomial([(0.0, conds[0]), (1.0, conds[1])], "ends")
        poly = Polynomial((Fraction(0),) + tuple(c / (i + 1) for i, c in enumerate(vel.coefficients)))
    else:
        poly = hermite_polynomial([(0.0, (0.0,) + conds[0]), (1.0, (require_finite("lift", lift),) + conds[1])], "ends")
    return _exact_law("velocity_blend", poly, "camgen: the lowest-degree polynomial meeting the neighbours' velocity, "
                      "acceleration and jerk (Norton, Design of Machinery, ch. 8, polynomial functions)",
                      {"start": conds[0], "end": conds[1], "lift": lift}, velocity_blend)


def _segment_rows(seg: "Segment", key: str, widths: tuple[int, int]) -> list[tuple[float, ...]]:
    """A segment's ``points`` / ``interior`` rows (position rad from the segment's start first),
    checked: ``widths`` numbers a row, the positions inside the span and increasing."""
    value = getattr(seg, key)
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
        raise ParameterError(seg._name(key), value, "a list of rows [position, ...]")
    rows = []
    for k, row in enumerate(value):
        if isinstance(row, (str, bytes)) or not isinstance(row, Sequence) or not widths[0] <= len(row) <= widths[1]:
            raise ParameterError(seg._name(f"{key}[{k}]"), row, f"{widths[0]} to {widths[1]} numbers" if widths[0] < widths[1]
                                 else f"{widths[0]} numbers")
        rows.append(tuple(require_finite(seg._name(f"{key}[{k}]"), x) for x in row))
    for k, row in enumerate(rows):
        if not 0.0 < row[0] < seg.span:
            raise ParameterError(seg._name(f"{key}[{k}]"), list(row), f"a position strictly inside the segment's span "
                                 f"(0 < position < {seg.span:.9g} rad)")
        if k and not row[0] > rows[k - 1][0]:
            raise ParameterError(seg._name(f"{key}[{k}]"), list(row), f"a position after {key}[{k - 1}]'s: rows in increasing order")
    return rows


def _spline_segment(seg: "Segment", name: str, span: float) -> tuple[Law, float | None, float | None, tuple | None, tuple | None]:
    """(shape, lift, start level, start, end) of a bspline, velocity_blend or polynomial-with-interior
    segment (per-rad conditions to tau units: ``d^k/dtau^k = span^k d^k/dtheta^k``)."""
    def tau_units(values: Sequence[float], level: float) -> tuple[float, ...]:
        return (values[0] - level,) + tuple(x * span**k for k, x in enumerate(values) if k)

    def checked_lift(lift: float) -> None:
        if seg.lift is not None:
            given = require_finite(seg._name("lift"), seg.lift)
            if abs(given - lift) > 1e-9 * max(1.0, abs(lift)):
                raise ParameterError(seg._name("lift"), seg.lift, f"end[0] - start[0] = {lift:g} (or omit it)")

    try:
        if name == "velocity_blend":
            if seg.start is not None or seg.end is not None:
                raise ParameterError(seg._name("start" if seg.start is not None else "end"), seg.start or seg.end,
                                     "no start/end for a velocity_blend segment (its ends are its neighbours')")
            lift = None if seg.lift is None else require_finite(seg._name("lift"), seg.lift)
            if seg.ends is None:  # not joined yet: MotionProgram gives it its neighbours' ends
                return velocity_blend((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), lift), lift, None, None, None
            ends = []
            for side in seg.ends:
                values = _conditions(seg._name("ends"), side)
                if len(values) != 3:
                    raise ParameterError(seg._name("ends"), seg.ends, "(v, a, j) per rad at each end")
                ends.append(tuple(x * span ** (k + 1) for k, x in enumerate(values)))
            shape = velocity_blend(ends[0], ends[1], lift)
            return shape, shape.end[0], None, None, None
        if seg.start is None and seg.end is None and name == "bspline":
            if seg.lift is None:
                raise ParameterError(seg._name("lift"), None, "a lift for a bspline segment (0: back to its start level), "
                                     "or its start and end conditions")
            lift = require_finite(seg._name("lift"), seg.lift)
            m = (5 if seg.degree is None else seg.degree) // 2
            start, end, level = (0.0,) * (m + 1), (lift,) + (0.0,) * m, None
        else:
            if seg.start is None or seg.end is None:
                raise ParameterError(seg._name("start" if seg.start is None else "end"), None,
                                     f"conditions at both ends of a {name} segment")
            start, end = _conditions(seg._name("start"), seg.start), _conditions(seg._name("end"), seg.end)
            lift, level = end[0] - start[0], start[0]
            checked_lift(lift)
        if name == "bspline":
            rows = _segment_rows(seg, "points", (2, 2)) if seg.points is not None else []
            shape = bspline([(t / span, s) for t, s in rows], 5 if seg.degree is None else seg.degree,
                            tau_units(start, start[0]), tau_units(end, start[0]))
        else:
            rows = _segment_rows(seg, "interior", (2, 4))
            base = start[0]
            shape = polynomial_through(tau_units(start, base), tau_units(end, base),
                                       [(r[0] / span, r[1] - base) + tuple(x * span ** (k + 1) for k, x in enumerate(r[2:])) for r in rows])
    except ParameterError as exc:
        name_ = exc.name if exc.name.startswith(seg.where) and seg.where else seg._name(exc.name)
        raise ParameterError(name_, exc.value, exc.valid, exc.why) from None
    return shape, lift, level, (start if level is not None else None), (end if level is not None else None)


def _joined_blends(segments: tuple["Segment", ...]) -> tuple["Segment", ...]:
    """The segments with every velocity_blend not yet joined given its neighbours' ends: the
    velocity, acceleration and jerk (per rad) where the segment before it ends and the one after it
    starts (cyclically: the program is one turn)."""
    n = len(segments)
    out = list(segments)
    for i, seg in enumerate(segments):
        if seg.shape.name != "velocity_blend" or seg.ends is not None:
            continue
        for k in ((i - 1) % n, (i + 1) % n):
            if segments[k].shape.name == "velocity_blend":
                raise ParameterError(f"{seg.where or f'segments[{i}]'}.law", "velocity_blend",
                                     "a velocity_blend between two segments of other laws",
                                     f"segments[{k}] is a velocity_blend too: a blend takes its ends from its neighbours")
        before, after = segments[(i - 1) % n].end_values(True), segments[(i + 1) % n].end_values(False)
        out[i] = replace(seg, ends=(before[1:], after[1:]))
    return tuple(out)


_CANONICAL.update(bspline=bspline(), velocity_blend=velocity_blend())
# ---- end SPLINE --------------------------------------------------------------------------------------------


#: alternative names users may write
ALIASES: dict[str, str] = {"harmonic": "simple_harmonic"}
#: every law by the name scene files use (aliases map to the same object)
LAWS: dict[str, Law] = {**_CANONICAL, **{a: _CANONICAL[c] for a, c in ALIASES.items()}}


# --------------------------------------------------------------------------------------------
# segments
# --------------------------------------------------------------------------------------------
def _conditions(key: str, value: object) -> tuple[float, ...]:
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence) or not 1 <= len(value) <= 4:
        raise ParameterError(key, value, "a list of 1 to 4 numbers: s [unit], v [unit/rad], a [unit/rad^2], j [unit/rad^3]")
    return tuple(require_finite(key, x) for x in value)


#: A segment's options and the laws that take them (:class:`Segment` refuses an option of another law).
_OPTION_LAWS = (("blend", "constant_velocity"), ("start", "polynomial or bspline"), ("end", "polynomial or bspline"),
                ("scca", "scca"), ("accel_fraction", "asymmetric_modified_sine or asymmetric_modified_trapezoid"),
                ("points", "bspline"), ("degree", "bspline"), ("interior", "polynomial"), ("ends", "velocity_blend"))


@dataclass(frozen=True)
class Segment:
    """One segment of a motion program.

    Parameters
    ----------
    law : str or Law
        A key of :data:`LAWS` (aliases allowed) or a :class:`Law`.
    span : float
        Cam angle the segment covers (rad), 0 < span <= 2 pi.
    lift : float, optional
        Displacement change over the segment (mm or rad; > 0 rise, < 0 return).  Must be 0 or
        omitted for a dwell, non-zero for the other laws; for ``polynomial`` it follows from
        ``end[0] - start[0]`` (if given, it must agree).
    blend : float, optional
        ``constant_velocity`` only: fraction of the span in each end blend, 0..0.5 (default 0:
        plain constant velocity).
    start, end : sequence of 1..4 floats, optional
        ``polynomial`` only (both required): absolute displacement s [unit], velocity ds/dtheta
        [unit/rad], acceleration [unit/rad^2], jerk [unit/rad^3] at the segment's start and end.
    scca : sequence of 3 floats, optional
        ``scca`` only (required): [b, c, d], fractions of the span (b + c + d = 1).
    accel_fraction : float, optional
        ``asymmetric_modified_sine`` / ``asymmetric_modified_trapezoid`` only (required): fraction
        of the span in the positive acceleration pulse, 0.05..0.95.
    where : str
        How messages name this segment (e.g. ``"cams.lifter.segments[2]"``); the program fills in
        ``segments[i]`` when empty.

    After construction ``lift`` is a float, ``shape`` the configured :class:`Law` (time-reversed
    for a return) and ``scale`` the factor on its S (``lift``; 1 for a polynomial, whose shape is in
    physical units).
    """

    law: str | Law
    span: float
    lift: float | None = None
    blend: float | None = None
    start: Sequence[float] | None = None
    end: Sequence[float] | None = None
    scca: Sequence[float] | None = None  # issue 26 LAWS: the scca law's [b, c, d]
    accel_fraction: float | None = None  # issue 26 LAWS: the skewed laws' fraction of the span at +A
    where: str = field(default="", compare=False)
    # SPLINE (issue 26): bspline points/degree, polynomial interior conditions, a velocity_blend's ends
    points: Sequence[Sequence[float]] | None = None
    degree: int | None = None
    interior: Sequence[Sequence[float]] | None = None
    ends: tuple[Sequence[float], Sequence[float]] | None = None
    shape: Law = field(init=False, repr=False, compare=False)
    scale: float = field(init=False, repr=False, compare=False)
    start_level: float | None = field(init=False, repr=False, compare=False)

    def _name(self, key: str) -> str:
        return f"{self.where}.{key}" if self.where else key

    def __post_init__(self) -> None:
        if isinstance(self.law, Law):
            base, name = self.law, self.law.name
        elif isinstance(self.law, str) and self.law in LAWS:
            base, name = LAWS[self.law], LAWS[self.law].name
        else:
            raise ParameterError(self._name("law"), self.law, f"one of {sorted(LAWS)}")
        span = require_positive(self._name("span"), self.span, "rad")
        if span > TWO_PI * (1 + 1e-12):
            raise ParameterError(self._name("span"), self.span, "0 < span <= 2 pi rad (360 deg)")
        object.__setattr__(self, "span", span)
        for key, allowed in _OPTION_LAWS:
            if getattr(self, key) is not None and name not in allowed.split(" or "):
                raise ParameterError(self._name(key), getattr(self, key), f"no '{key}' for a {name} segment (only for {allowed})")
        start_level = None
        if not isinstance(self.law, Law) and (name in ("bspline", "velocity_blend") or (name == "polynomial" and self.interior)):
            shape, lift, start_level, start, end = _spline_segment(self, name, span)  # SPLINE (issue 26)
            scale = 1.0
            if start is not None:
                object.__setattr__(self, "start", start)
                object.__setattr__(self, "end", end)
        elif name == "polynomial" and not isinstance(self.law, Law):
            if self.start is None or self.end is None:
                raise ParameterError(self._name("start" if self.start is None else "end"), None,
                                     "s, v, a (optionally j) at both ends of a polynomial segment")
            start = _conditions(self._name("start"), self.start)
            end = _conditions(self._name("end"), self.end)
            lift = end[0] - start[0]
            if self.lift is not None:
                given = require_finite(self._name("lift"), self.lift)
                if abs(given - lift) > 1e-9 * max(1.0, abs(lift)):
                    raise ParameterError(self._name("lift"), self.lift, f"end[0] - start[0] = {lift:g} (or omit it)")
            # physical per-rad conditions -> tau units (d^k/dtau^k = span^k d^k/dtheta^k), relative to s0
            shape = polynomial((0.0,) + tuple(x * span**k for k, x in enumerate(start) if k),
                               (lift,) + tuple(x * span**k for k, x in enumerate(end) if k))
            scale, start_level = 1.0, start[0]
            object.__setattr__(self, "start", start)
            object.__setattr__(self, "end", end)
        else:
            if name == "dwell":
                lift = 0.0 if self.lift is None else require_finite(self._name("lift"), self.lift)
                if lift != 0.0:
                    raise ParameterError(self._name("lift"), self.lift, "0 for a dwell (or omit it)")
            else:
                if self.lift is None:
                    raise ParameterError(self._name("lift"), None, f"a non-zero lift for a {name} segment")
                lift = require_finite(self._name("lift"), self.lift)
                if lift == 0.0:
                    raise ParameterError(self._name("lift"), self.lift, f"a non-zero lift for a {name} segment (use 'dwell' to stay)")
            try:
                shape = base.configure(blend=self.blend) if self.blend is not None else base
                # issue 26 LAWS: the scca and skewed laws take their required option
                option = {"scca": "scca", "asymmetric_modified_sine": "accel_fraction",
                          "asymmetric_modified_trapezoid": "accel_fraction"}.get(name)
                if option is not None and getattr(self, option) is not None:
                    shape = base.configure(**{option: getattr(self, option)})
                elif option is not None and not isinstance(self.law, Law):  # a law by name: the option is required
                    raise ParameterError(option, None, "[b, c, d] (fractions of the span, b + c + d = 1) for an scca segment"
                                         if option == "scca" else f"a fraction of the span for an {name} segment (0.5: "
                                         f"the symmetric {name.removeprefix('asymmetric_')})")
            except ParameterError as exc:
                raise ParameterError(self._name(exc.name), exc.value, exc.valid, exc.why) from None
            if lift < 0.0:
                shape = shape.reversed()
            scale = lift
        object.__setattr__(self, "lift", lift)
        object.__setattr__(self, "shape", shape)
        object.__setattr__(self, "scale", scale)
        object.__setattr__(self, "start_level", start_level)

    def values(self, tau: np.ndarray) -> list[np.ndarray]:
        """Displacement above the segment's start level and its cam-angle derivatives (per rad^n)."""
        return [self.scale * v / self.span**n for n, v in enumerate(self.shape.evaluate(tau))]

    def end_values(self, at_end: bool) -> tuple[float, float, float, float]:
        """Exact (s - start level, v, a, j) at the segment's start (``False``) or end (``True``)."""
        e = self.shape.end if at_end else self.shape.start
        scale, span = self.scale, self.span  # (scale e[n] / span^n, written out: the same operations)
        return scale * e[0] / span**0, scale * e[1] / span**1, scale * e[2] / span**2, scale * e[3] / span**3


# --------------------------------------------------------------------------------------------
# programs
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Join:
    """A segment join: cam ``angle`` (rad), the segments ``before``/``after`` (indices), the
    highest derivative order continuous there, the exact (s, v, a, j) on each side
    (unit/rad^n) and the ``jumps`` (after - before) of velocity, acceleration and jerk; ``unit``
    is the follower's ("mm" or "rad")."""

    angle: float
    before: int
    after: int
    continuity: int
    left: tuple[float, float, float, float]
    right: tuple[float, float, float, float]
    jumps: tuple[float, float, float]
    unit: str = "mm"

    def describe(self) -> str:
        """One line for a report, e.g. ``acceleration jumps by 2.5 mm/rad^2 at 120 deg (segments 1 -> 2)``."""
        unit = self.unit
        if self.continuity >= SMOOTH:
            return f"segments {self.before} -> {self.after} join smoothly up to jerk at {math.degrees(self.angle):.6g} deg"
        n = self.continuity + 1
        units = {1: f"{unit}/rad", 2: f"{unit}/rad^2", 3: f"{unit}/rad^3"}
        return (f"{ORDER_NAMES[n]} jumps by {self.jumps[n - 1]:.6g} {units[n]} at {math.degrees(self.angle):.6g} deg "
                f"(segments {self.before} -> {self.after})")


@dataclass(frozen=True)
class Peaks:
    """Largest |velocity|, |acceleration|, |jerk| (unit/rad^n) of a displacement over the turn,
    from the closed-form pieces (one-sided at breaks), and the cam angles (rad) where they occur.
    ``infinite_acceleration`` / ``infinite_jerk``: some join makes the velocity / acceleration jump
    (an impulse the finite values do not show)."""

    velocity: float
    velocity_at: float
    acceleration: float
    acceleration_at: float
    jerk: float
    jerk_at: float
    infinite_acceleration: bool = False
    infinite_jerk: bool = False


class MotionProgram:
    """Follower displacement over one cam turn from consecutive segments; a :class:`Displacement`.

    The first segment starts at cam angle 0 with displacement 0 (or, for a polynomial, its
    ``start[0]``); each next segment starts where the previous one ends.

    Parameters
    ----------
    segments : sequence of Segment
    unit : str
        The follower's unit for messages: ``"mm"`` (translating) or ``"rad"`` (oscillating).
    span_tol : float
        Tolerance (rad) on the spans adding up to 2 pi.
    join_tol : float
        Relative tolerance below which a derivative counts as continuous at a join: the jump is
        compared with the larger of the two sides and the program's peak of that derivative.

    Raises
    ------
    ParameterError
        If the spans do not add up to 360 deg, or the displacement jumps at a join (a polynomial
        segment not starting where the previous one ends, or the lifts not returning to the start):
        the message names ``segments[i]`` and the jump.
    """

    def __init__(self, segments: Sequence[Segment], unit: str = "mm", span_tol: float = 1e-9, join_tol: float = 1e-9) -> None:
        self.segments = tuple(segments)
        if unit not in ("mm", "rad"):
            raise ParameterError("unit", unit, "'mm' (translating follower) or 'rad' (oscillating follower)")
        self.unit = unit
        self.span_tol = require_positive("span_tol", span_tol, "rad")
        self.join_tol = require_positive("join_tol", join_tol, "")
        if not self.segments:
            raise ParameterError("segments", [], "at least one segment")
        for i, seg in enumerate(self.segments):
            if not isinstance(seg, Segment):
                raise ParameterError(f"segments[{i}]", seg, "a Segment")
        self.segments = _joined_blends(self.segments)  # SPLINE (issue 26): a velocity_blend takes its neighbours' ends
        n = len(self.segments)
        # the per-segment bookkeeping in Python floats (a program has a few segments)
        spans = [seg.span for seg in self.segments]
        ends = list(itertools.accumulate(spans))  # the running sum, as np.cumsum adds
        total = ends[-1]
        if abs(total - TWO_PI) > self.span_tol:
            raise ParameterError("segments", f"spans adding up to {math.degrees(total):.9g} deg",
                                 "spans adding up to 360 deg", f"tolerance {self.span_tol:g} rad")
        starts = [0.0] + ends[:-1]
        self.starts = np.array(starts)
        self.spans = np.array(spans)
        # absolute start level of every segment: chained, or a polynomial's own start[0]
        levels = []
        level = 0.0
        for seg in self.segments:
            if seg.start_level is not None:
                level = seg.start_level
            levels.append(level)
            assert seg.lift is not None  # Segment.__post_init__ sets every segment's lift
            level = level + seg.lift
        self.levels = np.array(levels)
        self._bookkeeping = (starts, levels)  # the same, as Python floats (for the plan)
        # peaks and extremes per segment (physical units)
        self._seg_peaks = []
        s_lo, s_hi = math.inf, -math.inf
        for seg, lvl, th0 in zip(self.segments, levels, starts):
            sh = seg.shape
            mn, tmn, mx, tmx = sh.s_range
            vals = sorted([(lvl + seg.scale * mn, tmn), (lvl + seg.scale * mx, tmx)])
            s_lo, s_hi = min(s_lo, vals[0][0]), max(s_hi, vals[1][0])
            self._seg_peaks.append([(abs(seg.scale) * p / seg.span ** (k + 1), th0 + t * seg.span) for k, (p, t) in enumerate(sh.peaks)])
        self._s_bounds = (s_lo, s_hi)
        peak = [max(abs(s_lo), abs(s_hi))] + [max(p[k][0] for p in self._seg_peaks) for k in range(3)]
        # joins: segment i-1 -> i at starts[i] (the join at 0 closes the turn)
        self._joins = []
        for i in range(n):
            prev = (i - 1) % n
            lp = self.segments[prev].end_values(True)
            left = (levels[prev] + lp[0],) + lp[1:]
            rp = self.segments[i].end_values(False)
            right = (levels[i] + rp[0],) + rp[1:]
            diff = [r - l for l, r in zip(left, right)]
            tol = self.join_tol
            if not abs(diff[0]) <= tol * max(abs(left[0]), abs(right[0]), peak[0]):
                where = math.degrees(starts[i])
                names = [seg.where or f"segments[{k}]" for k, seg in enumerate(self.segments)]
                if i == 0:
                    raise ParameterError(names[n - 1], f"ends at s = {left[0]:.9g} {unit}",
                                         f"ending where the program starts (s = {right[0]:.9g} {unit} at 0 deg)",
                                         f"the displacement jumps by {diff[0]:.6g} {unit} at 0 deg: the lifts must return to the start")
                raise ParameterError(names[i], f"starts at s = {right[0]:.9g} {unit}",
                                     f"starting where {names[prev]} ends (s = {left[0]:.9g} {unit})",
                                     f"the displacement jumps by {diff[0]:.6g} {unit} at {where:.9g} deg")
            continuity = SMOOTH  # the order below the first derivative that jumps (within tol of the larger side and peak)
            for k in (1, 2, 3):
                if not abs(diff[k]) <= tol * max(abs(left[k]), abs(right[k]), peak[k]):
                    continuity = k - 1
                    break
            self._joins.append(Join(starts[i], prev, i, continuity, left, right, (diff[1], diff[2], diff[3]), unit))
        # breaks: joins and internal law breaks; evaluation pieces in cam angle
        brk, cont = [], []
        piece_lo, piece_ref = [], []
        for i, (seg, th0) in enumerate(zip(self.segments, starts)):
            brk.append(th0)
            cont.append(self._joins[i].continuity)
            for b in seg.shape.breaks:
                brk.append(th0 + b.tau * seg.span)
                cont.append(b.continuity)
            for k, piece in enumerate(seg.shape.pieces):
                piece_lo.append(th0 + piece.lo * seg.span)
                piece_ref.append((i, k))
        order = sorted(range(len(brk)), key=brk.__getitem__)  # stable
        self.breaks = np.array([brk[k] for k in order], dtype=float)
        self.break_continuity = np.array([cont[k] for k in order], dtype=int)
        self._piece_lo = np.asarray(piece_lo, dtype=float)
        self._piece_ref = piece_ref

    def __getstate__(self) -> dict[str, object]:
        """The program without the values it keeps (:meth:`__call__`, :meth:`on_uniform_grid`): a
        pickled program (a scene sent to a worker) carries its definition only."""
        return {k: v for k, v in self.__dict__.items() if k not in _KEPT_VALUES}

    # -- the Displacement interface ----------------------------------------------------------
    def _plan(self) -> list[tuple]:
        """Per evaluation piece (in cam-angle order): its segment's start and span, the piece's
        ``ref`` and ``sign_in``, a constant, the piece's trig frequencies and the (4, nb) matrix that
        takes the basis ``1, w, .., w^D, sin(om_1 w), cos(om_1 w), ..`` to ``s`` and its three
        derivatives: per derivative order n = 0..3 the power coefficients (lowest first) and the
        (sin, cos) amplitudes, with the factor ``scale sign_out sign_in^n / span^n`` folded in and the
        constant ``level + scale offset`` added to ``s`` (made once per program).  The last entry is
        ``None``, or ``(piece, scale)`` for a piece that is not a polynomial-plus-trig
        :class:`_Piece` (the tilted cycloid): that piece evaluates itself (no matrix) and the
        constant is the segment's level."""
        plan = self.__dict__.get("_eval_plan")
        if plan is None:
            plan = []
            starts, levels = self._bookkeeping
            for i, k in self._piece_ref:
                seg = self.segments[i]
                piece = seg.shape.pieces[k]
                if not isinstance(piece, _Piece):  # evaluated by the piece itself (no matrix)
                    plan.append((starts[i], seg.span, 0.0, True, levels[i], (), None,
                                 (piece, seg.scale)))
                    continue
                scale, span = seg.scale * piece.sign_out, seg.span * piece.sign_in
                matrix = piece._unit_matrix[:4] * np.array((scale, scale / span, scale / span**2, scale / span**3)).reshape(4, 1)
                matrix[0, 0] += levels[i] + seg.scale * piece.offset
                matrix.flags.writeable = False
                plan.append((starts[i], seg.span, float(piece.ref), piece.sign_in > 0, 0.0,
                             piece.omegas, matrix, None))
            self.__dict__["_eval_plan"] = plan
        return plan

    def __call__(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """s (unit), ds/dtheta (unit/rad), d2s/dtheta2 (unit/rad^2), d3s/dtheta3 (unit/rad^3) at cam
        angles ``theta`` (rad, any real, any shape; periodic); at a break the following piece.

        The values of a call with at most :data:`_CALL_MEMO_ANGLES` angles asked for a second time
        are kept on the program for the calls with the same angles after it (among the last
        :data:`_CALL_MEMO_SIZE` distinct calls; a sweep's designs that keep the law ask for the same
        angles): each call returns fresh arrays, copies of the kept ones."""
        theta = np.asarray(theta, dtype=float)
        shape = theta.shape
        key = theta.tobytes() if theta.size <= _CALL_MEMO_ANGLES else None
        memo: dict[bytes, np.ndarray | None] = self.__dict__.setdefault("_call_memo", {})
        seen = False
        if key is not None:
            seen = key in memo
            kept = memo.pop(key, None)  # (pop and put back: the most recently used last)
            if kept is not None:
                memo[key] = kept
                res = kept.copy()
                return res[0].reshape(shape), res[1].reshape(shape), res[2].reshape(shape), res[3].reshape(shape)
        res = self._values(theta, key)
        if key is not None:
            if len(memo) >= _CALL_MEMO_SIZE:
                try:
                    del memo[next(iter(memo))]  # the least recently used
                except (KeyError, RuntimeError, StopIteration):  # another thread changed it meanwhile: nothing to drop
                    pass
            kept = None
            if seen:  # asked for before: kept from now on (angles asked once are only remembered)
                kept = res.copy()
                kept.setflags(write=False)
            memo[key] = kept
        return res[0].reshape(shape), res[1].reshape(shape), res[2].reshape(shape), res[3].reshape(shape)

    def at_kept_angles(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """What ``self(theta)`` gives (the same computation: the same sorted angles, pieces and
        bases, the same matrix products), four fresh arrays (theta.size,), for the cam angles
        ``theta`` (rad, 1-D, finite) of any count, with the angles' layout (their order, the
        pieces' bounds and each piece's basis) kept by their bytes in :func:`_angle_layout`:
        for a caller that asks programs whose pieces lie at the same places at the same many
        angles (a base-radius search of a lift sweep's failing designs on their check grid,
        7,210 angles, beyond :meth:`__call__`'s :data:`_CALL_MEMO_ANGLES`): only the matrix
        products are made once the layout is kept."""
        theta = np.asarray(theta, dtype=float)
        if theta.ndim != 1:
            raise ParameterError("theta", f"an array of shape {theta.shape}", "a 1-D array of cam angles, rad")
        res = self._values(theta, theta.tobytes())
        return res[0], res[1], res[2], res[3]

    def _places(self) -> _Places:
        """The places of this program's evaluation pieces (:class:`_Places`: the key of
        :func:`_angle_layout`), made once per program."""
        places = self.__dict__.get("_places_key")
        if places is None:
            plan = self._plan()
            numbers = [float(len(self._piece_lo)), *self._piece_lo.tolist()]
            bases: list[tuple[float, float, float, bool, tuple[float, ...], int] | None] = []
            for start, span, ref, forward, _, omegas, matrix, custom in plan:
                if custom is not None or matrix.shape[1] == 1:  # evaluated without a basis
                    numbers += [0.0]
                    bases.append(None)
                    continue
                degree = matrix.shape[1] - 1 - 2 * len(omegas)
                numbers += [1.0, start, span, ref, float(forward), float(degree), float(len(omegas)), *omegas]
                bases.append((start, span, ref, forward, omegas, degree))
            places = _Places(np.array(numbers, dtype=float).tobytes(), self._piece_lo, tuple(bases))
            self.__dict__["_places_key"] = places
        return places

    def _values(self, theta: np.ndarray | None, key: bytes | int | None = None) -> np.ndarray:
        """:meth:`__call__`'s values, computed: a (4, theta.size) block.  ``key``: the angles'
        bytes (``theta.tobytes()``), or ``n`` for ``theta = 2 pi arange(n) / n``: the angles'
        order, pieces and bases then come from :func:`_angle_layout` (kept across programs whose
        pieces lie at the same places: a sweep of lifts), only the matrix products are made
        (``theta`` is then not read: None for a sample grid)."""
        plan = self._plan()
        bounds: Sequence[int]
        if key is None:
            assert theta is not None  # (only a keyed call passes no angles)
            ths, order, bounds = _sorted_angles(theta.ravel(), self._piece_lo)
            bases: tuple[np.ndarray | None, ...] = (None,) * len(plan)
        else:
            ths, order, bounds, bases = _angle_layout(key, self._places())
        res = np.empty((4, ths.size))  # s and its three derivatives in one block (one allocation)
        for g, entry in enumerate(plan):
            lo, hi = bounds[g], bounds[g + 1]
            if lo < hi:
                basis = bases[g]
                if basis is None:
                    self._fill(entry, ths[lo:hi], res[:, lo:hi], None)
                else:  # what _fill makes of this basis
                    np.matmul(entry[6], basis, out=res[:, lo:hi])
        if order is not None:
            out = np.empty_like(res)
            out[:, order] = res
            res = out
        return res

    @staticmethod
    def _fill(entry: tuple, ths: np.ndarray, out: np.ndarray, step: float | None) -> None:
        """The displacement and its three derivatives (into ``out`` (4, m)) of one plan entry
        (:meth:`_plan`) at the cam angles ``ths`` (m,) inside its piece: the entry's matrix times
        the basis (powers of the piece's own variable ``w``, then the sines and cosines).  ``step``:
        the angles are ``ths[0] + j step`` (a uniform grid), and the sines and cosines come from
        :func:`_uniform_phasors` instead of one sin and cos per angle."""
        start, span, ref, forward, const, omegas, matrix, custom = entry
        if custom is None and matrix.shape[1] == 1:  # a constant piece (a dwell): its basis is the row of ones
            # (what the matrix product gives: every entry times 1.0 added to 0.0, i.e. -0.0 as +0.0)
            np.add(matrix, 0.0, out=out)
            return
        tau = ths - start
        tau /= span
        if custom is not None:
            piece, scale = custom
            for n, v in enumerate(piece.values(tau)):
                np.multiply(v, scale / span**n, out=out[n])
            out[0] += const
            return
        np.matmul(matrix, _piece_basis(tau, span, ref, forward, omegas, matrix.shape[1] - 1 - 2 * len(omegas), step), out=out)

    @staticmethod
    def _fill_grid_piece(entry: tuple, n: int, extra: np.ndarray, lo: int, hi: int, elo: int, ehi: int, res: np.ndarray) -> None:
        """:meth:`on_uniform_grid`'s values of one plan entry evaluated without a kept basis (the
        tilted cycloid): its uniform angles ``lo .. hi - 1`` and its added ones
        (columns ``elo .. ehi - 1`` of ``res``, (4, n + extra.size))."""
        step = TWO_PI / n
        if hi - lo >= _PHASOR_MIN_POINTS:  # angle addition pays off on the uniform part
            MotionProgram._fill(entry, np.arange(n)[lo:hi] * step, res[:, lo:hi], step)
            if elo < ehi:
                MotionProgram._fill(entry, extra[elo - n: ehi - n], res[:, elo:ehi], None)
        elif lo < hi or elo < ehi:  # few angles: the uniform and the added ones in one evaluation
            both = np.empty((4, hi - lo + ehi - elo))
            MotionProgram._fill(entry, np.concatenate([np.arange(n)[lo:hi] * step, extra[elo - n: ehi - n]]), both, None)
            res[:, lo:hi] = both[:, : hi - lo]
            res[:, elo:ehi] = both[:, hi - lo:]

    def on_uniform_grid(self, n: int, extra: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The displacement and its three derivatives at the cam angles ``k 2 pi / n`` (k = 0 .. n - 1)
        followed by the sorted angles ``extra`` (rad, in ``[0, 2 pi)``): what ``self(np.concatenate([np.arange(n)
        * (2 pi / n), extra]))`` gives, four arrays (n + extra.size,).  A piece covering at least
        :data:`_PHASOR_MIN_POINTS` uniform angles takes its sines and cosines there from angle addition
        (:func:`_uniform_phasors`: within a few ulps of the direct ones, at a fraction of their cost;
        the dense check grid of a cam is such a grid with the breaks added); a piece with fewer is
        evaluated at its uniform and added angles in one pass.

        The values are kept on the program for the next call with the same grid (a pure function
        of the program, which does not change, and the grid; at most :data:`_GRID_MEMO_SIZE`
        grids): the arrays returned are read-only, shared by every caller (a sweep's designs that
        keep the motion law evaluate it once)."""
        extra = np.zeros(0) if extra is None else np.asarray(extra, dtype=float)
        key = (n, extra.tobytes())
        memo: dict[tuple[int, bytes], tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = self.__dict__.setdefault("_grid_memo", {})
        kept = memo.get(key)
        if kept is not None:
            return kept
        plan = self._plan()
        res = np.empty((4, n + extra.size))
        layout = _grid_layout(n, key[1], self._places())
        for entry, (lo, hi, elo, ehi, uniform, added) in zip(plan, layout):
            if uniform is not None:  # what _fill makes of these bases
                np.matmul(entry[6], uniform, out=res[:, lo:hi])
                if added is not None:
                    np.matmul(entry[6], added, out=res[:, elo:ehi])
            elif added is not None:  # few uniform angles: with the added ones in one product, as _fill
                both = np.empty((4, hi - lo + ehi - elo))
                np.matmul(entry[6], added, out=both)
                res[:, lo:hi] = both[:, : hi - lo]
                res[:, elo:ehi] = both[:, hi - lo:]
            elif entry[7] is None:  # a constant piece (a dwell): what _fill makes of it, without angles
                if lo < hi:
                    np.add(entry[6], 0.0, out=res[:, lo:hi])
                if elo < ehi:
                    np.add(entry[6], 0.0, out=res[:, elo:ehi])
            else:  # a piece that evaluates itself (the tilted cycloid)
                self._fill_grid_piece(entry, n, extra, lo, hi, elo, ehi, res)
        res.setflags(write=False)
        if len(memo) >= _GRID_MEMO_SIZE:
            memo.clear()  # (one step: safe with threads sharing the program)
        memo[key] = values = (res[0], res[1], res[2], res[3])
        return values

    def on_uniform_grid_in_order(self, n: int, extra: np.ndarray, order: np.ndarray) -> np.ndarray:
        """:meth:`on_uniform_grid`'s values at the grid ``(n, extra)`` taken in ``order`` (integer
        (n + extra.size,): e.g. a cam's sorted check grid), as the rows of one (4, n + extra.size)
        block.  Read-only and kept on the program with the grid's values (a pure function of the
        program, the grid and the order; kept while the caller passes the same read-only ``order``
        array for that grid, which the memo holds: a sweep's designs that keep the law take it once)."""
        values = self.on_uniform_grid(n, extra)
        key = (n, extra.tobytes())
        memo: dict[tuple[int, bytes], tuple[np.ndarray, np.ndarray]] = self.__dict__.setdefault("_order_memo", {})
        kept = memo.get(key)
        if kept is not None and kept[0] is order:
            return kept[1]
        block = values[0].base
        if not (isinstance(block, np.ndarray) and block.shape == (4, values[0].size)):
            block = np.stack(values)
        taken = block.take(order, axis=1)
        taken.setflags(write=False)
        if len(memo) >= _GRID_MEMO_SIZE:
            memo.clear()  # (one step: safe with threads sharing the program)
        memo[key] = (order, taken)
        return taken

    def on_sample_grid(self, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """What ``self(2.0 * math.pi * np.arange(n) / n)`` gives (the same computation), four fresh
        arrays (n,): a cam's motion samples.  The values of an ``n`` asked for a second time are kept
        on the program for the calls after it (a sweep's designs that keep the law ask again; a
        program asked once keeps nothing), without :meth:`__call__`'s keying by the angles' bytes."""
        memo: dict[int, np.ndarray | None] = self.__dict__.setdefault("_sample_memo", {})
        seen = n in memo
        kept = memo.get(n)
        if kept is not None:
            res = kept.copy()
            return res[0], res[1], res[2], res[3]
        res = self._values(None, n)  # (the angles 2 pi arange(n) / n: _angle_layout's, none made here)
        if len(memo) >= _GRID_MEMO_SIZE:
            memo.clear()  # (one step: safe with threads sharing the program)
        if seen:  # asked for before: kept from now on
            kept = res.copy()
            kept.setflags(write=False)
        memo[n] = kept
        return res[0], res[1], res[2], res[3]

    # -- reports ------------------------------------------------------------------------------
    def joins(self) -> list[Join]:
        """Every segment join (the first at cam angle 0 closes the turn), in cam-angle order."""
        return list(self._joins)

    @property
    def stroke(self) -> float:
        """Largest minus smallest displacement over the turn (unit)."""
        return float(self._s_bounds[1] - self._s_bounds[0])

    @property
    def s_bounds(self) -> tuple[float, float]:
        """(smallest, largest) displacement over the turn (unit)."""
        return self._s_bounds

    def peak_values(self) -> Peaks:
        """Largest |s'|, |s''|, |s'''| (unit/rad^n) over the turn and where (see :class:`Peaks`).
        Made once per program (a pure function of its segments; :class:`Peaks` is immutable) and
        kept for the next calls (a sweep's designs that keep the law ask it again)."""
        kept = self.__dict__.get("_peaks")
        if kept is not None:
            return kept
        best = []  # (value, where) of the velocity, acceleration and jerk (max: the first of equal values)
        first = operator.itemgetter(0)
        for k in range(3):
            value, at = max([p[k] for p in self._seg_peaks], key=first)
            best.append((float(value), float(at % TWO_PI)))
        (vel, vel_at), (acc, acc_at), (jerk, jerk_at) = best
        least = min([j.continuity for j in self._joins])  # (the joins' continuity are among the breaks')
        peaks = Peaks(vel, vel_at, acc, acc_at, jerk, jerk_at, infinite_acceleration=least < 1,
                      infinite_jerk=least < 2 or bool((self.break_continuity < 2).any()))
        self.__dict__["_peaks"] = peaks
        return peaks
