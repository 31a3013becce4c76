"""Type the design paper's scenario character by character, then delete it again,
asking for completion and hover at every step (and signature help after `(` and
`,`, where editors ask for it): nothing may fail.

The snapshot is refreshed at each line end, as the debounce would do while a
user types, so most requests see a snapshot that lags behind the text.

Then storms of random client edits, with the characters ``str.splitlines()``
breaks at although LSP does not, each ending with the checker's findings.
"""

from __future__ import annotations

import asyncio

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lsprotocol import types
from pygls.workspace.position_codec import PositionCodec

from osc2lsp.convert import from_lsp_position, to_lsp_diagnostics
from osc2lsp.features.completion import complete
from osc2lsp.features.hover import hover
from osc2lsp.features.signature_help import signature_help
from osc2lsp.options import Options
from osc2lsp.session.scheduler import State
from osc2lsp.text import LineIndex, key_to_uri
from tests.osc2lsp.cli_findings import cli_findings, lsp_findings
from tests.osc2lsp.lsp_helpers import seed_path, snapshot
from tests.osc2lsp.storms import final_text, storms


def _steps(target: str):
    for i in range(len(target) + 1):
        yield target[:i]
    for i in range(len(target) - 1, -1, -1):
        yield target[:i]


@pytest.mark.slow
def test_typing_and_deleting_the_seed_never_fails():
    target = seed_path().read_text(encoding="utf-8")
    snap = snapshot("")
    requests = 0
    for text in _steps(target):
        if text.endswith("\n") or not text:
            snap = snapshot(text)
        offset = len(text)
        result = complete(snap, text, offset)
        assert 0 <= result.start <= result.end <= offset
        assert all(isinstance(item.label, str) and item.label for item in result.items)
        if text.endswith(("(", ",")):
            signature_help(snap, text, offset)
        for probe in (len(snap.text) - 1, len(snap.text) // 2):
            found = hover(snap, max(probe, 0))
            assert found is None or found.markdown
        requests += 1
    assert requests == 2 * len(target) + 1


# ---- edit storms with the characters str.splitlines() breaks at ---------------------------

STORM_BASE = (
    "# a\fcomment\u2028with\x85separators\x1c\x1d\x1e\x0b\u2029\n"
    "import osc.standard\n"
    "scenario s:\n"
    "    hero: vehicle\r\n"
    "    x: int = 1\r"
    "    do hero.drive()\n"
)
STORM_URI = "file:///tmp/osc2lsp-tests/feature-storm.osc"


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(storms(STORM_BASE, max_edits=10), st.sampled_from(["utf-16", "utf-8", "utf-32"]))
def test_edit_storms_end_with_the_clis_findings(edits, encoding):
    """The edits as a client sends them, applied as ``did_change`` does and analysed as
    the server does: the diagnostics are the checker's findings of the client's text."""
    codec = PositionCodec(encoding)

    async def scenario():
        state = State(Options(debounce=0, verify=False))
        state.open(STORM_URI, STORM_BASE, 1)
        lines, text = LineIndex(STORM_BASE), STORM_BASE
        for version, edit in enumerate(edits, start=2):
            change = edit.change(text, encoding)
            start = from_lsp_position(lines, types.Position(**change["range"]["start"]), codec)
            end = from_lsp_position(lines, types.Position(**change["range"]["end"]), codec)
            lines = lines.edited(start, end, change["text"])
            text = edit.apply(text)
            state.change(STORM_URI, lines.text, version, lines)
        snap = await state.fresh(STORM_URI)
        await state.shutdown()
        return snap, text

    snap, text = asyncio.run(scenario())
    assert snap.text == text == final_text(STORM_BASE, edits)
    shown = to_lsp_diagnostics(snap.lines_of, snap.diagnostics, key_to_uri, codec)
    assert lsp_findings(shown) == cli_findings(STORM_URI, text, encoding)
