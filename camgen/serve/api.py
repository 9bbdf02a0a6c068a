"""What each endpoint of ``camgen serve`` computes, as plain functions (no HTTP: the tests call
them directly; :mod:`camgen.serve.server` routes requests to them).

Each call computes from its arguments only: evaluations from several requests may run at once,
and share nothing but the :class:`~camgen.serve.files.FileStore`.  Bad input in a request's scene
is an answer (``ok: false`` with the error line ``camgen check`` prints for it), not a failed
request; a request the page could not have sent (not a JSON object, a missing field) raises
:class:`RequestError` (the server's 400).
"""
from __future__ import annotations

import functools
import importlib
import re
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping

from camgen.errors import CamgenError, ParameterError, SceneError

if TYPE_CHECKING:
    from camgen.serve.files import FileStore

__all__ = ["PAGE_FORMATS", "RequestError", "SceneSource", "error_json", "evaluate", "load_source", "make_files", "save",
           "scene_json", "schema"]

#: The outputs an evaluation plans (report.json, and report.html's plot data): the same analysis
#: as ``camgen run`` (report.json's figures, but those of the meshes, ``solid_*``: the cam is not
#: meshed), no file rendered.
PAGE_FORMATS = ("json", "html")
#: Most formats one files request may ask for.
MAX_FORMATS = 40
#: The scene's table path at the start of a SceneError's message (``[cams.plate]: unknown key``).
_TABLE = re.compile(r"^\[([^\]]{1,200})\]")


class RequestError(CamgenError):
    """A request the page could not have sent (the server answers 400 with this message)."""


@dataclass(frozen=True)
class SceneSource:
    """The scene the server was started with.

    name : the scene's name where its table gives none (the file's stem, as ``camgen run`` takes it).
    text : its TOML text as read, comments and all.
    data : the decoded TOML.
    source : how reports name it (the path given, or ``templates/default.toml``).
    base_dir : where its relative file names point (a lift table's CSV), or None.
    """

    name: str
    text: str
    data: Mapping[str, Any]
    source: str
    base_dir: Path | None


def load_source(path: str | None) -> SceneSource:
    """The scene file ``path`` (None: the bundled default scene), read and decoded as ``camgen
    run`` reads it (the same size, nesting and item limits); not validated against the schema:
    the page shows what is wrong with it.  Raises :class:`SceneError` if it cannot be read or is
    not TOML."""
    from camgen.scene import MAX_NESTING, read_text_bounded, template_path
    from camgen.scenetext import restore_integers, scan_scene_text

    if path is None:
        file, source = template_path("default"), "templates/default.toml"
    elif not path.strip():
        raise ParameterError("SCENE", path, "the path of a scene file (TOML); give none for the bundled default scene")
    else:
        file, source = Path(path), path
    text = read_text_bounded(file, "scene file")
    scanned = scan_scene_text(text, MAX_NESTING)
    try:
        data = restore_integers(tomllib.loads(scanned.text), scanned.integers)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"scene file '{file}' is not valid TOML: {exc}") from None
    except (RecursionError, ValueError) as exc:
        raise SceneError(f"scene file '{file}' cannot be read: {exc}") from None
    return SceneSource(file.stem, text, data, source, file.parent)


def scene_json(source: SceneSource) -> dict[str, Any]:
    """``GET /api/scene``: the scene's name, text and decoded table."""
    from camgen.serve.payload import json_safe

    name = source.data.get("name", source.name)
    return {"name": name if isinstance(name, str) else source.name, "text": source.text, "data": json_safe(source.data)}


def schema() -> dict[str, Any]:
    """``GET /api/schema`` (:func:`camgen.serve.schema_json.schema_json`)."""
    from camgen.serve.schema_json import schema_json

    return schema_json()


def _one_line(text: str) -> str:
    return " ".join(text.split())


def error_json(exc: CamgenError) -> dict[str, Any]:
    """The page's error: the scene key it names (a ParameterError's key, a SceneError's table;
    None if none) and the line ``camgen`` prints for it."""
    key: str | None = None
    if isinstance(exc, ParameterError):
        key = str(exc.name)
    else:
        match = _TABLE.match(str(exc))
        key = match.group(1) if match else None
    return {"key": key, "message": f"camgen: error: {_one_line(str(exc))}"}


def _field(body: object, name: str, kind: type, what: str) -> Any:
    if not isinstance(body, dict):
        raise RequestError("the request body must be a JSON object")
    value = body.get(name)
    if not isinstance(value, kind) or isinstance(value, bool) and kind is not bool:
        raise RequestError(f"the request's '{name}' must be {what}")
    return value


def _scene(source: SceneSource, data: Mapping[str, Any], only: tuple[str, ...] | None = None) -> Any:
    from camgen.scene import parse_scene

    return parse_scene(data, source.name, source.source, source.base_dir, only)


@functools.lru_cache(maxsize=64)
def _key_names(kind: str, form: str) -> frozenset[str]:
    """The key names of a cam table of ``kind`` and ``form`` (the registries' keys are built anew on
    every call: a few ms each, kept here once per server)."""
    from camgen.kinds import get_kind

    return frozenset(k.name for k in get_kind(kind, form).keys)


