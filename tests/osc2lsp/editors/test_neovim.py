"""A scripted headless Neovim session (Debian's 0.7.2 is the oldest supported): push
diagnostics after Neovim's own incremental edits, with characters that
``str.splitlines()`` would break at; formatting with Neovim's default options
(tabs of width 8) keeps the file's spaces; the server stops with the session.

Skipped when ``nvim`` is not installed (``apt-get install neovim``).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys

import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.config import Config
from tests.osc2lsp.lsp_helpers import REPO

NVIM = shutil.which("nvim")
SCRIPT = REPO / "tests" / "osc2lsp" / "editors" / "nvim_session.lua"

TEXT = (
    "# notes\f with\x0b separators\u2028 that are no\x85 line breaks\n"
    "import osc.standard\n"
    "scenario s:\n"
    "    hero: vehicle\n"
    "    x: int = 1\n"
)


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


def _edit(text: str, start: int, end: int, new: str) -> tuple[list, str]:
    (r1, c1), (r2, c2) = _byte_position(text, start), _byte_position(text, end)
    return [r1, c1, r2, c2, new.split("\n")], text[:start] + new + text[end:]


def _expected(path: str, text: str) -> list:
    """What the checker reports, as Neovim shows it: (row, byte column, code, message)."""
    analysis = analyze([SourceInput(path, text)], Config().analysis_options(verify=False))
    lines = text.split("\n")
    found = []
    for d in analysis.diagnostics:
        if d.span.uri == path:
            line = lines[d.span.line - 1]
            column = len(line[: d.span.column - 1].encode("utf-8"))
            found.append([d.span.line - 1, column, d.code.code, d.message])
    return sorted(found, key=lambda f: (f[0], f[1], f[2]))


def test_a_neovim_session(tmp_path):
    path = tmp_path / "session.osc"
    path.write_text(TEXT, encoding="utf-8")
    text, edits = TEXT, []
    for needle, new in (
        ("x: int = 1", "x: int = 1\n    do serial:\n        hreo.drive()"),
        (" with", " with\f\u2029 more"),
        ("hero: vehicle", "hero: vehicle\n    y: speed = 3kph"),
    ):
        at = text.index(needle)
        edit, text = _edit(text, at, at + len(needle), new)
        edits.append(edit)
    env = {"PYTHONPATH": os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH")) if p)}
    spec = {
        "cmd": [sys.executable, "-m", "osc2lsp"],
        "env": env,
        "root": str(tmp_path),
        "file": str(path),
        "init_options": {"osc2": {"verify": False, "diagnostics": {"debounce": 10}}},
        "edits": edits,
        "expected_before": _expected(str(path), TEXT),
        "expected_after": _expected(str(path), text),
        "timeout_ms": 30000,
        "result": str(tmp_path / "result.json"),
    }
    (tmp_path / "spec.json").write_text(json.dumps(spec), encoding="utf-8")
    home = tmp_path / "home"
    home.mkdir()
    run_env = dict(os.environ, OSC2LSP_SPEC=str(tmp_path / "spec.json"), HOME=str(home))
    run_env["XDG_CONFIG_HOME"] = run_env["XDG_DATA_HOME"] = str(home)
    run_env["XDG_STATE_HOME"] = run_env["XDG_CACHE_HOME"] = str(home)
    subprocess.run(
        [NVIM, "--headless", "-n", "-i", "NONE", "-u", str(SCRIPT)],
        env=run_env,
        timeout=180,
        check=False,
        stdin=subprocess.DEVNULL,
        capture_output=True,
    )
    result = json.loads((tmp_path / "result.json").read_text(encoding="utf-8"))
    assert "error" not in result, result["error"]
    assert result["text"] + "\n" == text  # the buffer is the text the edits describe
    assert [code for _, _, code, _ in spec["expected_after"]] == ["N101"]
    assert result["before"] == spec["expected_before"]
    assert result["after"] == spec["expected_after"]
    assert result["format_options"] == {"insertSpaces": False, "tabSize": 8}
    assert "\t" not in result["formatted"]
    assert "\n    hero: vehicle\n" in result["formatted"]
    assert result["stopped"]
