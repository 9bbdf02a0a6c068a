"""The cam-form axis: the body that realises a motion for a follower.

A cam form is one module in :mod:`camgen.forms` exposing ``FORM``, a :class:`CamForm`: its keys
(the follower it carries, its body, its checks), how to read them with a displacement law into a
typed :class:`~camgen.kinds.base.CamSpec`, how to build the cam and which checks it owns.  A
form with ``read`` realises every displacement-law motion (:class:`camgen.motions.base.Motion`
with ``read_law``); a form without one is realised only by the motions that name it in their
``realisations`` (the three-arc constant-breadth cam today).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping

from camgen.schema import Key

if TYPE_CHECKING:
    from camgen.checks import CamEvaluation
    from camgen.kinds.base import BuiltCam, CamSpec
    from camgen.motions.base import Motion

__all__ = ["CamForm"]


@dataclass(frozen=True)
class CamForm:
    """A registered cam form.

    Attributes
    ----------
    name : the ``form`` value in scene files.
    summary : one line for ``camgen keys``.
    keys : ``() -> keys``: the form's keys (follower, body, checks, ...), after the motion's; a
        function, so that a follower registered later is among them.
    read : ``(where, name, parsed, motion, base_dir) -> CamSpec``: the form's keys and the motion's
        law (:attr:`Motion.read_law`) into the typed spec; None: no law realisation (see above).
    build, evaluate, follower_dynamics, report_section : as :class:`camgen.kinds.base.CamKind`.
    expand : ``(spec) -> specs``: a form that realises one scene cam as several bodies (a conjugate
        pair: two cams) gives their specs, each then built, checked and written as a cam of the
        run under its own name (the scene cam's name and a suffix; the scene reader refuses a name
        that clashes); None: the scene cam is one body.
    formats_refused : output format -> why this form's cams cannot have it (a polar lift table of
        a body that turns about no axis); a run asking for one is refused naming ``output.formats``.
    writers : output format -> ``"module:function"`` writing that format for this form's cams
        instead of the registered writer (:data:`camgen.outputs.OUTPUTS`), with its signature: a
        body that is not a plate with pockets (a barrel cam) writes its own drawing and program.
    stages : per-cam stage name (:data:`camgen.outputs.CAM_STAGES`) -> ``"module:function"``
        running that stage for this form's cams instead of the registered runner (a barrel cam's
        solid is not an extruded outline).
    """

    name: str
    summary: str
    keys: Callable[[], tuple[Key, ...]] = tuple
    read: "Callable[[str, str, Mapping[str, Any], Motion, Path | None], CamSpec] | None" = None
    build: "Callable[[CamSpec, frozenset[str]], BuiltCam] | None" = None
    evaluate: "Callable[[BuiltCam, CamSpec, float, bool], CamEvaluation] | None" = None
    follower_dynamics: "Callable[[BuiltCam, CamSpec], tuple[Any, float]] | None" = None
    report_section: str = ""
    expand: "Callable[[CamSpec], tuple[CamSpec, ...]] | None" = None
    formats_refused: Mapping[str, str] = field(default_factory=dict)
    writers: Mapping[str, str] = field(default_factory=dict)
    stages: Mapping[str, str] = field(default_factory=dict)
