"""Run every benchmark and write benchmarks/RESULTS.md (and the summary block of README.md).

    python benchmarks/run_all.py            # with camgen installed (pip install -e ".[test]")
    python benchmarks/run_all.py --only bench_sweep,bench_evaluate   # re-run these, keep the others' tables


Each ``bench_*.py`` runs in its own process; its printed tables go into RESULTS.md under its
name, with the commit it was measured at (``--only``: the named scripts are re-run, the other
sections are kept as they were measured).  The header names the machine, the commit and the SHA-256 of the benchmark sources: a test
(tests/test_benchmarks.py) checks that RESULTS.md was produced by the current scripts and
that README.md's block between the ``benchmarks:summary`` markers is the summary written here.
"""
from __future__ import annotations

import hashlib
import re
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
#: The order of the sections (the others follow alphabetically).
ORDER = ("bench_cli", "bench_three_arc", "bench_tricycle", "bench_motion_laws", "bench_peers", "bench_horse_leg",
         "bench_exports", "bench_scaling", "bench_report", "bench_step", "bench_refusals", "bench_evaluate")
START, END = "<!-- benchmarks:summary:start -->", "<!-- benchmarks:summary:end -->"


def sources_digest(folder: Path = HERE) -> str:
    """SHA-256 over the benchmark sources (every .py in the folder, by name)."""
    digest = hashlib.sha256()
    for path in sorted(folder.glob("*.py")):
        digest.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def machine() -> str:
    sys.path.insert(0, str(HERE))
    from _common import machine as describe

    return describe()


def commit() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def _first_table(text: str) -> str:
    lines = text.splitlines()
    start = next((i for i, line in enumerate(lines) if line.startswith("|")), len(lines))
    end = next((i for i in range(start, len(lines)) if not lines[i].startswith("|")), len(lines))
    return "\n".join(lines[start:end])


def summary(sections: dict[str, str]) -> str:
    """The README's summary: the whole-process run times (bench_cli's first table) and camgen
    against the peers (bench_peers' table and its ratio line), as RESULTS.md has them."""
    cli = sections.get("bench_cli", "")
    peers = sections.get("bench_peers", "")
    ratio = next((line for line in peers.splitlines() if line.startswith("camgen / ")), "")
    return (f"Whole-process `camgen run` times (medians; targets of issue 13), from benchmarks/RESULTS.md:\n\n{_first_table(cli)}\n\n"
            f"camgen against the `mechanism` package on the same cam, in one run:\n\n{_first_table(peers)}\n\n{ratio}\n")


def _kept_sections() -> dict[str, str]:
    """The sections of the current RESULTS.md (name -> text), for ``--only``."""
    path = HERE / "RESULTS.md"
    if not path.is_file():
        return {}
    text = path.read_text(encoding="utf-8").split("\n## Summary\n")[0]
    header = re.search(r"; commit (\w+)", text)
    parts = re.split(r"^## (bench_\w+)\n\n", text, flags=re.M)
    out = {}
    for i in range(1, len(parts) - 1, 2):
        body = parts[i + 1].rstrip()
        if not body.startswith("Measured at commit") and header:  # written by a whole run: the header's commit
            body = f"Measured at commit {header.group(1)}.\n\n{body}"
        out[parts[i]] = body
    return out


def main() -> None:
    scripts = sorted(HERE.glob("bench_*.py"), key=lambda p: (ORDER.index(p.stem) if p.stem in ORDER else len(ORDER), p.stem))
    only = None
    if len(sys.argv) == 3 and sys.argv[1] == "--only":
        only = set(sys.argv[2].split(","))
        unknown = only - {p.stem for p in scripts}
        if unknown:
            sys.exit(f"run_all.py: no benchmark named {', '.join(sorted(unknown))}")
    kept = _kept_sections() if only is not None else {}
    sections: dict[str, str] = {}
    for script in scripts:
        if only is not None and script.stem not in only and script.stem in kept:
            sections[script.stem] = kept[script.stem]
            continue
        start = time.perf_counter()
        proc = subprocess.run([sys.executable, str(script)], cwd=HERE, capture_output=True, text=True)
        took = time.perf_counter() - start
        body = proc.stdout.strip() if proc.returncode == 0 else f"FAILED (exit {proc.returncode}):\n{proc.stderr[-2000:]}"
        sections[script.stem] = f"Measured at commit {commit()}.\n\n{body}"
        print(f"{script.name}: {took:.0f} s{'' if proc.returncode == 0 else ' FAILED'}", flush=True)
    head = [
        "# camgen benchmark results",
        "",
        f"Written by `benchmarks/run_all.py` on {machine()}; commit {commit()}"
        + (f" (re-run: {', '.join(sorted(only))}; each section names the commit it was measured at)." if only else "."),
        f"Benchmark sources SHA-256: `{sources_digest()}`",
        "",
        "Times are medians of repeated runs measured in one process per script (ratios within a table are measured in one run).",
        "",
    ]
    body = [f"## {name}\n\n{text}\n" for name, text in sections.items()]
    summary_text = summary(sections)
    (HERE / "RESULTS.md").write_text("\n".join(head) + "\n".join(body) + f"\n## Summary\n\n{summary_text}", encoding="utf-8")
    readme = ROOT / "README.md"
    text = readme.read_text(encoding="utf-8")
    if START in text and END in text:
        text = re.sub(re.escape(START) + ".*?" + re.escape(END), f"{START}\n{summary_text}{END}", text, flags=re.S)
        readme.write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()
