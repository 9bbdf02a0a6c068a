"""Motion ``lift_table``: a table of cam angle and lift (a CSV file), a displacement law.

The lift follows a periodic quintic spline through the rows
(:func:`camgen.synthesis.lift_table.read_lift_table`: continuous through the jerk); every cam
form that realises a law takes it (the open plate cam: :mod:`camgen.forms.plate`).  The
lift column is in mm for a translating follower and in degrees of swing for an oscillating one.
A linear cam (:mod:`camgen.forms.linear`, whose ``travel_mm`` is then among the parsed keys)
reads the first column as the plate travel x in mm, its turn being the travel.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from camgen.errors import ParameterError
from camgen.keynames import renamed
from camgen.motions.base import LawReading, Motion
from camgen.schema import REQUIRED, Key, Number, Text

if TYPE_CHECKING:
    from camgen.synthesis.followers import FollowerSpec

KEYS = (
    Key("lift_table_csv", Text(), "CSV file of rows 'angle_deg, lift' (cam angle in deg; lift in mm, or deg of swing for an "
        "oscillating follower), relative to the scene file; one turn, closed automatically; '#' comments and a header row allowed. "
        "A linear cam (form = \"linear\") reads the first column as the plate travel x in mm, one turn = travel_mm.",
        ("profile",), default=REQUIRED),
    # SMOOTH (issue 26 item 3): measured lift data smoothed within a stated tolerance
    Key("smoothing_mm", Number("mm", 0.0, 10.0), "Measured lift data: 0 interpolates every row (the spline passes through each "
        "reading); > 0 fits instead the smoothest periodic quintic spline (least integral of the squared jerk) within this many mm "
        "of every reading (the readings' uncertainty: e.g. half their last digit plus the instrument's noise); the residuals "
        "(largest, RMS, per reading) are in the report, and the undercut, contact-stress and jump checks say how far the readings' "
        "noise would have moved them. Translating followers and linear cams (lift in mm); not with half_turn.",
        ("profile", "report"), default=0.0, example=0.005),
)


def read_law(where: str, parsed: Mapping[str, Any], follower: "FollowerSpec", base_dir: Path | None = None) -> LawReading:
    """The lift table of a cam table for ``follower`` (lift in mm for a translating one, degrees
    of swing for an oscillating one, read into rad): the file is read now."""
    from camgen.synthesis.lift_table import LiftTable, read_two_column_table

    path = Path(parsed["lift_table_csv"])
    path = path if path.is_absolute() or base_dir is None else base_dir / path
    oscillating = follower.motion == "oscillating"
    # a linear cam (its form's travel_mm) gives the first column as the travel x in mm: its turn is the travel
    angle_scale = 360.0 / parsed["travel"] if "travel" in parsed else 1.0

    def read():
        angles, lifts, labels = read_two_column_table(path, "lift_table_csv", ("angle_deg", "lift"))
        if "travel" in parsed:  # say what is wrong with the x column in mm (LiftTable speaks of cam angles)
            import numpy as np

            travel = parsed["travel"]
            bad = np.flatnonzero((np.diff(angles) <= 0) | (angles[1:] - angles[0] > travel * (1 + 1e-12)))
            if bad.size:
                i = int(bad[0]) + 1
                raise ParameterError("lift_table_csv", f"{labels[i]}: x {angles[i]:.9g} mm after {angles[i - 1]:.9g} mm",
                                     f"x (mm) strictly increasing and within one travel: <= {angles[0] + travel:.9g} mm (first row + "
                                     "travel_mm)")
        return LiftTable(angles * angle_scale, lifts * (math.pi / 180.0 if oscillating else 1.0), unit="rad" if oscillating else "mm",
                         key="lift_table_csv", rows=labels)

    table = renamed(where, KEYS, read)
    figures = {"lift_table_csv": parsed["lift_table_csv"], "table_rows": int(table.angles.size), "table_spline_degree": table.degree}
    tolerance = parsed.get("smoothing", 0.0)
    if tolerance > 0:  # SMOOTH (issue 26 item 3): one call
        from camgen.motions.smoothing import smoothed_table

        return smoothed_table(where, table, tolerance, oscillating, figures)
    return LawReading(table, figures)


def read_half_law(where: str, parsed: Mapping[str, Any], follower: "FollowerSpec", base_dir: Path | None = None) -> LawReading:
    """The lift table of a cam table whose rows cover the first half-turn (from 0 to 180 deg, both
    rows given), completed by ``s(theta + 180 deg) = C - s(theta)``
    (:func:`camgen.synthesis.breadth.mirror_rows`)."""
    import numpy as np

    from camgen.errors import ParameterError
    from camgen.synthesis.breadth import mirror_rows
    from camgen.synthesis.lift_table import LiftTable, read_two_column_table

    path = Path(parsed["lift_table_csv"])
    path = path if path.is_absolute() or base_dir is None else base_dir / path
    oscillating = follower.motion == "oscillating"
    name = f"{where}.lift_table_csv"
    if parsed.get("smoothing", 0.0) > 0:  # SMOOTH: the fit would have to keep the breadth rule; not offered
        raise ParameterError(f"{where}.smoothing_mm", parsed["smoothing"], "0 with half_turn = true",
                             "a smoothed table is not offered for a half-turn program (its fit does not state the breadth rule)")
    angles, lifts, _ = renamed(where, KEYS, lambda: read_two_column_table(path, "lift_table_csv", ("angle_deg", "lift")))
    if angles.size < 2 or angles[0] != 0.0 or angles[-1] != 180.0 or bool(np.any(np.diff(angles) <= 0)):
        raise ParameterError(name, f"rows from {angles[0]:.9g} to {angles[-1]:.9g} deg" if angles.size else "no rows",
                             "increasing cam angles from 0 to 180 deg, both rows given",
                             "half_turn = true: the rows give the first half-turn, the rule s(theta + 180 deg) = C - s(theta) the second")
    full_angles, full_lifts = mirror_rows(angles, lifts * (math.pi / 180.0 if oscillating else 1.0))
    table = renamed(where, KEYS, lambda: LiftTable(full_angles, full_lifts, unit="rad" if oscillating else "mm", key="lift_table_csv"))
    figures = {"lift_table_csv": parsed["lift_table_csv"], "table_rows": int(angles.size), "table_spline_degree": table.degree,
               "half_turn": True}
    return LawReading(table, figures)


MOTION = Motion(
    name="lift_table",
    summary="disk cam from a CSV table of cam angle and lift (a periodic quintic spline through the rows) for a translating or "
            "oscillating roller, flat face or knife, as the exact envelope",
    keys=KEYS,
    read_law=read_law,
    read_half_law=read_half_law,
)
