"""The last guard before a run's files are written: no number in a text file is NaN or infinite.

A writer that formats a NaN or an infinity prints ``nan``, ``inf``, ``-inf`` (Python, numpy),
``NaN``/``Infinity`` or ``NAN``/``INF`` (``%G``).  Names print the same letters (a scene called
``v1.nan``, a cam ``cam-inf``, a file ``nan.toml``), so the guard reads each file by its format
and looks only where a number stands:

* every file: the word must stand alone, between the format's separators, not inside a longer
  word (``v1.nan``, ``cam-inf``, ``nan.toml`` and ``information`` are words, not numbers);
* CSV: not in a ``#`` comment or a quoted field; G-code: anywhere outside comments (``(...)``,
  ``;``), where every word is a letter and a number (``Xnan``); DXF: the value of a numeric group
  code (not a layer, text or handle); STEP: not inside a quoted string; ASCII STL: not on the
  ``solid``/``endsolid`` lines that carry the name; OBJ: not in comments, object and group names;
  Gmsh ``.msh``: not in quoted names; Abaqus/CalculiX ``.inp``: not on keyword or comment lines,
  nor in the ``*HEADING`` text; PLY and VTU: their ASCII data only (binary data holds no text).

Binary files (binary STL, PLY, VTU data, 3MF) are not read.  The search is a literal search over
the bytes (about 1 GB/s); the format's rules run only where one of those words occurs.
"""
from __future__ import annotations

import re
from pathlib import PurePosixPath
from typing import Callable, Mapping

from camgen.errors import ExportError

__all__ = ["check_files", "first_nonfinite"]

# The spellings formatters give a NaN or an infinity (found case-sensitively: a literal search).
_WORDS = ("nan", "NaN", "NAN", "inf", "Inf", "INF")
_FIND_TEXT = re.compile("|".join(_WORDS))
_FIND_BYTES = re.compile("|".join(_WORDS).encode())
#: A non-finite number as a whole token (an optional sign; "infinity" spelt out).
_NUMBER = re.compile(r"[+-]?(?:nan|inf(?:inity)?)", re.IGNORECASE)
#: What separates numbers in the text formats (CSV fields, mesh and STEP lists, G-code words).
_SEPARATORS = frozenset(" \t\r\n,;=()[]{}<>\"'")

#: DXF group codes whose values are text (R2010 reference, "Group Code Value Types").
_DXF_TEXT_CODES = frozenset(range(0, 10)) | frozenset(range(100, 106)) | frozenset(range(300, 370)) | \
    frozenset(range(390, 400)) | frozenset(range(410, 420)) | frozenset(range(430, 440)) | \
    frozenset(range(470, 482)) | {999} | frozenset(range(1000, 1010))


class _Text:
    """One file's text (str, or bytes read as Latin-1: one character per byte, so positions hold)."""

    def __init__(self, content: str | bytes) -> None:
        self.content = content
        self.is_bytes = isinstance(content, bytes)
        self._counted = (0, 0)  # quotes before a position, counted so far (positions only grow)

    def quotes_before(self, quote: str, pos: int) -> int:
        """The number of ``quote`` characters before ``pos`` (asked for growing positions)."""
        upto, count = self._counted
        count += self.count(quote, upto, pos)
        self._counted = (pos, count)
        return count

    def find(self, sub: str, start: int = 0, end: int | None = None) -> int:
        if isinstance(self.content, bytes):
            return self.content.find(sub.encode("latin-1"), start, end)
        return self.content.find(sub, start, end)

    def rfind(self, sub: str, start: int = 0, end: int | None = None) -> int:
        if isinstance(self.content, bytes):
            return self.content.rfind(sub.encode("latin-1"), start, end)
        return self.content.rfind(sub, start, end)

    def count(self, sub: str, start: int, end: int) -> int:
        if isinstance(self.content, bytes):
            return self.content.count(sub.encode("latin-1"), start, end)
        return self.content.count(sub, start, end)

    def text(self, start: int, end: int) -> str:
        part = self.content[start:end]
        return part.decode("latin-1") if isinstance(part, bytes) else part

    def line_at(self, pos: int) -> tuple[int, int]:
        """(start, end) of the line holding ``pos``, its line break excluded."""
        start = self.rfind("\n", 0, pos) + 1
        end = self.find("\n", pos)
        return start, len(self.content) if end < 0 else end


