"""Command line: ``camgen run | check | templates | new | keys``.

Only argparse is imported at start-up; each command imports what it needs.  Exit status:
0 every check passed; 1 a design check failed (``run`` writes the report showing it and no
manufacturing file for a cam that cannot be made; one line per failed check on stderr);
2 bad input (one ``camgen: error: ...`` line naming the key, nothing written).
"""
from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING, Sequence

from camgen import __version__
from camgen.errors import CamgenError

if TYPE_CHECKING:
    from camgen.pipeline import RunResult
    from camgen.scene import Scene

EXAMPLES = {
    "run": """examples:
  camgen run                                  the bundled default scene into outputs/default/
  camgen run my_cam.toml -o build             my_cam.toml into build/<scene name>/
  camgen run my_cam.toml --only dxf,ngc       just the DXF drawings and G-code (and report.json)""",
    "check": """examples:
  camgen check my_cam.toml                    synthesis and design checks only; exit 1 if one fails
  camgen check my_cam.toml && camgen run my_cam.toml""",
    "templates": """examples:
  camgen templates                            the bundled scenes with a line each""",
    "new": """examples:
  camgen new plate_cam                        copy templates/plate_cam.toml to ./plate_cam.toml
  camgen new lift_table                       copy templates/lift_table.toml and its lift_table.csv here
  camgen new tricycle designs/steering.toml   copy it under another name""",
    "keys": """examples:
  camgen keys                                 every scene key: type, range, default, what it changes
  camgen keys motion_law                      the keys of one cam kind ([cams.<name>] with that kind)
  camgen keys machining                       the keys of one table (output, machining, a mechanism)""",
}


def _scene(path: str | None) -> "Scene":
    from camgen.scene import load_scene, load_template

    return load_scene(path) if path else load_template("default")


def _report_failures(result: "RunResult") -> int:
    failed = result.failed_checks()
    for cam, check in failed:
        where = f" at {', '.join(f'{w:g}' for w in check.where_deg[:6])} deg" if check.where_deg else ""
        value = f"{check.value:.6g}" if isinstance(check.value, float) else check.value
        limit = f"{check.limit:.6g}" if isinstance(check.limit, float) else check.limit
        if check.comparison:  # a measured value against its limit
            what = f"{check.name} = {value}{' ' + check.unit if check.unit else ''}, must be {check.comparison} {limit}{where}"
        else:  # an output that could not be made (an export check): its note says why
            what = f"{check.name}: {check.note}"
        print(f"camgen: check failed: cams.{cam}: {what}" + (" (no manufacturing file written for this cam)" if check.blocks_manufacture else ""),
              file=sys.stderr)
    return 1 if failed else 0


def _cmd_run(args: argparse.Namespace) -> int:
    from camgen.pipeline import run_scene
    from camgen.progress import TerminalProgress

    only = [f.strip() for f in args.only.split(",") if f.strip()] if args.only is not None else None
    progress = TerminalProgress(enabled=not args.quiet)
    try:
        result = run_scene(_scene(args.scene), args.outdir, only, progress)
    finally:
        progress.close()
    if not args.quiet:
        target = f"{args.outdir}/{result.scene.name}"
        for name in result.files:
            print(f"{target}/{name}")
    return _report_failures(result)


