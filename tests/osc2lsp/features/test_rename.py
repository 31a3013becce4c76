"""Rename on the plain functions."""

from __future__ import annotations

import pytest

from osc2lsp.features.rename import RenameError, prepare_rename, rename
from osc2lsp.session.analysis import analyse
from tests.osc2lsp.lsp_helpers import cursor, seed_text, snapshot


def _rename(marked: str, new: str):
    text, offset = cursor(marked)
    return rename(snapshot(text), offset, new)


def test_rename_lag_changes_all_four_places():
    edits = _rename(seed_text().replace("(lag * 3)", "(l$0ag * 3)"), "gap")
    [(key, changes)] = edits.items()
    assert [e.span.line for e in changes] == [21, 22, 32, 63]
    assert all(e.new_text == "gap" for e in changes)


def test_prepare_rename_gives_the_name_and_range():
    text, offset = cursor(seed_text().replace("var lag", "var la$0g"))
    span, placeholder = prepare_rename(snapshot(text), offset)
    assert placeholder == "lag" and text[span.start : span.end] == "lag"


@pytest.mark.parametrize(
    "marked, new, reason",
    [
        (
            seed_text().replace("hero.change_lane(", "hero.change$0_lane("),
            "swerve",
            "standard library",
        ),
        (seed_text().replace("var lag", "var l$0ag"), "do", "keyword"),
        (seed_text().replace("var lag", "var l$0ag"), "2lag", "not a valid name"),
        (seed_text().replace("var lag", "var l$0ag"), "safety_gap", "already has a member"),
        ("$0\nscenario s:\n", "x", "no symbol"),
    ],
)
def test_rename_refusals(marked, new, reason):
    with pytest.raises(RenameError, match=reason):
        _rename(marked, new)


def test_rename_a_soft_keyword_name_is_allowed():
    edits = _rename(seed_text().replace("var lag", "var l$0ag"), "range")
    assert sum(len(v) for v in edits.values()) == 4


def test_rename_across_files_is_namespace_aware(tmp_path):
    lib = tmp_path / "lib.osc"
    lib_text = "namespace robots\nexport *\nactor robot\n\nnamespace other\nactor robot\n"
    lib.write_text(lib_text, encoding="utf-8")
    main = tmp_path / "main.osc"
    main_text = 'import "lib.osc"\n\nscenario s:\n    r: robots::robot\n    o: other::robot\n'
    snaps = analyse([(main.as_uri(), main_text, 1)])
    snap = snaps[main.as_uri()]
    edits = rename(snap, main_text.index("robots::robot") + 9, "droid")
    lines = sorted((key.rsplit("/", 1)[-1], e.span.line) for key, es in edits.items() for e in es)
    assert lines == [("lib.osc", 3), ("main.osc", 4)]
