"""Cam form ``plate``: the open plate (disk) cam, the exact envelope of its follower.

Realises every displacement law (:attr:`camgen.motions.base.Motion.read_law`) for a translating
or oscillating roller, flat face or knife edge, the cam turning either way: the profile is the
exact envelope of the follower within ``fit_tol_mm``, sized on request, checked from the closed
forms of the follower's kinematics (:mod:`camgen.kinds.disk`), with the follower train's
dynamics when the table gives one (:mod:`camgen.kinds.dynamics`).  The steering cam of paper
004 is a plate cam too, made by that paper's synthesis (:mod:`camgen.motions.trajectory`).
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from camgen.forms.base import CamForm
from camgen.kinds.base import body_keys, check_keys, source_key
from camgen.kinds.disk import build_disk, disk_spec, evaluate_disk, follower_keys, read_follower
from camgen.kinds.disk_margins import margin_keys
from camgen.kinds.disk_ranges import ranges_key
from camgen.kinds.dynamics import disk_kinematics, dynamics_keys

if TYPE_CHECKING:
    from camgen.kinds.base import CamSpec
    from camgen.motions.base import Motion

__all__ = ["FORM"]


def read(where: str, name: str, parsed: Mapping[str, Any], motion: "Motion", base_dir: Path | None = None) -> "CamSpec":
    """The typed spec of a plate cam: its follower and sizing, then the motion's law for it."""
    assert motion.read_law is not None, f"motion {motion.name!r} is not a displacement law"
    follower, sizing = read_follower(where, parsed)
    reading = motion.read_law(where, parsed, follower, base_dir)
    return disk_spec(where, name, motion.name, parsed, reading.law, follower, sizing, reading.figures, base_dir)


FORM = CamForm(
    name="plate",
    summary="open plate (disk) cam: the exact envelope of a translating or oscillating roller, flat face or knife",
    keys=lambda: follower_keys() + (source_key(),) + body_keys() + check_keys() + dynamics_keys() + margin_keys() + ranges_key(),
    read=read,
    build=build_disk,
    evaluate=evaluate_disk,
    follower_dynamics=disk_kinematics,
)
