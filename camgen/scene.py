"""Scene files: TOML -> a validated, typed :class:`Scene`.

A scene names the cams to build (``[cams.<name>]``, each with a ``kind`` from
:mod:`camgen.kinds`), the outputs wanted (``[output]``, :mod:`camgen.outputs`), the machining
settings of the G-code (``[machining]``) and the mechanisms to analyse (``[mechanisms.<name>]``,
:mod:`camgen.jobs`).  The keys of every table come from those registries; ``camgen keys``
prints them all.

Reading never evaluates user text.  Limits, each refused with a one-line error: the file is at
most :data:`MAX_SCENE_BYTES` bytes of UTF-8 TOML, nested at most :data:`MAX_NESTING` levels,
of at most :data:`camgen.scenetext.MAX_SCENE_ITEMS` keys and values (the nesting and the count
are checked on the text, before the TOML parser reads it: :mod:`camgen.scenetext`); names are
plain file names (:data:`NAME_RULE`); unknown keys, wrong types and out-of-range values (an
integer beyond the float range included) raise :class:`~camgen.errors.SceneError` or
:class:`~camgen.errors.ParameterError` naming the key by its path (``cams.x.a_mm``).
"""
from __future__ import annotations

import dataclasses
import math
import re
import tomllib
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping, Sequence, TypeVar

from camgen.errors import ParameterError, SceneError
from camgen.schema import Choice, Key, Text, check_keys, parse_table, quoted_names, too_deep, type_name

if TYPE_CHECKING:
    from camgen.export.gcode import MachiningSpec
    from camgen.frozen import Keyed
    from camgen.kinds.base import CamSpec
    from camgen.outputs import OutputSpec

_S = TypeVar("_S")

#: Largest scene file read, bytes.
MAX_SCENE_BYTES = 1 << 20
#: Deepest nesting of tables and lists in a scene (the schema needs 3).
MAX_NESTING = 8
#: Names of scenes and cams become file and folder names.
NAME_RULE = "1 to 64 characters: letters, digits, '_', '.', '-', starting with a letter or digit"
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")

TOP_KEYS = ("name", "output", "machining", "cams", "mechanisms", "sweep", "tolerance")


@dataclass(frozen=True)
class MechanismSpec:
    """A mechanism to analyse: its job name and typed settings."""

    name: str
    settings: Any  # the job's own frozen dataclass (see its module)


@dataclass(frozen=True)
class Scene:
    """A validated scene: every spec in it final (tolerances, decimals, the tool radius of the
    cams' checks), so that the later stages trust it.

    ``machining_given``: the scene has a [machining] table.  ``machined``: the run writes G-code
    (``ngc`` in ``output.formats`` or in the run's ``--only``): ``machining`` is then checked
    against the chord tolerance and every cam's depth, and carries ``output.chord_tol``.
    """

    name: str
    source: str
    output: "OutputSpec"
    machining: "MachiningSpec"
    cams: "tuple[CamSpec, ...]" = field(default_factory=tuple)
    mechanisms: tuple[MechanismSpec, ...] = field(default_factory=tuple)
    machining_given: bool = False
    machined: bool = False


def check_name(where: str, name: object, hint: str = "") -> str:
    """``name`` if it is a plain file name (:data:`NAME_RULE`), else a ParameterError."""
    if not isinstance(name, str) or not _NAME.match(name):
        shown = name if not isinstance(name, str) or len(name) < 80 else f"<{len(name)} characters>"
        raise ParameterError(where, shown, NAME_RULE, hint or "used as a file name")
    return name


#: Output and machining specs :func:`parse_scene` keeps (the last tables read: a study's designs
#: share them), keyed by the table's values (:func:`camgen.frozen.frozen`).
SPEC_CACHE = 8


def _cached(read: Callable[..., _S], cached: Callable[..., _S], table: object, *args: Any) -> _S:
    """``read(table, *args)``, kept by ``cached`` (the same reader under ``lru_cache``, taking the
    table :class:`~camgen.frozen.Keyed`) where the table has a hashable form."""
    from camgen.frozen import Keyed, Unfreezable

    try:
        keyed = Keyed(table)
    except Unfreezable:  # no TOML value: read (and refused) without the cache
        return read(table, *args)
    return cached(keyed, *args)


@lru_cache(maxsize=SPEC_CACHE)
def _cached_output(table: "Keyed") -> "OutputSpec":
    return _output(table.value)


@lru_cache(maxsize=SPEC_CACHE)
def _cached_machining(table: "Keyed", output: "OutputSpec", machined: bool) -> "MachiningSpec":
    return _machining(table.value, output, machined)


