"""Which scenario of a file is the one to run: the root of the invocation tree.

The rule (the standard leaves the choice of the top-level scenario to the tool;
``top`` is its convention in examples and in the migration guide): the scenario
named by the user; else the scenario named ``top``; else the one scenario of
the file that no other scenario of the file invokes. Anything else is an error
that lists the choices. The runner and ``osc2check.solve`` share it.
"""

from __future__ import annotations

from osc2check.semantics.members import (
    MemberList,
    declaration_bodies,
    scenario_members,
)
from osc2check.semantics.model import Model
from osc2check.semantics.phases import invocations
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast

__all__ = [
    "RootScenarioError",
    "file_scenarios",
    "invoked_scenarios",
    "invokers",
    "root_scenario",
]

TOP = "top"


class RootScenarioError(Exception):
    """No scenario, or no single one, to run; ``choices`` are the candidates."""

    def __init__(self, message: str, choices: tuple[str, ...] = ()) -> None:
        super().__init__(message)
        self.choices = choices


def file_scenarios(model: Model, declarations: tuple[ast.Node, ...]) -> list[Symbol]:
    """The scenarios a file declares, in source order."""
    found: list[Symbol] = []
    for decl in declarations:
        if isinstance(decl, ast.ScenarioDecl):
            sym = model.declarations.get(decl)
            if sym is not None and sym.kind is SymbolKind.SCENARIO:
                found.append(sym)
    return found


def invoked_scenarios(model: Model, scenarios: list[Symbol]) -> set[Symbol]:
    """The scenarios that one of ``scenarios`` invokes in its behaviour (directly)."""
    return set(invokers(model, scenarios))


def invokers(
    model: Model, scenarios: list[Symbol], bodies: dict[Symbol, list[MemberList]] | None = None
) -> dict[Symbol, list[Symbol]]:
    """Each scenario one of ``scenarios`` invokes in its behaviour (directly: in the
    ``do`` it runs and its ``on`` directives, its ``extend``s' and ancestors' included,
    as the runner compiles it), with the scenarios that invoke it, in order. ``bodies``:
    ``members.declaration_bodies(model)``, when the caller has it."""
    if bodies is None:
        bodies = declaration_bodies(model)
    invoked: dict[Symbol, list[Symbol]] = {}
    for scenario in scenarios:
        members = scenario_members(model, bodies, scenario)
        dos = [m for m in members if isinstance(m, ast.DoDirective)]
        trees: list[ast.DoDirective | ast.OnDirective] = [
            m for m in members if isinstance(m, ast.OnDirective)
        ]
        trees += dos[-1:]  # the last `do` replaces earlier ones
        for tree in trees:
            for inv in invocations(tree):
                target = model.reference(inv.name)
                if target is not None and target.kind is SymbolKind.SCENARIO:
                    by = invoked.setdefault(target, [])
                    if scenario not in by:
                        by.append(scenario)
    return invoked


def root_scenario(model: Model, scenarios: list[Symbol], name: str | None = None) -> Symbol:
    """The scenario to run among ``scenarios`` (see the module docstring)."""
    names = tuple(s.name for s in scenarios)
    if name is not None:
        for sym in scenarios:
            if sym.name == name or sym.qualified_name == name:
                return sym
        raise RootScenarioError(f"no scenario `{name}`", names)
    if not scenarios:
        raise RootScenarioError("declares no scenario to run")
    if len(scenarios) == 1:
        return scenarios[0]
    tops = [s for s in scenarios if s.name == TOP]
    if len(tops) == 1:
        return tops[0]
    invoked = invoked_scenarios(model, scenarios)
    roots = [s for s in scenarios if s not in invoked]
    if len(roots) == 1:
        return roots[0]
    candidates = tuple(s.name for s in (roots or scenarios))
    raise RootScenarioError(
        "declares several scenarios that no other invokes and none named `top`", candidates
    )
