"""VDI 2143 (Bewegungsgesetze für Kurvengetriebe, Blatt 1): the standard's names of the laws, the
motion task of each segment and its characteristic values.

**Names.**  :data:`VDI_NAMES` gives, per law name of :data:`camgen.synthesis.laws.LAWS`, the name
VDI 2143 and the German literature use beside the textbook (Norton) name, with what confirms it.
Sources we could read: the manual of the cam program after VDI 2143 by Halbritter
(``i-halbritter.de/camdoku``: "Modifizierte Sinuslinie", usable for U-G and G-G tasks, R as a
special case of G) and the motion-function list of the Beckhoff TwinCAT camming library, which
follows VDI 2143 ("InclinedSinusoid", Bestehorn's sine = the German "geneigte Sinuslinie";
"ModifiedSinusoid"; "Polynomial5", "Polynomial7"; "Sinusoid"; "AccelerationTrapezoid").  Names we
could not confirm from a source we read are marked ``confirmed=False`` (the Kosinuslinie of the
simple harmonic law, the "quadratische Parabel" of constant acceleration, the "Gerade" of constant
velocity, the modified trapezoid's "modifiziertes Beschleunigungstrapez"); the double harmonic,
Wildt's modified cycloid and the SCCA family have no VDI 2143 name we know (``None``).

**Motion tasks.**  VDI 2143 classifies a segment by the follower's state at each end: *Rast* (R,
rest: v = 0, a = 0), *Gleichgeschwindigkeit* (G, constant velocity: v != 0, a = 0), *Umkehr* (U,
reversal: v = 0, a != 0) and *Bewegung* (B, general motion: v != 0, a != 0).  A segment's task is
the pair (start-end): a rise between dwells is R-R, a simple harmonic rise U-U, Norton's
double-harmonic rise R-U.  A dwell is a rest, "R".  Zero means at most :data:`TASK_ZERO_TOL`
of the segment's own peak of that derivative (the laws' exact ends are zero to rounding).

**Characteristic values** (Kennwerte) of the normalised law ``S(tau)`` (S from 0 to 1 over
tau in [0, 1]): ``Cv = max|V|``, ``Ca = max|A|``, ``Cj = max|J|`` (the finite peaks inside the
segment, Norton's Table 8-3 for the laws between two dwells) and the dynamic characteristic value
``C_Mdyn = max|V A|`` (the peak of the inertia's power, hence of the drive torque it needs: VDI
2143's "dynamischer Kennwert").  A return is the time-reversed rise (the same values); a
polynomial segment, given in physical units, is normalised by its lift, or by its own excursion
when it ends where it starts.  Closed form: the cycloid's ``C_Mdyn = 2 pi max (1 - cos x) sin x
= 3 sqrt(3) pi / 2 = 8.162``.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from camgen.synthesis.laws import Law, MotionProgram, Segment

__all__ = ["C_MDYN_SAMPLES", "TASK_NAMES", "TASK_ZERO_TOL", "VDI_NAMES", "VdiName", "SegmentValues", "c_mdyn",
           "end_state", "program_values", "program_figures", "segment_values"]

#: An end's velocity (acceleration) counts as zero at most this fraction of the segment's own peak of it.
TASK_ZERO_TOL = 1e-9
#: Samples per piece of a law where the search for the peak of |V A| starts (then bisection on its derivative).
C_MDYN_SAMPLES = 513
_BISECTIONS = 60

#: The end states of VDI 2143's motion tasks.
TASK_NAMES = {"R": "Rast (rest)", "G": "Gleichgeschwindigkeit (constant velocity)", "U": "Umkehr (reversal)",
              "B": "Bewegung (general motion)"}


@dataclass(frozen=True)
class VdiName:
    """A law's VDI 2143 name (German), its English rendering, and whether a source we read confirms it."""

    german: str
    english: str
    confirmed: bool


#: law name (LAWS) -> its VDI 2143 name; a law missing here has none we know.
VDI_NAMES: dict[str, VdiName] = {
    "dwell": VdiName("Rast", "dwell", True),  # VDI 2143's R
    "constant_velocity": VdiName("Gerade", "straight line (constant velocity)", False),
    "simple_harmonic": VdiName("Kosinuslinie (einfache Sinuslinie)", "cosine (simple sine)", False),  # Beckhoff: "Sinusoid"
    "harmonic": VdiName("Kosinuslinie (einfache Sinuslinie)", "cosine (simple sine)", False),
    "cycloidal": VdiName("geneigte Sinuslinie (Sinoide)", "inclined sine", True),  # Beckhoff: "InclinedSinusoid" (Bestehorn)
    "modified_sine": VdiName("modifizierte Sinuslinie", "modified sine", True),  # Halbritter camdoku; Beckhoff "ModifiedSinusoid"
    "modified_trapezoid": VdiName("modifiziertes Beschleunigungstrapez", "modified acceleration trapezoid", False),
    "poly345": VdiName("Polynom 5. Grades", "polynomial of degree 5", True),  # Beckhoff: "Polynomial5"
    "poly4567": VdiName("Polynom 7. Grades", "polynomial of degree 7", True),  # Beckhoff: "Polynomial7"
    "constant_acceleration": VdiName("quadratische Parabel", "quadratic parabola", False),
    "trapezoidal": VdiName("Beschleunigungstrapez", "acceleration trapezoid", True),  # Beckhoff: "AccelerationTrapezoid"
}


def _polynomial_name(degree: int) -> VdiName:
    return VdiName(f"Polynom {degree}. Grades", f"polynomial of degree {degree}", True)