def _output(table: object) -> "OutputSpec":
    from camgen.outputs import OUTPUTS, REMOVED_OUTPUT_KEYS, OutputSpec, output_keys
    from camgen.export.drawing_spec import drawing_spec

    table = {} if table is None else table
    for key, replacement in REMOVED_OUTPUT_KEYS.items():
        if isinstance(table, dict) and key in table:
            raise ParameterError(f"output.{key}", table[key], f"no such key: it was replaced by {replacement}", "a removed key")
    p = parse_table("output", table, output_keys())
    assert isinstance(table, dict)  # parse_table refuses anything else
    for key in table:  # a key of some formats only (the registry's OutputFormat.keys), none of them written
        owners = [f.name for f in OUTPUTS.values() if key in f.keys]
        if owners and not set(owners) & set(p["formats"]):
            needs = f'"{owners[0]}"' if len(owners) == 1 else ", ".join(owners)
            raise ParameterError(f"output.{key}", table[key], f"only with {needs} in output.formats",
                                 "it changes only that file" if len(owners) == 1 else "it changes only those files")
    if p["dxf_version"] == "R12" and p["dxf_splines"] != "biarc":  # issue 27 item 5: R12 has no SPLINE
        raise ParameterError("output.dxf_splines", p["dxf_splines"], '"biarc" with output.dxf_version = "R12"', "R12 has no SPLINE entity")
    return OutputSpec(p["formats"], p["chord_tol"], p["dxf_splines"], p["dxf_construction"], p["lift_step"],
                      p.get("fea_element_size"), p["fea_elements"], drawing_spec(p), dxf_version=p["dxf_version"], step_schema=p["step_schema"])


def _machining(table: object, output: "OutputSpec", machined: bool) -> "MachiningSpec":
    """The final machining spec: where the run writes G-code, with the run's chord tolerance and
    checked against it (the printed decimals must resolve a share of it:
    :class:`camgen.export.gcode.MachiningSpec`), before anything is computed; errors name the
    scene key (``machining.decimals``, ``output.chord_tol_mm``)."""
    from camgen.export.gcode import MachiningSpec
    from camgen.export.wire_edm_spec import wire_edm_table
    from camgen.keynames import renamed
    from camgen.outputs import MACHINING_FORMATS, machining_keys, output_keys

    keys = machining_keys()
    table = {} if table is None else table
    p = parse_table("machining", table, keys)
    assert isinstance(table, dict)  # parse_table refuses anything else
    p = wire_edm_table(p)  # wire EDM (camgen.export.wire_edm_spec): its keys into one spec, milling keys refused
    if not set(MACHINING_FORMATS) & set(output.formats):  # the tool diameter also sets the machinability check's limit
        gcode = " or ".join(f'"{name}"' for name in MACHINING_FORMATS)
        for key in sorted(set(table) - {"tool_diameter_mm"}, key=str):
            raise ParameterError(f"machining.{key}", table[key], f"only with {gcode} in output.formats", "it changes only the G-code")
    if not machined:  # no G-code: the spec gives the tool radius only
        return renamed("machining", keys, lambda: MachiningSpec(**p))
    return renamed("machining", keys, lambda: MachiningSpec(**p, chord_tol=output.chord_tol), also=(("output", output_keys()),))


def _check_passes(machining: "MachiningSpec", cams: "tuple[CamSpec, ...]") -> None:
    """Refuse a ``step_down_mm`` that would take a plate cam's depth (thickness + breakthrough) in
    more than :data:`camgen.export.gcode.MAX_PASSES` passes, quoting the least step that fits."""
    from camgen.errors import ceil_significant
    from camgen.export.gcode import MAX_PASSES, depth_passes

    from camgen.forms import get_form

    step = machining.step_down
    for spec in cams:
        if "ngc" in get_form(spec.form).writers:  # a form that writes its own program bounds its own passes (a barrel's groove)
            continue
        depth = spec.body.thickness + machining.breakthrough
        if depth_passes(depth, step) > MAX_PASSES:
            least = ceil_significant(depth / MAX_PASSES, 3)
            while depth_passes(depth, least) > MAX_PASSES:  # the quoted least is tried: depth / least may round above
                least = float(f"{least + 10.0 ** (math.floor(math.log10(least)) - 2):.3g}")  # one unit of the 3rd digit up
            passes = depth_passes(depth, step)
            raise ParameterError("machining.step_down_mm", step, f">= {least:.3g} mm for cam '{spec.name}'",
                                 f"its {depth:g} mm (thickness + breakthrough) would take "
                                 f"{passes if passes < 1e9 else 'more than 10^9'} passes, more than "
                                 f"the {MAX_PASSES} a program may hold")


