"""What the scripted editor sessions share: the document, the edits a user makes to
it, what the checker reports for each text, and running an editor on a spec."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from osc2check.analysis import SourceInput, analyze
from osc2check.config import Config
from tests.osc2lsp.lsp_helpers import REPO

# Characters that ``str.splitlines()`` breaks at and LSP does not: form feed, VT, U+2028,
# NEL (and U+2029 in an edit).
TEXT = (
    "# notes\f with\x0b separators\u2028 that are no\x85 line breaks\n"
    "import osc.standard\n"
    "scenario s:\n"
    "    hero: vehicle\n"
    "    x: int = 1\n"
)

# (what is replaced, by what): the last edit leaves one finding, `hreo` undefined.
REPLACEMENTS = (
    ("x: int = 1", "x: int = 1\n    do serial:\n        hreo.drive()"),
    (" with", " with\f\u2029 more"),
    ("hero: vehicle", "hero: vehicle\n    y: speed = 3kph"),
)


def edits(text: str = TEXT) -> tuple[list[tuple[int, int, str, str]], str]:
    """The edits as ``(start, end, new, text before)`` (code-point offsets into the text
    before each edit), and the text after them all."""
    made = []
    for needle, new in REPLACEMENTS:
        at = text.index(needle)
        made.append((at, at + len(needle), new, text))
        text = text[:at] + new + text[at + len(needle) :]
    return made, text


def expected(path: str, text: str, utf8_columns: bool) -> list:
    """What the checker reports as ``[row, column, code, message]`` (rows from 0;
    columns in UTF-8 bytes as Neovim counts them, else in characters)."""
    analysis = analyze([SourceInput(path, text)], Config().analysis_options(verify=False))
    lines = text.split("\n")
    found = []
    for d in analysis.diagnostics:
        if d.span.uri == path:
            column = d.span.column - 1
            if utf8_columns:
                column = len(lines[d.span.line - 1][:column].encode("utf-8"))
            found.append([d.span.line - 1, column, d.code.code, d.message])
    return sorted(found, key=lambda f: (f[0], f[1], f[2]))


def run_session(editor: list[str], tmp_path: Path, spec: dict) -> dict:
    """Run ``editor`` (it reads the spec named by ``OSC2LSP_SPEC``, writes
    ``spec["result"]``) with a fresh home; what it wrote."""
    python_path = os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH")) if p)
    spec = dict(
        spec,
        cmd=[sys.executable, "-m", "osc2lsp"],
        env={"PYTHONPATH": python_path},  # the server's (Neovim: cmd_env)
        root=str(tmp_path),
        init_options={"osc2": {"verify": False, "diagnostics": {"debounce": 10}}},
        timeout_ms=30000,
        result=str(tmp_path / "result.json"),
    )
    (tmp_path / "spec.json").write_text(json.dumps(spec), encoding="utf-8")
    home = tmp_path / "home"
    home.mkdir()
    env = dict(os.environ, OSC2LSP_SPEC=str(tmp_path / "spec.json"), HOME=str(home))
    env["XDG_CONFIG_HOME"] = env["XDG_DATA_HOME"] = str(home)
    env["XDG_STATE_HOME"] = env["XDG_CACHE_HOME"] = str(home)
    env["PYTHONPATH"] = python_path
    session = subprocess.run(
        editor,
        env=env,
        timeout=180,
        check=False,
        stdin=subprocess.DEVNULL,
        capture_output=True,
        text=True,
        errors="replace",
    )
    written = Path(spec["result"])
    assert written.exists(), session.stderr[-3000:]
    result = json.loads(written.read_text(encoding="utf-8"))
    assert "error" not in result, (result["error"], session.stderr[-3000:])
    return result
