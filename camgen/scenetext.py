"""What reaches the TOML parser: one linear scan of a scene's text before :mod:`tomllib` reads it.

The parser's work is not linear in every input: a dotted key or table header of n parts costs it
O(n^2) time and memory (a 40 KB key of 20,000 parts took 1.6 GB), brackets nest by recursion,
and an integer literal of more than 4300 decimal digits stops it with Python's ValueError.  This
scan bounds them before the parser runs, aware of TOML's strings (basic, literal, both
multi-line) and comments:

* a key, table header or inline array/table that puts a value more than ``max_nesting`` levels
  deep is refused naming the key, as :func:`camgen.schema.too_deep` would refuse it after parsing
  (the scan counts the parts of headers and dotted keys and the brackets: never more than the
  parsed value's depth, so it refuses nothing the parse would accept);
* a scene of more than :data:`MAX_SCENE_ITEMS` keys, values and table headers is refused, so
  that the scan and the parser do a bounded number of steps whatever the text holds;
* an integer literal (decimal, hexadecimal, octal or binary) too large for a float, >= 2**1024,
  is beyond every key's range: the parser is given a placeholder string in its place, and
  :func:`restore_integers` puts a :class:`LargeInteger` (which no key accepts, and which
  messages show by its digit count) where the parser put the placeholder.  The schema then names
  the key by its path and gives its valid range, as it does for any other value.

Every integer the parser reads is below 2**1028 (at most 310 decimal digits), within Python's
digit limit for converting integers to and from text.
"""
from __future__ import annotations

import math
import re
import secrets
from dataclasses import dataclass
from typing import Any

from camgen.errors import SceneError

__all__ = [
    "FLOAT_RANGE_BITS", "LargeInteger", "MAX_SCENE_ITEMS", "ScannedText", "large_integer", "restore_integers",
    "scan_scene_text",
]

#: Most keys, values and table headers in a scene (a scene of 200 cams holds about 10,000): the
#: scan and the parser take a few steps for each.
MAX_SCENE_ITEMS = 20_000
#: Every float is below 2**1024: an integer literal at least that large is refused by every key.
FLOAT_RANGE_BITS = 1024
#: Longest part of a key quoted in an error (a key part can be as long as the file), and the
#: most parts quoted.
_SHOWN_PART = 40
_SHOWN_PARTS = 10

# One token of TOML with the blanks before it: a line end (with the blank and comment lines after
# it), a comment, the four kinds of strings, the opening quote of a string with no end on its line
# (invalid: the scan skips the line), punctuation, or bare text (keys, numbers, dates, booleans).
_TOKEN = re.compile(r"""[ \t]*(?:
     (?P<nl>\r?\n(?:[\r\n \t]++|\#[^\n]*+)*+)
    |(?P<comment>\#[^\n]*)
    |(?P<mlbasic>"{3}(?:[^"\\]|\\.|"{1,2}(?!"))*+"{3,5})
    |(?P<mlliteral>'{3}(?:[^']|'{1,2}(?!'))*+'{3,5})
    |(?P<basic>"(?:[^"\\\n]|\\.)*+")
    |(?P<literal>'[^'\n]*+')
    |(?P<unterminated>["'])
    |(?P<punct>[\[\]{}=,])
    |(?P<atom>[^ \t\r\n\#"'\[\]{}=,]++)
    |(?P<other>.)
)""", re.VERBOSE | re.DOTALL)

#: A TOML integer literal (underscores between digits; the parser checks the finer rules).
_INTEGER = re.compile(r"[+-]?(?:0x(?P<hex>[0-9A-Fa-f_]+)|0o(?P<oct>[0-7_]+)|0b(?P<bin>[01_]+)|(?P<dec>[0-9_]+))\Z")
_BASES = {"hex": (16, "hexadecimal "), "oct": (8, "octal "), "bin": (2, "binary "), "dec": (10, "")}

# The scan's states: a line's start; after the first '[' of '[['; a header's key; before the
# second ']' of ']]'; a key; a value; after a value; after a line's content (only a comment may
# follow).
_LINE, _OPEN_AOT, _HEADER, _CLOSE_AOT, _KEY, _VALUE, _AFTER_VALUE, _AFTER_LINE = range(8)


