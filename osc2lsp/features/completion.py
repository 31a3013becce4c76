"""Completion from the parser state and the resolved chunk around the cursor.

The grammar says which keywords may come next; the focus analysis (see
``context.py``) says what the names around the cursor mean. In order of
precedence the contexts are: a unit after a number, a member after `.`, an
event after `@`, a named argument of the invocation being written, a type
after `:`, and otherwise the names in scope plus the keywords.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from osc2check.semantics.builtins import (
    EVENT_FUNCTIONS,
    LIST_METHODS,
    PREDEFINED_EVENTS,
    PRIMITIVE_TYPES,
    STANDARD_MODULE_NAMES,
)
from osc2check.semantics.model import Model
from osc2check.semantics.scope import BEHAVIOUR_KINDS, Scope
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.semantics.types import Kind, Type
from osc2check.semantics.visibility import visible_globals
from osc2check.syntax import ast
from osc2check.syntax.expected import keywords
from osc2lsp.features import describe
from osc2lsp.features.context import PLACEHOLDER, Cursor, Focus, cursor_at, focus
from osc2lsp.snapshot import Snapshot

_TYPE_AFTER = frozenset({"COLON", "OF", "ARROW", "INHERITS", "EXTEND"})
_DECLARING = frozenset(
    {
        "SCENARIO",
        "ACTOR",
        "STRUCT",
        "ACTION",
        "MODIFIER",
        "ENUM",
        "TYPE",
        "UNIT",
        "EVENT",
        "DEF",
        "VAR",
        "NAMESPACE",
        "AS",
        "GLOBAL",
    }
)
_VALUE_KINDS = (
    SymbolKind.FIELD,
    SymbolKind.VARIABLE,
    SymbolKind.GLOBAL,
    SymbolKind.ARGUMENT,
    SymbolKind.IMPLICIT,
    SymbolKind.LABEL,
)

# Sort groups: lower comes first.
CONTEXT, EXPECTED, LOCAL, MEMBER, GLOBAL, KEYWORD = 0, 1, 2, 3, 4, 6


@dataclass(frozen=True, slots=True)
class Candidate:
    label: str
    kind: str  # keyword, field, variable, method, action, scenario, modifier, event, unit,
    #            enum_member, type, argument, label, module, function
    detail: str = ""
    documentation: str = ""
    insert_text: str | None = None
    group: int = GLOBAL


@dataclass
class CompletionResult:
    items: list[Candidate]
    start: int  # the items replace text[start:end] of the current text
    end: int
    incomplete: bool = False


@dataclass
class _Collector:
    snapshot: Snapshot | None
    focus: Focus | None
    items: dict[str, Candidate] = field(default_factory=dict)

    def add(self, item: Candidate) -> None:
        old = self.items.get(item.label)
        if old is None or item.group < old.group:
            self.items[item.label] = item

    def symbol(
        self, sym: Symbol, group: int, label: str | None = None, insert: str | None = None
    ) -> None:
        snap = self.snapshot
        detail = describe.signature(snap, sym) if snap is not None else sym.kind.value
        self.add(
            Candidate(
                label or sym.name,
                _KIND_NAMES.get(sym.kind, "variable"),
                detail,
                describe.markdown_doc(sym),
                insert,
                group,
            )
        )


_KIND_NAMES = {
    SymbolKind.FIELD: "field",
    SymbolKind.VARIABLE: "variable",
    SymbolKind.GLOBAL: "variable",
    SymbolKind.ARGUMENT: "variable",
    SymbolKind.IMPLICIT: "variable",
    SymbolKind.LABEL: "label",
    SymbolKind.EVENT: "event",
    SymbolKind.METHOD: "method",
    SymbolKind.SCENARIO: "scenario",
    SymbolKind.ACTION: "action",
    SymbolKind.MODIFIER: "modifier",
    SymbolKind.ENUM: "type",
    SymbolKind.ENUM_MEMBER: "enum_member",
    SymbolKind.STRUCT: "type",
    SymbolKind.ACTOR: "type",
    SymbolKind.PHYSICAL_TYPE: "type",
    SymbolKind.PRIMITIVE: "type",
    SymbolKind.UNIT: "unit",
}


def complete(
    snapshot: Snapshot | None,
    text: str,
    offset: int,
    limit: int = 200,
    cursor: Cursor | None = None,
) -> CompletionResult:
    """Completion candidates at ``offset`` of ``text`` (the document as it is now).

    ``snapshot`` is the latest analysis of the document, possibly of an older
    version; it supplies everything outside the declaration being edited.
    """
    cursor = cursor or cursor_at(text, offset)
    start, end = cursor.word[0], offset
    if cursor.in_comment or cursor.in_string:
        return CompletionResult([], offset, offset)
    prev = cursor.previous()
    if prev is not None and prev.type in _DECLARING:
        # a name being declared: nothing to suggest but the grammar's keywords
        return _finish(_keywords_only(cursor, snapshot), cursor, start, end, limit)
    f = focus(snapshot, text, offset, cursor)
    out = _Collector(snapshot, f)
    if cursor.number is not None:
        _units(out, f, _expected_type(f))
        return _finish(out, cursor, cursor.word[0], end, limit)
    if prev is not None and prev.type == "IMPORT":
        for module in STANDARD_MODULE_NAMES:
            out.add(Candidate(module, "module", "standard library module", group=CONTEXT))
        return _finish(out, cursor, start, end, limit)
    if _event_path(out, f, cursor):
        return _finish(out, cursor, start, end, limit)
    if prev is not None and prev.type == "DOT":
        _members(out, f, cursor)
        return _finish(out, cursor, start, end, limit)
    accepts = cursor.accepts
    if "NAME" in accepts and "INT" not in accepts and prev is not None and prev.type in _TYPE_AFTER:
        _types(out, f, prev.type)
        _grammar_keywords(out, cursor)
        return _finish(out, cursor, start, end, limit)
    if prev is not None and prev.type == "EMIT":
        _events(out, f.model, f.scope, CONTEXT)
        return _finish(out, cursor, start, end, limit)
    _arguments(out, f, cursor)
    expected = _expected_type(f)
    if expected is not None and expected.kind is Kind.ENUM and expected.symbol is not None:
        for member in f.model.enum_values(expected.symbol):
            out.symbol(member, EXPECTED)
    where = _statement_place(f, cursor)
    if where is not None:
        _statements(out, f, where)
        _grammar_keywords(out, cursor, LOCAL)
        if where != "body":
            _names_in_scope(out, f, cursor.prefix)
        return _finish(out, cursor, start, end, limit)
    if "NAME" in accepts or not accepts:
        if "INT" in accepts or not accepts:
            _names_in_scope(out, f, cursor.prefix)
            if prev is not None and prev.type in ("WAIT", "UNTIL", "ON", "IF"):
                for name, builtin in EVENT_FUNCTIONS.items():
                    doc = f"{builtin.signature}: {builtin.doc}"
                    out.add(Candidate(name, "function", doc, group=LOCAL))
    _grammar_keywords(out, cursor)
    return _finish(out, cursor, start, end, limit)


# ---- the contexts ---------------------------------------------------------------


def _keywords_only(cursor: Cursor, snapshot: Snapshot | None) -> _Collector:
    out = _Collector(snapshot, None)
    _grammar_keywords(out, cursor)
    return out


def _grammar_keywords(out: _Collector, cursor: Cursor, group: int = KEYWORD) -> None:
    table = keywords()
    state = cursor.state
    if state is None:
        return
    for term in cursor.accepts:
        if cursor.statement_start and term in ("TRUE", "FALSE"):
            continue
        if term in table and state.keyword_use(term):
            out.add(Candidate(table[term], "keyword", group=group))


def _units(out: _Collector, f: Focus, expected: Type | None) -> None:
    model = f.model
    dim = None
    if expected is not None:
        if expected.kind is Kind.RANGE and expected.element is not None:
            expected = expected.element
        if expected.kind is Kind.PHYSICAL:
            dim = expected.dimension
        elif expected.kind is not Kind.UNKNOWN:
            return  # a plain number, an enum...: no unit fits
    for name, unit in model.all_units().items():
        if dim is not None and unit.dimension != dim:
            continue
        kind_name = unit.type.symbol.name if unit.type is not None and unit.type.symbol else ""
        out.add(
            Candidate(
                name,
                "unit",
                f"unit of {kind_name}".strip(),
                describe.markdown_doc(unit),
                group=CONTEXT if dim else GLOBAL,
            )
        )


def _members(out: _Collector, f: Focus, cursor: Cursor) -> None:
    target_type = _target_type(f, cursor)
    if target_type is None:
        return
    model = f.model
    if target_type.kind is Kind.LIST:
        for name, builtin in LIST_METHODS.items():
            doc = f"list method {builtin.signature}: {builtin.doc}"
            out.add(Candidate(name, "method", doc, group=MEMBER))
        return
    if target_type.kind is Kind.RANGE:
        for name in ("lower", "upper"):
            out.add(Candidate(name, "method", "range bound", group=MEMBER))
        return
    owner = target_type.symbol
    if owner is None:
        return
    statement = _is_statement_invocation(f, cursor)
    if owner.kind is SymbolKind.ACTOR:
        for sym in model.behaviours_of(owner):
            out.symbol(sym, CONTEXT if statement else MEMBER)
    for sym in model.all_members(owner):
        if sym.kind is SymbolKind.EVENT:
            continue
        out.symbol(sym, MEMBER if statement else CONTEXT)


def _is_statement_invocation(f: Focus, cursor: Cursor) -> bool:
    name = f.name_at_cursor()
    for node in reversed(f.path):
        if isinstance(node, ast.Invocation) and node.name is name:
            return True
    return False


def _target_type(f: Focus, cursor: Cursor) -> Type | None:
    """The type of the expression before the `.` at the cursor."""
    name = f.name_at_cursor()
    model = f.model
    if name is not None:
        for node in reversed(f.path):
            if isinstance(node, ast.MemberAccess) and node.member is name:
                return model.expr_types.get(node.target) or _chain_type(f, cursor)
            if isinstance(node, ast.Invocation) and node.name is name and node.actor is not None:
                return model.expr_types.get(node.actor) or _chain_type(f, cursor)
    return _chain_type(f, cursor)


def _chain_type(f: Focus, cursor: Cursor) -> Type | None:
    """Type a `a.b.c` chain from the tokens before the cursor (when the parse lost it)."""
    tokens = cursor.tokens
    names: list[str] = []
    i = len(tokens) - 1
    while i >= 1 and tokens[i].type == "DOT" and re.fullmatch(r"\w+", tokens[i - 1].value or ""):
        names.append(tokens[i - 1].value)
        i -= 2
    if not names:
        return None
    names.reverse()
    model, scope = f.model, f.scope
    current = _name_type(model, scope, names[0])
    for name in names[1:]:
        if current is None or current.symbol is None:
            return None
        found = model.member(current.symbol, name)
        current = found[0].type if found else None
    return current


def _name_type(model: Model, scope: Scope, name: str) -> Type | None:
    if name == "it":
        return scope.it
    if name == "actor" and scope.actor is not None:
        return scope.actor.type
    if name in scope.locals:
        return scope.locals[name].type
    if scope.owner is not None:
        found = model.member(scope.owner, name)
        if found:
            return found[0].type
    found = model.lookup(name, scope.context)
    return found[0].type if found else None


def _event_path(out: _Collector, f: Focus, cursor: Cursor) -> bool:
    """Events after `@` (and `@a.b.` paths). Returns True when this is the context."""
    tokens = cursor.tokens
    i = len(tokens) - 1
    path: list[str] = []
    while i >= 1 and tokens[i].type == "DOT" and re.fullmatch(r"\w+", tokens[i - 1].value or ""):
        path.append(tokens[i - 1].value)
        i -= 2
    if i < 0 or tokens[i].type != "AT":
        return False
    path.reverse()
    model, scope = f.model, f.scope
    if not path:
        _events(out, model, scope, CONTEXT)
        for sym in scope.locals.values():
            if sym.kind is SymbolKind.LABEL:
                out.symbol(sym, LOCAL)
        for sym in _owner_members(model, scope):
            if (
                sym.kind is SymbolKind.FIELD
                and sym.type is not None
                and sym.type.kind is Kind.COMPOUND
            ):
                out.symbol(sym, MEMBER)
        return True
    target = _name_type(model, scope, path[0])
    label = scope.locals.get(path[0])
    for name in path[1:]:
        if target is None or target.symbol is None:
            target = None
            break
        found = model.member(target.symbol, name)
        target = found[0].type if found else None
    if target is not None and target.symbol is not None:
        for sym in model.all_members(target.symbol):
            if sym.kind is SymbolKind.EVENT:
                out.symbol(sym, CONTEXT)
    if (label is not None and label.kind is SymbolKind.LABEL) or (
        target is not None and target.symbol is not None and target.symbol.kind.is_behaviour
    ):
        for name in PREDEFINED_EVENTS:
            out.add(Candidate(name, "event", "standard event of a behaviour", group=CONTEXT))
    return True


def _events(out: _Collector, model: Model, scope: Scope, group: int) -> None:
    for sym in _owner_members(model, scope):
        if sym.kind is SymbolKind.EVENT:
            out.symbol(sym, group)


def _owner_members(model: Model, scope: Scope) -> list[Symbol]:
    return model.all_members(scope.owner) if scope.owner is not None else []


def _types(out: _Collector, f: Focus, after: str) -> None:
    model = f.model
    physical_only = after == "OF" and any(t.type == "UNIT" for t in f.cursor.tokens[-4:])
    for sym in visible_globals(model, f.scope.context, lambda s: s.kind.is_type):
        if physical_only and sym.kind is not SymbolKind.PHYSICAL_TYPE:
            continue
        out.symbol(sym, CONTEXT)
    if not physical_only:
        for name in PRIMITIVE_TYPES:
            out.add(Candidate(name, "type", "primitive type", group=CONTEXT))


def _arguments(out: _Collector, f: Focus, cursor: Cursor) -> None:
    """Named arguments of the invocation or call whose argument list holds the cursor."""
    call = enclosing_call(f)
    if call is None:
        return
    node, callee = call
    prev = cursor.previous()
    if prev is None or prev.type not in ("LPAR", "COMMA"):
        return
    params = describe.parameters_of(f.model, callee)
    given = {a.name.text for a in _arguments_of(node) if isinstance(a, ast.NamedArgument)}
    for param in params:
        if param.name in given:
            continue
        detail = (
            describe.parameter_text(out.snapshot, param) if out.snapshot is not None else param.name
        )
        out.add(
            Candidate(
                f"{param.name}:",
                "argument",
                detail,
                describe.markdown_doc(param),
                f"{param.name}: ",
                CONTEXT,
            )
        )
    if callee.kind is SymbolKind.SCENARIO or callee.kind is SymbolKind.ACTION:
        if "duration" not in given:
            out.add(
                Candidate(
                    "duration:",
                    "argument",
                    "duration: range of time",
                    "How long the behaviour lasts.",
                    "duration: ",
                    CONTEXT,
                )
            )


def _arguments_of(node: ast.Node) -> tuple[ast.Node, ...]:
    return getattr(node, "arguments", ())


def enclosing_call(f: Focus) -> tuple[ast.Invocation | ast.Call, Symbol] | None:
    """The innermost invocation or call whose arguments contain the cursor, and its callee."""
    model = f.model
    path = f.path
    for i in range(len(path) - 1, 0, -1):
        node = path[i]
        child = path[i + 1] if i + 1 < len(path) else None
        if (
            child is None
            and isinstance(node, (ast.Invocation, ast.Call))
            and f.cursor.argument_index() is not None
        ):
            head = node.name if isinstance(node, ast.Invocation) else node.callee
            if head.span.end < f.cursor.offset:
                child = next(iter(node.arguments), None) or node
                if child is node:
                    sym = _callee_of(model, node)
                    return (node, sym) if sym is not None else None
        if (
            isinstance(node, ast.Invocation)
            and child is not None
            and any(child is a for a in node.arguments)
        ):
            sym = model.references.get(node.name)
            return (node, sym) if sym is not None else None
        if (
            isinstance(node, ast.Call)
            and child is not None
            and any(child is a for a in node.arguments)
        ):
            name = node.callee_name
            sym = model.references.get(name) if name is not None else None
            return (node, sym) if sym is not None else None
    return None


def _expected_type(f: Focus) -> Type | None:
    """The type the context asks for at the cursor, when it says."""
    model = f.model
    path = f.path
    for i in range(len(path) - 1, 0, -1):
        node, parent = path[i], path[i - 1]
        if isinstance(node, ast.NamedArgument):
            sym = model.references.get(node.name)
            if sym is None:
                call = _callee_of(model, parent)
                if call is not None:
                    found = [
                        p for p in describe.parameters_of(model, call) if p.name == node.name.text
                    ]
                    sym = found[0] if found else None
            if sym is not None:
                return sym.type
            return _builtin_expected(model, parent, f)
        if isinstance(node, ast.PositionalArgument):
            call = _callee_of(model, parent)
            if call is None:
                return _builtin_expected(model, parent, f)
            params = describe.parameters_of(model, call)
            positional = [a for a in _arguments_of(parent) if isinstance(a, ast.PositionalArgument)]
            index = next((k for k, a in enumerate(positional) if a is node), 0)
            return params[index].type if index < len(params) else None
        child = path[i + 1] if i + 1 < len(path) else None
        if isinstance(node, ast.Binary) and child is not None and child is node.right:
            left = model.expr_types.get(node.left)
            if left is not None and not left.is_unknown:
                return left
        if (
            isinstance(node, ast.FieldDecl)
            and child is not None
            and child is node.default
            and node.names
        ):
            sym = model.references.get(node.names[0])
            return sym.type if sym is not None else None
        if isinstance(node, ast.Parameter) and child is not None and child is node.default:
            sym = model.references.get(node.name)
            return sym.type if sym is not None else None
    return None


def _callee_of(model: Model, node: ast.Node) -> Symbol | None:
    if isinstance(node, ast.Invocation):
        return model.references.get(node.name)
    if isinstance(node, ast.Call):
        callee = node.callee
        name = (
            callee.member
            if isinstance(callee, ast.MemberAccess)
            else callee.name.name
            if isinstance(callee, ast.NameRef)
            else None
        )
        return model.references.get(name) if name is not None else None
    if isinstance(node, ast.Emit):
        return model.references.get(node.event)
    return None


def _builtin_expected(model: Model, node: ast.Node, f: Focus) -> Type | None:
    if isinstance(node, ast.Call) and isinstance(node.callee, ast.NameRef):
        name = node.callee.name.name.text
        builtin = EVENT_FUNCTIONS.get(name)
        if builtin is not None and builtin.parameters[0].type == "time":
            found = [
                s
                for s in model.lookup("time", f.scope.context)
                if s.kind is SymbolKind.PHYSICAL_TYPE
            ]
            if not found:
                found = [
                    s
                    for s in model.lookup("time", f.scope.context, "stdtypes")
                    if s.kind is SymbolKind.PHYSICAL_TYPE
                ]
            if found:
                return found[0].type
            return Type(Kind.PHYSICAL, None, (0, 0, 1, 0, 0, 0, 0, 0))
    return None


def _statement_place(f: Focus, cursor: Cursor) -> str | None:
    """Where a statement starts at the cursor: in a ``with:`` block, a ``do`` tree or a
    declaration body; None when the cursor is not at the start of a statement."""
    if not cursor.statement_start or f.scope.owner is None:
        return None
    if f.scope.modifier_block:
        return "with"
    for node in reversed(f.path):
        if isinstance(node, (ast.DoMember, ast.DoDirective, ast.Composition)):
            return "do"
        if isinstance(node, ast.FieldDecl):
            return "with"
        if isinstance(node, (ast.StructuredDecl, ast.ExtendDecl)):
            return "body"
    return None


def _statements(out: _Collector, f: Focus, where: str) -> None:
    """Behaviours and modifiers that may start a statement here."""
    model, scope = f.model, f.scope
    if where == "with":
        if scope.modifier_block:
            for sym in _modifiers(model, scope):
                out.symbol(sym, CONTEXT)
        return
    if where == "do":
        if scope.actor is not None:
            for sym in model.behaviours_of(scope.actor):
                out.symbol(sym, LOCAL)
        for sym in model.behaviours_of(None):
            out.symbol(sym, GLOBAL)
        for sym in _owner_members(model, scope):
            if (
                sym.kind in (SymbolKind.FIELD, SymbolKind.VARIABLE)
                and sym.type is not None
                and sym.type.kind is Kind.COMPOUND
            ):
                out.symbol(sym, CONTEXT)
    elif scope.owner is not None and scope.owner.kind in BEHAVIOUR_KINDS:
        for sym in _modifiers(model, scope):
            out.symbol(sym, MEMBER)


def _modifiers(model: Model, scope: Scope) -> list[Symbol]:
    """Modifiers applicable in the current `with:` block or behaviour body, the way
    the checker looks them up."""
    keys: list[Symbol | None] = []
    if scope.behaviour is not None:
        keys.append(scope.behaviour)
    if scope.actor is not None:
        keys.append(scope.actor)
    owner = scope.owner
    if owner is not None and owner.kind in BEHAVIOUR_KINDS:
        keys.append(owner)
        if owner.actor is not None:
            keys.append(owner.actor)
    keys.append(None)
    found: dict[int, Symbol] = {}
    for key in keys:
        for sym in model.modifiers_of(key):
            found.setdefault(id(sym), sym)
    return list(found.values())


def _names_in_scope(out: _Collector, f: Focus, prefix: str) -> None:
    model, scope = f.model, f.scope
    for sym in scope.locals.values():
        out.symbol(sym, LOCAL)
    if scope.it is not None:
        out.add(Candidate("it", "keyword", f"it: {describe.type_text(scope.it)}", group=LOCAL))
    if scope.actor is not None:
        out.add(Candidate("actor", "keyword", f"actor: {scope.actor.name}", group=LOCAL))
    for sym in _owner_members(model, scope):
        if sym.kind in (SymbolKind.FIELD, SymbolKind.VARIABLE, SymbolKind.METHOD):
            out.symbol(sym, MEMBER)
    kinds = (SymbolKind.GLOBAL, SymbolKind.ENUM) if prefix else (SymbolKind.GLOBAL,)
    for sym in visible_globals(model, scope.context, lambda s: s.kind in kinds):
        out.symbol(sym, GLOBAL)


# ---- result ---------------------------------------------------------------------


def _matches(prefix: str, label: str) -> bool:
    """Case-insensitive subsequence match, first character anchored."""
    if not prefix:
        return True
    wanted, text = prefix.lower(), label.lower()
    if not text.startswith(wanted[0]):
        return False
    i = 0
    for ch in text:
        if i < len(wanted) and ch == wanted[i]:
            i += 1
    return i == len(wanted)


def _finish(out: _Collector, cursor: Cursor, start: int, end: int, limit: int) -> CompletionResult:
    prefix = cursor.text[start:end]
    items = [c for c in out.items.values() if _matches(prefix, c.label) and c.label != PLACEHOLDER]
    items.sort(key=lambda c: (c.group, not c.label.lower().startswith(prefix.lower()), c.label))
    incomplete = len(items) > limit
    return CompletionResult(items[:limit], start, end, incomplete)
