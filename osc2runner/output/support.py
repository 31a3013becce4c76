"""``docs/coverage.md``: what the runner supports, generated from the method registry
and the capability table (``osc2check.capabilities``, which the checker's A308 reads).

Every action, modifier and ``is undefined`` method of the bundled library
(the standard ``std`` namespace and the toolkit's own) is listed, supported
or not. Regenerate with ``python -m osc2runner.output.support > docs/coverage.md``;
a test fails when the file is out of date.
"""

from __future__ import annotations

from collections.abc import Iterator

from osc2check.capabilities import FORMS, absent_reason, label_of
from osc2check.semantics.model import Model
from osc2check.semantics.stdlib import standard_library
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2runner.compile.registry import MethodRegistry, standard_registry

__all__ = ["coverage_markdown"]

_HEADER = """\
# Runner coverage

What `osc2run` executes, for every action, modifier and implemented method of
the bundled library (ASAM OpenSCENARIO DSL 2.1 `std` plus the toolkit's
`osc2toolkit` extensions and CARLA's world, `carla`; what plug-ins implement for
your own libraries is not listed: docs/plugins.md). Generated from the runner's method registry by
`python -m osc2runner.output.support > docs/coverage.md`; a test checks that this
file is up to date. Invoking anything marked "no" is an error before the run
starts, with its location: nothing is skipped silently. The reasons, and the forms
below, are the capability table `osc2check.capabilities`: `osc2check` reports
each use as A308 (a warning), and `osc2run` refuses such a file before tick 0
with the same finding. A trailer (an actor
whose catalogue row is a trailer) has no engine or driver: of the actions it
takes only `assign_position` and `assign_orientation`, and a vehicle tows it
(`connect_trailer`).

"""


def _library_symbols(model: Model, kind: SymbolKind) -> list[Symbol]:
    return [s for s in model.symbols if s.kind is kind and (s.library or s.toolkit)]


def _subtypes(model: Model, actor: Symbol | None) -> Iterator[Symbol]:
    if actor is None:
        return
    yield actor
    for child in model.children.get(actor, ()):
        yield from _subtypes(model, child)


def _is_base(action: Symbol) -> bool:
    return action.name in ("osc_action",) or action.name.startswith("action_for_")


def _doc(sym: Symbol) -> str:
    text = (sym.doc or "").strip().splitlines()
    return text[0] if text else ""


def _escape(text: str) -> str:
    return text.replace("|", "\\|")


def _actions(model: Model, reg: MethodRegistry) -> list[str]:
    rows = [
        "## Actions",
        "",
        "| action | namespace | runs for | runner behaviour | note |",
        "|---|---|---|---|---|",
    ]
    for action in sorted(
        _library_symbols(model, SymbolKind.ACTION),
        key=lambda s: (s.actor.name if s.actor else "", s.name),
    ):
        label = f"`{action.qualified_name}`"
        if _is_base(action):
            rows.append(f"| {label} | {action.namespace} | base action, not invoked | | |")
            continue
        runs_for: list[str] = []
        entries = {}
        for actor in _subtypes(model, action.actor):
            entry = reg.find_action(model, actor, action)
            if entry is not None and actor.library:
                runs_for.append(actor.name)
                entries[entry.label] = entry
        if not runs_for:
            owner = action.actor.name if action.actor else ""
            why = _escape(absent_reason(f"{owner}.{action.name}"))
            rows.append(f"| {label} | {action.namespace} | **no** | | {why} |")
            continue
        shown = _compact(model, action.actor, runs_for)
        entry = next(iter(entries.values()))
        note = "; ".join(e.note for e in entries.values() if e.note)
        rows.append(
            f"| {label} | {action.namespace} | {shown} | `{entry.target.__name__}` "
            f"| {_escape(note)} |"
        )
    return rows


def _compact(model: Model, declared: Symbol | None, names: list[str]) -> str:
    """``all`` when every library subtype of the declaring actor runs it."""
    every = [s.name for s in _subtypes(model, declared) if s.library]
    if declared is not None and sorted(set(names)) == sorted(set(every)):
        return f"every {declared.name}"
    return ", ".join(dict.fromkeys(names))


def _modifiers(model: Model, reg: MethodRegistry) -> list[str]:
    rows = [
        "## Modifiers",
        "",
        "| modifier | applies to | supported | runner class | note |",
        "|---|---|---|---|---|",
    ]
    for mod in sorted(
        _library_symbols(model, SymbolKind.MODIFIER),
        key=lambda s: (s.actor.name if s.actor else "", s.name),
    ):
        where = (
            mod.actor.name
            if mod.actor is not None
            else (
                f"actions of {mod.of.actor.name}" if mod.of is not None and mod.of.actor else "any"
            )
        )
        entry = reg.find_modifier(model, mod)
        if entry is None:
            why = _escape(absent_reason(label_of(mod)))
            rows.append(f"| `{mod.qualified_name}` | {where} | **no** | | {why} |")
        else:
            rows.append(
                f"| `{mod.qualified_name}` | {where} | yes | `{entry.target.__name__}` "
                f"| {_escape(entry.note)} |"
            )
    return rows


def _methods(model: Model, reg: MethodRegistry) -> list[str]:
    rows = [
        "## Methods implemented by the runner",
        "",
        "Methods the library declares `is undefined`; methods `is expression` are "
        "evaluated from their body.",
        "",
        "| method | supported | why not |",
        "|---|---|---|",
    ]
    found = []
    for sym in model.symbols:
        if sym.kind is not SymbolKind.METHOD or not (sym.library or sym.toolkit):
            continue
        decl = sym.decl
        if not isinstance(decl, ast.MethodDecl) or decl.kind != "undefined":
            continue
        owner = sym.owner.name if sym.owner is not None else ""
        found.append((owner, sym.name, reg.find_method(model, sym) is not None))
    for owner, name, ok in sorted(found):
        why = "" if ok else _escape(absent_reason(f"{owner}.{name}"))
        rows.append(f"| `{owner}.{name}` | {'yes' if ok else '**no**'} | {why} |")
    return rows


def _forms() -> list[str]:
    rows = [
        "## Forms the runner does not execute",
        "",
        "Calls that run, written in a way the runner does not carry out (A308).",
        "",
        "| form | why |",
        "|---|---|",
    ]
    for form in FORMS.values():
        rows.append(f"| {_escape(form.written)} | {_escape(form.reason)} |")
    return rows


def coverage_markdown(reg: MethodRegistry | None = None) -> str:
    """The text of ``docs/coverage.md``."""
    reg = reg or standard_registry()
    model = standard_library().model
    actions = [s for s in _library_symbols(model, SymbolKind.ACTION) if not _is_base(s)]
    modifiers = _library_symbols(model, SymbolKind.MODIFIER)
    supported_actions = sum(
        1 for a in actions if any(reg.find_action(model, t, a) for t in _subtypes(model, a.actor))
    )
    supported_modifiers = sum(1 for m in modifiers if reg.find_modifier(model, m))
    summary = (
        f"Supported: {supported_actions} of {len(actions)} actions, "
        f"{supported_modifiers} of {len(modifiers)} modifiers.\n\n"
    )
    parts = [
        _HEADER + summary,
        *_actions(model, reg),
        "",
        *_modifiers(model, reg),
        "",
        *_methods(model, reg),
        "",
        *_forms(),
    ]
    return "\n".join(parts) + "\n"


if __name__ == "__main__":  # pragma: no cover
    import sys

    sys.stdout.write(coverage_markdown())
