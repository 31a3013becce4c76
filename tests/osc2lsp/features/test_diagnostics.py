"""Diagnostics: the checker's own findings, and result ids for pull requests."""

from __future__ import annotations

from osc2check.analysis import SourceInput, analyze
from osc2check.config import Config
from osc2lsp.features.diagnostics import diagnostics, result_id
from osc2lsp.options import Options, apply_options
from tests.osc2lsp.lsp_helpers import REPO, URI, snapshot

TYPOS = (REPO / "examples" / "unsafe_typos.osc").read_text(encoding="utf-8")


def test_diagnostics_are_exactly_the_checkers():
    expected = analyze([SourceInput("/tmp/osc2lsp-tests/document.osc", TYPOS)]).diagnostics
    found = diagnostics(snapshot(TYPOS, URI))
    assert [(d.code.code, d.message, d.span.line, d.span.column) for d in found] == [
        (d.code.code, d.message, d.span.line, d.span.column) for d in expected
    ]


def test_diagnostics_follow_select_ignore_and_strict():
    ignore = apply_options(Config(), Options(ignore=("N104",)))
    assert "N104" not in {d.code.code for d in diagnostics(snapshot(TYPOS, config=ignore))}
    select = apply_options(Config(), Options(select=("N",)))
    assert {d.code.code[0] for d in diagnostics(snapshot(TYPOS, config=select))} == {"N"}


def test_result_ids_name_identical_findings():
    assert result_id(snapshot(TYPOS)) == result_id(snapshot(TYPOS + "\n"))
    assert result_id(snapshot(TYPOS)) != result_id(snapshot(TYPOS.replace("kmph2", "kmph")))