@dataclass(frozen=True)
class LargeInteger:
    """An integer literal of a scene too large for a float (>= 2**1024), in place of its value.

    No key accepts it (it is neither a number nor a string), so the schema refuses it naming the
    key; messages show it as ``<4000-digit hexadecimal integer>``.
    """

    digits: int
    base_name: str = ""
    negative: bool = False

    #: how messages name its type ("[cams.x] must be a table, not int")
    toml_type = "int"

    def __repr__(self) -> str:
        return f"<{self.digits}-digit {'negative ' if self.negative else ''}{self.base_name}integer>"

    __str__ = __repr__


@dataclass(frozen=True)
class ScannedText:
    """A scene's text ready for the parser: ``text`` with each too-large integer literal replaced
    by a placeholder string, ``integers`` mapping each placeholder to its :class:`LargeInteger`."""

    text: str
    integers: dict[str, LargeInteger]


def large_integer(literal: str) -> LargeInteger | None:
    """The :class:`LargeInteger` of a TOML integer literal >= 2**1024, else None (a smaller
    integer, or not an integer literal)."""
    match = _INTEGER.match(literal)
    if match is None:
        return None
    group = match.lastgroup or "dec"
    base, base_name = _BASES[group]
    digits = match.group(group).replace("_", "").lstrip("0")
    # s significant digits in base b: the value is at least b**(s - 1), >= 2**1024 when (s - 1) log2(b) >= 1024
    if (len(digits) - 1) * math.log2(base) < FLOAT_RANGE_BITS:
        return None
    return LargeInteger(len(digits), base_name, literal.startswith("-"))


class _Key:
    """A dotted key or table header being read: the depth of its value and, shortened, its name."""

    def __init__(self, base: int, prefix: str = "") -> None:
        self.base = base  # the depth of the table the key is in (the root table: 0)
        self.dots = 0
        self.empty = True  # no part read yet
        self.shown: list[str] = [prefix] if prefix else []
        self.current = ""

    def add(self, token: str, quoted: bool) -> None:
        """Read a token of the key: a quoted part, or bare text holding the dots between parts."""
        self.empty = False
        if quoted:
            self.current += token[: _SHOWN_PART + 2]
            return
        dots = token.count(".")
        pieces = token.split(".", _SHOWN_PARTS) if dots else [token]
        self.current += pieces[0][:_SHOWN_PART]
        for piece in pieces[1:]:
            if len(self.shown) <= _SHOWN_PARTS:
                self.shown.append(self.current)
            self.current = piece[:_SHOWN_PART]
        self.dots += dots

    @property
    def depth(self) -> int:
        """The depth of the key's value (a top-level key's: 1)."""
        return self.base + self.dots + 1

    def name(self) -> str:
        """The key as written (its first parts when there are many)."""
        parts = [p for p in self.shown + [self.current] if p]
        if len(parts) > _SHOWN_PARTS or self.dots >= _SHOWN_PARTS:
            return ".".join(parts[:_SHOWN_PARTS]) + f"... ({self.dots + 1} parts)"
        return ".".join(parts)


