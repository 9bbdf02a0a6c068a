"""The scene schema: every key a scene accepts, its type, unit, range, default, and what it changes.

One :class:`Key` per scene key.  The kinds (:mod:`camgen.kinds`), the outputs
(:mod:`camgen.outputs`) and the scene reader (:mod:`camgen.scene`) build their tables from
keys; the key reference (``camgen keys``, ``docs/scene-keys.md``) is generated from the same
objects, and a test walks every key and proves it changes the outputs its ``affects`` names.

Values are validated strictly: a number must be a TOML integer or float (not a boolean, not a
string, not a list), finite, inside its stated range; a whole number must be an integer inside
its range; lists and strings have stated maximum sizes.  Every failure is a
:class:`~camgen.errors.ParameterError` naming the key by its scene path (``cams.x.a_mm``), the
value and the valid range.  Lengths are millimetres and angles degrees at this edge; inside
they are millimetres and radians (a ``_deg`` key is stored in radians under its field name).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any, Mapping, Sequence, TypeGuard

from camgen.errors import ParameterError, SceneError, quoted

#: What a key can change.  The key-effect test checks these outputs' bytes change.
EFFECTS = {
    "profile": "the cam profile: DXF, points and lift tables, meshes, STEP and G-code",
    "pitch": "the follower-centre path (DXF PITCH layer)",
    "body": "the cam body (bore, keyway, thickness): DXF BORE/KEYWAY layers, meshes, STEP, the G-code's bore (cut or said to be left)",
    "thickness": "the cam thickness: meshes, STEP, G-code depth",
    "gcode": "the G-code program",
    "dxf": "the DXF drawing only",
    "report": "report.json and report.html only (checks, figures)",
    "files": "which files are written and their names",
    "mechanism": "the mechanism's report section and files (leg paths)",
    "tables": "the lift table (<cam>_lift.csv)",
    "motion": "the follower table at the cam's speed (<cam>_follower.csv)",
    "tolerance": "every flattened output: DXF biarcs, point lists, meshes, G-code",
    "fea": "the FEA meshes (vtu, msh, inp) only",
    "drawing": "the manufacturing drawing (<cam>_drawing.svg, .pdf) and the inspection table (<cam>_inspection.csv) only",
    "step": "the STEP file only",
}

#: Largest number of items of any list key (lists are small in every real scene).
MAX_LIST = 1000
#: Largest length of a text value (expressions have their own limit, 2000).
MAX_TEXT = 500


class ValueType:
    """How a key's value is read.  Subclasses implement :meth:`parse` and :meth:`describe`."""

    def parse(self, path: str, value: object) -> Any:  # pragma: no cover - abstract
        raise NotImplementedError

    def describe(self) -> str:  # pragma: no cover - abstract
        raise NotImplementedError

    def to_scene(self, value: Any) -> Any:
        """The inverse of :meth:`parse` for documentation (defaults in scene units)."""
        return value


def _is_number(value: object) -> TypeGuard[int | float]:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def type_name(value: object) -> str:
    """The type of a scene value as messages name it (Python's name; a
    :class:`~camgen.scenetext.LargeInteger` is an ``int``)."""
    return getattr(value, "toml_type", type(value).__name__)


def _number(path: str, value: object, valid: str) -> float:
    if not _is_number(value):
        raise ParameterError(path, value, valid)
    try:
        number = float(value)
    except OverflowError:
        raise ParameterError(path, value, valid) from None  # quoted by its number of digits
    if not math.isfinite(number):
        raise ParameterError(path, value, valid)
    return number


def _fmt(x: float) -> str:
    return f"{x:g}"


@dataclass(frozen=True)
class Number(ValueType):
    """A finite real number in ``[low, high]`` (``low_open``/``high_open``: strict bounds), of
    ``unit``; ``scale`` converts the scene value to the stored one (degrees -> radians)."""

    unit: str
    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False
    scale: float = 1.0

    def describe(self) -> str:
        lo = "" if self.low == -math.inf else f"{_fmt(self.low)} {'<' if self.low_open else '<='} "
        hi = "" if self.high == math.inf else f" {'<' if self.high_open else '<='} {_fmt(self.high)}"
        unit = f" {self.unit}" if self.unit else ""
        return f"a number{unit}" + (f", {lo}x{hi}" if lo or hi else "")

    def parse(self, path: str, value: object) -> float:
        kind = type(value)
        if kind is float or kind is int or _is_number(value):  # the usual case first: the range's text is made only for a refusal
            try:
                number = float(value)  # type: ignore[arg-type]
            except OverflowError:
                number = math.nan
            if math.isfinite(number):
                below = number <= self.low if self.low_open else number < self.low
                above = number >= self.high if self.high_open else number > self.high
                if not (below or above):
                    return number * self.scale
        _number(path, value, self.describe())  # not a finite number: refused by the same words
        raise ParameterError(path, value, self.describe())  # out of range

    def to_scene(self, value: Any) -> Any:
        return None if value is None else value / self.scale


