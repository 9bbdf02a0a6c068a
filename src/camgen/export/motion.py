"""The follower inspection table (``<cam>_follower.csv``): the follower's motion at the cam's speed."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from camgen.export.tables import csv_table

if TYPE_CHECKING:
    from camgen.checks import Motion


def follower_csv(motion: "Motion", rpm: float, cam: str, scene: str) -> str:
    """CSV text: cam angle (deg), time (s), lift, velocity, acceleration and jerk at ``rpm``.

    Translating followers: lift mm, velocity mm/s, acceleration m/s^2, jerk m/s^3; oscillating
    ones: the arm's swing in deg and its angular velocity, acceleration and jerk in rad/s,
    rad/s^2, rad/s^3.  One row per sample of ``motion`` (cam angles from 0 over one turn); the
    time is the cam angle over the cam speed.
    """
    omega = 2.0 * math.pi * rpm / 60.0
    v, a, j, _ = motion.rates(rpm)
    oscillating = motion.unit == "rad"
    lift = np.degrees(motion.lift) if oscillating else motion.lift
    if oscillating:
        names = ("lift_deg", "velocity_rad_per_s", "acceleration_rad_per_s2", "jerk_rad_per_s3")
    else:
        names = ("lift_mm", "velocity_mm_per_s", "acceleration_m_per_s2", "jerk_m_per_s3")
    impulses = (f"; the acceleration jumps (a jerk impulse, not in the jerk column) at cam angles "
                f"{', '.join(f'{x:g}' for x in motion.jerk_impulses_deg[:24])} deg" if motion.jerk_impulses_deg else "")
    comments = [
        f"camgen follower table of cam '{cam}' (scene '{scene}') at {rpm:g} rpm (omega {omega:.9g} rad/s, one turn {60.0 / rpm:.9g} s)",
        "cam_angle_deg = the cam's rotation from cam angle 0, in its direction of rotation; time_s = cam angle / omega",
        ("lift_deg = the arm's swing from zero swing (deg, positive away from the cam); velocity rad/s, acceleration rad/s^2, jerk rad/s^3"
         if oscillating else
         "lift_mm = the follower's travel from zero lift (mm, positive away from the cam axis); velocity mm/s, acceleration m/s^2, "
         "jerk m/s^3") + impulses,
        f"{motion.cam_angle.size} rows, cam angle step {math.degrees(2.0 * math.pi / motion.cam_angle.size):g} deg",
    ]
    return csv_table(comments, {"cam_angle_deg": np.degrees(motion.cam_angle), "time_s": motion.cam_angle / omega,
                                names[0]: lift, names[1]: v, names[2]: a, names[3]: j})
