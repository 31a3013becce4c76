"""osc2check against a peer's test suite: Robomous/Scena's DSL cases (``scena-2.2``).

Each portable ``check``/``resolve`` case of ``../shared/conformance/scena-2.2``
is checked as Scena checked it: as DSL 2.2, Scena's level (``--osc-version 2.2``;
``stdlib_mode`` says which library is in use,
``search_paths`` where ``import a.b`` looks), and osc2check must agree with the
peer on accepting it (no error-level finding) or rejecting it. ``DELIBERATE``
lists the cases where we disagree on purpose, each with its reason; one that
starts to agree must leave the list. ``pytest -s`` prints the agreement rate.
"""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

import pytest

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.diagnostics import Severity

SUITE = Path(__file__).resolve().parents[3].parent / "shared" / "conformance" / "scena-2.2"
if not (SUITE / "cases.json").is_file():
    pytest.skip(f"no conformance data at {SUITE}", allow_module_level=True)

MINIMUM_AGREEMENT = 0.90

LIBRARY_22 = "2.2 library content: "
BOTTOM_UP = (
    "§7.3.3: an overloaded enum literal is resolved by the type requirements of its "
    "place, and an error only when several choices stay valid; compared with a field of "
    "one of its enums, one does. Scena types expressions bottom-up and rejects every bare "
    "literal that two enums share (its policy)"
)

# case id -> why osc2check decides otherwise than Scena.
STANDING_AFTER_SPEED = (
    "`assign_speed(10mps)` is instant, so the `remain_stationary` after it starts at time 0 "
    "with the actor at 10 m/s, and remain_stationary holds speed 0 throughout "
    "(docs/runner.md): the start cannot hold (L501) and osc2run refuses the file; Scena "
    "does not place actors"
)
DELIBERATE: dict[str, str] = {
    "resolve_0006": "§7.3.11.3.2: a default constraint that is not overridden must hold, and "
    "an error is raised when it cannot; Scena drops `keep(default 1 > 2)` with a warning "
    "(C401)",
    "resolve_0014": "§7.3.10.2: only an event without parameters may have an event "
    "specification; Scena accepts `event fast(at: float) is rise(at > 1.0)` (N112)",
    "resolve_0025": "`sample(n, @tick, 0.0)` reads `n`, which nothing declares (N101); Scena "
    "does not resolve the arguments of `sample`, which it does not execute",
    "resolve_0092": "`go` is a method of `thing`: a `do` invokes actions and scenarios "
    "(a method goes through `call`); Scena does not check the invoked name (A301)",
    "resolve_0095": "the grammar gives actors no modifier applications (actor-member-decl); "
    "Scena accepts `tweak(1)` in an actor body (N112)",
    "resolve_0129": "§7.3.7.2: `is only` with no method to override is not an error; Scena "
    "rejects it, the change ASAM issue 883 proposes",
    "check_0038": "`ego.bounding_box` is a `bounding_box`, not the `physical_object` that "
    "`reference` takes (T203); Scena does not type behaviour arguments when checking and "
    "rejects this only when lowering",
    "check_0047": STANDING_AFTER_SPEED,
    "check_0049": STANDING_AFTER_SPEED,
    "check_0068": STANDING_AFTER_SPEED,
    "check_0081": STANDING_AFTER_SPEED,
    "check_0085": "`junction.xodr` is not there: osc2check reads a scenario's map (relative "
    "to the scenario file) and reports a map file it cannot read (L516); Scena's checker "
    "does not open map files",
    "check_0086": "`flat.xodr` is not there: a map file that cannot be read is L516 (see "
    "check_0085)",
    "check_0089": BOTTOM_UP,
    "check_0096": BOTTOM_UP,
    "check_0099": BOTTOM_UP,
    "check_0115": "`no_such_map.xodr` is not there: a map file that cannot be read is L516 "
    "(see check_0085)",
    "check_0100": LIBRARY_22 + "Scena makes `change_speed` and `keep_speed` unassociated "
    "modifiers; the standard's library (2.1's, and the 2.2 additions) declares them `of "
    "movable_object.action_for_movable_object`, so they apply only in the `with:` of such "
    "an action (A301)",
}


def _cases() -> list[dict]:
    cases = json.loads((SUITE / "cases.json").read_text(encoding="utf-8"))
    return [c for c in cases if c["stage"] in ("check", "resolve") and c.get("portable", True)]


CASES = _cases()


def _config(case: dict) -> AnalysisOptions:
    root = SUITE / case["file"]
    implicit = ("osc.standard.types",) if case["stdlib_mode"] == "types" else ()
    search = tuple(str(root.parent / p) for p in case.get("search_paths") or ())
    return AnalysisOptions(
        implicit_imports=implicit, modules={}, search_paths=search, osc_version="2.2"
    )


@cache
def _outcome(case_id: str) -> tuple[str, tuple[str, ...]]:
    """osc2check's verdict on a case ("ok" or "error") and its error findings."""
    case = next(c for c in CASES if c["id"] == case_id)
    path = SUITE / case["file"]
    # the default seed=None samples no witness; the verdict does not depend on one
    analysis = analyze([SourceInput(str(path), path.read_text(encoding="utf-8"))], _config(case))
    errors = tuple(
        f"{d.span.line}: {d.code.code} {d.message}"
        for d in analysis.diagnostics
        if d.severity is Severity.ERROR
    )
    return ("error" if errors else "ok"), errors


def test_search_paths_are_followed(tmp_path):
    (tmp_path / "probe").mkdir()
    (tmp_path / "probe" / "module.osc").write_text("struct probed\n", encoding="utf-8")
    root = SourceInput(str(tmp_path / "elsewhere" / "main.osc"), "import probe.module\n")
    options = AnalysisOptions(search_paths=(str(tmp_path),))
    assert analyze([root], options).diagnostics == []


def test_the_suite_has_the_portable_cases_its_readme_counts():
    assert len(CASES) == 256
    assert set(DELIBERATE) <= {c["id"] for c in CASES}


@pytest.mark.parametrize("case", CASES, ids=[c["id"] for c in CASES])
def test_osc2check_agrees_with_scena(case):
    verdict, errors = _outcome(case["id"])
    if case["id"] in DELIBERATE:
        assert verdict != case["expect"], (
            f"{case['id']} now agrees with Scena; remove it from DELIBERATE"
        )
        return
    scena = [
        f"{d['line']}: {d['message']}"
        for d in case.get("diagnostics") or []
        if d["severity"] == "error"
    ]
    assert verdict == case["expect"], (
        f"{case['file']}: Scena says {case['expect']} {scena}, osc2check says {verdict} "
        f"{list(errors)}"
    )


def test_agreement_rate():
    agreed = sum(_outcome(c["id"])[0] == c["expect"] for c in CASES)
    rate = agreed / len(CASES)
    print(f"\nscena agreement: {agreed}/{len(CASES)} = {rate:.1%}")
    assert rate >= MINIMUM_AGREEMENT
