"""Every example and conformance file: what the checker passes, the runner compiles and
starts; what it refuses (an error, or A308), the runner refuses before tick 0 with the
very same findings and nothing of its own (issue 19). A file with several scenarios to
choose from is tried with each of them as the root (``--scenario``); a file that
declares none is a library. ``../shared/conformance`` (or the folder
``OSC2_CONFORMANCE`` names) is read when present (skipped when absent), never
copied."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from osc2check import codes
from osc2check.analysis import SourceInput, analyze
from osc2check.diagnostics import Severity
from osc2check.semantics.roots import RootScenarioError, file_scenarios, root_scenario
from osc2runner.errors import ScenarioError
from osc2runner.runner import build_world, check_analysis, compile_checked, execute

ROOT = Path(__file__).resolve().parents[3]
CONFORMANCE = Path(
    os.environ.get("OSC2_CONFORMANCE", ROOT.parent / "shared" / "conformance")
)  # beside the checkout, as the checker's conformance tests read it


def _files(folder: Path) -> list[Path]:
    return sorted(folder.rglob("*.osc")) if folder.is_dir() else []


def _roots(analysis, uri: str) -> list[str]:  # type: ignore[no-untyped-def]
    """The scenario names to try as the root: the one chosen, else every candidate."""
    program = analysis.programs.get(uri)
    result = program.files.get(uri) if program is not None else None
    if result is None or result.ast is None:
        return []
    scenarios = file_scenarios(program.model, result.ast.declarations)
    try:
        return [root_scenario(program.model, scenarios).qualified_name]
    except RootScenarioError as exc:
        return list(exc.choices)


def _agree(path: Path) -> None:
    uri = str(path)
    analysis = analyze([SourceInput(uri, path.read_text(encoding="utf-8"))])
    refusing = sorted(
        (d.code.code, d.span.uri, d.span.line, d.span.column, d.message)
        for d in analysis.diagnostics
        if d.severity is Severity.ERROR or d.code is codes.NOT_EXECUTED
    )
    roots = _roots(analysis, uri)
    if not roots:
        pytest.skip("a library: it declares no scenario to run")
    for name in roots:
        try:
            checked = check_analysis(analysis, uri, scenario=name)
            prepared = build_world(compile_checked(checked))
            result = execute(prepared, duration=float(prepared.ctx.dt))
        except ScenarioError as exc:
            assert not exc.problems, f"{name}: refused with messages the checker never gave: " + (
                "; ".join(str(p) for p in exc.problems)
            )
            got = sorted(
                (d.code.code, d.span.uri, d.span.line, d.span.column, d.message)
                for d in exc.diagnostics
            )
            assert got == refusing, f"{name}: the runner refused with other findings"
            continue
        assert not refusing, f"{name}: the checker refused and the runner started"
        assert result.outcome.status != "error", f"{name}: {result.outcome.reason}"


EXAMPLES = _files(ROOT / "examples")
CONFORMANCE_FILES = _files(CONFORMANCE)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: str(p.relative_to(ROOT)))
def test_example_compiles_and_starts_or_is_refused_with_the_checkers_findings(path: Path):
    _agree(path)


@pytest.mark.skipif(not CONFORMANCE_FILES, reason=f"no conformance files at {CONFORMANCE}")
@pytest.mark.parametrize(
    "path",
    CONFORMANCE_FILES,
    ids=lambda p: str(p.relative_to(CONFORMANCE)),
)
def test_conformance_file_compiles_and_starts_or_is_refused_with_the_checkers_findings(
    path: Path,
):
    _agree(path)
