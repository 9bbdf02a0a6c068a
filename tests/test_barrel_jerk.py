"""A barrel cam's jerk limit at rpm (issue 26 item 5): the follower's largest jerk is the
cycloidal law's closed form (Norton, *Design of Machinery*, eq. 8.6: ``s''' = h 4 pi^2 / beta^3
cos(2 pi u)``, largest at the ends of the rise) times omega^3, and the check passes 1e-6 above it
and fails 1e-6 below it; a limit in the oscillating follower's unit on a translating one, or one
without rpm, is refused naming the key."""
from __future__ import annotations

import math

import pytest

from test_barrel_form import BETA, H, cam, check, run

RPM = 120.0


def closed_form_peak_m_per_s3() -> float:
    omega = 2.0 * math.pi * RPM / 60.0
    return H * 4.0 * math.pi**2 / BETA**3 * omega**3 * 1e-3  # mm/rad^3 * (rad/s)^3 -> m/s^3


@pytest.mark.parametrize("factor, status", [(1.0 + 1e-6, "pass"), (1.0 - 1e-6, "fail")])
def test_the_jerk_limit_holds_the_closed_form_peak_at_its_threshold(factor, status):
    peak = closed_form_peak_m_per_s3()
    _, report = run(cam(rpm=RPM, jerk_limit_m_per_s3=peak * factor))
    got = check(report, "jerk_limit")
    assert got["value"] == pytest.approx(peak, rel=1e-9)
    assert got["status"] == status


@pytest.mark.parametrize("extra, key", [({"rpm": RPM, "jerk_limit_rad_per_s3": 10.0}, "jerk_limit_rad_per_s3"),
                                        ({"jerk_limit_m_per_s3": 10.0}, "rpm")])
def test_a_jerk_limit_in_the_wrong_unit_or_without_rpm_is_refused(extra, key, tmp_path, capsys):
    from camgen.cli import main
    from helpers import scene_toml

    path = tmp_path / "s.toml"
    path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"c": cam(**extra)}}))
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("camgen: error:") and key in err[0]
    assert not (tmp_path / "out").exists()
