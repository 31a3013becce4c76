"""Definition pass: fill namespaces with the symbols each file declares.

Then the structure pass binds what declarations say about each other:
physical dimensions and units, the actor of each behaviour and modifier,
inheritance, ``extend``, and the members (fields, events, methods) of every
compound type. Expressions inside bodies are checked later (``bodies.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Literal, TypedDict, Unpack, cast

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.numbers import exact_number
from osc2check.semantics import types as T
from osc2check.semantics.enums import resolve_aliases
from osc2check.semantics.model import Context, Model
from osc2check.semantics.overrides import check_overrides
from osc2check.semantics.suggest import closest
from osc2check.semantics.symbols import COMPOUND_KINDS, Symbol, SymbolKind
from osc2check.syntax import ast

_DECL_KINDS = {
    ast.StructDecl: SymbolKind.STRUCT,
    ast.ActorDecl: SymbolKind.ACTOR,
    ast.ScenarioDecl: SymbolKind.SCENARIO,
    ast.ActionDecl: SymbolKind.ACTION,
    ast.ModifierDecl: SymbolKind.MODIFIER,
}
TOOLKIT_NAMESPACE = "osc2toolkit"
# The toolkit's own library files (its extensions, CARLA's world): they may use what the
# toolkit adds to the standard without a warning (D803).
TOOLKIT_NAMESPACES = (TOOLKIT_NAMESPACE, "carla")

# How the structure pass resolves a type reference and a behaviour name (``resolve._Names``).
TypeResolver = Callable[[ast.TypeRef, Context], T.Type]
BehaviourResolver = Callable[[ast.BehaviourName, Context], Symbol | None]
# The model's behaviours or modifiers: actor or behaviour (None: unassociated) → name → symbols.
_KeyedTable = dict[Symbol | None, dict[str, list[Symbol]]]


@dataclass
class Unit:
    """One file to declare, with the context its first line starts in."""

    uri: str
    file: ast.File
    context: Context
    library: bool = False
    comments: dict[int, str] = field(default_factory=dict)  # line → comment text


def si_dimension(
    args: tuple[ast.Argument, ...],
    *,
    for_unit: bool,
    report: Callable[[Diagnostic], None] | None = None,
) -> tuple[T.Dimension, Fraction, Fraction]:
    """The SI exponents, factor and offset of ``SI(m: 1, s: -1, factor: ...)`` (a type's
    or, with ``for_unit``, a unit's); what is not one of them is reported (T207's
    neighbours) when ``report`` is given, and left out."""
    dim = [0] * len(T.BASE_UNITS)
    factor, offset = Fraction(1), Fraction(0)
    tell = report or (lambda _: None)
    for arg in args:
        if not isinstance(arg, ast.NamedArgument):
            tell(messages.si_argument(arg.span, None))
            continue
        key = arg.name.text
        number = _constant_number(arg.value)
        if key in T.BASE_UNITS:
            if number is None or number.denominator != 1:
                tell(messages.si_argument(arg.span, key))
                continue
            dim[T.BASE_UNITS.index(key)] = int(number)
        elif for_unit and key in ("factor", "offset"):
            if number is None:
                tell(messages.si_argument(arg.span, key))
                continue
            if key == "factor":
                factor = T.snap_factor(number)
            else:
                offset = T.snap_factor(number)
        else:
            tell(messages.si_argument(arg.name.span, key))
    return cast(T.Dimension, tuple(dim)), factor, offset  # one exponent per base unit


class _SymbolFields(TypedDict, total=False):
    """The ``Symbol`` fields that some declarations set when they are declared."""

    type: T.Type | None
    owner: Symbol | None
    value: int
    default: ast.Expr | None
    has_default: bool
    parameters: tuple[Symbol, ...]


@dataclass
class Pending:
    decl: ast.Declaration
    symbol: Symbol | None
    context: Context
    unit: Unit


class Declarer:
    """Runs the definition and structure passes over a set of files."""

    def __init__(self, model: Model, report: Callable[[Diagnostic], None]):
        self.model = model
        self.report = report
        self.pending: list[Pending] = []
        self.extensions: list[Pending] = []
        self.methods: list[tuple[Symbol, Symbol]] = []  # (owner, method), declaration order
        self.exported_names: list[tuple[ast.QualifiedName, Context]] = []
        self.aliases: list[Symbol] = []  # enum members whose value names another member

    # ---- pass 1 ------------------------------------------------------------------

    def declare(self, unit: Unit) -> None:
        ctx = unit.context
        for decl in unit.file.declarations:
            match decl:
                case ast.NamespaceDecl():
                    name = "" if decl.name.text == "null" else decl.name.text
                    uses = tuple(u.text for u in decl.uses)
                    if name.startswith("std") and not unit.library:
                        self.report(messages.reserved_name(decl.name.span, name))
                    self.model.namespace(name, create=True) if not self._is_library_ns(
                        name
                    ) else None
                    ctx = Context(name, uses)
                case ast.UseStatement():
                    added: list[str] = []
                    for dotted in decl.names:
                        added.extend(n.text for n in dotted)
                    ctx = Context(ctx.namespace, tuple(dict.fromkeys((*ctx.uses, *added))))
                    if not unit.library:
                        self.report(
                            messages.use_statement(
                                decl.span,
                                ".".join(n.text for n in decl.names[0]) if decl.names else "",
                            )
                        )
                case ast.ExportDecl():
                    self._export(decl, ctx)
                case ast.ImportDecl():
                    pass
                case ast.ExtendDecl() | ast.EnumExtension():
                    self.extensions.append(Pending(decl, None, ctx, unit))
                case _:
                    symbol = self._declare_one(decl, ctx, unit)
                    self.pending.append(Pending(decl, symbol, ctx, unit))

    def _is_library_ns(self, name: str) -> bool:
        base = self.model.base
        return base is not None and name in base.namespaces

    def _export(self, decl: ast.ExportDecl, ctx: Context) -> None:
        ns = self.model.namespace(ctx.namespace, create=True)
        for item in decl.items:
            if item.kind == "all":
                ns.exports_all = True
            elif item.kind == "namespace" and item.namespace is not None:
                ns.reexports.append((item.namespace.text, None))
            elif item.name is not None:
                self.exported_names.append((item.name, ctx))
                if item.name.namespace not in (None, ctx.namespace):
                    ns.reexports.append((item.name.namespace, item.name.name.text))
                else:
                    ns.exports.add(item.name.name.text)

    def _new(
        self,
        kind: SymbolKind,
        name: ast.Name,
        decl: ast.Node,
        ctx: Context,
        unit: Unit,
        **kw: Unpack[_SymbolFields],
    ) -> Symbol:
        sym = Symbol(
            kind,
            name.text,
            ctx.namespace,
            unit.uri,
            decl,
            name.span,
            library=unit.library,
            toolkit=ctx.namespace == TOOLKIT_NAMESPACE,
            doc=_doc_comment(unit, decl),
            context=ctx,
            **kw,
        )
        self.model.declarations[decl] = sym
        self.model.references[name] = sym
        self.model.symbols.append(sym)
        return sym

    def _add_global(self, sym: Symbol, ctx: Context) -> None:
        ns = self.model.namespace(ctx.namespace, create=True)
        if ns is None:
            return
        before = list(ns.symbols.get(sym.name, ()))
        if self.model.base is not None and ctx.namespace in self.model.base.namespaces:
            before += self.model.base.namespaces[ctx.namespace].symbols.get(sym.name, ())
        ns.add(sym)
        if before and sym.name_span is not None:
            self.report(messages.duplicate_definition(sym.name_span, sym.name, before[0]))

    def _declare_one(self, decl: ast.Node, ctx: Context, unit: Unit) -> Symbol | None:
        match decl:
            case ast.PhysicalTypeDecl():
                sym = self._new(SymbolKind.PHYSICAL_TYPE, decl.name, decl, ctx, unit)
                sym.dimension = self._dimension(decl.si, decl, for_unit=False)[0]
                sym.type = T.Type(T.Kind.PHYSICAL, sym, sym.dimension)
                self._add_global(sym, ctx)
                return sym
            case ast.UnitDecl():
                sym = self._new(SymbolKind.UNIT, decl.name, decl, ctx, unit)
                dim, factor, offset = self._dimension(decl.si, decl, for_unit=True)
                sym.dimension, sym.factor, sym.offset = dim, factor, offset
                previous = self.model.unit(sym.name)
                if previous is not None and previous.decl is not None:
                    self.report(messages.duplicate_definition(decl.name.span, sym.name, previous))
                self.model.units[sym.name] = sym
                return sym
            case ast.EnumDecl():
                sym = self._new(SymbolKind.ENUM, decl.name, decl, ctx, unit)
                sym.type = T.Type(T.Kind.ENUM, sym)
                self._add_global(sym, ctx)
                self._enum_members(sym, decl.members, ctx, unit)
                return sym
            case ast.GlobalDecl():
                syms = []
                for name in decl.field.names:
                    sym = self._new(
                        SymbolKind.GLOBAL,
                        name,
                        decl.field,
                        ctx,
                        unit,
                        default=decl.field.default,
                        has_default=decl.field.default is not None,
                    )
                    self._add_global(sym, ctx)
                    syms.append(sym)
                return syms[0] if syms else None
            case ast.StructuredDecl():
                kind = _DECL_KINDS[type(decl)]
                sym = self._new(kind, decl.name.name, decl, ctx, unit)
                if kind is not SymbolKind.MODIFIER:
                    sym.type = T.Type(T.Kind.COMPOUND, sym)
                if decl.name.actor is None and kind is not SymbolKind.MODIFIER:
                    self._add_global(sym, ctx)
                return sym
        return None

    def _enum_members(
        self, enum: Symbol, members: tuple[ast.EnumMember, ...], ctx: Context, unit: Unit
    ) -> None:
        """Declare members; a literal value sets the count for the next implicit ones, a
        value that names another member is an alias, resolved by `enums.resolve_aliases`."""
        existing = self.model.enum_values(enum)
        plain = [m.value for m in existing if "alias" not in m.extra]
        next_value = max(plain, default=-1) + 1
        by_name = {m.name: m for m in existing}
        for member in members:
            value = next_value
            alias = member.value if isinstance(member.value, (ast.NameRef, ast.EnumRef)) else None
            if isinstance(member.value, ast.IntLiteral):
                value = member.value.value
            sym = self._new(
                SymbolKind.ENUM_MEMBER,
                member.name,
                member,
                ctx,
                unit,
                owner=enum,
                value=value,
                type=enum.type,
            )
            if alias is not None:
                sym.extra["alias"] = alias
                self.aliases.append(sym)
            else:
                next_value = value + 1
            if member.name.text in by_name and not member.name.missing:
                self.report(
                    messages.duplicate_member(
                        member.name.span, member.name.text, enum.name, by_name[member.name.text]
                    )
                )
            by_name[member.name.text] = sym
            self.model.enum_members.setdefault(enum, []).append(sym)

    def _dimension(
        self, args: tuple[ast.Argument, ...], decl: ast.Node, *, for_unit: bool
    ) -> tuple[T.Dimension, Fraction, Fraction]:
        return si_dimension(args, for_unit=for_unit, report=self.report)

    # ---- pass 2: structure -----------------------------------------------------------

    def structure(
        self, resolve_type: TypeResolver, resolve_behaviour_name: BehaviourResolver
    ) -> None:
        """Bind units, actors, parents, extensions and members (in that order)."""
        self._resolve_type = resolve_type
        self._bind_exports()
        for p in self.pending:
            if isinstance(p.decl, ast.UnitDecl) and p.symbol is not None:
                self._unit_type(p)
        structured = [
            p
            for p in self.pending
            if isinstance(p.decl, ast.StructuredDecl) and p.symbol is not None
        ]
        for p in structured:  # modifiers `of` a behaviour need the behaviours first
            if not (isinstance(p.decl, ast.ModifierDecl) and p.decl.of is not None):
                self._associate(p, resolve_behaviour_name)
        for p in structured:
            if isinstance(p.decl, ast.ModifierDecl) and p.decl.of is not None:
                self._associate(p, resolve_behaviour_name)
        for p in self.pending:
            if isinstance(p.decl, ast.StructuredDecl) and p.symbol is not None:
                self._inherit(p, resolve_behaviour_name)
        for p in self.pending:
            if isinstance(p.decl, ast.StructuredDecl) and p.symbol is not None:
                self._members(p.symbol, p.decl.members, p.context, p.unit)
            elif isinstance(p.decl, ast.GlobalDecl):
                t = resolve_type(p.decl.field.type, p.context) if p.decl.field.type else T.UNKNOWN
                for name in p.decl.field.names:
                    sym = self.model.references.get(name)
                    if sym is not None:
                        sym.type = t
        for p in self.extensions:
            self._extend(p, resolve_behaviour_name)
        check_overrides(self.model, self.methods, self.report)
        resolve_aliases(self.model, self.aliases, self.report)

    def _bind_exports(self) -> None:
        """Bind `export name` to the declaration; an unprefixed name that a used
        namespace declares is re-exported from there (§7.7.4.1)."""
        for qname, ctx in self.exported_names:
            found = self.model.lookup(qname.name.text, ctx, qname.namespace)
            if not found:
                continue  # fields and methods are exported too; globals are bound here
            self.model.references[qname.name] = found[0]
            if qname.namespace is None and found[0].namespace != ctx.namespace:
                ns = self.model.namespace(ctx.namespace, create=True)
                ns.reexports.append((found[0].namespace, qname.name.text))

    def _unit_type(self, p: Pending) -> None:
        decl = p.decl
        sym = p.symbol
        assert isinstance(decl, ast.UnitDecl) and sym is not None  # as `structure` picks them
        target = self._lookup_type(decl.type, p.context)
        if target is None:
            return
        if target.kind is not SymbolKind.PHYSICAL_TYPE:
            self.report(messages.not_a_physical_type(decl.type.span, str(decl.type), target))
            return
        sym.type = target.type
        sym.owner = target
        assert sym.dimension is not None  # set when the unit was declared
        if target.dimension is not None and sym.dimension != target.dimension:
            self.report(
                messages.unit_dimension(
                    decl.name.span, sym.name, sym.dimension, target.name, target.dimension
                )
            )
            sym.dimension = target.dimension

    def _lookup_type(self, qname: ast.QualifiedName, ctx: Context) -> Symbol | None:
        found = self.model.lookup(
            qname.name.text,
            ctx,
            qname.namespace,
            lambda s: s.kind.is_type or s.kind is SymbolKind.MODIFIER,
        )
        if self.model.ambiguous(found):
            self.report(messages.ambiguous_name(qname.span, qname.name.text, found))
            return None
        if found:
            self.model.references[qname.name] = found[0]
            return found[0]
        if qname.namespace is None and qname.name.text in T.PRIMITIVES:
            return None
        if not qname.name.missing:
            candidates = [n for ns in self._visible_names(ctx) for n in ns]
            self.report(
                messages.undefined_type(
                    qname.span, str(qname), closest(qname.name.text, candidates)
                )
            )
        return None

    def _visible_names(self, ctx: Context) -> Iterator[list[str]]:
        for ns in (ctx.namespace, *ctx.uses, ""):
            for part in self.model.namespace_parts(ns):
                yield [n for n, syms in part.symbols.items() if any(s.kind.is_type for s in syms)]

    def _associate(self, p: Pending, resolve_behaviour_name: BehaviourResolver) -> None:
        decl = p.decl
        sym = p.symbol
        assert isinstance(decl, ast.StructuredDecl) and sym is not None  # as `structure` picks
        if decl.name.actor is not None:
            actor = self._lookup_type(decl.name.actor, p.context)
            if actor is not None and actor.kind is not SymbolKind.ACTOR:
                self.report(messages.not_an_actor(decl.name.actor.span, actor))
                actor = None
            sym.actor = actor
            if actor is None:
                return
        table = (
            self.model.modifiers
            if sym.kind is SymbolKind.MODIFIER
            else self.model.behaviours
            if sym.kind.is_behaviour
            else None
        )
        if isinstance(decl, ast.ModifierDecl) and decl.of is not None:
            target = resolve_behaviour_name(decl.of, p.context)
            if target is not None and not target.kind.is_behaviour:
                self.report(messages.modifier_of_not_behaviour(decl.of.span, target))
                target = None
            sym.of = target
            if target is not None:
                self._register(self.model.modifiers, target, sym)
            return
        if table is not None:
            if sym.actor is not None or sym.kind is SymbolKind.MODIFIER:
                self._register(table, sym.actor, sym)

    def _register(self, table: _KeyedTable, key: Symbol | None, sym: Symbol) -> None:
        group = table.setdefault(key, {}).setdefault(sym.name, [])
        previous = [s for s in self._existing_keyed(table, key, sym.name) if s is not sym]
        group.append(sym)
        if previous and sym.name_span is not None:
            self.report(
                messages.duplicate_definition(sym.name_span, sym.qualified_name, previous[0])
            )

    def _existing_keyed(self, table: _KeyedTable, key: Symbol | None, name: str) -> list[Symbol]:
        attr: Literal["behaviours", "modifiers"] = (
            "modifiers" if table is self.model.modifiers else "behaviours"
        )
        return self.model._keyed(attr, key, name)

    def _inherit(self, p: Pending, resolve_behaviour_name: BehaviourResolver) -> None:
        decl = p.decl
        sym = p.symbol
        assert isinstance(decl, ast.StructuredDecl) and sym is not None  # as `structure` picks
        if decl.inherits is None:
            return
        if sym.kind is SymbolKind.MODIFIER:
            self.report(
                messages.invalid_inheritance(
                    decl.inherits.span, sym, None, "a modifier cannot inherit"
                )
            )
            return
        parent = resolve_behaviour_name(decl.inherits.target, p.context)
        if parent is None:
            return
        if parent.kind is not sym.kind:
            self.report(
                messages.invalid_inheritance(
                    decl.inherits.target.span, sym, parent, "different kinds"
                )
            )
            return
        if parent is sym or any(a is sym for a in self.model.ancestors(parent)):
            self.report(
                messages.invalid_inheritance(decl.inherits.target.span, sym, parent, "cycle")
            )
            return
        span = decl.inherits.target.span
        if sym.kind.is_behaviour and _has_actor(sym) != _has_actor(parent):
            # §7.3.8.1: a behaviour of an actor inherits from a behaviour of an actor,
            # one without an actor from one without.
            self.report(
                messages.invalid_inheritance(
                    span, sym, parent, "actor" if _has_actor(sym) else "no actor"
                )
            )
        elif (
            sym.actor is not None
            and parent.actor is not None
            and not T.is_subtype(sym.actor, parent.actor)
        ):
            self.report(messages.invalid_inheritance(span, sym, parent, "actor"))
        if decl.inherits.condition is None and _is_conditional(parent):
            # §7.3.8.2.3, rule 1: a conditional type cannot be inherited unconditionally.
            self.report(messages.invalid_inheritance(span, sym, parent, "conditional"))
        sym.parent = parent
        sym.condition = decl.inherits.condition
        self.model.children.setdefault(parent, []).append(sym)

    def _extend(self, p: Pending, resolve_behaviour_name: BehaviourResolver) -> None:
        decl = p.decl
        assert isinstance(decl, (ast.ExtendDecl, ast.EnumExtension))  # what `declare` defers
        target = resolve_behaviour_name(decl.target, p.context)
        if target is None:
            return
        if isinstance(decl, ast.EnumExtension):
            if target.kind is not SymbolKind.ENUM:
                self.report(messages.cannot_extend(decl.target.span, target, "enum members"))
                return
            self._enum_members(target, decl.members, p.context, p.unit)
            return
        if target.kind not in COMPOUND_KINDS and target.kind is not SymbolKind.PRIMITIVE:
            self.report(messages.cannot_extend(decl.target.span, target, "members"))
            return
        self.model.declarations[decl] = target
        self._members(target, decl.members, p.context, p.unit)

    def _members(
        self, owner: Symbol, members: tuple[ast.Member, ...], ctx: Context, unit: Unit
    ) -> None:
        for member in members:
            match member:
                case ast.FieldDecl():
                    t = self._resolve_type(member.type, ctx) if member.type else T.UNKNOWN
                    kind = SymbolKind.VARIABLE if member.is_var else SymbolKind.FIELD
                    for name in member.names:
                        sym = self._new(
                            kind,
                            name,
                            member,
                            ctx,
                            unit,
                            type=t,
                            owner=owner,
                            default=member.default,
                            has_default=member.default is not None
                            or any(
                                isinstance(w, ast.KeepConstraint) and w.strength == "default"
                                for w in member.with_members
                            ),
                        )
                        self._add_member(owner, sym)
                case ast.EventDecl():
                    params = self._parameters(member.parameters, ctx, unit)
                    sym = self._new(
                        SymbolKind.EVENT,
                        member.name,
                        member,
                        ctx,
                        unit,
                        owner=owner,
                        parameters=params,
                    )
                    self._add_member(owner, sym)
                case ast.MethodDecl():
                    params = self._parameters(member.parameters, ctx, unit)
                    ret = (
                        self._resolve_type(member.return_type, ctx)
                        if member.return_type
                        else T.NONE
                    )
                    sym = self._new(
                        SymbolKind.METHOD,
                        member.name,
                        member,
                        ctx,
                        unit,
                        owner=owner,
                        parameters=params,
                        type=ret,
                    )
                    self._add_member(owner, sym)

    def _parameters(
        self, params: tuple[ast.Parameter, ...], ctx: Context, unit: Unit
    ) -> tuple[Symbol, ...]:
        result = []
        seen: dict[str, Symbol] = {}
        for param in params:
            t = self._resolve_type(param.type, ctx)
            sym = self._new(
                SymbolKind.ARGUMENT,
                param.name,
                param,
                ctx,
                unit,
                type=t,
                default=param.default,
                has_default=param.default is not None,
            )
            if param.name.text in seen:
                self.report(
                    messages.duplicate_member(
                        param.name.span, param.name.text, None, seen[param.name.text]
                    )
                )
            seen[param.name.text] = sym
            result.append(sym)
        return tuple(result)

    def _add_member(self, owner: Symbol, sym: Symbol) -> None:
        own = self.model.members.setdefault(owner, {}).setdefault(sym.name, [])
        same_ns = [
            s
            for s in self.model.own_members(owner, sym.name)
            if s.namespace == sym.namespace and s is not sym
        ]
        own.append(sym)
        if sym.kind is SymbolKind.METHOD:
            # methods may be redeclared to override; `overrides.check_overrides` decides
            self.methods.append((owner, sym))
            same_ns = [s for s in same_ns if s.kind is not SymbolKind.METHOD]
        if sym.name_span is None or sym.name == "":
            return
        if same_ns:
            self.report(messages.duplicate_member(sym.name_span, sym.name, owner.name, same_ns[0]))
            return
        if sym.kind in (SymbolKind.METHOD, SymbolKind.EVENT):
            return  # an inheriting type may override a method or an event (§7.3.7.2, §7.3.10.2)
        inherited = [
            s
            for a in list(self.model.ancestors(owner))[1:]
            for s in self.model.own_members(a, sym.name)
            if s.namespace == sym.namespace
        ]
        if inherited:
            self.report(
                messages.shadows_inherited(sym.name_span, sym.name, owner.name, inherited[0])
            )


def _has_actor(behaviour: Symbol) -> bool:
    """Whether a scenario or action is declared `actor.name` (resolved or not)."""
    decl = behaviour.decl
    return isinstance(decl, ast.StructuredDecl) and decl.name.actor is not None


def _is_conditional(symbol: Symbol) -> bool:
    decl = symbol.decl
    return (
        isinstance(decl, ast.StructuredDecl)
        and decl.inherits is not None
        and decl.inherits.condition is not None
    )


def _constant_number(expr: ast.Expr) -> Fraction | None:
    match expr:
        case ast.IntLiteral() | ast.FloatLiteral():
            try:
                return Fraction(exact_number(expr.text))
            except ValueError:  # no exact value, or out of range (reported as T209)
                return None
        case ast.Unary(op="-"):
            inner = _constant_number(expr.operand)
            return -inner if inner is not None else None
        case ast.Unary(op="+"):
            return _constant_number(expr.operand)
    return None


def _doc_comment(unit: Unit, decl: ast.Node) -> str | None:
    """The comment block directly above a declaration, without the `#` marks."""
    if not unit.comments:
        return None
    line = decl.span.line - 1
    lines = []
    while line in unit.comments:
        lines.append(unit.comments[line].lstrip("#").strip())
        line -= 1
    return "\n".join(reversed(lines)) if lines else None