#: Smallest length a scene may give, mm (1 nm): below it lengths are rounding noise.
MIN_LENGTH = 1e-6


def Length(low: float = MIN_LENGTH, high: float = 1e5, low_open: bool = False) -> Number:
    """A length in mm, by default 1 nm <= x <= 100 m."""
    return Number("mm", low, high, low_open=low_open)


def Angle(low: float = -360.0, high: float = 360.0, low_open: bool = False, high_open: bool = False) -> Number:
    """An angle given in degrees, stored in radians."""
    return Number("deg", low, high, low_open, high_open, scale=math.pi / 180.0)


@dataclass(frozen=True)
class Count(ValueType):
    """A whole number in ``[low, high]``."""

    low: int
    high: int
    unit: str = ""

    def describe(self) -> str:
        return f"a whole number{' of ' + self.unit if self.unit else ''}, {self.low} <= n <= {self.high}"

    def parse(self, path: str, value: object) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or not self.low <= value <= self.high:
            raise ParameterError(path, value, self.describe())  # a huge integer is quoted by its number of digits
        return value


@dataclass(frozen=True)
class Flag(ValueType):
    """true or false."""

    def describe(self) -> str:
        return "true or false"

    def parse(self, path: str, value: object) -> bool:
        if not isinstance(value, bool):
            raise ParameterError(path, value, self.describe())
        return value


@dataclass(frozen=True)
class Choice(ValueType):
    """One of a fixed set of strings."""

    values: tuple[str, ...]

    def describe(self) -> str:
        return "one of " + ", ".join(f'"{v}"' for v in self.values)

    def parse(self, path: str, value: object) -> str:
        if not isinstance(value, str) or value not in self.values:
            raise ParameterError(path, value, self.describe())
        return value


@dataclass(frozen=True)
class Text(ValueType):
    """A string of at most ``max_length`` characters (non-empty unless ``allow_empty``)."""

    max_length: int = MAX_TEXT
    allow_empty: bool = False

    def describe(self) -> str:
        return f"a string of {'0' if self.allow_empty else '1'} to {self.max_length} characters"

    def parse(self, path: str, value: object) -> str:
        if not isinstance(value, str):
            raise ParameterError(path, value, self.describe())
        if len(value) > self.max_length:
            raise ParameterError(path, f"<{len(value)} characters>", self.describe())
        if not value.strip() and not self.allow_empty:
            raise ParameterError(path, value, self.describe())
        if "\x00" in value:  # no file name, expression or note holds one; C and the OS end text there
            raise ParameterError(path, value, self.describe(), f"a NUL character at position {value.index(chr(0))}")
        return value


@dataclass(frozen=True)
class ChoiceList(ValueType):
    """A list of distinct strings from ``values`` (``min_items`` .. ``len(values)`` items)."""

    values: tuple[str, ...]
    min_items: int = 1

    def describe(self) -> str:
        # the names bare (no quotes): the refusal of a list stays one short line as the values grow
        return f"a list of {self.min_items} or more distinct values from " + ", ".join(self.values)

    def parse(self, path: str, value: object) -> tuple[str, ...]:
        if not isinstance(value, list) or not self.min_items <= len(value) <= len(self.values):
            raise ParameterError(path, value if not isinstance(value, list) or len(value) < 20 else f"<list of {len(value)}>", self.describe())
        for i, item in enumerate(value):
            if not isinstance(item, str) or item not in self.values:
                raise ParameterError(f"{path}[{i}]", item, "one of " + ", ".join(f'"{v}"' for v in self.values))
        if len(set(value)) != len(value):
            raise ParameterError(path, value, self.describe(), "a value is repeated")
        return tuple(value)