def _cmd_check(args: argparse.Namespace) -> int:
    from camgen.pipeline import Plan, compute

    scene = _scene(args.scene)
    result = compute(scene, Plan((), frozenset(), full_report=False))
    rows = [("cam", "check", "result", "value", "limit", "unit")]
    shown = {"pass": "pass", "fail": "FAIL", "info": "info"}
    for cam in result.cams:
        for c in cam.checks:
            value = f"{c.value:.6g}" if isinstance(c.value, float) else str(c.value)
            limit = "none" if c.limit is None else f"{c.comparison} {c.limit:.6g}" if isinstance(c.limit, float) else f"{c.comparison} {c.limit}"
            rows.append((cam.name, c.name, shown[c.status], value, limit, c.unit))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    for row in rows:
        print("  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip())
    return _report_failures(result)


def _cmd_templates(args: argparse.Namespace) -> int:
    from camgen.scene import template_names, template_path

    names = template_names()
    width = max(len(n) for n in names)
    for name in names:
        first = next((line.lstrip("# ").strip() for line in template_path(name).read_text(encoding="utf-8").splitlines()
                      if line.startswith("#")), "")
        print(f"{name.ljust(width)}  {first}")
    return 0


def _cmd_new(args: argparse.Namespace) -> int:
    from pathlib import Path

    from camgen.errors import SceneError
    from camgen.scene import template_path

    source = template_path(args.template)
    dest = Path(args.dest) if args.dest else Path(f"{args.template}.toml")
    if dest.is_dir():
        dest = dest / f"{args.template}.toml"
    data = source.with_suffix(".csv")  # a template's table (lift_table.csv), named in it relative to the scene
    data_dest = dest.parent / data.name
    for path in (dest, data_dest) if data.is_file() else (dest,):
        if path.exists():
            raise SceneError(f"'{path}' exists already: camgen new does not overwrite files")
    from camgen.export.atomic import write_atomic

    write_atomic(dest, source.read_text(encoding="utf-8"))
    if data.is_file():
        write_atomic(data_dest, data.read_text(encoding="utf-8"))
        print(f"{data_dest}: copied from template '{args.template}' (the scene reads it)")
    print(f"{dest}: copied from template '{args.template}'; run it with: camgen run {dest}")
    return 0


def _cmd_keys(args: argparse.Namespace) -> int:
    from camgen.errors import ParameterError
    from camgen.keyref import reference, sections

    if args.section is not None and args.section not in sections():
        raise ParameterError("keys", args.section, "one of " + ", ".join(sections()))
    sys.stdout.write(reference(args.section))
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="camgen", description="Cam profiles from required motion: synthesis, design checks, DXF/STL/STEP/G-code.",
        epilog="exit status: 0 all checks passed; 1 a design check failed; 2 bad input.\n"
               "'camgen COMMAND --help' shows each command's options and examples.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"camgen {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def command(name: str, help: str) -> argparse.ArgumentParser:
        return sub.add_parser(name, help=help, description=help, epilog=EXAMPLES[name], formatter_class=argparse.RawDescriptionHelpFormatter)

    run = command("run", "run a scene: synthesis, checks, and its output files")
    run.add_argument("scene", nargs="?", help="scene file (TOML); default: the bundled default scene")
    run.add_argument("-o", "--outdir", default="outputs", help="output folder (default: outputs); files go to OUTDIR/<scene name>/")
    run.add_argument("--only", metavar="FORMATS", help="write only these formats, comma-separated (e.g. dxf,ngc); report.json is always written")
    run.add_argument("-q", "--quiet", action="store_true", help="print no file list and no progress")
    run.set_defaults(func=_cmd_run)
    check = command("check", "synthesis and design checks of a scene, as a table; writes nothing")
    check.add_argument("scene", nargs="?", help="scene file (TOML); default: the bundled default scene")
    check.set_defaults(func=_cmd_check)
    templates = command("templates", "list the bundled template scenes")
    templates.set_defaults(func=_cmd_templates)
    new = command("new", "copy a bundled template scene to start a design")
    new.add_argument("template", help="template name (see camgen templates)")
    new.add_argument("dest", nargs="?", help="destination file or folder (default: ./TEMPLATE.toml)")
    new.set_defaults(func=_cmd_new)
    keys = command("keys", "the scene-key reference: type, range, default and what each key changes")
    keys.add_argument("section", nargs="?", help="a cam kind, output, machining or a mechanism (default: all)")
    keys.set_defaults(func=_cmd_keys)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except CamgenError as exc:
        text = " ".join(str(exc).split())  # one line, whatever the message holds
        print(f"camgen: error: {text}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