def scan_scene_text(text: str, max_nesting: int) -> ScannedText:
    """Check ``text`` (a scene's TOML) for what the parser cannot take in bounded time and memory.

    Parameters
    ----------
    text : the scene file's text.
    max_nesting : the deepest level of a value (a top-level key's value is level 1), as
        :func:`camgen.schema.too_deep` counts it.

    Returns
    -------
    ScannedText
        The text to parse, large integer literals replaced by placeholders.

    Raises
    ------
    SceneError
        A key, header or bracket deeper than ``max_nesting``, or more than
        :data:`MAX_SCENE_ITEMS` items, naming the key and the line.

    Text that is not valid TOML is left to the parser's error: the scan skips the rest of a line
    it cannot follow (each skip counted as an item) and goes on from the next.
    """
    nonce = secrets.token_hex(8)
    integers: dict[str, LargeInteger] = {}
    pieces: list[str] = []  # the text for the parser, built only when a literal is replaced
    copied = 0
    line = 1
    items = 0
    state = _LINE
    table = _Key(0)  # the current table (before any header: the root table, depth 0)
    table.dots = -1
    key = table
    array_of_tables = False  # reading a [[header]]
    stack: list[tuple[str, int, str]] = []  # open inline arrays and tables: (bracket, their depth, their key)
    depth = 0  # the depth of the value about to be read
    where = ""  # the key whose value is being read

    def refuse(name: str, what: str) -> SceneError:
        return SceneError(f"{name or 'scene'}: {what} (the limit of a scene; line {line})")

    pos, end = 0, len(text)
    while pos < end:
        match = _TOKEN.match(text, pos)
        assert match is not None  # "other" matches any character
        pos = match.end()
        kind = match.lastgroup
        assert kind is not None  # every alternative of _TOKEN is a named group
        if kind == "comment":
            continue
        token = match.group(kind)
        if kind == "nl":
            line += token.count("\n")
            if not (stack and stack[-1][0] == "[" and state in (_VALUE, _AFTER_VALUE)):  # only arrays span lines
                state = _LINE
                stack.clear()
            continue
        if kind in ("mlbasic", "mlliteral"):
            line += token.count("\n")
        expected = True
        quoted = kind != "atom"
        if state == _LINE:
            items += 1
            if token == "[":
                array_of_tables = text.startswith("[", pos)
                key = _Key(0)
                state = _OPEN_AOT if array_of_tables else _HEADER
            elif kind in ("atom", "basic", "literal"):
                key = _Key(table.depth, table.name())
                key.add(token, quoted)
                state = _KEY
            else:
                expected = False
        elif state == _OPEN_AOT:  # the second '[' of '[['
            state = _HEADER
        elif state in (_HEADER, _KEY):
            if kind in ("atom", "basic", "literal"):
                key.add(token, quoted)
                if key.depth > max_nesting:
                    raise refuse(key.name(), f"tables and lists nest more than {max_nesting} levels deep")
            elif state == _HEADER and token == "]" and not key.empty:
                table = key
                state = _CLOSE_AOT if array_of_tables else _AFTER_LINE
            elif state == _KEY and token == "=" and not key.empty:
                depth, where = key.depth, key.name()
                state = _VALUE
            elif state == _KEY and token == "}" and key.empty and stack and stack[-1][0] == "{":
                stack.pop()  # an empty inline table
                state = _AFTER_VALUE
            else:
                expected = False
        elif state == _CLOSE_AOT:  # the second ']' of ']]'
            expected = token == "]"
            state = _AFTER_LINE
        elif state == _VALUE:
            items += 1
            opens = kind == "punct" and token in ("[", "{")
            if depth > max_nesting and (opens or kind in ("atom", "basic", "literal", "mlbasic", "mlliteral")):
                raise refuse(where, f"tables and lists nest more than {max_nesting} levels deep")
            if opens:
                stack.append((token, depth, where))
                if token == "[":
                    depth += 1
                else:
                    key = _Key(depth, where)
                    state = _KEY
            elif kind == "punct" and token == "]" and stack and stack[-1][0] == "[":
                stack.pop()  # an empty array, or a comma before the ']'
                state = _AFTER_VALUE
            elif kind == "punct" or kind in ("unterminated", "other"):
                expected = False
            else:
                large = large_integer(token) if kind == "atom" else None
                if large is not None:
                    placeholder = f"camgen-{nonce}-{len(integers)}"
                    integers["\x00" + placeholder] = large
                    pieces += [text[copied:match.start(kind)], f'"\\u0000{placeholder}"']
                    copied = pos
                state = _AFTER_VALUE
        elif state == _AFTER_VALUE:
            if token == "," and stack:
                bracket, container_depth, container_key = stack[-1]
                if bracket == "[":
                    depth = container_depth + 1
                    state = _VALUE
                else:
                    key = _Key(container_depth, container_key)
                    state = _KEY
            elif kind == "punct" and token in ("]", "}") and stack and stack[-1][0] == ("[" if token == "]" else "{"):
                stack.pop()
            else:
                expected = False
        else:  # _AFTER_LINE
            expected = False
        if not expected:  # not TOML (the parser will say where): go on at the next line
            items += 1
            newline = text.find("\n", pos)
            pos = end if newline < 0 else newline
            state = _LINE
            stack.clear()
        if items > MAX_SCENE_ITEMS:
            raise refuse(where if state in (_VALUE, _AFTER_VALUE) else key.name() or table.name(),
                         f"more than {MAX_SCENE_ITEMS} keys, values and tables")
    if not integers:
        return ScannedText(text, {})
    return ScannedText("".join(pieces) + text[copied:], integers)


def restore_integers(data: Any, integers: dict[str, LargeInteger]) -> Any:
    """``data`` (the parser's output) with each placeholder string of :func:`scan_scene_text`
    replaced by its :class:`LargeInteger`, in place (iteratively: no recursion on deep data)."""
    if not integers:
        return data
    todo = [data]
    while todo:
        item = todo.pop()
        entries = item.items() if isinstance(item, dict) else enumerate(item) if isinstance(item, list) else ()
        for k, v in list(entries):
            if isinstance(v, str) and v in integers:
                item[k] = integers[v]
            elif isinstance(v, (dict, list)):
                todo.append(v)
    return data
