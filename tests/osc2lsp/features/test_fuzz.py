"""Type the design paper's scenario character by character, then delete it again,
asking for completion and hover at every step (and signature help after `(` and
`,`, where editors ask for it): nothing may fail.

The snapshot is refreshed at each line end, as the debounce would do while a
user types, so most requests see a snapshot that lags behind the text.
"""

from __future__ import annotations

from osc2lsp.features.completion import complete
from osc2lsp.features.hover import hover
from osc2lsp.features.signature_help import signature_help
from tests.osc2lsp.lsp_helpers import seed_path, snapshot


def _steps(target: str):
    for i in range(len(target) + 1):
        yield target[:i]
    for i in range(len(target) - 1, -1, -1):
        yield target[:i]


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
