"""The ASAM OSC2 2.1.0 library files as vendored by scenario_execution (``asam-2.1``).

``types.osc`` parses cleanly. ``standard.osc`` has one syntax problem (line 855,
see the folder's README), after which everything is recovered; analysed as a
library, with ``import osc.types`` naming ``types.osc``, it has exactly the
defects in ``EXPECTED`` and nothing more.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.semantics.symbols import SymbolKind
from osc2check.syntax import ast, parse
from osc2check.syntax.walk import walk

FOLDER = Path(__file__).resolve().parents[3].parent / "shared" / "conformance" / "asam-2.1"
if not (FOLDER / "standard.osc").is_file():
    pytest.skip(f"no conformance data at {FOLDER}", allow_module_level=True)

STANDARD = FOLDER / "standard.osc"
TYPES = FOLDER / "types.osc"

# (line, code) of every finding in standard.osc, and why each is real.
EXPECTED = [
    (499, "N102"),  # `actor osc_actor` again: types.osc declares it at line 212
    (502, "N101"),  # `bounding_box: bounding_box`: the struct was left out of this copy
    (625, "N102"),  # `struct route` again: line 51 declares it
    (854, "T203"),  # the orphaned `keep(default it == 1)` compares the action with a number
    (855, "P002"),  # `side:` dedents to column 5, which no block uses
]


def _text(path: Path) -> str:
    return path.read_bytes().decode("utf-8")  # as is: CRLF line ends included


def _outline(node: ast.Node) -> tuple:
    """Kinds and names of a file's declarations and their members (constraints left out)."""
    name = getattr(node, "name", None)
    names = [n.text for n in getattr(node, "names", ())]
    if isinstance(name, ast.BehaviourName):
        names.append(name.name.text)
    elif isinstance(name, ast.Name):
        names.append(name.text)
    members = getattr(node, "members", None) or getattr(node, "declarations", None) or ()
    return (
        type(node).__name__,
        tuple(names),
        tuple(_outline(m) for m in members if not isinstance(m, ast.KeepConstraint)),
    )


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2check/conformance/test_conformance_asam")


@pytest.fixture(scope="module")
def analysis():
    config = AnalysisOptions(implicit_imports=(), modules={"osc.types": str(TYPES)})
    return analyze([SourceInput(str(STANDARD), _text(STANDARD))], config)


def test_types_osc_parses_and_resolves_cleanly():
    assert parse(_text(TYPES), str(TYPES)).diagnostics == ()
    config = AnalysisOptions(implicit_imports=(), modules={})
    assert analyze([SourceInput(str(TYPES), _text(TYPES))], config).diagnostics == []


def test_standard_osc_has_exactly_one_syntax_error_at_line_855():
    result = parse(_text(STANDARD), str(STANDARD))
    assert [(d.span.line, d.code.code) for d in result.diagnostics] == [(855, "P002")]


def test_every_declaration_after_the_error_is_recovered():
    text = _text(STANDARD)
    lines = text.splitlines(keepends=True)
    assert "keep(default it == 1)" in lines[853]
    repaired = parse("".join(lines[:853] + lines[854:]), str(STANDARD))
    assert repaired.diagnostics == ()
    original = parse(text, str(STANDARD))
    assert _outline(original.ast) == _outline(repaired.ast)
    after = [d for d in original.ast.declarations if d.span.line > 855]
    assert len(after) == 27
    change_lane = next(d for d in original.ast.declarations if d.span.line == 852)
    assert [n.text for m in change_lane.members for n in getattr(m, "names", ())] == [
        "side",
        "rate_peak",
        "target",
    ]


def test_the_library_has_exactly_the_known_defects(analysis):
    assert [(d.span.line, d.code.code) for d in analysis.diagnostics] == EXPECTED
    duplicate_actor = analysis.diagnostics[0]
    assert [(r.span.uri, r.span.line) for r in duplicate_actor.related] == [(str(TYPES), 212)]


def test_a_shared_enum_member_is_decided_by_the_value_it_is_compared_with(analysis):
    """`keep(default it == none)` at line 675: `none` belongs to five enums, and `it` is a
    `hitch_type`, so only `hitch_type!none` fits (§7.3.3) — not one of the defects."""
    model = analysis.programs[str(STANDARD)].model
    (literal,) = [
        node
        for node in walk(analysis.parses[str(STANDARD)].ast)
        if isinstance(node, ast.NameRef) and node.span.line == 675 and node.name.name.text == "none"
    ]
    member = model.references[literal.name.name]
    assert member.kind is SymbolKind.ENUM_MEMBER
    assert (member.owner.name, member.name) == ("hitch_type", "none")
    owners = {
        s.owner.name for s in model.symbols if s.kind is SymbolKind.ENUM_MEMBER and s.name == "none"
    }
    assert len(owners) == 5
