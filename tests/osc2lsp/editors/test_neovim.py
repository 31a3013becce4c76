"""A scripted headless Neovim session (Debian's 0.7.2 is the oldest supported): push
diagnostics after Neovim's own incremental edits, with characters that
``str.splitlines()`` would break at; formatting with Neovim's default options
(tabs of width 8) keeps the file's spaces; the server stops with the session.

Skipped when ``nvim`` is not installed (``apt-get install neovim``).
"""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from tests.osc2lsp.editors.sessions import TEXT, edits, expected, run_session
from tests.osc2lsp.lsp_helpers import REPO

NVIM = shutil.which("nvim")
SCRIPT = REPO / "tests" / "osc2lsp" / "editors" / "nvim_session.lua"


def _version() -> tuple[int, ...]:
    if NVIM is None:
        return ()
    first = subprocess.run([NVIM, "--version"], capture_output=True, text=True).stdout
    found = re.search(r"NVIM v(\d+)\.(\d+)", first)
    return tuple(int(n) for n in found.groups()) if found else ()


pytestmark = pytest.mark.skipif(_version() < (0, 7), reason="needs Neovim 0.7 or newer")


def _byte_position(text: str, offset: int) -> tuple[int, int]:
    """Neovim's (row, byte column) of a code-point offset (lines split at LF only)."""
    before = text[:offset]
    row = before.count("\n")
    column = len(before[before.rfind("\n") + 1 :].encode("utf-8"))
    return row, column


def test_a_neovim_session(tmp_path):
    path = tmp_path / "session.osc"
    path.write_text(TEXT, encoding="utf-8")
    made, text = edits()
    nvim_edits = []
    for start, end, new, before in made:
        (r1, c1), (r2, c2) = _byte_position(before, start), _byte_position(before, end)
        nvim_edits.append([r1, c1, r2, c2, new.split("\n")])
    spec = {
        "file": str(path),
        "edits": nvim_edits,
        "expected_before": expected(str(path), TEXT, utf8_columns=True),
        "expected_after": expected(str(path), text, utf8_columns=True),
    }
    assert NVIM is not None
    neovim = [NVIM, "--headless", "-n", "-i", "NONE", "-u", str(SCRIPT)]
    result = run_session(neovim, tmp_path, spec)
    assert result["text"] + "\n" == text  # the buffer is the text the edits describe
    assert [code for _, _, code, _ in spec["expected_after"]] == ["N101"]
    assert result["before"] == spec["expected_before"]
    assert result["after"] == spec["expected_after"]
    assert result["format_options"] == {"insertSpaces": False, "tabSize": 8}
    assert "\t" not in result["formatted"]
    assert "\n    hero: vehicle\n" in result["formatted"]
    assert result["stopped"]
