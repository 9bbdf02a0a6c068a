"""Cam form ``conjugate``: two plate cams on one shaft holding one follower with two rollers.

Realises every displacement law for a translating follower (roller B on the stem, a fixed
distance below roller A, on the other side of the shaft) or an oscillating one (roller B on a
second arm of the rocker at a fixed angle); the scene cam ``x`` becomes the two cams ``x_a``
(cam A, roller A) and ``x_b`` (cam B, roller B) of the run (:attr:`CamForm.expand`), each the
exact envelope of its roller with the plate cam's checks and files; with the dynamics keys the
pair is a form-closed follower train whose dynamics (both rollers' contacts, the pair's camshaft
torque) are reported on ``x_a``.  The derivation, the preload
and the conventions are in :mod:`camgen.kinds.conjugate`, which is imported only when a scene
uses the form.
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from camgen.forms.base import CamForm
from camgen.kinds.base import body_keys, check_keys, source_key

if TYPE_CHECKING:
    from camgen.checks import CamEvaluation
    from camgen.kinds.base import BuiltCam, CamSpec
    from camgen.motions.base import Motion

__all__ = ["FORM"]


def _keys() -> tuple[Any, ...]:
    from camgen.kinds.conjugate import conjugate_keys

    from camgen.kinds.dynamics import dynamics_keys

    return conjugate_keys() + (source_key(),) + body_keys() + check_keys() + dynamics_keys()


def _read(where: str, name: str, parsed: Mapping[str, Any], motion: "Motion", base_dir: Path | None = None) -> "CamSpec":
    from camgen.kinds.conjugate import read_conjugate

    return read_conjugate(where, name, parsed, motion, base_dir)


def _expand(spec: "CamSpec") -> "tuple[CamSpec, ...]":
    from camgen.kinds.conjugate import expand_conjugate

    return expand_conjugate(spec)


def _build(spec: "CamSpec", stages: frozenset[str]) -> "BuiltCam":
    from camgen.kinds.conjugate import build_conjugate

    return build_conjugate(spec, stages)


def _kinematics(cam: "BuiltCam", spec: "CamSpec") -> tuple[Any, float]:
    from camgen.kinds.conjugate import conjugate_kinematics

    return conjugate_kinematics(cam, spec)


def _evaluate(cam: "BuiltCam", spec: "CamSpec", tool_radius: float, tool_is_limit: bool) -> "CamEvaluation":
    from camgen.kinds.conjugate import evaluate_conjugate

    return evaluate_conjugate(cam, spec, tool_radius, tool_is_limit)


FORM = CamForm(
    name="conjugate",
    summary="conjugate pair: two plate cams on one shaft (<cam>_a, <cam>_b) holding a follower with two rollers, translating or "
            "oscillating, without a spring",
    keys=_keys,
    read=_read,
    build=_build,
    evaluate=_evaluate,
    follower_dynamics=_kinematics,
    report_section="camgen.kinds.conjugate:pair_section",
    expand=_expand,
)
