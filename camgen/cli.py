"""Command line: ``camgen run | check | templates | new | keys | sweep | tolerance | optimize | serve``.

Only argparse is imported at start-up; each command imports what it needs.  Exit status
(:data:`EXIT_STATUS`): 0 every check passed; 1 a design check failed (``run`` writes the report
showing it and no manufacturing file for a cam that cannot be made; one line per failed check on
stderr); 2 bad input (one ``camgen: error: ...`` line naming the key, nothing written); 70 an
internal error, a bug (one line; the details go to a crash file it names); 130 / 143 stopped by
SIGINT (Ctrl-C) / SIGTERM (one line; the previous outputs whole).  Never a traceback.
"""
from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING, NoReturn, Sequence

from camgen import __version__
from camgen.errors import CamgenError, ParameterError

if TYPE_CHECKING:
    from camgen.checks import CheckResult
    from camgen.results import RunResult
    from camgen.scene import Scene

__all__ = [
    "EXAMPLES", "EXIT_BAD_INPUT", "EXIT_BROKEN_PIPE", "EXIT_CHECK_FAILED", "EXIT_INTERNAL_ERROR", "EXIT_PASSED",
    "EXIT_STATUS", "build_parser", "entry", "main",
]

#: The run folders this command has written (a signal after that does not undo them).
_WRITTEN: list[str] = []

#: Exit statuses (README "Command line and exit status").
EXIT_PASSED, EXIT_CHECK_FAILED, EXIT_BAD_INPUT = 0, 1, 2
#: An unexpected exception: a bug in camgen (sysexits.h EX_SOFTWARE), never a design verdict.
EXIT_INTERNAL_ERROR = 70
#: A write to a closed pipe (``camgen keys | head``): 128 + SIGPIPE, as a shell reports it.
EXIT_BROKEN_PIPE = 141
EXIT_STATUS = {EXIT_PASSED: "every check passed", EXIT_CHECK_FAILED: "a design check failed", EXIT_BAD_INPUT: "bad input",
               EXIT_INTERNAL_ERROR: "an internal error (a bug)", 130: "stopped by SIGINT (Ctrl-C)", 143: "stopped by SIGTERM",
               EXIT_BROKEN_PIPE: "the output pipe was closed"}

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
    "tolerance": """examples:
  camgen tolerance cam.toml --error roller_radius_mm=normal:0.01 --error phase_deg=uniform:-0.2:0.2
  camgen tolerance cam.toml --samples 5000 --seed 3       the errors of the scene's [tolerance.errors] table
exit status: 0 the checks pass at the percentile; 1 one fails there; 2 bad input""",
    "optimize": """examples:
  camgen optimize plate_cam.toml --vary base_radius_mm=20:45 --minimize outer_radius_mm
                                              the smallest plate cam whose every check passes
  camgen optimize my_cam.toml --vary cams.a.base_radius_mm=30:60 --vary cams.a.follower_offset_mm=0:10 \\
      --minimize fig.a.torque_peak_n_m --method de --seed 1 --max-evaluations 200 -o build""",
    "serve": """examples:
  camgen serve                                the bundled default scene at http://127.0.0.1:8765/
  camgen serve my_cam.toml --port 8800        edit my_cam.toml in the browser (Save gives the edited TOML)""",
    "sweep": """examples:
  camgen sweep plate_cam.toml --vary base_radius_mm=30:60:5 --vary roller_radius_mm=8,10,12
  camgen sweep plate_cam.toml --vary base_radius_mm=30:60 --method lhs --samples 1000 --workers 2
  camgen sweep plate_cam.toml --points designs.parquet --cluster tcp://10.0.0.5:8786
  camgen sweep plate_cam.toml --vary base_radius_mm=30:60:1 --resume      continue a stopped sweep""",
}


