"""What a new user reads first (issue 21, item 14): a template copied by ``camgen new`` says only
true things where it lands, and ``camgen keys | head`` shows keys."""
from __future__ import annotations

import re
import shlex
import subprocess
import sys

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
    from camgen.scene import load_scene

    cams = [spec.name for spec in load_scene(copy).cams]  # the run's cams (a conjugate pair's two among them)
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


def _every_key_name() -> set[str]:
    """Every key of every table, read from the kinds, mechanisms and output tables (the schema)."""
    from camgen.jobs import get_job, job_names
    from camgen.kinds import get_kind, kind_names
    from camgen.outputs import machining_keys, output_keys

    groups = [get_kind(k).keys for k in kind_names()] + [get_job(j).keys for j in job_names()] + [output_keys(), machining_keys()]
    names = set()
    for keys in groups:
        for key in keys:
            names.add(key.name)
            names |= {sub.name for sub in getattr(key.type, "keys", None) or ()}
    return names


def test_the_first_lines_of_camgen_keys_name_keys(capsys):
    """`camgen keys | head` shows keys of every table: the index comes before the prose."""
    assert main(["keys"]) == 0
    head = capsys.readouterr().out.splitlines()[:10]
    quoted = set(re.findall(r"`([a-z_0-9]+)`", "\n".join(head)))
    keys = _every_key_name()
    assert len(quoted & keys) >= 20
    from camgen.outputs import output_keys

    assert {k.name for k in output_keys()} <= quoted  # the [output] table in full
    assert "chord_tol_mm" in quoted and "base_radius_mm" in quoted


def test_camgen_keys_into_a_pipe_nobody_reads_ends_quietly(tmp_path):
    """The pipe's reading end is closed before camgen starts, so its first write fails (EPIPE)
    every time: camgen stops writing without a traceback, with status 0 or 141 (a shell tool
    ended by SIGPIPE: 128 + 13)."""
    import os

    read, write = os.pipe()
    os.close(read)
    try:
        proc = subprocess.run([sys.executable, "-m", "camgen", "keys"], stdout=write, stderr=subprocess.PIPE, text=True,
                              timeout=120, cwd=tmp_path)
    finally:
        os.close(write)
    assert proc.stderr == "" and proc.returncode in (0, 141), (proc.returncode, proc.stderr[-2000:])


def test_camgen_keys_piped_to_head_shows_the_first_line_quietly(tmp_path):
    command = f"{shlex.quote(sys.executable)} -m camgen keys | head -1; echo status=${{PIPESTATUS[0]}}"
    proc = subprocess.run(["bash", "-c", command], capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert proc.stdout.splitlines()[0] == "# camgen scene keys"
    assert proc.stderr == "", proc.stderr[-2000:]
    assert int(re.search(r"status=(\d+)", proc.stdout).group(1)) in (0, 141)
