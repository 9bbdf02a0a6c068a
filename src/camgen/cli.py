"""Command line: ``camgen run [SCENE] [-o OUTDIR]``.

Only argparse is imported at start-up; each subcommand imports what it needs.
User errors (:class:`~camgen.errors.CamgenError`) print one line and exit with status 2.
"""
from __future__ import annotations

import argparse
import sys
from typing import Sequence

from camgen import __version__
from camgen.errors import CamgenError


def _cmd_run(args: argparse.Namespace) -> int:
    from camgen.pipeline import run_scene
    from camgen.scene import load_scene, load_template

    scene = load_scene(args.scene) if args.scene else load_template("default")
    paths = run_scene(scene, args.outdir)
    for path in paths:
        print(path)
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="camgen", description="Cam profiles from required motion, checked and exported.")
    parser.add_argument("--version", action="version", version=f"camgen {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run a scene file and write its outputs")
    run.add_argument("scene", nargs="?", help="scene file (TOML); default: the bundled templates/default.toml")
    run.add_argument("-o", "--outdir", default="outputs", help="output folder (default: outputs); files go to OUTDIR/<scene>/")
    run.set_defaults(func=_cmd_run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except CamgenError as exc:
        print(f"camgen: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
