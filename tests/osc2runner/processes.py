"""Helpers of the tests that start a real ``osc2run`` and signal it."""

from __future__ import annotations

import os
import subprocess
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
POSIX = pytest.mark.skipif(os.name != "posix", reason="POSIX signals")


def env() -> dict[str, str]:
    """The environment of a child ``python -m osc2runner``: this checkout importable."""
    path = os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])
    return dict(os.environ, PYTHONPATH=path)


def wait_for(path: Path, marker: str, proc: subprocess.Popen, deadline: float = 120.0) -> None:
    """Poll ``path`` until it contains ``marker`` (the process is still running then)."""
    end = time.monotonic() + deadline
    while marker not in path.read_text(errors="replace"):
        if proc.poll() is not None:
            pytest.fail(f"osc2run ended before {marker!r}: {path.read_text()[-2000:]}")
        if time.monotonic() > end:
            proc.kill()
            pytest.fail(f"no {marker!r} from osc2run within {deadline:g} s")
        time.sleep(0.05)
