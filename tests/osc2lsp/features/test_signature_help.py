"""Signature help."""

from __future__ import annotations

from osc2lsp.features.signature_help import signature_help
from tests.osc2lsp.lsp_helpers import cursor, insert_line, seed_text, snapshot


def _help(marked: str, base: str | None = None):
    text, offset = cursor(marked)
    return signature_help(snapshot(base if base is not None else text), text, offset)


def _active(result) -> str:
    start, end, _ = result.parameters[result.active]
    return result.label[start:end]


def test_signature_help_for_a_modifier_being_written():
    seed = seed_text()
    result = _help(insert_line(seed, "hero.drive() with:", "          lane($0"), base=seed)
    assert result.label.startswith("std::lane(lane: uint = 1")
    assert _active(result) == "lane: uint = 1"


def test_signature_help_follows_named_and_positional_arguments():
    seed = seed_text()
    result = _help(seed.replace("lane(1, at: start)", "lane(1, at: st$0art)"))
    assert _active(result) == "at: at = all"
    result = _help(seed.replace("speed(0kph, at: start)", "speed(0k$0ph, at: start)", 1))
    assert _active(result).startswith("speed: speed")


def test_signature_help_for_built_in_event_functions():
    result = _help(seed_text().replace("elapsed(0.5s)", "elapsed(0.5$0"))
    assert result.label == "elapsed(duration: time)" and result.active == 0


def test_signature_help_outside_a_call_is_none():
    assert _help("scenario s:\n    $0\n") is None
