"""The follower inspection table (``<cam>_follower.csv``): the follower's motion at the cam's speed.

The CSV is a header row and numbers (:func:`camgen.export.tables.csv_table`); its units, speed
and the cam angles where the acceleration jumps are stated by :func:`follower_metadata`, which
report.json's ``tables`` object holds.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.export.tables import csv_table

if TYPE_CHECKING:
    from camgen.checks import Motion

__all__ = ["follower_columns", "follower_csv", "follower_metadata"]


def follower_columns(oscillating: bool) -> dict[str, str]:
    """Columns of the follower table and what they hold: translating followers in mm, mm/s,
    m/s^2, m/s^3; oscillating ones swing in deg and turn in rad/s, rad/s^2, rad/s^3."""
    common = {
        "cam_angle_deg": "the cam's rotation from cam angle 0, in its direction of rotation, deg",
        "time_s": "time from cam angle 0 at the cam's speed (cam angle / omega), s",
    }
    if oscillating:
        return {**common,
                "lift_deg": "the arm's swing from zero swing (positive away from the cam), deg",
                "velocity_rad_per_s": "the arm's angular velocity, rad/s",
                "acceleration_rad_per_s2": "the arm's angular acceleration, rad/s^2",
                "jerk_rad_per_s3": "the arm's angular jerk (finite part: jerk_impulses_deg lists the jumps of the acceleration), rad/s^3"}
    return {**common,
            "lift_mm": "the follower's travel from zero lift (positive away from the cam axis), mm",
            "velocity_mm_per_s": "the follower's velocity, mm/s",
            "acceleration_m_per_s2": "the follower's acceleration, m/s^2",
            "jerk_m_per_s3": "the follower's jerk (finite part: jerk_impulses_deg lists the jumps of the acceleration), m/s^3"}


def follower_csv(motion: "Motion", rpm: float) -> str:
    """CSV text: cam angle (deg), time (s), lift, velocity, acceleration and jerk at ``rpm``
    (units: :func:`follower_columns`), one row per sample of ``motion`` (cam angles from 0 over
    one turn); the time is the cam angle over the cam speed."""
    omega = 2.0 * math.pi * rpm / 60.0
    v, a, j, _ = motion.rates(rpm)
    oscillating = motion.unit == "rad"
    lift = np.degrees(motion.lift) if oscillating else motion.lift
    values = (np.degrees(motion.cam_angle), motion.cam_angle / omega, lift, v, a, j)
    return csv_table(dict(zip(follower_columns(oscillating), values)))


def follower_metadata(motion: "Motion", rpm: float) -> dict[str, Any]:
    """What :func:`follower_csv` holds (report.json ``tables``): the follower's motion, the cam
    speed, the rows' cam-angle step and the cam angles where the acceleration jumps."""
    oscillating = motion.unit == "rad"
    return {
        "content": "the follower's motion at the cam's speed over one turn, one row per cam-angle sample",
        "columns": follower_columns(oscillating),
        "follower_motion": "oscillating" if oscillating else "translating",
        "rpm": float(rpm),
        "omega_rad_per_s": 2.0 * math.pi * rpm / 60.0,
        "turn_s": 60.0 / rpm,
        "cam_angle_step_deg": 360.0 / motion.cam_angle.size,
        "jerk_impulses_deg": [float(x) for x in motion.jerk_impulses_deg],
    }
