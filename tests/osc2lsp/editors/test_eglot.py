"""A scripted batch Emacs session with Eglot (Debian's Emacs 28 and elpa-eglot 1.9):
push diagnostics after Eglot's own incremental edits, with characters that
``str.splitlines()`` would break at, placed where the checker reports them; one push
per version (Eglot used to receive two identical pushes on open); formatting with
Emacs' defaults (tabs of width 8) keeps the file's spaces; the server ends with the
session.

Skipped when ``emacs`` or its Eglot is not installed
(``apt-get install emacs-nox elpa-eglot``).
"""

from __future__ import annotations

import itertools
import shutil
import subprocess

import pytest

from tests.osc2lsp.editors.sessions import TEXT, edits, expected, run_session
from tests.osc2lsp.lsp_helpers import REPO
from tests.osc2lsp.protocol.raw_client import wait_gone

EMACS = shutil.which("emacs")
SCRIPT = REPO / "tests" / "osc2lsp" / "editors" / "eglot_session.el"


def _has_eglot() -> bool:
    if EMACS is None:
        return False
    probe = subprocess.run(
        [EMACS, "--batch", "--eval", "(require 'eglot)"],
        capture_output=True,
        stdin=subprocess.DEVNULL,
        check=False,
    )
    return probe.returncode == 0


pytestmark = pytest.mark.skipif(not _has_eglot(), reason="needs Emacs with Eglot")


def test_an_eglot_session(tmp_path):
    path = tmp_path / "session.osc"
    path.write_text(TEXT, encoding="utf-8")
    made, text = edits()
    spec = {
        "file": str(path),
        "edits": [[start, end, new] for start, end, new, _ in made],
        "expected_before": expected(str(path), TEXT, utf8_columns=False),
        "expected_after": expected(str(path), text, utf8_columns=False),
    }
    assert EMACS is not None
    result = run_session([EMACS, "--batch", "-l", str(SCRIPT)], tmp_path, spec)
    assert result["text"] == text  # the buffer is the text the edits describe
    assert [code for _, _, code, _ in spec["expected_after"]] == ["N101"]
    assert result["before"] == spec["expected_before"]
    assert result["after"] == spec["expected_after"]
    # One push on open, and none repeats the one before it.
    assert len(result["pushes_on_open"]) == 1
    pushes = [(p["version"], p["diagnostics"]) for p in result["pushes"]]
    assert pushes and all(a != b for a, b in itertools.pairwise(pushes))
    assert result["format_options"] == {"tabSize": 8, "insertSpaces": False}
    assert "\t" not in result["formatted"]
    assert "\n    hero: vehicle\n" in result["formatted"]
    assert result["stopped"] is True
    assert wait_gone(result["server_pid"], 30)