@dataclass(frozen=True)
class NumberList(ValueType):
    """A list of numbers, each of type ``item``; ``min_items`` .. ``max_items`` items; with
    ``distinct_decimals`` the values must differ after rounding to that many decimals."""

    item: Number
    min_items: int = 1
    max_items: int = 100
    distinct_decimals: int | None = None

    def describe(self) -> str:
        what = f"a list of {self.min_items} to {self.max_items} numbers, each {self.item.describe()}"
        if self.distinct_decimals is not None:
            what += f", distinct after rounding to {self.distinct_decimals} decimals"
        return what

    def parse(self, path: str, value: object) -> tuple[float, ...]:
        if not isinstance(value, list) or not self.min_items <= len(value) <= self.max_items:
            shown = value if not isinstance(value, list) or len(value) < 20 else f"<list of {len(value)}>"
            raise ParameterError(path, shown, self.describe())
        out = tuple(self.item.parse(f"{path}[{i}]", v) for i, v in enumerate(value))
        if self.distinct_decimals is not None:
            rounded = [round(v / self.item.scale, self.distinct_decimals) for v in out]
            if len(set(rounded)) != len(rounded):
                raise ParameterError(path, value, self.describe(), "two values are equal after rounding")
        return out

    def to_scene(self, value: Any) -> Any:
        return None if value is None else [v / self.item.scale for v in value]


@dataclass(frozen=True)
class TableList(ValueType):
    """A list of tables (``[[...]]`` in TOML), each read against ``keys``."""

    keys: tuple["Key", ...]
    min_items: int = 1
    max_items: int = 100
    what: str = "tables"

    def describe(self) -> str:
        return f"a list of {self.min_items} to {self.max_items} {self.what} with keys " + ", ".join(k.name for k in self.keys)

    def parse(self, path: str, value: object) -> tuple[dict[str, Any], ...]:
        if not isinstance(value, list) or not self.min_items <= len(value) <= self.max_items:
            shown = value if not isinstance(value, list) or len(value) < 20 else f"<list of {len(value)}>"
            raise ParameterError(path, shown, self.describe())
        schema = compiled(self.keys)
        return tuple([parse_with(f"{path}[{i}]", item, schema) for i, item in enumerate(value)])


_REQUIRED = object()


@dataclass(frozen=True)
class Key:
    """One scene key.

    Attributes
    ----------
    name : the key as written in the scene (its unit suffix included: ``a_mm``, ``span_deg``).
    type : how its value is read (:class:`ValueType`).
    doc : what the key is, one sentence (units in ``type``).
    affects : what it changes, names from :data:`EFFECTS`; the key-effect test checks them.
    default : the value in scene units when the key is left out; ``None``: optional with no
        default (the feature is off or derived, as ``doc`` says); :data:`REQUIRED`: must be given.
    example : a valid value different from the default, in scene units (key reference, tests).
    requires : other keys' values this key needs (``{"follower": ("roller",)}``): given
        without them, it is refused.
    attr : the attribute it is stored under, when not the name without its unit suffix.
    feeds : the internal parameter names its value becomes beyond ``field``, when a spec built
        from the parsed table names it otherwise (``follower`` is a FollowerSpec's ``kind``; the
        two keys ``pivot_x_mm`` and ``pivot_y_mm`` are its ``pivot``): the errors of that spec
        are renamed to the scene key through them (:func:`camgen.keynames.scene_key`).
    """

    name: str
    type: ValueType
    doc: str
    affects: tuple[str, ...]
    default: Any = None
    example: Any = None
    requires: Mapping[str, tuple[Any, ...]] = field(default_factory=dict)
    attr: str | None = None
    feeds: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        unknown = set(self.affects) - set(EFFECTS)
        if unknown:  # a programming error, caught by the tests that import every kind
            raise ValueError(f"key {self.name}: unknown effects {sorted(unknown)}")

    @property
    def field(self) -> str:
        """The attribute name: the key without its unit suffix (``a_mm`` -> ``a``)."""
        if self.attr is not None:
            return self.attr
        for suffix in ("_mm", "_deg"):
            if self.name.endswith(suffix):
                return self.name[: -len(suffix)]
        return self.name

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    def default_value(self) -> Any:
        """The default in internal units (radians for angles), or None."""
        if self.default is None or self.default is REQUIRED:
            return None
        return self.type.parse(self.name, self.default)


REQUIRED: Any = _REQUIRED


def quoted_names(names: Sequence[object], most: int = 5) -> str:
    """The first ``most`` of ``names``, each quoted shortened (:func:`camgen.errors.quoted`), and
    how many more: a message naming unknown keys stays one short line whatever the scene holds."""
    shown = ", ".join(quoted(n) for n in names[:most])
    return shown + (f" and {len(names) - most} more" if len(names) > most else "")