def _scene(path: str | None, only: "list[str] | None" = None) -> "Scene":
    """The scene at ``path`` (None: the bundled default), read for a run restricted to ``only``."""
    from camgen.scene import load_scene, load_template

    if path is None:
        return load_template("default", only)
    if not path.strip():
        raise ParameterError("SCENE", path, "the path of a scene file (TOML); give none for the bundled default scene")
    return load_scene(path, only=only)


def _number(value: object) -> str:
    """A check's value or limit as the table and the failure lines print it."""
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, (list, tuple)):
        return ", ".join(_number(v) for v in value)
    return str(value)


def _where(check: "CheckResult") -> str:
    """The cam angles a check names, as ``12.5, 30 deg`` (a linear cam's travel: ``mm``; at most
    six, then how many more)."""
    angles = check.where_deg
    if not angles:
        return ""
    shown = ", ".join(f"{w:g}" for w in angles[:6]) + (f" and {len(angles) - 6} more" if len(angles) > 6 else "")
    return f"{shown} {check.where_unit}"


def _report_failures(result: "RunResult") -> int:
    failed = result.failed_checks()
    for cam, check in failed:
        where = f" at {_where(check)}" if check.where_deg else ""
        if check.comparison:  # a measured value against its limit
            unit = " " + check.unit if check.unit else ""
            what = f"{check.name} = {_number(check.value)}{unit}, must be {check.comparison} {_number(check.limit)}{where}"
        else:  # an output that could not be made (an export check): its note says why
            what = f"{check.name}: {check.note}"
        print(f"camgen: check failed: cams.{cam}: {what}" + (" (no manufacturing file written for this cam)" if check.blocks_manufacture else ""),
              file=sys.stderr)
    return EXIT_CHECK_FAILED if failed else EXIT_PASSED


def _verdict(result: "RunResult") -> str:
    """The last line of a run or check: how many checks passed or failed, over how many cams."""
    checks = [c for cam in result.cams for c in cam.checks]
    limited = [c for c in checks if c.passed is not None]
    failed = sum(c.failed for c in limited)
    cams = f"{len(result.cams)} cam{'s' if len(result.cams) != 1 else ''}"
    if failed:
        return f"camgen: FAILED: {failed} of {len(limited)} checks with a limit failed ({cams}; the lines above name them)"
    return f"camgen: passed: all {len(limited)} checks with a limit passed ({cams}; {len(checks) - len(limited)} more are information)"


def _cmd_run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from camgen.interrupt import checkpoint
    from camgen.pipeline import execute, plan_run
    from camgen.progress import TerminalProgress
    from camgen.staging import preflight, write_run

    only = [f.strip() for f in args.only.split(",") if f.strip()] if args.only is not None else None
    if not args.outdir.strip():
        raise ParameterError("-o/--outdir", args.outdir, "a folder path (default: outputs)")
    scene = _scene(args.scene, only)
    plan = plan_run(scene, only)
    target = Path(args.outdir) / scene.name
    preflight(target)  # before anything is computed: the folder must be able to take the run
    display = TerminalProgress(enabled=not args.quiet)

    def progress(step: str) -> None:
        checkpoint()  # a signal a library swallowed on the way still stops the run
        display(step)

    try:
        result = execute(scene, plan, progress)
        progress("writing files")
        written = write_run(target, result.files)
        _WRITTEN.append(str(target))
    finally:
        display.close()
    if written.leftover is not None:
        print(f"camgen: warning: the previous run could not be removed from '{written.leftover}' (the next run of this scene "
              "removes it)", file=sys.stderr)
    status = _report_failures(result)
    if not args.quiet:
        for name in result.files:
            print(f"{target}/{name}")
        print(_verdict(result))
    return status


