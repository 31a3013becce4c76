"""Public syntax examples from py-osc2 (``open``), each as its README's table says."""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.syntax import ast, parse
from osc2check.syntax.walk import walk

FOLDER = Path(__file__).resolve().parents[3].parent / "shared" / "conformance" / "open"
if not (FOLDER / "demo.osc").is_file():
    pytest.skip(f"no conformance data at {FOLDER}", allow_module_level=True)

NO_LIBRARY = AnalysisOptions(implicit_imports=(), modules={})


def _analyze(name: str):
    path = FOLDER / name
    return analyze([SourceInput(str(path), path.read_text(encoding="utf-8"))], NO_LIBRARY)


def _findings(analysis) -> list[tuple[int, str]]:
    return [(d.span.line, d.code.code) for d in analysis.diagnostics]


def _declared(result) -> list[tuple[str, str]]:
    names = []
    for decl in result.ast.declarations:
        name = getattr(decl, "name", None)
        if isinstance(name, ast.BehaviourName):
            names.append((type(decl).__name__, name.name.text))
        elif isinstance(name, ast.Name):
            names.append((type(decl).__name__, name.text))
    return names


def test_demo_parses_and_only_the_missing_import_is_reported():
    path = FOLDER / "demo.osc"
    assert parse(path.read_text(encoding="utf-8"), str(path)).diagnostics == ()
    analysis = _analyze("demo.osc")
    assert _findings(analysis) == [(1, "N105")]
    assert "foo.osc" in analysis.diagnostics[0].message


def test_demo_error_reports_the_misspelling_and_recovers_the_rest():
    path = FOLDER / "demo-error.osc"
    result = parse(path.read_text(encoding="utf-8"), str(path))
    assert [(d.span.line, d.code.code) for d in result.diagnostics] == [(4, "P001")]
    assert "scexnario" in result.diagnostics[0].message
    assert _declared(result)[-4:] == [
        ("ScenarioDecl", "baz"),
        ("EnumDecl", "storm_type"),
        ("StructDecl", "storm_data"),
        ("ScenarioDecl", "snowstorm"),
    ]
    assert _findings(_analyze("demo-error.osc")) == [(1, "N105"), (4, "P001")]


@pytest.mark.parametrize("name", ["enums.osc", "float_literals.osc"])
def test_parses_and_checks_cleanly(name):
    path = FOLDER / name
    assert parse(path.read_text(encoding="utf-8"), str(path)).diagnostics == ()
    assert _findings(_analyze(name)) == []


def test_namespaces_resolve_every_prefixed_name():
    analysis = _analyze("namespaces.osc")
    assert analysis.diagnostics == []
    path = str(FOLDER / "namespaces.osc")
    model = analysis.programs[path].model
    bound = []
    for node in walk(analysis.parses[path].ast):
        if isinstance(node, (ast.QualifiedName, ast.BehaviourName)) and node.namespace is not None:
            symbol = model.references.get(node.name)
            found = (symbol.name, symbol.namespace) if symbol is not None else None
            bound.append((node.span.line, f"{node.namespace}::{node.name.text}", found))
    assert bound == [
        (14, "demo::foo", ("foo", "demo")),  # export of another namespace's name
        (22, "demo::foo", ("foo", "demo")),
        (23, "demo2::foo2", ("foo2", "demo2")),
        (24, "demo2::foo", ("foo", "demo")),  # demo2 re-exports demo::foo
        (30, "::user", ("user", "")),
        (37, "demo3::field4", ("field4", "demo3")),  # fields that `extend` adds in demo3
        (37, "demo3::field5", ("field5", "demo3")),
        (38, "demo3::field4", ("field4", "demo3")),
    ]