def _standalone(line: str, start: int, end: int) -> bool:
    """Whether ``line[start:end]`` is a whole token: separators (or the line's ends) around it."""
    return (start == 0 or line[start - 1] in _SEPARATORS) and (end == len(line) or line[end] in _SEPARATORS)


def _tokens(line: str, masked: Callable[[str, int], bool] = lambda line, i: False) -> str | None:
    """The first non-finite number standing alone in ``line`` outside what ``masked(line, i)``
    (is position i inside text?) says is text, or None."""
    for match in _NUMBER.finditer(line):
        if _standalone(line, match.start(), match.end()) and not masked(line, match.start()):
            return match.group()
    return None


def _in_quotes(quote: str) -> Callable[[str, int], bool]:
    """Inside a quoted string of the line (doubled quotes inside stay balanced: parity)."""
    return lambda line, i: line.count(quote, 0, i) % 2 == 1


def _after(mark: str) -> Callable[[str, int], bool]:
    """In a comment that runs from ``mark`` to the line's end."""
    return lambda line, i: mark in line[:i]


def _csv(text: _Text, start: int, end: int) -> str | None:
    quoted = _in_quotes('"')
    return _tokens(text.text(start, end), lambda line, i: quoted(line, i) or _after("#")(line, i))


def _gcode(text: _Text, start: int, end: int) -> str | None:
    line = text.text(start, end)
    for match in _NUMBER.finditer(line):
        i = match.start()
        in_comment = line.rfind("(", 0, i) > line.rfind(")", 0, i) or ";" in line[:i]
        word = i > 0 and line[i - 1].isalpha() and (i == 1 or not line[i - 2].isalpha())  # a letter and its number
        if not in_comment and (word or _standalone(line, i, match.end())) and (match.end() == len(line) or not line[match.end()].isalpha()):
            return match.group()
    return None


def _dxf(text: _Text, start: int, end: int, line_index: int) -> str | None:
    if line_index % 2 == 0 or start == 0:  # a group code line
        return None
    code_start, _ = text.line_at(start - 1)
    try:
        code = int(text.text(code_start, start - 1))
    except ValueError:
        return None
    value = text.text(start, end).strip()
    return value if code not in _DXF_TEXT_CODES and _NUMBER.fullmatch(value) else None


def _step(text: _Text, start: int, end: int, pos: int) -> str | None:
    # inside a string when an odd number of quotes come before ('' inside a string keeps the parity)
    before = text.quotes_before("'", start)
    return _tokens(text.text(start, end), lambda line, i: (before + line.count("'", 0, i)) % 2 == 1)


def _stl(text: _Text, start: int, end: int) -> str | None:
    line = text.text(start, end)
    return None if line.lstrip().lower().startswith(("solid", "endsolid")) else _tokens(line)


def _obj(text: _Text, start: int, end: int) -> str | None:
    line = text.text(start, end)
    if line.lstrip().startswith(("o ", "g ", "s ", "mtllib", "usemtl")):
        return None
    return _tokens(line, _after("#"))


def _msh(text: _Text, start: int, end: int) -> str | None:
    return _tokens(text.text(start, end), _in_quotes('"'))


def _inp(text: _Text, start: int, end: int) -> str | None:
    line = text.text(start, end)
    if line.lstrip().startswith("*"):  # a keyword or a ** comment
        return None
    keyword = text.rfind("\n*", 0, start) + 1  # the keyword line above the data line
    if text.text(keyword, keyword + 8).upper() == "*HEADING":
        return None
    return _tokens(line)


