"""The moves of a G-code program: a closed tool path cut into printable primitives (exact arcs,
biarcs or chords of spline segments), started anywhere on it, run either way round, and printed
from the printed current point (:class:`MoveWriter`; with Z for a ramp)."""
from __future__ import annotations

import io
import math

import numpy as np

from camgen.contour import Arc, Contour, Spline
from camgen.errors import GeometryError
from camgen.export.gcode_spec import FIT_SHARE, MachiningSpec
from camgen.export.tables import format_rows

__all__ = ["MoveWriter", "START_SAMPLING", "comment", "loop_moves", "primitives", "reverse_primitives", "rotate", "split_segment"]

#: Sagitta of the coarse polygon whose chord midpoints are the start-point candidates, as a
#: fraction of the contour size.
START_SAMPLING = 1e-3


def _shift_piece(c: np.ndarray, delta: float) -> np.ndarray:
    """Coefficients (p + 1, 2) of the degree-p polynomial piece ``c`` (highest power first)
    re-expanded at ``tau = delta`` (Taylor shift: the coefficient of ``tau^k`` becomes
    ``P^(k)(delta) / k!``), by repeated synthetic division (Horner's scheme applied p times:
    Knuth, TAOCP vol. 2, sec. 4.6.4)."""
    out = np.array(c, dtype=float)
    p = out.shape[0] - 1
    for i in range(p):  # pass i leaves the coefficient of tau^i (row p - i) final
        for j in range(1, p + 1 - i):
            out[j] = out[j] + delta * out[j - 1]
    return out


def split_segment(seg: Arc | Spline, u: float) -> tuple[Arc | Spline | None, Arc | Spline | None]:
    """``seg`` split at local parameter ``u`` in (0, 1): (head, tail); None for an empty part."""
    if isinstance(seg, Arc):
        return (Arc(seg.center, seg.radius, seg.start_angle, seg.sweep * u),
                Arc(seg.center, seg.radius, seg.start_angle + seg.sweep * u, seg.sweep * (1.0 - u)))
    t = seg.breaks[0] + u * seg.span
    j = int(np.clip(np.searchsorted(seg.breaks, t, side="right") - 1, 0, seg.n_pieces - 1))
    delta = t - seg.breaks[j]
    if delta <= 1e-12 * seg.span:  # on a break: no piece to cut
        head = Spline(seg.breaks[: j + 1], seg.coeffs[:, :j]) if j > 0 else None
        return head, Spline(seg.breaks[j:], seg.coeffs[:, j:])
    tail_coeffs = np.concatenate([_shift_piece(seg.coeffs[:, j], delta)[:, None], seg.coeffs[:, j + 1 :]], axis=1)
    tail = Spline(np.concatenate([[t], seg.breaks[j + 1 :]]), tail_coeffs)
    head = Spline(np.concatenate([seg.breaks[: j + 1], [t]]), seg.coeffs[:, : j + 1])
    return head, tail


def rotate(path: Contour, t: float) -> Contour:
    """The same closed path starting at global parameter ``t`` (the segment there is split)."""
    i = int(math.floor(t)) % path.n_segments
    u = t - math.floor(t)
    segs = list(path.segments)
    if u <= 0.0:
        order = segs[i:] + segs[:i]
    else:
        head, tail = split_segment(segs[i], u)
        assert tail is not None  # u < 1: the tail is never empty
        order = [tail] + segs[i + 1 :] + segs[:i] + ([head] if head is not None else [])
    return Contour(order, closure_tol=1e-5)


# ------------------------------------------------------------------------------------------
# primitives
# ------------------------------------------------------------------------------------------
def _line_tolerance(contour: Contour, spec: MachiningSpec) -> float:
    """Chord tolerance of ``lines`` mode, mm.

    Without compensation it is the fit share of ``chord_tol``.  With compensation LinuxCNC
    treats a chord corner below ``COMP_STRAIGHT`` rad as straight and starts the next offset
    chord where the previous one ended (no arc, no intersection).  For chords of sagitta ``f``
    on a radius ``R`` the tool then reaches into the part by ``f (1 + 2 r/R - (r/R)^2) <= 2 f``
    on a convex stretch and by ``r f / (R - r)`` on a concave one (the offset point of each
    vertex is tilted by the chord angle ``sqrt(8 f / R)``): ``f`` is scaled by
    ``min(1/2, (R - r) / r)`` with R the smallest concave radius of the spline segments.
    """
    fit = FIT_SHARE * spec.chord_tol
    if not spec.cutter_compensation:
        return fit
    r = spec.tool_radius
    u = np.linspace(0.0, 1.0, 4097)
    kappa = [np.min(seg.curvature(u)) for seg in contour.segments if not isinstance(seg, Arc)]
    least = min(kappa, default=0.0)
    scale = 0.5 if least >= 0.0 else min(0.5, (1.0 / -least - r) / r)
    return fit * scale


def primitives(contour: Contour, spec: MachiningSpec) -> list[tuple]:
    """Counter-clockwise primitives: ('arc', Arc) or ('lines', points (n, 2) excluding the start)."""
    if spec.spline_mode == "biarcs" and any(not isinstance(s, Arc) for s in contour.segments):
        from camgen.contour.arcspline import to_arc_spline

        contour = to_arc_spline(contour, FIT_SHARE * spec.chord_tol)
    tol = _line_tolerance(contour, spec)
    out: list[tuple] = []
    for seg in contour.segments:
        if isinstance(seg, Arc):
            out.append(("arc", seg))
        else:
            u = np.append(seg.flatten_params(tol)[1:], 1.0)
            out.append(("lines", seg.point(u)))
    return out