def check_keys(where: str, table: Mapping[str, Any], keys: Sequence[Key]) -> None:
    """Refuse unknown and missing keys of ``table`` (read at scene path ``where``)."""
    allowed = {k.name for k in keys}
    unknown = sorted(set(table) - allowed, key=str)
    if unknown:
        hint = ""
        near = [k for k in allowed if k.split("_")[0] == str(unknown[0]).split("_")[0]]
        if near:
            hint = f" (did you mean {', '.join(sorted(near))}?)"
        raise SceneError(f"[{where}]: unknown key(s) {quoted_names(unknown)}{hint}; allowed: {', '.join(sorted(allowed))}")
    missing = [k.name for k in keys if k.required and k.name not in table]
    if missing:
        raise SceneError(f"[{where}]: missing key(s) {', '.join(map(repr, missing))}")


class Parsed(dict):
    """What :func:`parse_table` returns: ``{field: value}`` in internal units, and ``given``: the
    scene names of the keys the table itself gave (a default filled in is not given), for
    keys refused unless another is given (e.g. the dynamics keys without a mass).

    ``tool_limit``: for a cam table, the radius (mm) of the cutting tool its concave radii are
    held to, set by the scene reader where the scene names a tool or the run machines the cam
    (None: the tool is information only); :func:`camgen.kinds.base.read_checks` puts it into the
    cam's check settings."""

    given: frozenset[str] = frozenset()
    tool_limit: float | None = None

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickled as its items and attributes (the key of a reader's cache, :mod:`camgen.frozen`)."""
        return (parsed_table, (dict(self), self.given, self.tool_limit))


def parsed_table(items: dict[str, Any], given: frozenset[str], tool_limit: float | None) -> Parsed:
    """A :class:`Parsed` of ``items`` with its attributes (what its pickle reads back)."""
    out = Parsed(items)
    out.given = given
    out.tool_limit = tool_limit
    return out


def given_keys(parsed: Mapping[str, Any], keys: Sequence[Key]) -> frozenset[str]:
    """The scene names of ``keys`` given in ``parsed`` (a :class:`Parsed`; for a plain mapping,
    the keys whose fields are present)."""
    if isinstance(parsed, Parsed):
        return parsed.given
    return frozenset(k.name for k in keys if k.field in parsed)


def parse_table(where: str, table: object, keys: Sequence[Key]) -> Parsed:
    """Validate ``table`` against ``keys``; return ``{field: value}`` in internal units, the
    defaults filled in (keys without a default and not given are absent), as a :class:`Parsed`
    that knows which keys were given.  ``keys`` is read through its :class:`Schema`."""
    return parse_with(where, table, compiled(keys))


def parse_with(where: str, table: object, schema: "Schema") -> Parsed:
    """:func:`parse_table` of ``table`` against the keys of ``schema`` (:func:`compiled`)."""
    if not isinstance(table, dict):
        raise SceneError(f"[{where}] must be a table, not {type_name(table)}")
    if not schema.names.issuperset(table) or any(name not in table for name in schema.required):
        check_keys(where, table, schema.keys)  # names the unknown or missing keys
    out = Parsed()
    out.given = frozenset(table)  # every key of the table is one of keys (checked)
    for name, field_, parse, default in schema.entries:
        if name in table:
            out[field_] = parse(f"{where}.{name}", table[name])
        elif default is _EACH_TIME:
            value = keys_by_name(schema, name).default_value()
            if value is not None:
                out[field_] = value
        elif default is not None:
            out[field_] = default
    for name, requires in schema.conditional:  # conditional keys: refused where they would have no effect
        if name in table:
            for other, allowed, other_default in requires:
                have = table.get(other, other_default)
                if have not in allowed:
                    raise ParameterError(
                        f"{where}.{name}", table[name],
                        f"only with {other} = {' or '.join(repr(a) for a in allowed)}",
                        f"{other} is {have!r} here, where {name} would have no effect",
                    )
    return out


def restricted(parsed: Mapping[str, Any], keys: Sequence[Key]) -> Parsed:
    """The part of ``parsed`` that ``keys`` give: their fields (in ``keys``' order) and which of
    them were given (not the tool limit): what a reader of those keys alone sees, the key of its
    cache (:mod:`camgen.frozen`)."""
    schema = compiled(keys)
    out = Parsed({f: parsed[f] for f in schema.fields if f in parsed})
    out.given = given_keys(parsed, keys) & schema.names
    return out


#: A default read per use (its value is mutable, or reading it raised).
_EACH_TIME = object()


@dataclass(frozen=True)
class Schema:
    """A tuple of keys made ready for :func:`parse_table` (:func:`compiled`): the names, the
    required ones, per key (name, field, parse, default in internal units or None, or
    :data:`_EACH_TIME`), the fields, and the conditional keys with (other, allowed, other's default)."""

    keys: tuple[Key, ...]
    names: frozenset[str]
    required: tuple[str, ...]
    entries: tuple[tuple[str, str, Any, Any], ...]
    fields: tuple[str, ...]
    conditional: tuple[tuple[str, tuple[tuple[str, tuple[Any, ...], Any], ...]], ...]


def keys_by_name(schema: Schema, name: str) -> Key:
    """The first key of ``schema`` named ``name``."""
    return next(k for k in schema.keys if k.name == name)


def _immutable(value: object) -> bool:
    """``value`` is a number, a string, a flag, None or a tuple of them (shared safely)."""
    if isinstance(value, tuple):
        return all(_immutable(v) for v in value)
    return value is None or type(value) in (int, float, str, bool)


def _default(key: Key) -> Any:
    try:
        value = key.default_value()
    except Exception:  # a bad default is refused where it is used, as before
        return _EACH_TIME
    return value if _immutable(value) else _EACH_TIME


def _compile(keys: tuple[Key, ...]) -> Schema:
    defaults: dict[str, Any] = {}
    for k in keys:
        defaults.setdefault(k.name, k.default)
    conditional = tuple((k.name, tuple((other, tuple(allowed), defaults.get(other)) for other, allowed in k.requires.items()))
                        for k in keys if k.requires)
    return Schema(keys, frozenset(k.name for k in keys), tuple(k.name for k in keys if k.required),
                  tuple((k.name, k.field, k.type.parse, _default(k)) for k in keys), tuple(k.field for k in keys), conditional)


class _Same:
    """A tuple of keys by identity (hashed and compared as the object itself): the key of
    :func:`_compiled_tuple`, which holds it while cached, so that no other tuple can take its id."""

    __slots__ = ("keys",)

    def __init__(self, keys: tuple[Key, ...]) -> None:
        self.keys = keys

    def __hash__(self) -> int:
        return id(self.keys)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _Same) and other.keys is self.keys


