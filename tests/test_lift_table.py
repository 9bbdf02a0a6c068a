"""Lift tables (camgen.synthesis.lift_table): spline order measured by convergence, continuity
measured at the rows, the CSV reader's errors and its guards against unbounded files."""
from __future__ import annotations

import builtins
import contextlib
import math
import os

import numpy as np
import pytest

from camgen.errors import ParameterError
from camgen.synthesis.laws import Displacement
from camgen.synthesis.lift_table import MIN_ROWS, LiftTable, read_lift_table

PI = math.pi


def smooth(theta):
    """A smooth periodic lift (mm) and its first three derivatives, in closed form."""
    s = 10 + 3 * np.sin(theta) + np.cos(2 * theta) + 0.5 * np.sin(3 * theta + 1)
    v = 3 * np.cos(theta) - 2 * np.sin(2 * theta) + 1.5 * np.cos(3 * theta + 1)
    a = -3 * np.sin(theta) - 4 * np.cos(2 * theta) - 4.5 * np.sin(3 * theta + 1)
    j = -3 * np.cos(theta) + 8 * np.sin(2 * theta) - 13.5 * np.cos(3 * theta + 1)
    return s, v, a, j


def table(n, jitter=0.0, start_deg=0.0, seed=3):
    """n rows over one turn, spacing jittered by +-jitter of the mean spacing (fixed seed)."""
    step = 360.0 / n
    offsets = np.random.default_rng(seed).uniform(-jitter, jitter, n) * step
    offsets[0] = 0.0
    angles = start_deg + np.arange(n) * step + offsets
    return angles, smooth(np.radians(angles))[0]


def errors(spline):
    theta = np.linspace(0, 2 * PI, 20001)
    got = spline(theta)
    return [float(np.max(np.abs(g - w))) for g, w in zip(got, smooth(theta))]


@pytest.mark.parametrize("degree, jitter", [(5, 0.0), (5, 0.25), (3, 0.0), (3, 0.25)])
def test_convergence_order(degree, jitter):
    """Interpolation error ~ h^(k+1-n) for the n-th derivative (k = degree): the measured slope of
    log(error) against log(N) over N = 32, 64, 128 is within 0.6 of that."""
    sizes = (32, 64, 128)
    errs = np.array([errors(LiftTable(*table(n, jitter), degree=degree)) for n in sizes])
    slopes = np.log2(errs[:-1] / errs[1:])  # per halving of h
    for n in range(4):
        expected = degree + 1 - n
        assert np.all(slopes[:, n] > expected - 0.6), (n, slopes[:, n])
        assert np.all(slopes[:, n] < expected + 0.9), (n, slopes[:, n])
    if degree == 5:
        assert errs[-1][0] < 1e-8  # 128 rows: s to 1e-8 mm


def test_interpolates_the_rows_and_is_periodic():
    angles, lifts = table(40, 0.3, start_deg=-25.0)
    spline = LiftTable(angles, lifts)
    assert isinstance(spline, Displacement)
    theta = np.radians(angles)
    assert np.max(np.abs(spline(theta)[0] - lifts)) < 1e-12
    for shift in (2 * PI, -6 * PI, 20 * PI):
        for got, want in zip(spline(theta + shift), spline(theta)):
            assert np.max(np.abs(got - want)) < 1e-9 * max(1.0, np.max(np.abs(want)))
    seam = spline(np.radians([angles[0], angles[0] + 360.0, angles[0] - 720.0]))[0]
    assert np.max(np.abs(seam - lifts[0])) < 1e-12
    assert spline.breaks.size == 40 and np.all(np.diff(spline.breaks) > 0)
    assert spline.breaks[0] >= 0 and spline.breaks[-1] < 2 * PI