def _cam(name: str, table: object, base_dir: Path | None, tool_limit: float | None) -> "CamSpec":
    from camgen.forms import form_names
    from camgen.kinds import forms_of, get_kind, kind_names
    from camgen.motions import get_motion

    where = f"cams.{name}"
    check_name(where, name, "a cam's name is used in its file names")
    if not isinstance(table, dict):
        raise SceneError(f"[{where}] must be a table, not {type_name(table)}")
    kinds = tuple(kind_names())
    kind_name = Choice(kinds).parse(f"{where}.kind", table.get("kind"))
    kind = None
    if "form" not in table:  # the motion's own form: get_kind composed it only if that form realises the motion
        try:
            form_name = get_motion(kind_name).default_form
            kind = get_kind(kind_name, form_name)
        except KeyError:
            kind = None  # refused below, naming the key
    if kind is None:
        form = Choice(forms_of(kind_name))  # the type of the cam's form key (camgen.kinds.form_key), its default the motion's form
        given = table.get("form", get_motion(kind_name).default_form)
        if isinstance(given, str) and given not in form.values and given in form_names():  # a form, not this motion's
            raise ParameterError(f"{where}.form", given, form.describe(), f"the {given} form does not realise the motion "
                                 f"kind = {kind_name!r} (camgen.forms, camgen.motions)")
        form_name = form.parse(f"{where}.form", given)
        kind = get_kind(kind_name, form_name)
    parsed = parse_table(where, {k: v for k, v in table.items() if k != "kind"}, kind.keys)
    parsed.tool_limit = tool_limit  # the kind's check settings hold it (read_checks)
    _jerk_limit(where, parsed)  # VDI: a jerk limit needs rpm and its follower motion's unit (issue 26 item 5)
    spec = kind.read(where, name, parsed, base_dir)
    return spec if spec.form == form_name else dataclasses.replace(spec, form=form_name)


def _jerk_limit(where: str, parsed: Mapping[str, Any]) -> None:
    from camgen.kinds.jerk_limit import read_jerk_limit

    read_jerk_limit(where, parsed)


def _bodies(cams: "tuple[CamSpec, ...]") -> "tuple[CamSpec, ...]":
    """The cams of the run: each scene cam as the bodies its form realises it as
    (:attr:`camgen.forms.base.CamForm.expand`: a conjugate pair is two cams), every name a plain
    file name and no two the same (a clash names the scene cam whose form made it)."""
    from camgen.forms import form_names, get_form

    scene_names = {spec.name for spec in cams}
    owners: dict[str, str] = {}
    out: list[CamSpec] = []
    for spec in cams:
        expand = get_form(spec.form).expand if spec.form in form_names() else None
        bodies = expand(spec) if expand is not None else (spec,)
        made = ", ".join(b.name for b in bodies)
        for body in bodies:
            if body.name != spec.name:
                check_name(f"cams.{spec.name}", body.name, f"the {spec.form} form makes its cams {made} of it")
            clash = body.name in owners or (body.name != spec.name and body.name in scene_names)
            if clash:
                raise ParameterError(f"cams.{spec.name}", spec.name, f"a cam name whose {spec.form} cams ({made}) are no other cam's "
                                     "name", f"cam '{body.name}' is also another cam of the scene")
            owners[body.name] = spec.name
        out.extend(bodies)
    return tuple(out)


def _mechanisms(table: object, cams: "tuple[CamSpec, ...]") -> tuple[MechanismSpec, ...]:
    from camgen.jobs import get_job, job_names

    if not isinstance(table, dict):
        raise SceneError(f"[mechanisms] must be a table of [mechanisms.<name>] tables, not {type_name(table)}")
    known = job_names()
    unknown = sorted(set(table) - set(known), key=str)
    if unknown:
        raise SceneError(f"[mechanisms]: unknown mechanism(s) {quoted_names(unknown)}; known: {', '.join(known)}")
    by_name = {c.name: c for c in cams}
    out = []
    for name, sub in table.items():
        job = get_job(name)
        parsed = parse_table(f"mechanisms.{name}", sub, job.keys)
        out.append(MechanismSpec(name, job.read(f"mechanisms.{name}", parsed, by_name)))
    return tuple(out)


#: The keys of a scene's top level (their tables are read by their own schemas).
_TOP = (Key("name", Text(64), "", ()), Key("output", Text(), "", ()), Key("machining", Text(), "", ()),
        Key("cams", Text(), "", ()), Key("mechanisms", Text(), "", ()), Key("sweep", Text(), "", ()),
        Key("tolerance", Text(), "", ()))


