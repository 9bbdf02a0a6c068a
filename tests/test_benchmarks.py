"""benchmarks/RESULTS.md was written by the current benchmark scripts, and README.md quotes it.

The benchmarks live in the checkout beside the tests, not in the installed package.
"""
from __future__ import annotations

import hashlib
import re
from pathlib import Path

from helpers import tree  # noqa: F401  (fixture)


def _digest(folder: Path) -> str:
    """The same digest as benchmarks/run_all.py's sources_digest, computed here independently."""
    digest = hashlib.sha256()
    for path in sorted(folder.glob("*.py")):
        digest.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def test_results_were_written_by_the_current_benchmarks(tree):
    results = (tree / "benchmarks" / "RESULTS.md").read_text(encoding="utf-8")
    match = re.search(r"Benchmark sources SHA-256: `([0-9a-f]{64})`", results)
    assert match, "RESULTS.md has no sources digest: run python benchmarks/run_all.py"
    assert match.group(1) == _digest(tree / "benchmarks"), "the benchmarks changed since RESULTS.md was written: run python benchmarks/run_all.py"
    scripts = sorted(p.stem for p in (tree / "benchmarks").glob("bench_*.py"))
    assert [name for name in scripts if f"## {name}\n" not in results] == []
    assert "FAILED (exit" not in results


def test_readme_quotes_the_results(tree):
    results = (tree / "benchmarks" / "RESULTS.md").read_text(encoding="utf-8")
    readme = (tree / "README.md").read_text(encoding="utf-8")
    block = re.search(r"<!-- benchmarks:summary:start -->\n(.*?)<!-- benchmarks:summary:end -->", readme, re.S)
    assert block, "README.md has no benchmarks:summary block"
    assert results.rstrip().endswith(block.group(1).rstrip())
