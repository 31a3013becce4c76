"""Inlay hints."""

from __future__ import annotations

from osc2lsp.features.inlay_hints import inlay_hints
from tests.osc2lsp.lsp_helpers import seed_text, snapshot


def _hints(text: str, **options):
    snap = snapshot(text)
    return [
        (snap.lines.position(h.offset)[0] + 1, h.label, h.kind)
        for h in inlay_hints(snap, 0, len(text), **options)
    ]


def test_inlay_hints_fold_initialisers_with_units():
    hints = _hints(seed_text())
    assert (19, "≈ 55.0 kph", "value") in hints
    assert (22, "= 12 m", "value") in hints
    assert not any(line == 18 for line, _, kind in hints if kind == "value")  # a literal


def test_inlay_hints_name_positional_arguments():
    hints = _hints(seed_text())
    assert (28, "lane:", "parameter") in hints and (29, "speed:", "parameter") in hints
    assert not any(label == "at:" for _, label, _ in hints)  # already named


def test_inlay_hints_can_be_limited_to_one_kind():
    assert all(kind == "value" for _, _, kind in _hints(seed_text(), parameter_names=False))
    assert all(kind == "parameter" for _, _, kind in _hints(seed_text(), values=False))
