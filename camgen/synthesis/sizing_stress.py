"""The Hertz contact stress of a disk cam's follower at speed, as a sizing limit.

The dynamics' own model (:func:`camgen.dynamics.analyse`: the rigid follower train, the contact
force along the normal, Rothbart's line-contact stress, eq. 9.11) on the closed-form kinematics
of :func:`camgen.synthesis.followers.kinematics`, converted as the disk cams' dynamics stage
converts them (:func:`camgen.kinds.dynamics.disk_kinematics`): the roller radius (a flat face:
infinite), the direction the follower moves, and an oscillating face's lever.
"""
from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.errors import GeometryError, ParameterError

if TYPE_CHECKING:
    from camgen.synthesis.followers import FollowerSpec, Kinematics

__all__ = ["contact_stress"]


def contact_stress(follower: "FollowerSpec", k: "Kinematics", train: Any, material: Any, rpm: float) -> tuple[float, int]:
    """The peak Hertz stress (MPa) of ``follower`` with kinematics ``k``, follower ``train``
    (:class:`camgen.dynamics.FollowerTrain`) and contact ``material``
    (:class:`camgen.dynamics.ContactMaterial`) at ``rpm`` (rev/min), and the
    index of the cam angle where it occurs; ``inf`` when the contact cannot carry a force (a
    concave part tighter than the roller, a pressure angle of 90 deg) or has no finite stress
    (a sharp knife)."""
    from camgen import dynamics as dy

    radius = follower.roller_radius if follower.contact == "point" else math.inf
    if not radius > 0:
        return math.inf, 0
    lever: Any = None
    if follower.motion == "translating":
        direction: Any = math.pi / 2
        arm = 0.0
    elif follower.contact == "face":
        assert k.arm_angle is not None and k.face_position is not None  # an oscillating face's kinematics carry them
        direction = k.arm_angle - follower.tau * math.pi / 2
        lever = np.hypot(k.face_position, follower.face_offset)
        arm = float(np.max(lever))
    else:
        assert k.arm_angle is not None  # an oscillating arm's kinematics carry its angle
        direction = k.arm_angle + follower.tau * math.pi / 2
        arm = follower.arm_length
    theta = np.mod(k.theta, 2.0 * math.pi)
    order = np.argsort(theta, kind="stable")
    keep = order[np.concatenate([[True], np.diff(theta[order]) > 0])]  # the dynamics take strictly increasing angles in [0, 2 pi)
    pick = (lambda v: v[keep] if isinstance(v, np.ndarray) else v)
    try:
        kin = dy.Kinematics(theta[keep], k.s[keep], k.ds[keep], k.d2s[keep], k.pressure_angle[keep], k.profile_radius[keep], radius,
                            pick(direction), lever=pick(lever))
        train = replace(train, arm_length=arm) if train.motion == "oscillating" else train
        result = dy.analyse(kin, train, rpm, material)
    except (GeometryError, ParameterError):  # the contact cannot carry the force there
        return math.inf, 0
    stresses = [h for h in (result.hertz_stress, result.hertz_stress_2) if h is not None]
    if not stresses:
        return math.inf, 0
    stress = np.max(np.stack(stresses), axis=0)
    i = int(np.argmax(stress))
    return float(stress[i]), int(keep[i])