def reverse_primitives(prims: list[tuple], start: np.ndarray) -> list[tuple]:
    """The same closed path travelled the other way round (clockwise), from the same start."""
    out: list[tuple] = []
    ends = [start] + [p[1].end_point if p[0] == "arc" else p[1][-1] for p in prims[:-1]]
    for (kind, item), begin in zip(reversed(prims), reversed(ends)):
        if kind == "arc":
            out.append(("arc", Arc(item.center, item.radius, item.start_angle + item.sweep, -item.sweep)))
        else:
            out.append(("lines", np.vstack([item[-2::-1], begin[None]])))
    return out



# ------------------------------------------------------------------------------------------
# writing
# ------------------------------------------------------------------------------------------
class MoveWriter:
    """Moves printed from the printed current point: I/J from printed values, zero-length moves
    dropped, arcs too short to print safely written as lines.  A move given ``z`` also prints its
    Z word (a ramp: lines with Z, helical G2/G3)."""

    def __init__(self, decimals: int, start: np.ndarray, z: float | None = None) -> None:
        self.d = decimals
        self.unit = 10.0 ** (-decimals)
        self.current = self.round(start)
        self.z = None if z is None else self.round_z(z)
        self.out = io.StringIO()

    def round(self, p: np.ndarray) -> np.ndarray:
        return np.round(np.asarray(p, dtype=float), self.d) + 0.0

    def round_z(self, z: float) -> float:
        return round(float(z), self.d) + 0.0

    def xy(self, p: np.ndarray) -> str:
        return f"X{p[0]:.{self.d}f} Y{p[1]:.{self.d}f}"

    def _z_word(self, z: float | None) -> str:
        if z is None:
            return ""
        self.z = self.round_z(z)
        return f" Z{self.z:.{self.d}f}"

    def line(self, p: np.ndarray, prefix: str = "", z: float | None = None) -> None:
        q = self.round(p)
        if np.array_equal(q, self.current) and not prefix and (z is None or self.round_z(z) == self.z):
            return
        self.out.write(f"{prefix}G1 {self.xy(q)}{self._z_word(z)}\n")
        self.current = q

    def lines(self, points: np.ndarray, z: np.ndarray | None = None) -> None:
        q = self.round(points)
        keep = np.any(q != np.vstack([self.current[None], q[:-1]]), axis=1)
        q = q[keep]
        if len(q):
            if z is None:
                self.out.write(format_rows(q, f"G1 X%.{self.d}f Y%.{self.d}f"))
            else:
                zq = np.round(np.asarray(z, dtype=float)[keep], self.d) + 0.0
                self.out.write(format_rows(np.column_stack([q, zq]), f"G1 X%.{self.d}f Y%.{self.d}f Z%.{self.d}f"))
                self.z = float(zq[-1])
            self.current = q[-1]

    def arc(self, arc: Arc, z: float | None = None) -> None:
        end = self.round(arc.end_point)
        centre = self.round(np.asarray(arc.center))
        chord = float(np.hypot(*(end - self.current)))
        sagitta = arc.radius * (1.0 - math.cos(min(abs(arc.sweep), math.pi) / 2.0))
        if chord < 100.0 * self.unit and sagitta <= math.sqrt(2.0) * self.unit:
            self.line(end, z=z)  # within the rounding budget, and never misread as a full circle
            return
        # the sweep the control will run: from the printed start to the printed end about the printed centre
        a0 = math.atan2(self.current[1] - centre[1], self.current[0] - centre[0])
        a1 = math.atan2(end[1] - centre[1], end[0] - centre[0])
        run = (a1 - a0) % (2 * math.pi) if arc.sweep > 0 else -((a0 - a1) % (2 * math.pi))
        if chord == 0.0 or abs(run - arc.sweep) > 1e-2 * max(1.0, abs(arc.sweep)):
            raise GeometryError(
                f"an arc of radius {arc.radius:.6g} mm and sweep {math.degrees(arc.sweep):.6g} deg cannot be "
                f"printed with {self.d} decimals; raise decimals"
            )
        ij = centre - self.current
        word = "G3" if arc.sweep > 0 else "G2"
        self.out.write(f"{word} {self.xy(end)}{self._z_word(z)} I{ij[0]:.{self.d}f} J{ij[1]:.{self.d}f}\n")
        self.current = end

    def text(self) -> str:
        return self.out.getvalue()


def loop_moves(prims: list[tuple], start: np.ndarray, decimals: int) -> str:
    """The moves of the closed path ``prims`` from ``start`` back to it (XY only: the Z of the
    pass is modal).  Raises :class:`GeometryError` when the written path does not close."""
    writer = MoveWriter(decimals, start)
    for kind, item in prims:
        if kind == "arc":
            writer.arc(item)
        else:
            writer.lines(item)
    gap = float(np.hypot(*(writer.current - writer.round(start))))
    if gap > 1e-4:
        raise GeometryError(f"the written contour does not close: it ends {gap:.3g} mm from its start")
    writer.line(start)  # a gap of the offset's closure tolerance, if any
    return writer.text()


def comment(text: str) -> str:
    """An RS274 comment: parentheses cannot nest, so they are replaced in the text."""
    return "(" + text.replace("(", "[").replace(")", "]") + ")"

