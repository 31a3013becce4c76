"""Resolution pass over declaration bodies: constraints, defaults, methods,
events, behaviour invocations, modifier applications and `do` trees.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from osc2check import memory, messages
from osc2check.diagnostics import Diagnostic
from osc2check.semantics import types as T
from osc2check.semantics.bindings import argument_values
from osc2check.semantics.builtins import OVERLAP_KINDS, PREDEFINED_EVENTS
from osc2check.semantics.calls import CallChecker, Extra, read_cover_item
from osc2check.semantics.declare import Pending
from osc2check.semantics.expressions import ExpressionChecker
from osc2check.semantics.model import Context, Model
from osc2check.semantics.phases import tree_members
from osc2check.semantics.scope import BEHAVIOUR_KINDS, Scope, declaration_scope
from osc2check.semantics.suggest import closest
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast


class BodyChecker:
    def __init__(self, model: Model, report: Callable[[Diagnostic], None]):
        self.model = model
        self.report = report
        self.expr = ExpressionChecker(model, report, self._method_call)
        self.calls = CallChecker(self.expr, report)
        self._time: T.Type | None = None
        self._dos: dict[Symbol, int] = {}  # `do` directives per declaration, extensions too

    # ---- helpers -------------------------------------------------------------------

    def _method_call(
        self,
        method: Symbol,
        params: list[Symbol],
        arguments: tuple[ast.Argument, ...],
        scope: Scope,
        call: ast.Node,
    ) -> None:
        self.calls.check(method, params, arguments, scope, call)

    @property
    def time_type(self) -> T.Type:
        if self._time is None:
            self._time = self.expr.physical_type((0, 0, 1, 0, 0, 0, 0, 0))
        return self._time

    def _duration_extra(self) -> tuple[Extra, ...]:
        return (Extra("duration", T.range_of(self.time_type)),)

    # ---- declarations ------------------------------------------------------------

    def check(self, pending: list[Pending], extensions: list[Pending]) -> None:
        try:
            for p in pending:
                decl = p.decl
                with memory.analysing(*_element(p)):  # named if the memory budget runs out
                    if isinstance(decl, ast.StructuredDecl) and p.symbol is not None:
                        self._structured(p.symbol, decl, p.context)
                    elif isinstance(decl, ast.GlobalDecl):
                        self._field(decl.field, Scope(p.context), None)
                    elif isinstance(decl, ast.EnumDecl):
                        self._enum_values(decl, p.context)
            for p in extensions:
                if isinstance(p.decl, ast.ExtendDecl):
                    target = self.model.declarations.get(p.decl)
                    if target is not None:
                        scope = declaration_scope(target, p.context)
                        self._members(target, p.decl.members, scope)
        finally:
            # The expression checker calls back into this one: unlinked, they leave no
            # reference cycle that would keep the model alive after its analysis.
            self.expr.check_call = None

    def _enum_values(self, decl: ast.EnumDecl, ctx: Context) -> None:
        for member in decl.members:
            if member.value is not None and not isinstance(
                member.value, (ast.IntLiteral, ast.NameRef, ast.EnumRef)
            ):
                self.expr.check(member.value, Scope(ctx), T.UINT, "enum value")

    def _structured(self, sym: Symbol, decl: ast.StructuredDecl, ctx: Context) -> None:
        scope = declaration_scope(sym, ctx)
        if decl.inherits is not None and decl.inherits.condition is not None and sym.parent:
            self._condition(sym, decl.inherits.condition, ctx)
        self._members(sym, decl.members, scope)

    def _condition(self, sym: Symbol, cond: ast.Node, ctx: Context) -> None:
        scope = Scope(ctx, owner=sym.parent)
        if isinstance(cond, ast.Binary) and cond.op == "==" and isinstance(cond.left, ast.NameRef):
            field_type = self.expr.check(cond.left, scope)
            if not field_type.is_unknown and field_type.kind not in (T.Kind.BOOL, T.Kind.ENUM):
                self.report(messages.inheritance_guard(cond.left.span, field_type))
                return
            self.expr.check(cond.right, scope, field_type, "inheritance condition")
            return
        self.expr.condition(cond, scope, "inheritance condition")

    def _members(self, owner: Symbol, members: tuple[ast.Member, ...], scope: Scope) -> None:
        emitted = self._implicit_events(owner, members)
        for member in members:
            match member:
                case ast.FieldDecl():
                    self._field(member, scope, owner)
                case ast.EventDecl():
                    self._event_declaration(member, scope)
                case ast.KeepConstraint():
                    self.expr.condition(member.expr, scope, "constraint")
                case ast.RemoveDefault():
                    self._remove_default(member, scope)
                case ast.MethodDecl():
                    self._method(member, scope)
                case ast.CoverageDecl():
                    self._coverage(member, scope)
                case ast.Invocation():
                    if owner.kind in BEHAVIOUR_KINDS:
                        self._modifier_application(member, scope, None, None)
                    else:  # struct and actor members include no modifier application
                        self.report(messages.misplaced_modifier(member.span, owner))
                case ast.OnDirective():
                    self._behaviour_allowed(owner, member)
                    local = self._event_spec(member.event, scope)
                    for item in member.members:
                        self._do_body(item, local, emitted)
                case ast.DoDirective():
                    if self._behaviour_allowed(owner, member):
                        self._dos[owner] = self._dos.get(owner, 0) + 1
                        if self._dos[owner] > 1:  # §7.3.9: extensions included
                            self.report(messages.second_do(member.span, owner))
                    self._do_member(member.member, scope.child(), emitted)

    def _behaviour_allowed(self, owner: Symbol, member: ast.Node) -> bool:
        if owner.kind in BEHAVIOUR_KINDS:
            return True
        self.report(
            messages.misplaced_member(
                member.span, owner, "do" if isinstance(member, ast.DoDirective) else "on"
            )
        )
        return False

    def _implicit_events(self, owner: Symbol, members: tuple[ast.Member, ...]) -> set[str]:
        """Events emitted but never declared (the paper's dialect) become implicit events."""
        emitted: set[str] = set()
        for member in members:
            if not isinstance(member, (ast.DoDirective, ast.OnDirective)):
                continue
            for node in tree_members(member):
                if isinstance(node, ast.Emit) and not node.event.missing:
                    name = node.event.text
                    declared = [
                        s for s in self.model.member(owner, name) if s.kind is SymbolKind.EVENT
                    ]
                    if not declared and name not in PREDEFINED_EVENTS:
                        sym = Symbol(
                            SymbolKind.EVENT,
                            name,
                            owner.namespace,
                            node.span.uri,
                            node,
                            node.event.span,
                            owner=owner,
                            extra={"implicit": True},
                        )
                        self.model.members.setdefault(owner, {}).setdefault(name, []).append(sym)
                        self.model.symbols.append(sym)
                    emitted.add(name)
        return emitted

    def _field(self, field: ast.FieldDecl, scope: Scope, owner: Symbol | None) -> None:
        sym = self.model.references.get(field.names[0]) if field.names else None
        ftype = sym.type if sym is not None and sym.type is not None else T.UNKNOWN
        if (
            field.type is not None
            and ftype.kind is T.Kind.RANGE
            and ftype.element is not None
            and not ftype.element.is_unknown
            and not ftype.element.is_numeric
        ):
            self.report(messages.range_of_non_numeric(field.type.span, ftype.element))
        if field.default is not None:
            what = f"default of `{field.names[0].text}`" if field.names else "default"
            if field.type is None:
                t = self.expr.check(field.default, scope)
                if sym is not None:
                    sym.type = t
            else:
                self.expr.check(field.default, scope, ftype, what)
        if field.with_members:
            inner = scope.child(it=ftype)
            for item in field.with_members:
                match item:
                    case ast.KeepConstraint() | ast.RemoveDefault():
                        self._with_member(item, inner, None, None)
                    case ast.Until():  # §7.3: a field's `with:` holds constraints only
                        self.report(messages.misplaced_in_with(item.span, "until", True))
                    case ast.Invocation() if not item.name.missing:
                        self.report(
                            messages.misplaced_in_with(item.name.span, item.name.text, True, True)
                        )

    def _remove_default(self, member: ast.RemoveDefault, scope: Scope) -> None:
        target = member.target
        if isinstance(target, ast.NameRef):
            sym = self.expr.value_symbol(target.name, scope)
            if sym is None or sym.kind is not SymbolKind.FIELD:
                self.report(messages.remove_default_target(target.span, str(target.name)))
                return
            self.model.references[target.name.name] = sym
            return
        self.expr.check(target, scope)

    def _method(self, member: ast.MethodDecl, scope: Scope) -> None:
        sym = self.model.declarations.get(member)
        inner = scope.child()
        if sym is not None:
            for param in sym.parameters:
                inner.locals[param.name] = param
                if param.default is not None:
                    self.expr.check(param.default, scope, param.type, f"default of `{param.name}`")
        if member.kind == "expression" and member.body is not None:
            expected = sym.type if sym is not None and sym.type is not T.NONE else None
            self.expr.check(member.body, inner, expected, "method result")
        for value in argument_values(member.external_arguments):  # `external pkg.fn(x)`
            self.expr.check(value, inner)

    def _event_declaration(self, member: ast.EventDecl, scope: Scope) -> None:
        sym = self.model.declarations.get(member)
        params = sym.parameters if sym is not None else ()
        inner = scope.child()
        for param in params:
            inner.locals[param.name] = param
            if param.default is not None:
                self.expr.check(param.default, scope, param.type, f"default of `{param.name}`")
        if member.spec is None:
            return
        if params:  # §7.3.10.2: only an event without parameters has a specification
            self.report(messages.event_spec_with_parameters(member.spec.span, member.name.text))
        self._event_spec(member.spec, inner)

    def _coverage(self, member: ast.CoverageDecl, scope: Scope) -> None:
        """`cover`/`record` (§7.5): the item's name is also its expression unless an
        `expression:` is given; `items:` and `override:` name other items."""
        cover, problems = read_cover_item(member, scope.owner)
        self.model.cover_items[member] = cover
        for problem in problems:
            self.report(problem)
        item, expression, named = cover.name_node, cover.expression, dict(cover.parameters)
        item_type = T.UNKNOWN if expression is None else self.expr.check(expression, scope)
        inner = scope.child()  # `ignore:` and `illegal:` speak of the item by its name
        if isinstance(item, ast.NameRef) and item.name.namespace is None:
            inner.locals[item.name.name.text] = Symbol(
                SymbolKind.IMPLICIT,
                item.name.name.text,
                decl=member,
                name_span=item.name.name.span,
                type=item_type,
            )
        for value in cover.positional:
            self.expr.check(value, scope)
        for key, value in named.items():
            if key in ("name", "expression", "items", "override"):
                continue
            if key == "unit" and isinstance(value, ast.NameRef):
                unit_name = value.name.name
                unit = self.model.unit(unit_name.text)
                if unit is None:
                    self.report(
                        messages.unknown_unit(
                            unit_name.span,
                            unit_name.text,
                            closest(unit_name.text, self.model.all_units()),
                        )
                    )
                else:
                    self.model.references[unit_name] = unit
            elif key == "event" and isinstance(value, ast.NameRef):
                self._event_path((value.name.name,), scope, value.span)
            elif key == "text":
                self.expr.check(value, scope, T.STRING, key)
            elif key in ("ignore", "illegal"):
                self.expr.condition(value, inner, f"`{key}` expression")
            else:
                self.expr.check(value, scope)

    # ---- events ---------------------------------------------------------------------

    def _event_spec(self, spec: ast.Node, scope: Scope) -> Scope:
        """Check an event spec; returns the scope its `as` binding is visible in."""
        if isinstance(spec, ast.EventReference):
            event = self._event_path(spec.path, scope, spec.span)
            inner = scope
            if spec.alias is not None:
                inner = scope.child()
                binding = Symbol(
                    SymbolKind.IMPLICIT,
                    spec.alias.text,
                    decl=spec,
                    name_span=spec.alias.span,
                    type=T.UNKNOWN,
                    extra={"event": event},
                )
                inner.locals[spec.alias.text] = binding
                self.model.references[spec.alias] = binding
            if spec.condition is not None:
                self.expr.condition(spec.condition, inner, "event condition")
            return inner
        if isinstance(spec, ast.EventCondition):
            self.expr.condition(spec.expr, scope, "event condition")
        return scope

    def _event_path(self, path: tuple[ast.Name, ...], scope: Scope, span: Span) -> Symbol | None:
        if not path or any(p.missing for p in path):
            return None
        *prefix, last = path
        owner = scope.owner
        if prefix:
            target = self.expr.check(
                ast.NameRef(prefix[0].span, ast.QualifiedName(prefix[0].span, None, prefix[0])),
                scope,
            )
            sym = self.model.references.get(prefix[0])
            for name in prefix[1:]:
                if target.kind is not T.Kind.COMPOUND or target.symbol is None:
                    break
                found = self.model.member(target.symbol, name.text)
                if not found:
                    self.report(messages.unknown_member(name.span, name.text, target, None))
                    return None
                sym = found[0]
                self.model.references[name] = sym
                target = sym.type or T.UNKNOWN
            if sym is not None and sym.kind is SymbolKind.LABEL:
                if last.text in PREDEFINED_EVENTS:
                    return None
            owner = target.symbol if target.kind is T.Kind.COMPOUND else None
            if target.is_unknown:
                return None
        if last.text in PREDEFINED_EVENTS:
            return None
        current: Scope | None = scope if not prefix else None
        candidates = [owner] if prefix else []
        while current is not None:
            if current.owner is not None:
                candidates.append(current.owner)
            current = current.parent
        for cand in candidates:
            if cand is None:
                continue
            events = [s for s in self.model.member(cand, last.text) if s.kind is SymbolKind.EVENT]
            if events:
                self.model.references[last] = events[0]
                return events[0]
        names = [
            s.name
            for c in candidates
            if c is not None
            for s in self.model.all_members(c)
            if s.kind is SymbolKind.EVENT
        ]
        self.report(
            messages.undefined_event(
                last.span, last.text, closest(last.text, [*names, *PREDEFINED_EVENTS])
            )
        )
        return None

    # ---- behaviour -------------------------------------------------------------------

    def _do_member(self, member: ast.DoMember, scope: Scope, emitted: set[str]) -> None:
        if member.label is not None and not member.label.missing:
            label = Symbol(
                SymbolKind.LABEL,
                member.label.text,
                decl=member,
                name_span=member.label.span,
                type=T.UNKNOWN,
            )
            scope.locals[member.label.text] = label
            self.model.references[member.label] = label
        self._do_body(member.body, scope, emitted)

    def _do_body(self, body: ast.Node, scope: Scope, emitted: set[str]) -> None:
        match body:
            case ast.Composition():
                self._composition(body, scope, emitted)
            case ast.Invocation():
                behaviour = self._behaviour_invocation(body, scope)
                label = next(
                    (
                        s
                        for s in scope.locals.values()
                        if s.kind is SymbolKind.LABEL
                        and s.decl is not None
                        and getattr(s.decl, "body", None) is body
                    ),
                    None,
                )
                if label is not None and behaviour is not None:
                    label.type = behaviour.type
            case ast.Wait():
                self._event_spec(body.event, scope)
            case ast.Emit():
                self._emit(body, scope)
            case ast.CallDirective():
                self.expr.check(body.call, scope)

    def _emit(self, emit: ast.Emit, scope: Scope) -> None:
        if emit.event.missing:
            return
        event = self._event_path((emit.event,), scope, emit.span)
        if event is not None and event.extra.get("implicit"):
            self.report(messages.undeclared_event(emit.event.span, emit.event.text))
        params = list(event.parameters) if event is not None else []
        if emit.arguments or event is not None:  # bound with none given: defaults apply
            self.calls.check(
                event or Symbol(SymbolKind.EVENT, emit.event.text),
                params,
                emit.arguments,
                scope,
                emit,
            )

    def _composition(self, comp: ast.Composition, scope: Scope, emitted: set[str]) -> None:
        op_symbol = Symbol(SymbolKind.ACTION, comp.op)
        extras = list(self._duration_extra())
        if comp.op == "parallel":
            extras += [
                Extra("overlap", T.UNKNOWN, words=OVERLAP_KINDS),
                Extra("start_to_start", self.time_type),
                Extra("end_to_end", self.time_type),
            ]
        binding = self.calls.check(op_symbol, [], comp.arguments, scope, comp, tuple(extras))
        overlap = binding.extra("overlap")
        if overlap is not None:
            value = overlap.value
            if not (isinstance(value, ast.NameRef) and value.name.name.text in OVERLAP_KINDS):
                self.report(messages.invalid_overlap(value.span, OVERLAP_KINDS))
        if comp.op == "one_of":
            for member in comp.members:
                if isinstance(member.body, ast.Wait):
                    self.report(messages.one_of_race(member.body.span))
                    break
        for member in comp.members:
            self._do_member(member, scope, emitted)
        inner = scope.child(it=None)
        for item in comp.with_members:
            self._with_member(item, inner, None, None)

    def _actor_of(self, expr: ast.Node | None, scope: Scope) -> tuple[Symbol | None, bool]:
        """The actor type an invocation's receiver denotes, and whether it is known."""
        if expr is None:
            return None, True
        t = self.expr.check(expr, scope)
        if t.is_unknown:
            return None, False
        if t.kind is T.Kind.COMPOUND and t.symbol is not None:
            return t.symbol, True
        self.report(messages.not_an_actor_value(expr.span, t))
        return None, False

    def _behaviour_invocation(self, inv: ast.Invocation, scope: Scope) -> Symbol | None:
        actor, known = self._actor_of(inv.actor, scope)
        if not known or inv.name.missing:
            self._loose(inv, scope)
            return None
        name = inv.name.text
        found: list[Symbol] = []
        if actor is not None:
            found = self.model.behaviour(actor, name)
        else:
            if scope.actor is not None:
                found = self.model.behaviour(scope.actor, name)
            if not found:
                found = self.model.lookup(name, scope.context, None, lambda s: s.kind.is_behaviour)
                if self.model.ambiguous(found):
                    self.report(messages.ambiguous_name(inv.name.span, name, found))
                    self._loose(inv, scope)
                    return None
        if not found:
            pool = [s.name for s in self.model.behaviours_of(actor or scope.actor)]
            self.report(messages.unknown_behaviour(inv.name.span, name, actor, closest(name, pool)))
            self._loose(inv, scope)
            return None
        behaviour = found[0]
        self.model.references[inv.name] = behaviour
        if behaviour.toolkit:
            self.report(messages.toolkit_extension(inv.name.span, behaviour))
        binding = self.calls.check(
            behaviour,
            self.model.parameters(behaviour),
            inv.arguments,
            scope,
            inv,
            self._duration_extra(),
            library_rules=behaviour.library,
            allow_range=True,
        )
        untils = tuple(w for w in inv.with_members if isinstance(w, ast.Until))
        if untils:
            self.model.bindings[inv] = replace(binding, until=untils)
        inner = scope.child(it=behaviour.type, behaviour=behaviour)
        for item in inv.with_members:
            self._with_member(item, inner, behaviour, actor or scope.actor)
        return behaviour

    def _loose(self, inv: ast.Invocation, scope: Scope) -> None:
        for value in argument_values(inv.arguments):
            self.expr.check(value, scope)
        for item in inv.with_members:
            if isinstance(item, ast.KeepConstraint):
                self.expr.check(item.expr, scope.child(it=T.UNKNOWN))

    def _with_member(
        self, item: ast.Node, scope: Scope, behaviour: Symbol | None, actor: Symbol | None
    ) -> None:
        match item:
            case ast.KeepConstraint():
                self.expr.condition(item.expr, scope, "constraint")
            case ast.RemoveDefault():
                self._remove_default(item, scope)
            case ast.Until():
                self._event_spec(item.event, scope)
            case ast.Invocation():
                self._modifier_application(item, scope, behaviour, actor)

    def _modifier_application(
        self, inv: ast.Invocation, scope: Scope, behaviour: Symbol | None, actor: Symbol | None
    ) -> None:
        if inv.name.missing:
            return
        name = inv.name.text
        receiver, known = (
            self._actor_of(inv.actor, scope) if inv.actor is not None else (None, True)
        )
        if not known:
            self._loose(inv, scope)
            return
        found: list[Symbol] = []
        keys: list[Symbol | None] = []
        if receiver is not None:
            keys = [receiver]
        else:
            if behaviour is not None:
                keys.append(behaviour)
            if actor is not None:
                keys.append(actor)
            if scope.owner is not None and scope.owner.kind in BEHAVIOUR_KINDS:
                keys.append(scope.owner)
                if scope.owner.actor is not None:
                    keys.append(scope.owner.actor)
            keys.append(None)
        for key in keys:
            found = self.model.modifier(key, name)
            if found:
                break
        if not found and receiver is None:
            found = [
                s for s in self.model.lookup(name, scope.context) if s.kind is SymbolKind.MODIFIER
            ]
        if not found:
            self._unknown_modifier(inv, name, keys, scope)
            self._loose(inv, scope)
            return
        modifier = found[0]
        self.model.references[inv.name] = modifier
        if modifier.toolkit:
            self.report(messages.toolkit_extension(inv.name.span, modifier))
        self.calls.check(
            modifier,
            self.model.parameters(modifier),
            inv.arguments,
            scope,
            inv,
            library_rules=modifier.library,
            allow_range=True,
        )
        if inv.with_members:
            inner = scope.child(it=None)
            for item in inv.with_members:
                self._with_member(item, inner, None, None)

    def _unknown_modifier(
        self, inv: ast.Invocation, name: str, keys: list[Symbol | None], scope: Scope
    ) -> None:
        elsewhere = [
            s
            for s in self.model.symbols + (self.model.base.symbols if self.model.base else [])
            if s.kind is SymbolKind.MODIFIER and s.name == name
        ]
        if elsewhere:
            self.report(messages.modifier_not_applicable(inv.name.span, elsewhere[0]))
            return
        pool: list[str] = []
        for key in keys:
            pool.extend(s.name for s in self.model.modifiers_of(key))
        self.report(messages.unknown_modifier(inv.name.span, name, closest(name, pool)))


def _element(p: Pending) -> tuple[Span, str]:
    """Where a declaration is and what it is, for ``memory.analysing``."""
    sym = p.symbol
    if sym is not None and sym.name_span is not None:
        return sym.name_span, f"checking {sym.kind.value} `{sym.qualified_name}`"
    return p.decl.span, "checking a declaration"
