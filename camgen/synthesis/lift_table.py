"""Lift tables: a periodic spline through a user's (cam angle, lift) rows; a ``Displacement``.

The spline is a periodic interpolating spline with its knots at the rows.  Its order is chosen,
not defaulted: **quintic** (``degree=5``, the default) is continuous through the 4th derivative,
so the jerk is continuous everywhere (every row is a break of continuity 3 in the
:class:`~camgen.synthesis.laws.Displacement` sense); a **cubic** (``degree=3``) is only C2: its
jerk steps at every row (continuity 2), which the checks would report.  Interpolation error on a
smooth lift: O(h^(k+1)) for s, O(h^(k+1-n)) for the n-th derivative (h = row spacing, k = degree).

CSV format (:func:`read_lift_table`)
------------------------------------
* one row per line: ``angle_deg, lift`` (cam angle in degrees, lift in mm, or rad for an
  oscillating follower); fields separated by a comma, a semicolon, or blanks (one kind per line;
  no decimal commas);
* ``#`` starts a comment (whole line or the rest of a line); blank lines are ignored;
* the first non-comment row may be a header (two non-numeric fields, e.g. ``angle_deg,lift_mm``);
* angles strictly increasing and within one turn: ``last - first < 360``; the turn is closed
  automatically (the spline runs from the last row back to the first, 360 deg later).  A final row
  at exactly ``first + 360`` is accepted as the closing row if its lift equals the first lift
  (within ``close_tol``), and is then dropped;
* at least ``MIN_ROWS`` and at most ``max_rows`` rows; the file is read only if it is a regular
  file of at most ``max_bytes`` bytes (a device such as /dev/zero or a pipe is refused at once).

Every problem raises :class:`~camgen.errors.ParameterError` naming the key ``lift_table_csv``, the
file and the line.
"""
from __future__ import annotations

import math
import os
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from camgen.errors import ParameterError
from camgen.numerics.interpolate import periodic_spline
from camgen.synthesis.laws import SMOOTH, Peaks

__all__ = [
    "DEGREES", "LiftTable", "MAX_BYTES", "MAX_ROWS", "MIN_ROWS", "parse_lift_table", "parse_two_column_table",
    "read_lift_table", "read_two_column_table",
]

TWO_PI = 2.0 * math.pi
#: default largest number of rows
MAX_ROWS = 100_000
#: default largest file size read (bytes)
MAX_BYTES = 8 * 1024 * 1024
#: fewest rows a table may have
MIN_ROWS = 8
#: spline degrees offered (odd: knots at the rows)
DEGREES = (3, 5)