def evaluate(source: SceneSource, body: object) -> dict[str, Any]:
    """``POST /api/evaluate``: ``{"seq": int, "data": scene}`` -> the scene's checks, figures and
    curves per cam (:func:`camgen.serve.payload.cam_payload`) and report.json's ``mechanisms``, computed as ``camgen check``
    computes them (:func:`camgen.scene.parse_scene`, :func:`camgen.pipeline.compute`), with the
    analysis report.json's figures need; bad input: ``ok`` false and ``error``
    (:func:`error_json`), ``verdict`` None."""
    from camgen.pipeline import compute, plan_run
    from camgen.report import report_dict
    from camgen.report_data import report_input
    from camgen.serve.payload import cam_payload, json_safe

    seq = _field(body, "seq", int, "an integer")
    data = _field(body, "data", dict, "a scene table (a JSON object)")
    start = time.perf_counter()
    try:
        scene = _scene(source, data)
        plan_run(scene)  # the refusals of the scene's own run (camgen check plans it)
        plan = plan_run(scene, PAGE_FORMATS)
        result = compute(scene, plan)
        report = report_input(result.scene, result.cams, result.jobs, plan.stages, ["report.json", "report.html"], drawn=True)
        tree = report_dict(report)
    except CamgenError as exc:
        return {"seq": seq, "ok": False, "error": error_json(exc), "verdict": None, "cams": [],
                "elapsed_ms": (time.perf_counter() - start) * 1e3}
    by_name = tree["cams"]
    assert isinstance(by_name, Mapping)
    cams = []
    for cam in report.cams:
        keys = _key_names(cam.kind, cam.form)
        entry = by_name[cam.name]
        assert isinstance(entry, Mapping)
        cams.append(cam_payload(cam, entry, keys))
    return {"seq": seq, "ok": True, "error": None, "verdict": "fail" if tree["status"] == "fail" else "pass", "cams": cams,
            "mechanisms": json_safe(tree["mechanisms"]), "elapsed_ms": (time.perf_counter() - start) * 1e3}


def _editor() -> Callable[[str, Mapping[str, Any]], str] | None:
    """``camgen.scene_edit.edit_scene_text`` (keeps the original's comments), if installed."""
    try:
        module = importlib.import_module("camgen.scene_edit")
    except ImportError:
        return None
    function: Callable[[str, Mapping[str, Any]], str] = getattr(module, "edit_scene_text")
    return function


def _decoded(text: str) -> object:
    try:
        return tomllib.loads(text)
    except (tomllib.TOMLDecodeError, ValueError, RecursionError):
        return None


def save(source: SceneSource, body: object) -> dict[str, Any]:
    """``POST /api/save``: ``{"text": original TOML, "data": scene}`` -> ``{"text": the edited
    scene's TOML, "error": null or the error a run of it would stop on}``: the original's
    comments kept where the editor is installed (``camgen.scene_edit``), else the original text
    itself when nothing was changed, or the scene written plainly
    (:func:`camgen.serve.toml_text.scene_toml`)."""
    from camgen.serve.toml_text import scene_toml

    text = _field(body, "text", str, "the original scene text")
    data = _field(body, "data", dict, "a scene table (a JSON object)")
    from camgen.pipeline import plan_run

    edit = _editor()
    new: str | None = None
    try:
        plain = scene_toml(data)  # refuses a value TOML cannot hold (a JSON null) naming its key
        if edit is not None:
            new = edit(text, data)
        else:  # unchanged: the original, comments and all; else written plainly
            new = text if _decoded(text) == data else plain
        decoded = _decoded(new)
        if not isinstance(decoded, dict):  # a writer's bug, said as such
            raise SceneError("the saved scene is not valid TOML (a bug in camgen's scene writer)")
        plan_run(_scene(source, decoded))  # what `camgen run` refuses before it computes
    except CamgenError as exc:
        return {"text": new, "error": error_json(exc)}
    return {"text": new, "error": None}


def make_files(source: SceneSource, body: object, store: "FileStore") -> dict[str, Any]:
    """``POST /api/files``: ``{"data": scene, "formats": [...]}`` -> the files ``camgen run
    --only FORMATS`` writes for the scene (report.json with them), rendered in memory and kept in
    ``store``; ``{"files": [{"name", "url", "bytes"}], "error": null}``, or no files and the
    error line."""
    from camgen.pipeline import execute, plan_run

    data = _field(body, "data", dict, "a scene table (a JSON object)")
    formats = _field(body, "formats", list, "a list of format names")
    if not formats or len(formats) > MAX_FORMATS or not all(isinstance(f, str) for f in formats):
        raise RequestError(f"the request's 'formats' must be a list of 1 to {MAX_FORMATS} format names")
    only = tuple(formats)
    try:
        scene = _scene(source, data, only)
        with store.making:  # one run's files at a time (the mesher and the STEP kernel are not thread-safe)
            result = execute(scene, plan_run(scene, only))
    except CamgenError as exc:
        return {"files": [], "error": error_json(exc)}
    made = store.add(result.files)
    return {"files": [{"name": f.name, "url": f.url, "bytes": f.bytes} for f in made], "error": None}