@pytest.mark.parametrize("degree, continuity", [(5, 3), (3, 2)])
def test_continuity_at_the_rows(degree, continuity):
    """Jumps measured from both sides of every row (including the seam): the quintic is continuous
    through the jerk, the cubic's jerk steps."""
    angles, lifts = table(24, 0.2)
    spline = LiftTable(angles, lifts, degree=degree)
    theta = np.radians(angles)
    delta = 1e-8
    left, right = spline(theta - delta), spline(theta + delta)
    scale = [max(1.0, float(np.max(np.abs(x)))) for x in spline(np.linspace(0, 2 * PI, 2001))]
    jumps = [float(np.max(np.abs(r - l))) / s for l, r, s in zip(left, right, scale)]
    assert max(jumps[:3]) < 1e-5
    if continuity == 3:
        assert jumps[3] < 1e-5
    else:
        assert jumps[3] > 1e-3
    assert set(spline.break_continuity) == {continuity}
    if continuity == 2:  # exactly at a row the following piece's jerk is used
        at = spline(theta)[3]
        assert np.max(np.abs(at - right[3])) < 1e-5 * scale[3] < np.min(np.abs(at - left[3]))


def test_seam_uses_the_first_row_piece():
    """-1e-300 rad wraps to 2 pi in floating point: it must still evaluate as the seam's right-hand
    (first row's) piece -- visible in a cubic, whose jerk steps there."""
    angles, lifts = table(16, 0.2)
    spline = LiftTable(angles, lifts, degree=3)
    tiny, zero, before = spline(np.array([-1e-300])), spline(np.array([0.0])), spline(np.array([-1e-9]))
    assert tiny[3][0] == zero[3][0]
    assert abs(before[3][0] - zero[3][0]) > 1e-3


def test_peaks_and_stroke():
    """A pure sine table: v peaks at amplitude A, a at A, j at A (per rad^n), stroke 2A."""
    angles = np.arange(0, 360, 3.0)
    spline = LiftTable(angles, 4 + 2.5 * np.sin(np.radians(angles)))
    peaks = spline.peak_values()
    assert (peaks.velocity, peaks.acceleration, peaks.jerk) == pytest.approx((2.5, 2.5, 2.5), rel=1e-6)
    assert math.cos(peaks.velocity_at) == pytest.approx(math.copysign(1, math.cos(peaks.velocity_at)), abs=1e-6)
    assert spline.stroke == pytest.approx(5.0, rel=1e-9)


def test_closing_row_is_the_same_table():
    angles, lifts = table(30)
    closed = LiftTable(np.append(angles, 360.0), np.append(lifts, lifts[0]))
    open_ = LiftTable(angles, lifts)
    theta = np.linspace(-1, 7, 999)
    for a, b in zip(closed(theta), open_(theta)):
        assert np.array_equal(a, b)