def _cmd_check(args: argparse.Namespace) -> int:
    """Everything ``run`` does but writing: the same refusals, the same checks and export checks."""
    from camgen.interrupt import checkpoint
    from camgen.pipeline import execute, plan_run

    scene = _scene(args.scene)
    result = execute(scene, plan_run(scene), lambda step: checkpoint())
    rows = [("cam", "check", "result", "value", "limit", "unit", "where")]
    shown = {"pass": "pass", "fail": "FAIL", "info": "info"}
    for cam in result.cams:
        for c in cam.checks:
            limit = "" if c.limit is None else f"{c.comparison} {_number(c.limit)}"
            rows.append((cam.name, c.name, shown[c.status], _number(c.value), limit, c.unit, _where(c)))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    for row in rows:
        print("  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip())
    status = _report_failures(result)
    print(_verdict(result))
    return status


def _cmd_sweep(args: argparse.Namespace) -> int:
    from camgen.study.sweep import sweep_command

    return sweep_command(args)


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


def _cmd_tolerance(args: argparse.Namespace) -> int:
    from camgen.study.tolerance_command import run

    return run(args)


def _cmd_optimize(args: argparse.Namespace) -> int:
    from camgen.study.optimize import optimize_command

    return optimize_command(args.scene, args.vary, args.minimize, args.maximize, args.method, args.seed,
                            args.max_evaluations, args.outdir, args.quiet)
def _cmd_serve(args: argparse.Namespace) -> int:
    from camgen.serve.server import serve

    return serve(args.scene, args.host, args.port, args.allow_remote)


class _Parser(argparse.ArgumentParser):
    """argparse with camgen's one-line errors (argparse prints the usage and exits 2 itself)."""

    def error(self, message: str) -> "NoReturn":
        raise _UsageError(f"{message} (see '{self.prog} --help')")


class _UsageError(CamgenError):
    """A command line argparse cannot parse."""


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="camgen", description="Cam profiles from required motion: synthesis, design checks, DXF/STL/STEP/G-code.",
        epilog="exit status: 0 all checks passed; 1 a design check failed; 2 bad input; 70 an internal error (a bug);\n"
               "130/143 stopped by SIGINT/SIGTERM.  'camgen COMMAND --help' shows each command's options and examples.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"camgen {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def command(name: str, help: str) -> argparse.ArgumentParser:
        return sub.add_parser(name, help=help, description=help, epilog=EXAMPLES[name], formatter_class=argparse.RawDescriptionHelpFormatter)

    run = command("run", "run a scene: synthesis, checks, and its output files")
    run.add_argument("scene", nargs="?", help="scene file (TOML); default: the bundled default scene")
    run.add_argument("-o", "--outdir", default="outputs", help="output folder (default: outputs); files go to OUTDIR/<scene name>/")
    run.add_argument("--only", metavar="FORMATS", help="write only these formats, comma-separated (e.g. dxf,ngc); report.json is always written")
    run.add_argument("-q", "--quiet", action="store_true", help="print no file list, no verdict line and no progress")
    run.set_defaults(func=_cmd_run)
    check = command("check", "synthesis, design checks and export checks of a scene, as a table; writes nothing")
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
    tol = command("tolerance", "Monte Carlo of manufacturing and assembly errors: the follower motion error and check margins")
    tol.add_argument("scene", help="scene file (TOML)")
    tol.add_argument("--cam", help="the cam to study (needed when the scene has more than one it can study)")
    tol.add_argument("--error", action="append", default=[], metavar="NAME=DIST",
                     help="an error and its distribution: normal:SIGMA, normal:MEAN:SIGMA or uniform:A:B (repeatable)")
    tol.add_argument("--samples", type=int, help="Monte Carlo samples, 10 to 20000 (default 1000)")
    tol.add_argument("--seed", type=int, help="random seed (default 0)")
    tol.add_argument("--percentile", type=float, help="the checks must pass at this percentile, 50 <= p < 100 (default 95)")
    tol.add_argument("-o", "--outdir", default="outputs", help="output folder; files go to OUTDIR/<scene name>-tolerance/")
    tol.add_argument("-q", "--quiet", action="store_true", help="print no file list and no verdict line")
    tol.set_defaults(func=_cmd_tolerance)
    opt = command("optimize", "the design minimising a figure over scene-key ranges with every check passing; writes and runs it")
    opt.add_argument("scene", nargs="?", help="scene file (TOML); default: the bundled default scene")
    opt.add_argument("--vary", action="append", metavar="KEY=LOW:HIGH", help="a scene key and its bounds (repeat for more keys)")
    goal = opt.add_mutually_exclusive_group()
    goal.add_argument("--minimize", metavar="FIGURE", help="a main figure (outer_radius_mm, torque_peak_n_m, ...; "
                      "fig.<cam>.<figure>) or a check's value (check.<cam>.<check>)")
    goal.add_argument("--maximize", metavar="FIGURE", help="the same, maximised")
    opt.add_argument("--method", default="de", help="de (differential evolution, then COBYLA; default) or cobyla (local)")
    opt.add_argument("--seed", type=int, default=0, help="the optimiser's seed (default 0: the same seed, the same designs)")
    opt.add_argument("--max-evaluations", type=int, default=400, help="designs evaluated at most (default 400)")
    opt.add_argument("-o", "--outdir", default="outputs", help="output folder (default: outputs); files go to OUTDIR/<scene name>-optimum/")
    opt.add_argument("-q", "--quiet", action="store_true", help="print no file list and no optimum line")
    opt.set_defaults(func=_cmd_optimize)
    serve = command("serve", "the live design page: edit a scene in the browser, see its checks and plots (a local server)")
    serve.add_argument("scene", nargs="?", help="scene file (TOML); default: the bundled default scene")
    serve.add_argument("--port", type=int, default=8765, help="TCP port (default 8765; 0: any free port)")
    serve.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1; others need --allow-remote)")
    serve.add_argument("--allow-remote", action="store_true", help="allow a --host that is not loopback (no authentication: "
                       "anyone who reaches the port can use the server)")
    serve.set_defaults(func=_cmd_serve)
    sweep = command("sweep", "evaluate a scene over many values of its keys: one row per design (README: Design sweeps)")
    sweep.add_argument("scene", nargs="?", help="scene file (TOML); default: the bundled default scene; its [sweep] table "
                       "gives defaults for the options below")
    sweep.add_argument("--vary", action="append", metavar="KEY=SPEC", help="a key and its values: low:high:step (grid), "
                       "low:high (sampled) or v1,v2,...; repeat for more keys")
    sweep.add_argument("--method", choices=["grid", "lhs", "sobol"], help="the points: every combination (default when "
                       "every key has a step or values), a Latin hypercube or a Sobol sequence")
    sweep.add_argument("--samples", type=int, help="points of an lhs or sobol design")
    sweep.add_argument("--seed", type=int, help="the sampler's seed (default 0)")
    sweep.add_argument("--points", metavar="FILE", help="the points from a .csv or .parquet file, one column per key")
    sweep.add_argument("--workers", type=int, help="local Dask worker processes (default 1: in this process)")
    sweep.add_argument("--cluster", metavar="ADDRESS", help="a Dask scheduler's address (tcp://host:port, tls://...; "
                       "default: $DASK_SCHEDULER_ADDRESS when --workers is not given)")
    sweep.add_argument("--batch", type=int, help="points per task (default: from a measured evaluation)")
    sweep.add_argument("--dashboard", action="store_true", help="the local cluster's Dask dashboard on 127.0.0.1:8787")
    sweep.add_argument("--resume", action="store_true", help="continue the sweep in the results folder: only missing points")
    sweep.add_argument("-o", "--outdir", default="outputs", help="output folder (default: outputs); results go to "
                       "OUTDIR/<scene name>-sweep/")
    sweep.add_argument("--map", metavar="KEY,KEY", help="report.html's feasibility map: two varied keys (default: the first two)")
    sweep.add_argument("--pareto", metavar="FIG,FIG", help="report.html's Pareto front of two figures, both minimised ('-FIG': "
                       "maximised; default: outer_radius_mm,pressure_angle_deg)")
    sweep.add_argument("--rank", metavar="FIG", help="the figure ranking the best designs (default: outer_radius_mm, smallest first)")
    sweep.add_argument("--best", type=int, default=10, help="the best designs listed in report.html with their scenes in best/ "
                       "(default 10)")
    sweep.add_argument("--keep-files", type=int, default=0, metavar="N", help="run the best N designs as camgen run does, "
                       "into best/<key>/ (default 0)")
    sweep.add_argument("-q", "--quiet", action="store_true", help="no progress and no summary lines")
    sweep.set_defaults(func=_cmd_sweep)
    return parser


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _say(line: str) -> None:
    """One line on stderr, in UTF-8 whatever the locale: a file name an ASCII locale decoded to
    surrogates is written back as its own bytes (the terminal shows it as the user typed it)."""
    try:
        buffer = sys.stderr.buffer
    except AttributeError:  # a text-only stream (a test's capture)
        print(line, file=sys.stderr)
        return
    try:
        sys.stderr.flush()
        buffer.write(line.encode("utf-8", "surrogateescape") + b"\n")
        buffer.flush()
    except (OSError, ValueError):  # no stderr to write to: nothing more can be said
        pass


def _crash_file(exc: BaseException, argv: Sequence[str]) -> str:
    """Write the details of an unexpected exception to a crash file; return where it went."""
    import datetime
    import os
    import platform
    import tempfile
    import traceback
    from pathlib import Path

    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%dT%H%M%SZ")
    text = (f"camgen {__version__} internal error, {stamp}\npython {platform.python_version()} on {platform.platform()}\n"
            f"command: camgen {' '.join(argv)}\ncurrent folder: {os.getcwd()}\n\n"
            + "".join(traceback.format_exception(type(exc), exc, exc.__traceback__)))
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    for folder in (Path(cache) / "camgen", Path(tempfile.gettempdir())):
        try:
            folder.mkdir(parents=True, exist_ok=True)
            path = folder / f"camgen-crash-{stamp}-{os.getpid()}.txt"
            path.write_text(text, encoding="utf-8")
            return f"the details are in {path}"
        except OSError:
            continue
    return "the details could not be saved (no writable cache or temp folder)"


def entry() -> None:
    """The ``camgen`` program (console script and ``python -m camgen``): :func:`main`, then exit."""
    sys.exit(main(exiting=True))


def main(argv: Sequence[str] | None = None, exiting: bool = False) -> int:
    """Run the command line ``argv`` (default: the program's arguments); return the exit status.

    ``exiting``: the process exits right after (signals are then ignored, not handed back).
    """
    from camgen.interrupt import Interrupted, checkpoint, handling, received, signal_name

    argv = list(sys.argv[1:] if argv is None else argv)
    _WRITTEN.clear()

    def stopped(signum: int) -> int:
        state = (f"the run had been written into '{_WRITTEN[-1]}'" if _WRITTEN else "the previous outputs are as they were")
        _say(f"camgen: stopped by {signal_name(signum)}; {state}")
        return 128 + signum

    with handling(exiting):
        try:
            args = build_parser().parse_args(argv)
            status = args.func(args)
            sys.stdout.flush()
            checkpoint()  # a signal during the last step
            return int(status)
        except Interrupted as exc:
            return stopped(exc.signum)
        except CamgenError as exc:
            if received() is not None:  # an error the signal caused (a library's import cut short)
                return stopped(received() or 0)
            _say(f"camgen: error: {_one_line(str(exc))}")
            return EXIT_BAD_INPUT
        except BrokenPipeError:
            import os

            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # Python's own flush at exit must not fail again
            return EXIT_BROKEN_PIPE
        except Exception as exc:  # anything else is a bug in camgen, never a design verdict
            if received() is not None:
                return stopped(received() or 0)
            where = _crash_file(exc, argv)
            _say(f"camgen: internal error (a bug in camgen, not a verdict on the design): {type(exc).__name__}: "
                 f"{_one_line(str(exc))[:200]}; {where}; please report it with the scene")
            return EXIT_INTERNAL_ERROR


if __name__ == "__main__":  # pragma: no cover
    entry()