def _ply(text: _Text, start: int, end: int, pos: int) -> str | None:
    header_end = text.find("end_header")
    if header_end < 0 or pos < header_end or text.find("format ascii", 0, header_end) < 0:
        return None  # the header (comments, names), or binary data
    return _tokens(text.text(start, end))


def _vtu(text: _Text, start: int, end: int, pos: int) -> str | None:
    opened = text.rfind("<DataArray", 0, pos)
    if opened < 0 or text.rfind("</DataArray", 0, pos) > opened:
        return None
    tag_end = text.find(">", opened)
    if tag_end < 0 or pos < tag_end or text.find('format="ascii"', opened, tag_end) < 0:
        return None  # in the tag (names), or base64 data
    return _tokens(text.text(start, end))


def _generic(text: _Text, start: int, end: int) -> str | None:
    double, single = _in_quotes('"'), _in_quotes("'")
    return _tokens(text.text(start, end), lambda line, i: double(line, i) or single(line, i) or _after("#")(line, i))


def _binary_mesh(content: str | bytes, suffix: str) -> bool:
    """Whether a mesh file is binary (its data holds no text to read)."""
    if not isinstance(content, bytes):
        return False
    head = content[:200]
    if suffix == ".stl":
        return not head.lstrip().startswith(b"solid")
    if suffix == ".msh":
        return b"$MeshFormat" in head and re.search(rb"\$MeshFormat\s+\S+\s+1\b", head) is not None
    return False


def first_nonfinite(name: str, content: str | bytes) -> tuple[int, str] | None:
    """(line number, the word) of the first non-finite number in the file ``name`` holding
    ``content``, or None; files whose format holds no text (3MF, binary STL and mesh data) give
    None."""
    suffix = PurePosixPath(name).suffix.lower()
    if suffix in (".3mf", ".zip", ".png") or _binary_mesh(content, suffix):
        return None
    if isinstance(content, bytes) and suffix not in _BY_POSITION and suffix not in _BY_LINE and suffix != ".dxf":
        return None  # a binary format this guard does not know
    text = _Text(content)
    if isinstance(content, bytes):
        positions = (match.start() for match in _FIND_BYTES.finditer(content))
    else:
        positions = (match.start() for match in _FIND_TEXT.finditer(content))
    line, counted = 1, 0
    seen_line = -1
    for pos in positions:
        line += text.count("\n", counted, pos)
        counted = pos
        if line == seen_line:
            continue  # the whole line was read
        seen_line = line
        start, end = text.line_at(pos)
        if suffix in _BY_POSITION:
            found = _BY_POSITION[suffix](text, start, end, pos)
        elif suffix == ".dxf":
            found = _dxf(text, start, end, line - 1)
        else:
            found = _BY_LINE.get(suffix, _generic)(text, start, end)
        if found is not None:
            return line, found
    return None


_BY_LINE: Mapping[str, Callable[[_Text, int, int], str | None]] = {
    ".csv": _csv, ".ngc": _gcode, ".nc": _gcode, ".stl": _stl, ".obj": _obj, ".msh": _msh, ".inp": _inp,
}
_BY_POSITION: Mapping[str, Callable[[_Text, int, int, int], str | None]] = {
    ".step": _step, ".stp": _step, ".ply": _ply, ".vtu": _vtu,
}


def check_files(files: Mapping[str, str | bytes]) -> None:
    """Raise :class:`~camgen.errors.ExportError` naming the file and line of the first non-finite
    number in ``files`` (name -> content), before anything is written."""
    for name, content in files.items():
        found = first_nonfinite(name, content)
        if found is not None:
            line, word = found
            raise ExportError(f"{name} would hold the non-finite number '{word}' at line {line}: nothing written "
                              "(a bug: please report the scene)")
