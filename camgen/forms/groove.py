"""Cam form ``groove``: a groove (track, face) plate cam: a roller running in a groove cut into a
plate, held both ways by the groove's walls (form-closed: no spring, no jump).

Realises every displacement law (:attr:`camgen.motions.base.Motion.read_law`) for a
translating or oscillating roller, the cam turning either way: the walls are the exact
envelopes of the roller (widened by half the clearance) on both sides of the pitch curve
(:mod:`camgen.kinds.groove`).
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from camgen.forms.base import CamForm
from camgen.kinds.base import body_keys, check_keys, source_key
from camgen.kinds.disk import disk_spec, read_follower
from camgen.kinds.dynamics import dynamics_keys
from camgen.kinds.groove import build_groove, evaluate_groove, groove_keys, groove_kinematics, groove_spec, roller_keys

if TYPE_CHECKING:
    from camgen.kinds.base import CamSpec
    from camgen.motions.base import Motion

__all__ = ["FORM"]


def read(where: str, name: str, parsed: Mapping[str, Any], motion: "Motion", base_dir: Path | None = None) -> "CamSpec":
    """The typed spec of a groove cam: its roller, then the motion's law for it, then the groove."""
    assert motion.read_law is not None, f"motion {motion.name!r} is not a displacement law"
    follower, sizing = read_follower(where, parsed)
    reading = motion.read_law(where, parsed, follower, base_dir)
    spec = disk_spec(where, name, motion.name, parsed, reading.law, follower, sizing, reading.figures, base_dir, form_closed=True)
    return groove_spec(where, spec, parsed)


FORM = CamForm(
    name="groove",
    summary="groove (track) plate cam: a roller running in a groove cut into a plate, both walls the exact envelopes of the roller",
    keys=lambda: roller_keys() + (source_key(),) + body_keys() + check_keys() + groove_keys() + dynamics_keys(),
    read=read,
    build=build_groove,
    evaluate=evaluate_groove,
    follower_dynamics=groove_kinematics,
)