class LiftTable:
    """Periodic spline displacement through table rows.

    Parameters
    ----------
    angles_deg : array of shape (n,)
        Cam angles (deg), strictly increasing, ``last - first <= 360`` (see the module notes).
    lifts : array of shape (n,)
        Lift at each angle (``unit``).
    degree : int
        Spline degree, 5 (continuous jerk; default) or 3 (jerk steps at every row).
    unit : str
        ``"mm"`` or ``"rad"`` (messages only).
    close_tol : float
        Tolerance on a closing row's lift repeating the first lift, relative to
        ``max(1, max |lift|)``.
    max_rows : int
        Largest number of rows accepted.
    key : str
        Parameter name used in errors; ``rows``: labels of the rows for errors (default "row i").
    """

    def __init__(self, angles_deg: npt.ArrayLike, lifts: npt.ArrayLike, degree: int = 5, unit: str = "mm",
                 close_tol: float = 1e-9, max_rows: int = MAX_ROWS, key: str = "lift_table",
                 rows: Sequence[str] | None = None) -> None:
        if degree not in DEGREES or isinstance(degree, bool):
            raise ParameterError("degree", degree, f"one of {DEGREES}", "5: continuous jerk; 3: jerk steps at every row")
        if unit not in ("mm", "rad"):
            raise ParameterError("unit", unit, "'mm' (translating follower) or 'rad' (oscillating follower)")
        a = np.asarray(angles_deg, dtype=float)
        s = np.asarray(lifts, dtype=float)
        if a.ndim != 1 or s.shape != a.shape:
            raise ParameterError(key, f"arrays of shapes {a.shape} and {s.shape}", "two 1-D arrays of equal length (angle_deg, lift)")
        labels = list(rows) if rows is not None else [f"row {i + 1}" for i in range(a.size)]
        if a.size > max_rows:
            raise ParameterError(key, f"{a.size} rows", f"at most {max_rows} rows")
        if a.size < MIN_ROWS:
            raise ParameterError(key, f"{a.size} rows", f"at least {MIN_ROWS} rows")
        bad = np.flatnonzero(~(np.isfinite(a) & np.isfinite(s)))
        if bad.size:
            i = int(bad[0])
            raise ParameterError(key, f"{labels[i]}: ({a[i]}, {s[i]})", "finite numbers (angle_deg, lift)")
        step = np.diff(a)
        bad = np.flatnonzero(step <= 0)
        if bad.size:
            i = int(bad[0]) + 1
            raise ParameterError(key, f"{labels[i]}: angle {a[i]:.9g} deg after {a[i - 1]:.9g} deg", "strictly increasing cam angles")
        turn = a - a[0]
        beyond = np.flatnonzero(turn > 360.0 + 1e-9)
        if beyond.size:
            i = int(beyond[0])
            raise ParameterError(key, f"{labels[i]}: angle {a[i]:.9g} deg", f"angles within one turn: < {a[0] + 360:.9g} deg (first row + 360)")
        if abs(turn[-1] - 360.0) <= 1e-9:  # the closing row
            scale = max(1.0, float(np.max(np.abs(s))))
            if abs(s[-1] - s[0]) > close_tol * scale:
                raise ParameterError(key, f"{labels[-1]}: lift {s[-1]:.9g} {unit} at {a[-1]:.9g} deg",
                                     f"the first lift {s[0]:.9g} {unit}",
                                     "a row at first angle + 360 deg closes the turn and must repeat the first lift")
            a, s = a[:-1], s[:-1]
            if a.size < MIN_ROWS:
                raise ParameterError(key, f"{a.size} rows besides the closing row", f"at least {MIN_ROWS} rows")
        self.degree = int(degree)
        self.unit = unit
        self.angles = np.radians(a)  # rad, rows (closing row dropped)
        self.lifts = s.copy()
        self._origin = float(self.angles[0])
        x = np.append(self.angles - self._origin, TWO_PI)
        y = np.append(s, s[0])
        pp = periodic_spline(x, y, self.degree)  # numpy: no scipy import
        self._pp = [pp] + [pp.derivative(n) for n in (1, 2, 3)]
        self._build_buckets()
        self.breaks = np.sort(np.mod(self.angles, TWO_PI))
        self.break_continuity = np.full(self.breaks.size, SMOOTH if self.degree == 5 else 2, dtype=int)
        self._peaks: Peaks | None = None
        self._bounds: tuple[float, float] | None = None

    def __call__(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """s (unit), ds/dtheta (unit/rad), d2s/dtheta2, d3s/dtheta3 at cam angles ``theta`` (rad, any
        real, any shape; periodic)."""
        theta = np.asarray(theta, dtype=float)
        if not np.all(np.isfinite(theta)):
            raise ParameterError("theta", "non-finite cam angles", "finite angles in rad")
        u = _wrap(theta.ravel() - self._origin)
        x = self._pp[0].x
        i = self._piece_index(u)
        dx = u - x[i]
        # Horner for the value and the first three derivatives at once (highest power first)
        coef = self._pp[0].c[:, i]
        p = coef[0].copy()
        d1, d2, d3 = np.zeros_like(p), np.zeros_like(p), np.zeros_like(p)
        for row in coef[1:]:
            d3 *= dx
            d3 += d2
            d2 *= dx
            d2 += d1
            d1 *= dx
            d1 += p
            p *= dx
            p += row
        out = [p.reshape(theta.shape), d1.reshape(theta.shape), (2.0 * d2).reshape(theta.shape), (6.0 * d3).reshape(theta.shape)]
        return out[0], out[1], out[2], out[3]

    def _piece_index(self, u: np.ndarray) -> np.ndarray:
        """Index of the polynomial piece holding each u in [0, 2 pi) (the right-hand piece at a row):
        a uniform bucket table gives the first candidate, a few vectorised steps finish."""
        x = self._pp[0].x
        if self._bucket_first is None:
            return np.clip(np.searchsorted(x, u, side="right") - 1, 0, x.size - 2)
        # one bucket early: rounding of u * scale can never put a point past its piece
        b = np.clip((u * self._bucket_scale).astype(np.intp) - 1, 0, self._bucket_first.size - 1)
        i = self._bucket_first[b]
        for _ in range(self._bucket_steps):
            i += x[i + 1] <= u
        return i

    def _build_buckets(self, max_steps: int = 4) -> None:
        x = self._pp[0].x
        self._bucket_first = None
        self._bucket_steps = 0
        m = 2 * x.size
        edges = np.arange(m + 1) * (TWO_PI / m)
        first = np.searchsorted(x, edges, side="right") - 1
        steps = int(np.max(first[2:] - first[:-2])) + 1  # pieces starting inside two buckets, +1
        if steps <= max_steps:
            self._bucket_first = first[:-1].astype(np.intp)
            self._bucket_scale = m / TWO_PI
            self._bucket_steps = steps

    def _extremes(self, n: int) -> tuple[float, float, float, float]:
        """(min, where, max, where) of the n-th derivative: breakpoints and roots of the next."""
        x = self._pp[0].x
        roots = self._pp[0].derivative(n + 1).roots() if n + 1 < self.degree else np.empty(0)
        cand = np.concatenate([x[:-1], roots[roots < x[-1]]])
        f = self._pp[n](cand)
        i, j = int(np.argmin(f)), int(np.argmax(f))
        at = np.mod(cand + self._origin, TWO_PI)
        return float(f[i]), float(at[i]), float(f[j]), float(at[j])

    @property
    def s_bounds(self) -> tuple[float, float]:
        """(smallest, largest) displacement of the spline over the turn (unit)."""
        if self._bounds is None:
            mn, _, mx, _ = self._extremes(0)
            self._bounds = (mn, mx)
        return self._bounds

    @property
    def stroke(self) -> float:
        """Largest minus smallest displacement (unit)."""
        lo, hi = self.s_bounds
        return hi - lo

    def peak_values(self) -> Peaks:
        """Largest |s'|, |s''|, |s'''| (unit/rad^n) and where (rad); a cubic's jerk steps at rows."""
        if self._peaks is None:
            best: list[tuple[float, float]] = []  # (value, where) of the velocity, acceleration and jerk
            for n in (1, 2, 3):
                mn, tmn, mx, tmx = self._extremes(n)
                best.append((abs(mn), tmn) if abs(mn) > abs(mx) else (abs(mx), tmx))
            (vel, vel_at), (acc, acc_at), (jerk, jerk_at) = best
            self._peaks = Peaks(vel, vel_at, acc, acc_at, jerk, jerk_at, infinite_acceleration=False, infinite_jerk=False)
        return self._peaks


def _wrap(theta: np.ndarray) -> np.ndarray:
    """theta mod 2 pi in [0, 2 pi) (floor form: faster than np.mod, same result up to rounding)."""
    u = theta - TWO_PI * np.floor(theta * (1.0 / TWO_PI))
    u[u >= TWO_PI] -= TWO_PI
    u[u < 0.0] = 0.0
    return u


def _bad(path: str, where: str, valid: str, why: str = "", key: str = "lift_table_csv") -> ParameterError:
    return ParameterError(key, f"{path}{', ' + where if where else ''}", valid, why)


def _fields(line: str) -> tuple[list[str], str]:
    """The fields of a row and what separates them ("a comma", "a semicolon" or "blanks")."""
    if "," in line:
        return [f.strip() for f in line.split(",")], "a comma"
    if ";" in line:
        return [f.strip() for f in line.split(";")], "a semicolon"
    return line.split(), "blanks"


def _number(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def parse_two_column_table(text: str, path: str = "<text>", key: str = "lift_table_csv",
                           columns: tuple[str, str] = ("angle_deg", "lift"),
                           max_rows: int = MAX_ROWS) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Rows of a two-column CSV text (the format of the module docstring): (first column,
    second column, labels "<path>, line k" for later errors), shapes (n,), (n,), n.

    Shared by the lift table, the dynamics load table and the trajectory table (``x, y``).  A
    row of other than two fields (a third column, decimal commas) is refused, never truncated.

    Raises
    ------
    ParameterError
        Naming ``key``, the file, the line number and why the line is not a row (how many
        fields, which is not a number).  The message never quotes the file's text: the file
        may not be a table at all (a scene naming a password file must not print it).
    """
    first: list[float] = []
    second: list[float] = []
    labels: list[str] = []
    seen_row = False
    pair = f"'{columns[0]}, {columns[1]}'"
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        fields, separator = _fields(line)
        where = f"line {number}"
        if len(fields) != 2 or not all(fields):
            why = (f"line {number} has an empty field" if not all(fields)
                   else f"line {number} is one field: no comma, semicolon or blank separates two" if len(fields) == 1
                   else f"line {number} holds {len(fields)} fields separated by {separator}, not two")
            raise _bad(path, where, f"rows of two fields {pair} (comma, semicolon or blank separated; no decimal commas)", why, key)
        values = [_number(f) for f in fields]
        if values[0] is None and values[1] is None and not seen_row:
            seen_row = True  # the header row
            continue
        seen_row = True
        if values[0] is None or values[1] is None:
            column = 1 if values[0] is None else 2
            raise _bad(path, where, f"two numbers {pair}", f"field {column} of line {number} is not a number; only the first "
                       "row may be a header of two names", key)
        if not (math.isfinite(values[0]) and math.isfinite(values[1])):
            column = 1 if not math.isfinite(values[0]) else 2
            raise _bad(path, where, "finite numbers", f"field {column} of line {number} is not finite (inf or nan)", key)
        first.append(values[0])
        second.append(values[1])
        labels.append(f"{path}, line {number}")
        if len(first) > max_rows:
            raise _bad(path, where, f"at most {max_rows} rows", key=key)
    return np.array(first), np.array(second), labels


def parse_lift_table(text: str, path: str = "<text>", max_rows: int = MAX_ROWS) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Rows of a lift-table CSV text: (angles_deg, lifts, labels "line k" for errors)."""
    return parse_two_column_table(text, path, "lift_table_csv", ("angle_deg", "lift"), max_rows)


def read_two_column_table(path: str | os.PathLike[str], key: str, columns: tuple[str, str], max_rows: int = MAX_ROWS,
                          max_bytes: int = MAX_BYTES) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Read a two-column CSV file (regular, UTF-8, at most ``max_bytes`` bytes, no NUL) and parse
    it with :func:`parse_two_column_table`; errors name ``key``, the file and the line."""
    from camgen.textfile import TextFileError, read_text_file

    name = str(path)
    try:
        text = read_text_file(path, max_bytes)
    except TextFileError as exc:
        raise _bad(name, "", f"a readable regular UTF-8 file of at most {max_bytes} bytes", str(exc), key) from None
    if "\x00" in text:
        raise _bad(name, f"character {text.index(chr(0))}", "text without NUL characters", key=key)
    return parse_two_column_table(text, name, key, columns, max_rows)


def read_lift_table(path: str | os.PathLike[str], degree: int = 5, unit: str = "mm", close_tol: float = 1e-9,
                    max_rows: int = MAX_ROWS, max_bytes: int = MAX_BYTES, lift_scale: float = 1.0) -> LiftTable:
    """Read a lift-table CSV (format in the module docstring) and return its :class:`LiftTable`.

    ``lift_scale`` multiplies the lift column (e.g. pi/180: a swing given in degrees, ``unit="rad"``).

    The file must be a regular file of at most ``max_bytes`` bytes, UTF-8 text; at most
    ``max_bytes`` + 1 bytes are ever read.

    Raises
    ------
    ParameterError
        Naming ``lift_table_csv``, the file and the offending line.
    """
    angles, lifts, labels = read_two_column_table(path, "lift_table_csv", ("angle_deg", "lift"), max_rows, max_bytes)
    return LiftTable(angles, lifts * lift_scale, degree=degree, unit=unit, close_tol=close_tol, max_rows=max_rows,
                     key="lift_table_csv", rows=labels)
