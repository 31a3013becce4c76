"""``coverage.json``: the run's coverage items and every sample (§7.5).

The document is :meth:`osc2runner.execution.coverage.RunCoverage.to_json`
(its layout is described in docs/runner.md, "Coverage"), written whole or not
at all (:func:`osc2runner.output.files.write_atomically`). :func:`read_coverage`
reads one back, for campaigns that aggregate runs.
"""

from __future__ import annotations

import json
from pathlib import Path

from osc2runner.execution.coverage import RunCoverage
from osc2runner.output.files import write_atomically

__all__ = ["COVERAGE_FILE", "read_coverage", "write_coverage"]

COVERAGE_FILE = "coverage.json"


def write_coverage(folder: Path, coverage: RunCoverage) -> Path:
    """Write ``coverage.json`` into the folder ``folder``; returns its path."""
    text = json.dumps(coverage.to_json(), indent=2, allow_nan=False) + "\n"
    return write_atomically(folder / COVERAGE_FILE, text)


def read_coverage(path: str | Path) -> RunCoverage:
    """The coverage of a run from its ``coverage.json`` (or the folder holding it)."""
    target = Path(path)
    if target.is_dir():
        target = target / COVERAGE_FILE
    return RunCoverage.from_json(json.loads(target.read_text(encoding="utf-8")))
