"""The scan of a scene's text before the TOML parser (issue "Trust, round 2", items 3-4), against
the parser itself: on generated valid TOML (strings of every kind holding TOML syntax, comments,
dotted and quoted keys, headers, arrays over lines, inline tables, integers in every base) the
scan refuses exactly what nests too deep (:func:`camgen.schema.too_deep` on ``tomllib``'s
result), changes nothing else, and stands a :class:`LargeInteger` exactly for the integers no
float holds."""
from __future__ import annotations

import json
import sys
import tomllib

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from camgen.errors import SceneError
from camgen.scenetext import LargeInteger, restore_integers, scan_scene_text
from camgen.schema import too_deep

MAX_NESTING = 8
#: Every IEEE 754 double is below 2**1024 (largest: (2 - 2**-52) * 2**1023).
FLOAT_LIMIT = 2**1024

# Text holding what TOML gives meaning to: brackets, dots, quotes, comments, escapes, digits.
_TRICKY = st.lists(st.sampled_from(list("ab.#[]{}=,'\"\\ 0x9\t") + ["'''", '"""', "0x" + "f" * 300, "a." * 30]),
                   max_size=12).map("".join)


def _basic(text: str) -> str:
    return json.dumps(text)  # JSON's escapes are TOML basic-string escapes


def _ml_basic(text: str) -> str:
    return '"""' + text.replace("\\", "\\\\").replace('"', '\\"') + '\n"""'


def _literal(text: str) -> str:
    return "'" + text.replace("'", "").replace("\n", "") + "'"


def _ml_literal(text: str) -> str:
    return "'''\n" + text.replace("'", "") + "'''"


_STRINGS = st.builds(lambda f, t: f(t), st.sampled_from([_basic, _ml_basic, _literal, _ml_literal]), _TRICKY)


def _integer_literal(value: int, base: str, underscores: bool) -> str:
    if base == "dec":
        digits = str(abs(value))
        text = ("-" if value < 0 else "") + digits
    else:
        digits = format(abs(value), {"hex": "x", "oct": "o", "bin": "b"}[base])
        text = "0" + base[0] + digits.rjust(len(digits) + 2, "0")  # leading zeros: allowed after a prefix
    if underscores and len(digits) > 2 and "_" not in text:
        text = text[:-1] + "_" + text[-1]
    return text


#: (literal text, its value): small, large and huge integers in every base.
_INTEGERS = st.builds(
    lambda magnitude, sign, base, underscores: (_integer_literal(sign * magnitude if base == "dec" else magnitude, base, underscores),
                                                sign * magnitude if base == "dec" else magnitude),
    st.one_of(st.integers(0, 10**6), st.integers(2**1000, 2**1100), st.integers(10**4000, 10**4200)),
    st.sampled_from([1, -1]), st.sampled_from(["dec", "hex", "oct", "bin"]), st.booleans(),
).filter(lambda lv: len(lv[0]) < 4300)  # the test's own parse of the original text keeps Python's digit limit

_SCALARS = st.one_of(
    _STRINGS, _INTEGERS.map(lambda lv: lv[0]),
    st.sampled_from(["true", "false", "1.5", "-0.0", "6.626e-34", "inf", "-inf", "nan", "1979-05-27", "07:32:00",
                     "1979-05-27T07:32:00Z", "1e400"]),
)


def _gap(draw) -> str:
    """Blanks, a comment or a line break, where an array allows them."""
    return draw(st.sampled_from(["", " ", "\n", " # a comment [[ 'x' = \"\n", "\n\n  "]))


@st.composite
def _values(draw, depth: int) -> str:
    if depth <= 0 or draw(st.integers(0, 2)) == 0:
        return draw(_SCALARS)
    if draw(st.booleans()):
        items = [draw(_values(depth - 1)) for _ in range(draw(st.integers(0, 3)))]
        body = ",".join(_gap(draw) + item + _gap(draw) for item in items) + ("," + _gap(draw) if items and draw(st.booleans()) else "")
        return "[" + body + "]"
    items = [f"{draw(_keys(k))} = {draw(_values(depth - 1))}" for k in range(draw(st.integers(0, 3)))]
    return "{" + ", ".join(items) + "}"


@st.composite
def _keys(draw, index: int) -> str:
    """A key whose first part is unique by ``index``: bare, quoted, dotted (blanks around dots)."""
    parts = [f"k{index}"] + draw(st.lists(st.one_of(st.from_regex(r"[A-Za-z0-9_-]{1,4}", fullmatch=True), _STRINGS.filter(
        lambda s: s.startswith(("'", '"')) and not s.startswith(("'''", '"""')))), max_size=draw(st.sampled_from([2, 9]))))
    if draw(st.booleans()):
        parts[0] = _basic(parts[0])
    return draw(st.sampled_from([".", " . ", ".  "])).join(parts)


