"""Cam kind ``lift_table``: a disk cam from a table of cam angle and lift (a CSV file).

The lift follows a periodic quintic spline through the rows
(:func:`camgen.synthesis.lift_table.read_lift_table`: continuous through the jerk); the follower,
the exact envelope, sizing and the checks are the disk cams' (:mod:`camgen.kinds.disk`).  The
lift column is in mm for a translating follower and in degrees of swing for an oscillating one.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from camgen.keynames import renamed
from camgen.kinds.base import CamKind, CamSpec, body_keys, check_keys, source_key
from camgen.kinds.disk import build_disk, disk_spec, evaluate_disk, follower_keys, read_follower
from camgen.kinds.dynamics import disk_kinematics, dynamics_keys
from camgen.schema import REQUIRED, Key, Text

KEYS = (
    Key("lift_table_csv", Text(), "CSV file of rows 'angle_deg, lift' (cam angle in deg; lift in mm, or deg of swing for an "
        "oscillating follower), relative to the scene file; one turn, closed automatically; '#' comments and a header row allowed.",
        ("profile",), default=REQUIRED),
) + follower_keys() + (source_key(),) + body_keys() + check_keys() + dynamics_keys()


def read(where: str, name: str, parsed: dict[str, Any], base_dir: Path | None = None) -> CamSpec:
    """The typed spec of a ``lift_table`` cam table: the table is read now."""
    from camgen.synthesis.lift_table import read_lift_table

    follower, sizing = read_follower(where, parsed)
    path = Path(parsed["lift_table_csv"])
    path = path if path.is_absolute() or base_dir is None else base_dir / path
    oscillating = follower.motion == "oscillating"
    table = renamed(where, KEYS, lambda: read_lift_table(path, unit="rad" if oscillating else "mm",
                                                      lift_scale=math.pi / 180.0 if oscillating else 1.0))
    figures = {"lift_table_csv": parsed["lift_table_csv"], "table_rows": int(table.angles.size), "table_spline_degree": table.degree}
    return disk_spec(where, name, "lift_table", parsed, table, follower, sizing, figures, base_dir)


KIND = CamKind(
    name="lift_table",
    summary="disk cam from a CSV table of cam angle and lift (a periodic quintic spline through the rows) for a translating or "
            "oscillating roller, flat face or knife, as the exact envelope",
    keys=KEYS,
    read=read,
    build=build_disk,
    evaluate=evaluate_disk,
    follower_dynamics=disk_kinematics,
)
