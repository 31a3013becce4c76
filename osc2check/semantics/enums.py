"""Enum members whose value is another member (2.2 aliases: ``gray = grey``).

§7.3.3: an explicit value may name a member of this or another enum; the
alias takes that member's value, and references that form a cycle are an
error. The declaring pass leaves aliases out of the implicit numbering and
lists them; ``resolve_aliases`` gives them their values once every enum of the
program is declared.
"""

from __future__ import annotations

from collections.abc import Callable

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.semantics.model import Model
from osc2check.semantics.suggest import closest
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast


def resolve_aliases(
    model: Model, aliases: list[Symbol], report: Callable[[Diagnostic], None]
) -> None:
    """Give each alias the value of the member it names; report cycles."""
    targets: dict[int, Symbol | None] = {}

    def target_of(sym: Symbol) -> Symbol | None:
        if id(sym) not in targets:
            targets[id(sym)] = _target(model, sym, report)
        return targets[id(sym)]

    for sym in aliases:
        chain = [sym]
        target = target_of(sym)
        while target is not None and "alias" in target.extra and target not in chain:
            chain.append(target)
            target = target_of(target)
        if target is None:
            continue
        if target in chain:
            if target is sym:  # each member of a cycle reports it once
                names = [f"{m.owner.name if m.owner else '?'}!{m.name}" for m in (*chain, sym)]
                assert sym.name_span is not None  # declared from a name, as every alias
                report(messages.enum_value_cycle(sym.name_span, sym.name, names))
            continue
        sym.value = target.value


def _target(model: Model, sym: Symbol, report: Callable[[Diagnostic], None]) -> Symbol | None:
    """The member an alias names: ``e!m``, or a bare name, first in its own enum."""
    ref = sym.extra["alias"]
    enum, ctx = sym.owner, sym.context
    assert enum is not None and ctx is not None  # an alias is declared in its enum, in a file
    if isinstance(ref, ast.EnumRef):
        enums = model.lookup(
            ref.enum.name.text, ctx, ref.enum.namespace, lambda s: s.kind is SymbolKind.ENUM
        )
        if not enums:
            report(messages.undefined_type(ref.enum.span, str(ref.enum), None))
            return None
        enum, name, written = enums[0], ref.member, ref.member
        model.references[ref.enum.name] = enum
    else:
        name, written = ref.name.name, ref.name.name
    found = [m for m in model.enum_values(enum) if m.name == name.text]
    if not found and isinstance(ref, ast.NameRef) and ref.name.namespace is None:
        found = [
            m for e in model.visible_enums(ctx) for m in model.enum_values(e) if m.name == name.text
        ]
    if not found:
        report(
            messages.unknown_enum_member(
                written.span,
                name.text,
                enum,
                closest(name.text, [m.name for m in model.enum_values(enum)]),
            )
        )
        return None
    if len({id(m.owner) for m in found}) > 1:
        report(
            messages.ambiguous_enum_literal(
                written.span, name.text, [m.owner for m in found if m.owner]
            )
        )
        return None
    model.references[written] = found[0]
    return found[0]