@dataclass(frozen=True)
class SegmentValues:
    """One segment's VDI 2143 description: its law, VDI name (None: none known), motion task
    (``"R-R"``, ..., ``"R"`` for a dwell) and characteristic values of the normalised law."""

    law: str
    vdi_name: VdiName | None
    task: str
    cv: float
    ca: float
    cj: float
    c_mdyn: float

    def as_json(self) -> dict[str, Any]:
        """report.json's row (the coefficients are dimensionless)."""
        name = self.vdi_name
        return {"law": self.law, "vdi_name": name.german if name else None, "vdi_name_en": name.english if name else None,
                "vdi_name_confirmed": name.confirmed if name else False, "task": self.task,
                "Cv": self.cv, "Ca": self.ca, "Cj": self.cj, "C_Mdyn": self.c_mdyn}


def end_state(velocity: float, acceleration: float, velocity_peak: float, acceleration_peak: float) -> str:
    """VDI 2143's state at a segment end: R, G, U or B (module notes), from the end's velocity and
    acceleration and the segment's peaks of each (any consistent unit)."""
    moving = abs(velocity) > TASK_ZERO_TOL * velocity_peak
    accelerating = abs(acceleration) > TASK_ZERO_TOL * acceleration_peak
    return {(False, False): "R", (True, False): "G", (False, True): "U", (True, True): "B"}[(moving, accelerating)]


@functools.lru_cache(maxsize=128)
def c_mdyn(law: "Law") -> float:
    """``max |V A|`` of ``law`` over tau in [0, 1] (tau units; one-sided at breaks): per piece,
    samples and the sign changes of ``d(VA)/dtau = A^2 + V J`` refined by bisection (vectorised)."""
    best = 0.0
    for piece in law.pieces:
        u = np.linspace(piece.lo, piece.hi, C_MDYN_SAMPLES)
        v, a, j = piece.values(u, (1, 2, 3))
        g = a * a + v * j
        sg = np.sign(g)
        k = np.flatnonzero(sg[:-1] * sg[1:] < 0)
        product = np.abs(v * a)
        if k.size:
            lo, hi, side = u[k].copy(), u[k + 1].copy(), sg[k].copy()
            for _ in range(_BISECTIONS):
                mid = 0.5 * (lo + hi)
                vm, am, jm = piece.values(mid, (1, 2, 3))
                same = np.sign(am * am + vm * jm) == side
                lo = np.where(same, mid, lo)
                hi = np.where(same, hi, mid)
            vr, ar = piece.values(0.5 * (lo + hi), (1, 2))
            product = np.concatenate([product, np.abs(vr * ar)])
        best = max(best, float(np.max(product)))
    return best


def segment_values(segment: "Segment") -> SegmentValues:
    """The VDI 2143 description of one program segment (:class:`SegmentValues`): its law's
    (:func:`_law_values`) with the lift's normalising factor."""
    law = segment.shape
    (pv, _), (pa, _), _ = law.peaks
    if law.name == "dwell" or (pv == 0.0 and pa == 0.0):
        return _law_values(law, None)
    # the normalised law S = scale shape / L, L the lift (or the excursion of a segment ending where it started)
    lift = float(segment.lift or 0.0)
    s_min, _, s_max, _ = law.s_range
    reference = abs(lift) if lift != 0.0 else abs(segment.scale) * (s_max - s_min)
    return _law_values(law, abs(segment.scale) / reference)


#: Segment descriptions :func:`_law_values` keeps (a program's laws and factors: a sweep of lifts
#: keeps both, the factor of a law scaled by its lift being 1).
_LAW_VALUES_CACHE = 64


@functools.lru_cache(maxsize=_LAW_VALUES_CACHE)
def _law_values(law: "Law", factor: float | None) -> SegmentValues:
    """:class:`SegmentValues` of a segment of ``law`` whose normalised law is ``factor`` times its
    shape (None: a segment at rest): a pure function of the (immutable) law and the factor, kept
    keyed by the law object (laws compare by identity: a program read again, or a law made per
    design, is a new key) and the factor (the value is immutable)."""
    name = law.name
    vdi = VDI_NAMES.get(name)
    if name == "polynomial":
        degree = law.options.get("degree")
        vdi = _polynomial_name(degree) if isinstance(degree, int) else None
    if factor is None:
        return SegmentValues(name, VDI_NAMES["dwell"] if name == "dwell" else vdi, "R", 0.0, 0.0, 0.0, 0.0)
    (pv, _), (pa, _), (pj, _) = law.peaks
    start = law.start
    end = law.end
    task = f"{end_state(start[1], start[2], pv, pa)}-{end_state(end[1], end[2], pv, pa)}"
    return SegmentValues(name, vdi, task, factor * pv, factor * pa, factor * pj, factor * factor * c_mdyn(law))


def program_values(program: "MotionProgram") -> list[SegmentValues]:
    """:func:`segment_values` of every segment of ``program``, in order."""
    return [segment_values(seg) for seg in program.segments]


def program_figures(program: Any) -> dict[str, Any]:
    """report.json's ``figures.vdi2143`` of a motion program: the standard, the tolerance of the
    task types and one row per segment (:meth:`SegmentValues.as_json`); ``{}`` for a law that is no
    program of segments (a lift table)."""
    segments = getattr(program, "segments", None)
    if not segments:
        return {}
    return {"standard": "VDI 2143 Blatt 1 (motion laws of cam mechanisms)", "task_zero_tol": TASK_ZERO_TOL,
            "normalised": "S from 0 to 1 over the segment's span (tau in [0, 1]); C_Mdyn = max |V A|",
            "segments": [row.as_json() for row in program_values(program)]}