def write(tmp_path, text, name="lift.csv"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_csv_reader_formats(tmp_path):
    angles, lifts = table(36)
    rows = [f"{a:.17g}, {s:.17g}" for a, s in zip(angles, lifts)]
    text = "# cam lift table\n# unit: mm\nangle_deg, lift_mm\n\n" + "\n".join(r + ("  # comment" if i == 3 else "") for i, r in enumerate(rows))
    reference = LiftTable(angles, lifts)
    theta = np.linspace(0, 2 * PI, 501)
    for variant in (text, text.replace(", ", ";"), text.replace(", ", "\t").replace("angle_deg\tlift_mm", "angle lift"),
                    "\ufeff" + text + "\n"):
        got = read_lift_table(write(tmp_path, variant))
        assert np.array_equal(got(theta)[0], reference(theta)[0])


BAD_TABLES = {
    "not a number": ("0, 0\n10, x\n", "line 2"),
    "three fields": ("0, 0, 1\n", "line 1"),
    "empty field": ("0,\n", "line 1"),
    "decimal comma": ("0;0,5\n", "line 1"),
    "header later": ("0, 0\nangle, lift\n", "line 2"),
    "half header": ("angle, 3\n", "line 1"),
    "nan": ("0, nan\n", "line 1"),
    "decreasing": ("".join(f"{a}, 1\n" for a in (0, 10, 20, 15, 30, 40, 50, 60, 70)), "line 4"),
    "duplicate": ("".join(f"{a}, 1\n" for a in (0, 10, 20, 20, 30, 40, 50, 60, 70)), "line 4"),
    "beyond a turn": ("".join(f"{a}, 1\n" for a in (0, 50, 100, 150, 200, 250, 300, 350, 370)), "line 9"),
    "closing row differs": ("".join(f"{a}, {a / 100}\n" for a in (0, 50, 100, 150, 200, 250, 300, 350, 360)), "line 9"),
    "too few rows": ("0, 1\n10, 2\n20, 3\n", "3 rows"),
    "empty": ("# nothing\n", "0 rows"),
}


@pytest.mark.parametrize("case", sorted(BAD_TABLES))
def test_csv_reader_errors_name_the_key_and_line(tmp_path, case):
    text, where = BAD_TABLES[case]
    with pytest.raises(ParameterError, match=where) as info:
        read_lift_table(write(tmp_path, text))
    assert info.value.name == "lift_table_csv"


def test_csv_reader_row_and_size_caps(tmp_path):
    text = "".join(f"{a}, 1\n" for a in range(0, 360, 10))
    with pytest.raises(ParameterError, match="at most 20 rows") as info:
        read_lift_table(write(tmp_path, text), max_rows=20)
    assert info.value.name == "lift_table_csv"
    with pytest.raises(ParameterError, match="at most 100 bytes"):
        read_lift_table(write(tmp_path, text), max_bytes=100)
    huge = tmp_path / "huge.csv"  # sparse: refused by its size, never read
    with open(huge, "wb") as handle:
        handle.truncate(10**12)
    with never_opened(huge), pytest.raises(ParameterError, match="1000000000000 bytes"):
        read_lift_table(huge)


@contextlib.contextmanager
def never_opened(path):
    """Fail if ``path`` is opened inside the block: a refusal made from its size or type alone
    takes no time whatever the file holds (benchmarks/bench_refusals.py times it)."""
    real_open, real_os_open = builtins.open, os.open

    def guarded(opener):
        def call(file, *args, **kwargs):
            if isinstance(file, (str, bytes, os.PathLike)) and os.fspath(file) == os.fspath(path):
                raise AssertionError(f"{path} was opened")
            return opener(file, *args, **kwargs)
        return call

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(builtins, "open", guarded(real_open))
        patch.setattr(os, "open", guarded(real_os_open))
        yield


@pytest.mark.parametrize("path", ["/dev/zero", "/dev/urandom"])
def test_devices_fail_fast(path):
    if not os.path.exists(path):
        pytest.fail(f"{path} missing on this system")
    with never_opened(path), pytest.raises(ParameterError, match="regular file") as info:
        read_lift_table(path)
    assert info.value.name == "lift_table_csv"


def test_pipe_directory_missing_binary(tmp_path):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)  # opening it would block without a writer: refused by its type first
    with never_opened(fifo), pytest.raises(ParameterError, match="regular file"):
        read_lift_table(fifo)
    with pytest.raises(ParameterError, match="regular file"):
        read_lift_table(tmp_path)
    with pytest.raises(ParameterError, match="No such file"):
        read_lift_table(tmp_path / "missing.csv")
    binary = tmp_path / "binary.csv"
    binary.write_bytes(b"0, 1\n\xff\xfe, 2\n")
    with pytest.raises(ParameterError, match="UTF-8"):
        read_lift_table(binary)
    nul = tmp_path / "nul.csv"
    nul.write_bytes(b"0, 1\x00\n")
    with pytest.raises(ParameterError, match="NUL"):
        read_lift_table(nul)


def test_constructor_errors():
    angles, lifts = table(12)
    with pytest.raises(ParameterError, match="one of") as info:
        LiftTable(angles, lifts, degree=4)
    assert info.value.name == "degree"
    with pytest.raises(ParameterError, match="row 3"):
        LiftTable(np.r_[0, 10, np.inf, angles[3:]], lifts)
    with pytest.raises(ParameterError, match=f"at least {MIN_ROWS}"):
        LiftTable(angles[:MIN_ROWS - 1], lifts[:MIN_ROWS - 1])
    with pytest.raises(ParameterError, match="theta"):
        LiftTable(angles, lifts)(np.array([np.nan]))
