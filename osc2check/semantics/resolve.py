"""Run the definition, structure and body passes over a program's files."""

from __future__ import annotations

from collections.abc import Callable

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.semantics import types as T
from osc2check.semantics.bodies import BodyChecker
from osc2check.semantics.declare import Declarer, Unit
from osc2check.semantics.model import Context, Model
from osc2check.semantics.suggest import closest
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast


def resolve(model: Model, units: list[Unit]) -> list[Diagnostic]:
    """Declare and resolve ``units`` (dependencies first) into ``model``."""
    diagnostics: list[Diagnostic] = []
    report = diagnostics.append
    declarer = Declarer(model, report)
    for unit in units:
        declarer.declare(unit)
    names = _Names(model, report)
    declarer.structure(names.type_of, names.behaviour)
    BodyChecker(model, report).check(declarer.pending, declarer.extensions)
    return diagnostics


class _Names:
    """Resolution of type references and behaviour names in declarations."""

    def __init__(self, model: Model, report: Callable[[Diagnostic], None]):
        self.model = model
        self.report = report

    def _types(self, qname: ast.QualifiedName, ctx: Context) -> list[Symbol] | None:
        """The types ``qname`` names; None for an ambiguous name (reported here)."""
        found = self.model.lookup(qname.name.text, ctx, qname.namespace, lambda s: s.kind.is_type)
        if self.model.ambiguous(found):
            self.report(messages.ambiguous_name(qname.span, qname.name.text, found))
            return None
        return found

    def type_of(self, ref: ast.TypeRef, ctx: Context) -> T.Type:
        match ref:
            case ast.ListType():
                element = self.type_of(ref.element, ctx)
                if element.kind is T.Kind.LIST:
                    self.report(
                        messages.type_mismatch(
                            ref.span, element, None, "list element (lists of lists)"
                        )
                    )
                return T.list_of(element)
            case ast.RangeType():
                return T.range_of(self.type_of(ref.element, ctx))
            case ast.NamedType():
                qname = ref.name
                if qname.name.missing:
                    return T.UNKNOWN
                found = self._types(qname, ctx)
                if found is None:
                    return T.UNKNOWN
                if found:
                    self.model.references[qname.name] = found[0]
                    return found[0].type or T.UNKNOWN
                if qname.namespace is None and qname.name.text in T.PRIMITIVES:
                    return T.PRIMITIVES[qname.name.text]
                self.report(
                    messages.undefined_type(
                        qname.span, str(qname), closest(qname.name.text, self._type_names(ctx))
                    )
                )
        return T.UNKNOWN

    def _type_names(self, ctx: Context) -> list[str]:
        names = list(T.PRIMITIVES)
        for ns in (ctx.namespace, *ctx.uses, ""):
            for part in self.model.namespace_parts(ns):
                names.extend(
                    n for n, syms in part.symbols.items() if any(s.kind.is_type for s in syms)
                )
        return names

    def behaviour(self, name: ast.BehaviourName, ctx: Context) -> Symbol | None:
        """The declaration a `inherits`, `extend` or `of` clause names."""
        if name.name.missing:
            return None
        if name.actor is None:
            qname = ast.QualifiedName(name.span, name.namespace, name.name)
            found = self.model.lookup(
                name.name.text,
                ctx,
                name.namespace,
                lambda s: s.kind.is_type or s.kind is SymbolKind.MODIFIER,
            )
            if self.model.ambiguous(found):
                self.report(messages.ambiguous_name(name.span, name.name.text, found))
                return None
            if not found and name.namespace is None and name.name.text in T.PRIMITIVES:
                return Symbol(
                    SymbolKind.PRIMITIVE, name.name.text, type=T.PRIMITIVES[name.name.text]
                )
            if not found:
                self.report(
                    messages.undefined_type(
                        name.span, str(qname), closest(name.name.text, self._type_names(ctx))
                    )
                )
                return None
            self.model.references[name.name] = found[0]
            return found[0]
        actors = self._types(name.actor, ctx)
        if actors is None:
            return None
        if not actors:
            self.report(
                messages.undefined_type(
                    name.actor.span,
                    str(name.actor),
                    closest(name.actor.name.text, self._type_names(ctx)),
                )
            )
            return None
        actor = actors[0]
        self.model.references[name.actor.name] = actor
        found = self.model.behaviour(actor, name.name.text) or self.model.modifier(
            actor, name.name.text
        )
        if not found:
            pool = [s.name for s in self.model.behaviours_of(actor)]
            self.report(
                messages.unknown_behaviour(
                    name.name.span, name.name.text, actor, closest(name.name.text, pool)
                )
            )
            return None
        self.model.references[name.name] = found[0]
        return found[0]