def parse_scene(data: Mapping[str, Any], name: str, source: str = "<memory>", base_dir: Path | None = None,
                only: Sequence[str] | None = None) -> Scene:
    """Validate a decoded TOML table and return a :class:`Scene` whose specs are final.

    ``name`` is the scene's name when the table has none (the file's stem); ``base_dir`` is
    where relative file names in the scene point; ``only``: the formats the run is restricted
    to (``--only``; :func:`camgen.planning.plan_run` takes the same), which decide with
    ``output.formats`` whether the run writes G-code.
    """
    deep = too_deep(data, MAX_NESTING)
    if deep is not None:
        raise SceneError(f"{deep}: tables and lists nest more than {MAX_NESTING} levels deep (the limit of a scene)")
    check_keys("scene", data, _TOP)
    if "cams" not in data:
        raise SceneError("scene: missing key(s) 'cams': add at least one [cams.<name>] table")
    if "name" in data:
        scene_name = check_name("name", data["name"])
    else:
        scene_name = check_name("name", name, "the scene file's name is used when the scene sets no name = \"...\"")
    cams_table = data["cams"]
    if not isinstance(cams_table, dict) or not cams_table:
        raise SceneError("scene: [cams] must hold at least one [cams.<name>] table")
    output = _cached(_output, _cached_output, data.get("output"))
    from camgen.outputs import MACHINING_FORMATS

    machined = bool(set(MACHINING_FORMATS) & (set(output.formats) | set(only or ())))
    machining = _cached(_machining, _cached_machining, data.get("machining"), output, machined)
    # the tool is a limit where the scene names it or the run machines the cam
    tool_limit = machining.tool_radius if "machining" in data or machined else None
    cams = _bodies(tuple(_cam(k, v, base_dir, tool_limit) for k, v in cams_table.items()))
    mechanisms = _mechanisms(data.get("mechanisms", {}), cams)
    if "sweep" in data:  # camgen sweep's table: checked here too, so that check and run refuse what sweep would
        from camgen.study.space import sweep_table

        sweep_table(data)
    if "tolerance" in data:  # camgen tolerance's table: checked here too, so that check and run refuse what tolerance would
        from camgen.study.tolerance_settings import check_scene_table

        check_scene_table(data["tolerance"], cams)
    if machined:
        _check_passes(machining, cams)
    return Scene(scene_name, source, output, machining, cams, mechanisms, "machining" in data, machined)


def read_text_bounded(path: Path, what: str, limit: int = MAX_SCENE_BYTES) -> str:
    """The UTF-8 text of ``path``, read to at most ``limit`` bytes (:mod:`camgen.textfile`);
    errors name ``what`` and the file."""
    from camgen.textfile import TextFileError, read_text_file

    try:
        return read_text_file(path, limit)
    except TextFileError as exc:
        raise SceneError(f"cannot read {what} '{path}': {exc}") from None


def decode_scene_file(path: Path) -> tuple[str, dict[str, Any]]:
    """The text of the scene file at ``path`` and its decoded TOML table (not yet validated):
    read within the scene's limits (:data:`MAX_SCENE_BYTES`, :data:`MAX_NESTING`).

    Raises
    ------
    SceneError
        If the file cannot be read or is not valid TOML within the limits.
    """
    from camgen.scenetext import restore_integers, scan_scene_text

    text = read_text_bounded(path, "scene file")
    scanned = scan_scene_text(text, MAX_NESTING)  # what the parser cannot take in bounded time and memory
    try:
        data = tomllib.loads(scanned.text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"scene file '{path}' is not valid TOML: {exc}") from None
    except RecursionError:
        raise SceneError(f"scene file '{path}' nests tables or lists more than {MAX_NESTING} levels deep") from None
    except ValueError as exc:  # a number Python cannot convert (the scan leaves none: a last guard)
        raise SceneError(f"scene file '{path}' is not valid TOML: {exc}") from None
    return text, restore_integers(data, scanned.integers)


def load_scene(path: str | Path, display: str | None = None, only: Sequence[str] | None = None) -> Scene:
    """Read and validate a scene file; ``display`` is how reports name it (default: ``path``);
    ``only``: the run's ``--only`` formats (:func:`parse_scene`).

    Raises
    ------
    SceneError, ParameterError
        If the file cannot be read, is not valid TOML within the limits, or does not follow
        the schema.
    """
    path = Path(path)
    _, data = decode_scene_file(path)
    return parse_scene(data, path.stem, display or str(path), path.parent, only)


def template_dir() -> Path:
    """Folder of the bundled template scenes (package data ``camgen/templates``)."""
    from importlib.resources import files

    return Path(str(files("camgen.templates")))


def template_names() -> list[str]:
    return sorted(p.stem for p in template_dir().glob("*.toml"))


def template_path(name: str) -> Path:
    """Path of a bundled template scene (``camgen/templates/<name>.toml``)."""
    path = template_dir() / f"{name}.toml"
    if not _NAME.match(name) or not path.is_file():
        raise SceneError(f"no bundled template named '{name}'; templates: {', '.join(template_names())}")
    return path


def load_template(name: str, only: Sequence[str] | None = None) -> Scene:
    """Load a bundled template scene (``only``: the run's ``--only`` formats, :func:`parse_scene`)."""
    return load_scene(template_path(name), display=f"templates/{name}.toml", only=only)
