"""Cam types: a motion (:mod:`camgen.motions`) realised by a cam form (:mod:`camgen.forms`).

The scene's ``kind`` names the motion and ``form`` the cam form (default: the motion's own).  A
displacement-law motion is realised by every form with a law realisation (the form reads the
follower, body and checks, then the motion's law); a motion that is a design of its own names
the forms it realises.  :func:`get_kind` composes the two into the :class:`CamKind` the pipeline
builds, checks and reports; nothing here names a motion or a form.
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from camgen.kinds.base import CamKind
from camgen.schema import Choice, Key

if TYPE_CHECKING:
    from camgen.kinds.base import CamSpec
    from camgen.motions.base import Motion

__all__ = ["CamKind", "form_key", "forms_of", "get_kind", "kind_names"]


def kind_names() -> list[str]:
    """The motions a scene may name as ``kind``."""
    from camgen.motions import motion_names

    return motion_names()


def forms_of(motion_name: str) -> tuple[str, ...]:
    """The cam forms that realise motion ``motion_name``: its own realisations, and for a
    displacement law every form with a law realisation."""
    from camgen.forms import form_names, get_form
    from camgen.motions import get_motion

    motion = get_motion(motion_name)
    own = set(motion.realisations)
    if motion.read_law is not None:
        own |= {name for name in form_names() if get_form(name).read is not None}
    return tuple(sorted(own))


def form_key(motion_name: str) -> Key:
    """The ``form`` key of a cam table whose ``kind`` is ``motion_name``."""
    from camgen.forms import get_form
    from camgen.motions import get_motion

    forms = forms_of(motion_name)
    doc = "Cam form realising the motion (camgen.forms): " + "; ".join(f"{name}, {get_form(name).summary}" for name in forms) + "."
    return Key("form", Choice(forms), doc, ("profile",), default=get_motion(motion_name).default_form)


#: (motion name, form name) -> (the registries' state stamp it was composed at, the motion it was
#: composed from, the kind): a composed kind (its key schema included) is made once and reused
#: while no motion, form or follower is registered or removed (:func:`camgen.registry.generation`;
#: one registered or removed later recomposes it).  At most one entry per (motion, form) pair of
#: the registries.
_COMPOSED: dict[tuple[str, str], tuple[int, object, CamKind]] = {}


def get_kind(name: str, form: str | None = None) -> CamKind:
    """The cam type of motion ``name`` realised by ``form`` (default: the motion's default form);
    KeyError if either is unknown or the form does not realise the motion.  Composed once per
    registry state (:data:`_COMPOSED`): the same object while nothing is registered or removed."""
    from camgen.motions import get_motion
    from camgen.registry import generation

    motion = get_motion(name)
    form_name = form if form is not None else motion.default_form
    stamp = generation()
    hit = _COMPOSED.get((name, form_name))
    if hit is not None and hit[0] == stamp and hit[1] is motion:
        return hit[2]
    kind = _compose(name, form_name, motion)
    _COMPOSED[(name, form_name)] = (stamp, motion, kind)
    return kind


def _compose(name: str, form_name: str, motion: "Motion") -> CamKind:
    from camgen.forms import get_form

    if form_name not in forms_of(name):
        raise KeyError(f"form {form_name!r} does not realise motion {name!r}")
    key = form_key(name)
    if form_name in motion.realisations:
        own = motion.realisations[form_name]
        return CamKind(own.name, own.summary, (key,) + own.keys, own.read, own.build, own.report_section, own.evaluate,
                       own.follower_dynamics)
    form = get_form(form_name)
    assert form.read is not None and form.build is not None
    read = form.read

    def read_cam(where: str, cam_name: str, parsed: Mapping[str, Any], base_dir: Path | None = None) -> "CamSpec":
        return read(where, cam_name, parsed, motion, base_dir)

    return CamKind(name, motion.summary, (key,) + motion.keys + form.keys(), read_cam, form.build, form.report_section, form.evaluate,
                   form.follower_dynamics)
