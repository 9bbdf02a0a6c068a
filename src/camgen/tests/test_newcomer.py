"""What a new user reads first (issue 21, item 14): a template copied by ``camgen new`` says only
true things where it lands, and ``camgen keys | head`` shows keys."""
from __future__ import annotations

import re
import shlex
import subprocess
import sys
import tomllib

import pytest

from camgen.cli import main
from camgen.scene import template_names

#: A file named in a comment: a word with a file extension, with or without folders.
_FILE = re.compile(r"(?<![\w./-])((?:[\w.<>-]+/)*[\w<>-][\w.<>-]*\.(?:toml|csv|py|md|txt|json|dxf|stl|ngc|html))\b")
_COMMAND = re.compile(r"`(camgen [^`]*)`")


def _comments(text: str) -> list[str]:
    """The comments of a TOML text: what follows a '#' outside a string, line by line."""
    out = []
    for line in text.splitlines():
        quote = None
        for i, ch in enumerate(line):
            if quote is None and ch in "\"'":
                quote = ch
            elif ch == quote and line[i - 1] != "\\":
                quote = None
            elif quote is None and ch == "#":
                out.append(line[i + 1:])
                break
    return out


@pytest.mark.parametrize("template", template_names())
def test_a_copied_templates_comments_are_true_where_it_lands(template, tmp_path, monkeypatch, capsys):
    """Every file a comment names exists beside the copy or is a file the scene's run writes (a
    name from the output table with the scene's cam names), no comment names the bundled
    ``templates/`` folder, and every quoted ``camgen`` command works from the copy's folder (the
    scene file it runs is there, the template it copies exists)."""
    from camgen.outputs import OUTPUTS

    folder = tmp_path / "work"
    folder.mkdir()
    monkeypatch.chdir(folder)
    assert main(["new", template]) == 0
    capsys.readouterr()
    copy = folder / f"{template}.toml"
    text = copy.read_text(encoding="utf-8")
    comments = "\n".join(_comments(text))
    assert comments.strip(), "a template explains itself in comments"
    assert "templates/" not in comments
    cams = tomllib.loads(text).get("cams", {})
    written = {f.files.replace("{cam}", cam) for f in OUTPUTS.values() for cam in [*cams, "<cam>"]}
    for name in _FILE.findall(comments):
        assert (folder / name).exists() or name in written, f"{template}.toml names {name}: not beside the copy, not an output"
    commands = _COMMAND.findall(comments)
    assert commands, "a template says how to run it"
    for command in commands:
        words = shlex.split(command)
        if words[1] == "run" and len(words) > 2:
            assert (folder / words[2]).is_file(), command
        elif words[1] == "new":
            assert words[2] in template_names(), command


def test_the_comment_reader_finds_file_names():
    """The test's own reader: comments outside strings, file names with and without folders."""
    assert _comments('a = "x # y"  # z\n# w\nb = 1') == [" z", " w"]
    found = _FILE.findall(" run templates/plate_cam.toml, see camgen/mechanisms/tricycle.py and lift_table.csv; 5 mm/deg")
    assert found == ["templates/plate_cam.toml", "camgen/mechanisms/tricycle.py", "lift_table.csv"]