@st.composite
def _documents(draw) -> str:
    lines = []
    for i in range(draw(st.integers(0, 3))):
        lines.append(f"{draw(_keys(i))} = {draw(_values(draw(st.integers(0, 8))))}{draw(st.sampled_from(['', '  # [x.y] = 1']))}")
    for t in range(draw(st.integers(0, 3))):
        name = f"t{t}" + "".join("." + draw(st.sampled_from(["a", '"b.c"', "'d'"])) for _ in range(draw(st.integers(0, 8))))
        lines.append(f"[[{name}]]" if draw(st.booleans()) else f"[{name}]")
        for i in range(draw(st.integers(0, 3))):
            lines.append(f"{draw(_keys(i))} = {draw(_values(draw(st.integers(0, 6))))}")
    return "\n".join(lines) + draw(st.sampled_from(["", "\n", "\r\n"]))


def _parse_without_digit_limit(text: str):
    limit = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(0)
    try:
        return tomllib.loads(text)
    finally:
        sys.set_int_max_str_digits(limit)


def _leaves(value, path=()):
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _leaves(v, path + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _leaves(v, path + (i,))
    else:
        yield path, value


def _agrees_with_the_parser(text: str) -> int | None:
    """The scan of ``text`` against tomllib's parse of it: refused only when too deep (None);
    else the same data, with a LargeInteger only where no float holds the integer (their count)."""
    try:
        original = _parse_without_digit_limit(text)
    except tomllib.TOMLDecodeError:
        assume(False)  # a duplicate key, or a table defined twice: not a valid document
    deep = too_deep(original, MAX_NESTING)
    try:
        scanned = scan_scene_text(text, MAX_NESTING)
    except SceneError as exc:
        assert deep is not None, f"the scan refused what the parser reads within {MAX_NESTING} levels: {exc}"
        return None
    has_array_tables = any(line.lstrip().startswith("[[") for line in text.splitlines())
    assert deep is None or has_array_tables, f"{deep} nests too deep but the scan let it through"  # [[...]] adds levels it does not count
    restored = restore_integers(tomllib.loads(scanned.text), scanned.integers)
    got, want = list(_leaves(restored)), list(_leaves(original))
    assert [p for p, _ in got] == [p for p, _ in want]
    for (path, value), (_, true_value) in zip(got, want):
        if isinstance(value, LargeInteger):  # only where no float holds the value
            assert isinstance(true_value, int) and abs(true_value) >= FLOAT_LIMIT, path
            assert value.negative == (true_value < 0)
        elif isinstance(true_value, float) and true_value != true_value:
            assert value != value  # NaN
        else:
            assert value == true_value and type(value) is type(true_value), path
            if isinstance(value, int):  # every integer the parser read converts to text within Python's limit
                assert abs(value) < 16 * FLOAT_LIMIT, path
    return sum(isinstance(value, LargeInteger) for _, value in got)


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(_documents())
def test_the_scan_agrees_with_the_parser(text):
    _agrees_with_the_parser(text)


_HEX = "0x" + "f" * 300  # 1200 bits
_DEEP = "b." * 12 + "c"
#: TOML's constructs, written by hand, each where a scan that misread it would misfire.
CONSTRUCTS = {
    "ml-basic": f'a = """\n{_DEEP} = {_HEX}\n[{_DEEP}]\n"""\nd = {_HEX}\n',
    "ml-basic-quotes": f'a = """x""""\nb = {_HEX}\nc = """ ""\\"" "" """\nd = {_HEX}\n',
    "ml-basic-escaped-newline": f'a = """one \\\n  {_DEEP} = 1"""\nb = {_HEX}\n',
    "ml-literal": f"a = '''\n{_DEEP} = {_HEX}\n\\'''\nd = {_HEX}\n",
    "ml-literal-quotes": f"a = '''x'''''\nb = {_HEX}\n",
    "basic-escapes": f'a = "x\\" # {_DEEP} = 1 \\\\"\nb = {_HEX}\n',
    "literal-backslash": f"a = 'C:\\dir\\'\nb = {_HEX}\n",
    "array-over-lines": f"a = [\n  1, # {_DEEP} = 1\n\n  {_HEX},\n  [\n {_HEX} ], # ]\n]\nb = {_HEX}\n",
    "inline-table": f"a = {{ b = [\n {_HEX},\n ], \"c.d\" = {{ e = {_HEX} }} }}\nf = {_HEX}\n",
    "quoted-keys": f"\"a.b = c\".'d.e'.\"[f]\" = {_HEX}\n[\"g.h\" . 'i']\nj = {_HEX}\n",
    "array-tables": f"[[t]]\na = {_HEX}\n[[t]]\nb = [{_HEX}]\n[t.u] # [[x]]\nc = {_HEX}\n",
    "crlf": f"a = [\r\n  {_HEX},\r\n]\r\nb = \"\"\"\r\n{_DEEP} = 1\r\n\"\"\"\r\n",
    "values": f"a = [1979-05-27T07:32:00Z, 07:32:00, 1e400, -inf, nan, true, 0o17, 0b101, -{_HEX[2:].replace('f', '9')}]\n",
    "empty-containers": "a.b.c.d.e.f.g.h = []\ni.j.k.l.m.n.o.p = {}\n",
}


@pytest.mark.parametrize("name", CONSTRUCTS)
def test_the_scan_reads_tomls_constructs(name):
    text = CONSTRUCTS[name]
    large = _agrees_with_the_parser(text)
    assert large is not None and (large > 0 or _HEX not in text)


@pytest.mark.parametrize("template", sorted(__import__("camgen.scene", fromlist=["template_dir"]).template_dir().glob("*.toml")),
                         ids=lambda p: p.name)
def test_the_scan_leaves_every_template_as_it_is(template):
    text = template.read_text(encoding="utf-8")
    scanned = scan_scene_text(text, MAX_NESTING)
    assert scanned.text == text and scanned.integers == {}


def test_a_huge_literal_shows_its_digits():
    """The message form of item 3: the literal's significant digits and base."""
    scanned = scan_scene_text("a = 0x00" + "f" * 4000 + "\nb = [-" + "9" * 5000 + "]\nc = 0b" + "1" * 1025 + "\n", MAX_NESTING)
    data = restore_integers(tomllib.loads(scanned.text), scanned.integers)
    assert [repr(data["a"]), repr(data["b"][0]), repr(data["c"])] == [
        "<4000-digit hexadecimal integer>", "<5000-digit negative integer>", "<1025-digit binary integer>"]


@pytest.mark.parametrize("text, refused", [
    ("a.b.c.d.e.f.g.h = 1\n", None),  # level 8
    ("a.b.c.d.e.f.g.h.i = 1\n", "a.b.c.d.e.f.g.h.i"),
    ("[a.b.c.d]\ne.f.g.h = 1\n", None),
    ("[a.b.c.d]\ne.f.g.h.i = 1\n", "a.b.c.d.e.f.g.h.i"),
    ("a = [[[[[[[[]]]]]]]]\n", None),  # the 8th array empty
    ("a = [[[[[[[[1]]]]]]]]\n", "a"),
    ("a.b.c.d.e.f.g = {h = {}}\n", None),
    ("a.b.c.d.e.f.g = {h = {i = 1}}\n", "a.b.c.d.e.f.g.h.i"),
    ("a = '''\n" + "b." * 100 + "c = 1'''\n", None),  # in a string
    ("# " + "b." * 100 + "c = 1\n", None),  # in a comment
    ("a." * 20_000 + "b = 1\n", "a.a.a.a.a.a.a.a.a.a... (20001 parts)"),
])
def test_nesting_is_counted_as_the_parser_nests(text, refused):
    """Levels counted by hand (a top-level key's value is level 1, as too_deep counts)."""
    if refused is None:
        scan_scene_text(text, MAX_NESTING)
        assert too_deep(tomllib.loads(text), MAX_NESTING) is None
    else:
        with pytest.raises(SceneError, match=r"^" + refused.replace(".", r"\.").replace("(", r"\(").replace(")", r"\)")
                           + ": tables and lists nest more than 8 levels deep"):
            scan_scene_text(text, MAX_NESTING)


def test_a_scene_holds_at_most_max_scene_items():
    """Each `k = 1` line is a key and a value, a header one table: the limit at its boundary."""
    from camgen.scenetext import MAX_SCENE_ITEMS

    lines = "".join(f"k{i} = 1\n" for i in range(MAX_SCENE_ITEMS // 2 - 1))
    scan_scene_text(lines + "[t]\n", MAX_NESTING)  # MAX_SCENE_ITEMS - 1
    scan_scene_text(lines + "z = 1\n", MAX_NESTING)  # MAX_SCENE_ITEMS
    with pytest.raises(SceneError, match=f"^t.z: more than {MAX_SCENE_ITEMS} keys, values and tables"):
        scan_scene_text(lines + "[t]\nz = 1\n", MAX_NESTING)  # MAX_SCENE_ITEMS + 1: the value of t.z