#: Key tuples whose :class:`Schema` is kept (the kinds', the output's, the segments', ...).
SCHEMA_CACHE = 64


@lru_cache(maxsize=SCHEMA_CACHE)
def _compiled_tuple(keys: _Same) -> Schema:
    return _compile(keys.keys)


def compiled(keys: Sequence[Key]) -> Schema:
    """The :class:`Schema` of ``keys``: made once per tuple of keys (the same tuple object: keys
    are frozen, a kind's or a table's tuple is made once), per call for any other sequence."""
    if type(keys) is tuple:
        return _compiled_tuple(_Same(keys))
    return _compile(tuple(keys))


def too_deep(value: object, limit: int, path: str = "scene") -> str | None:
    """The path (``cams.x.a_mm[0][0]``) of the first place where lists/tables in a decoded TOML
    value nest more than ``limit`` levels, or None (iterative: deep input cannot exhaust the
    interpreter's stack)."""
    values: list[object] = [value]  # the levels' values first, without their paths (the usual scene is within the limit)
    for _ in range(limit + 1):
        below: list[object] = []
        for item in values:
            if isinstance(item, dict):
                below.extend(item.values())
            elif isinstance(item, list):
                below.extend(item)
        if not below:
            return None
        values = below
    level: list[tuple[str, object]] = [(path, value)]
    for _ in range(limit + 1):
        children: list[tuple[str, object]] = []
        for where, item in level:
            if isinstance(item, dict):
                children.extend((f"{where}.{k}" if where != "scene" else str(k), v) for k, v in item.items())
            elif isinstance(item, list):
                children.extend((f"{where}[{i}]", v) for i, v in enumerate(item))
        if not children:
            return None
        level = children
    return level[0][0]


def key_reference_rows(keys: Sequence[Key]) -> list[tuple[str, str, str, str, str]]:
    """Rows (name, type and range, default, what it changes, doc) of a key reference."""
    rows = []
    for key in keys:
        if key.required:
            default = "required"
        elif key.default is None:
            default = "-"
        else:
            default = repr(key.default).replace("'", '"') if not isinstance(key.default, bool) else str(key.default).lower()
        effect = ", ".join(key.affects)
        doc = key.doc
        if key.requires:
            doc += " Only with " + "; ".join(f"{k} = {' or '.join(repr(v).replace(chr(39), chr(34)) for v in vals)}" for k, vals in key.requires.items()) + "."
        rows.append((key.name, key.type.describe(), default, effect, doc))
    return rows
