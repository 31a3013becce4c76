"""Code actions."""

from __future__ import annotations

from osc2lsp.features.code_actions import code_actions
from tests.osc2lsp.lsp_helpers import REPO, snapshot

TYPOS = (REPO / "examples" / "unsafe_typos.osc").read_text(encoding="utf-8")


def _actions(text: str, line: int | None = None):
    snap = snapshot(text)
    if line is None:
        start, end = 0, len(text)
    else:
        start = snap.lines.offset(line - 1, 0)
        end = snap.lines.offset(line - 1, 200)
    return snap, code_actions(snap, start, end)


def _apply(text: str, edits) -> str:
    for edit in sorted(edits, key=lambda e: e.span.start, reverse=True):
        text = text[: edit.span.start] + edit.new_text + text[edit.span.end :]
    return text


def test_code_actions_fix_did_you_mean_names_and_units():
    snap, actions = _actions(TYPOS)
    titles = [a.title for a in actions if not a.title.startswith("Suppress")]
    assert titles == ["Replace with `drive`", "Replace with `right`", "Replace with `kmph`"]
    fixed = TYPOS
    for action in actions:
        if action.title.startswith("Replace"):
            fixed = _apply(fixed, action.edits[snap.key])
    codes = {d.code.code for d in snapshot(fixed).diagnostics}
    assert not codes & {"A301", "N106", "N104"}


def test_code_action_adds_the_standard_import_after_the_header_comment():
    text = "# my scenario\nscenario s:\n    hero: vehicle\n"
    snap, actions = _actions(text, 3)
    add = next(a for a in actions if a.title == "Add `import osc.standard`")
    fixed = _apply(text, add.edits[snap.key])
    assert fixed == "# my scenario\nimport osc.standard\nscenario s:\n    hero: vehicle\n"
    assert not [d for d in snapshot(fixed).diagnostics if d.code.code == "N101"]


def test_code_action_suppresses_a_finding_on_its_line():
    snap, actions = _actions(TYPOS, 14)
    suppress = next(a for a in actions if a.title.startswith("Suppress N104"))
    fixed = _apply(TYPOS, suppress.edits[snap.key])
    assert "speed(60kmph2)  # osc2check: ignore[N104]" in fixed
    assert "N104" not in {d.code.code for d in snapshot(fixed).diagnostics}


def test_code_action_merges_into_an_existing_suppression():
    text = "scenario s:\n    x: int = 1.5  # osc2check: ignore[N101]\n"
    snap, actions = _actions(text, 2)
    suppress = next(a for a in actions if a.title.startswith("Suppress T204"))
    fixed = _apply(text, suppress.edits[snap.key])
    assert "# osc2check: ignore[N101, T204]" in fixed


def test_code_actions_on_a_clean_line_are_empty():
    assert _actions("scenario s:\n    x: int = 1\n", 2)[1] == []
