"""The ``camgen tolerance`` command (its options: :func:`camgen.cli.build_parser`): read, study,
write, say the verdict (exit 0 / 1; bad input 2)."""
from __future__ import annotations

import argparse
import sys

from camgen.errors import ParameterError

__all__ = ["percentile_of", "run"]

def run(args: argparse.Namespace) -> int:
    """Run the study the parsed command line asks; the exit status."""
    from pathlib import Path

    from camgen.scene import load_scene
    from camgen.staging import preflight, write_run
    from camgen.study.tolerance import study, study_files
    from camgen.study.tolerance_settings import ToleranceOptions

    if not args.outdir.strip():
        raise ParameterError("-o/--outdir", args.outdir, "a folder path (default: outputs)")
    if not str(args.scene).strip():
        raise ParameterError("SCENE", args.scene, "the path of a scene file (TOML)")
    target = Path(args.outdir) / f"{load_scene(args.scene).name}-tolerance"
    preflight(target)
    options = ToleranceOptions(args.cam, args.samples, args.seed, args.percentile, tuple(args.error))
    from camgen.progress import TerminalProgress

    display = TerminalProgress(enabled=not args.quiet)
    try:
        result = study(args.scene, options, display)
        display("writing files")
        written = write_run(target, study_files(result))
    finally:
        display.close()
    if written.leftover is not None:
        print(f"camgen: warning: the previous study could not be removed from '{written.leftover}'", file=sys.stderr)
    p = result.settings.percentile
    for c in result.failed:
        print(f"camgen: check failed: cams.{result.cam}: {c.name} at the {p:g}th percentile = {c.at_percentile.value:.6g} {c.unit}, "
              f"must be <= {c.limit:.6g} {c.unit} (nominal {c.nominal:.6g})", file=sys.stderr)
    if not args.quiet:
        for name in ("tolerance.json", "tolerance.csv", "report.json"):
            print(f"{target}/{name}")
        worst = float(result.max_error.max())
        at = percentile_of(result.max_error, p)
        state = "FAILED" if result.failed else "passed"
        print(f"camgen: {state}: {result.settings.samples} samples; motion error p{p:g} = {at:.4g} {result.unit}, max {worst:.4g} {result.unit}; "
              f"{len(result.checks) - len(result.failed)} of {len(result.checks)} checks pass at the {p:g}th percentile")
    return 1 if result.failed else 0


def percentile_of(values: object, p: float) -> float:
    """The ``p``-th percentile of ``values`` (numpy's linear), as a float."""
    import numpy as np

    return float(np.percentile(np.asarray(values, dtype=float), p))
