"""Build AST nodes from the parser's callbacks: one method per rule or alias.

The builder runs inline in the LALR parser (no intermediate lark ``Tree``), so
it must be pure: error recovery forks the parser and may call a method on
children that a fork later discards. Spans are computed from the first and
last child. The file being parsed is held in a context variable, because the
parser (and this builder) is shared by every parse in the process.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from contextvars import ContextVar
from dataclasses import dataclass, fields
from fractions import Fraction
from typing import Any, TypeVar, overload

from osc2check.numbers import NumberOutOfRange, exact_number
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.syntax.lexer import Token

_URI: ContextVar[str] = ContextVar("osc2_uri", default="")
_PROBLEMS: ContextVar[list[BuildProblem] | None] = ContextVar("osc2_build_problems", default=None)

_PHYSICAL = re.compile(r"((?:\d+(?:\.\d+)?|\.\d+)(?:[eE][+-]?\d+)?)(.*)", re.DOTALL)
# A rule's children as lark passes them: tokens, nodes, helper groups, method bodies and
# None for an absent ``[optional]`` part. Which is where is said by the grammar, not by
# Python types, so they are Any; each callback returns a typed node.
Children = list[Any]
_T = TypeVar("_T")
_U = TypeVar("_U")
_V = TypeVar("_V")
_S = TypeVar("_S", bound=ast.StructuredDecl)
# A method's body until ``method_decl`` unpacks it: kind, expression, external name, arguments.
_MethodBody = tuple[str, ast.Expr | None, tuple[ast.Name, ...], tuple[ast.Argument, ...]]

_ESCAPES = {"n": "\n", "t": "\t", "r": "\r", "\\": "\\", '"': '"', "'": "'", "0": "\0"}


@dataclass(frozen=True, slots=True)
class BuildProblem:
    """Grammatical but meaningless input, such as ``x.y`` where an invocation is expected
    (kind ``invocation``) or a number beyond the budget (kind ``number``, with why)."""

    span: Span
    kind: str
    number: NumberOutOfRange | None = None


@dataclass(frozen=True, slots=True)
class _Group:
    """Children of a helper rule (arguments, a with block) until the parent unpacks them."""

    kind: str
    items: tuple[Any, ...]  # the helper rule's children, of the kinds the grammar gives
    span: Span | None


def _span_maker() -> Callable[[str, int, int, int, int, int, int], Span]:
    """``Span(uri, line, column, end_line, end_column, start, end)``, made faster: a frozen
    dataclass's ``__init__`` sets each field by ``object.__setattr__``, this by the field's
    slot, and the builder makes a span for every name and every node."""
    if [f.name for f in fields(Span)] != list(_SPAN_FIELDS) or hasattr(Span, "__post_init__"):
        return Span  # Span is not the plain record this was written for
    new = object.__new__
    uri, line, column, end_line, end_column, start, end = (
        getattr(Span, name).__set__ for name in _SPAN_FIELDS
    )

    def span(u: str, li: int, co: int, eli: int, eco: int, st: int, en: int) -> Span:
        made: Span = new(Span)
        uri(made, u)
        line(made, li)
        column(made, co)
        end_line(made, eli)
        end_column(made, eco)
        start(made, st)
        end(made, en)
        return made

    return span


_SPAN_FIELDS = ("uri", "line", "column", "end_line", "end_column", "start", "end")
_span = _span_maker()


def _tok_span(tok: Token) -> Span:
    return _span(
        _URI.get(), tok.line, tok.column, tok.end_line, tok.end_column, tok.start_pos, tok.end_pos
    )


def span_of(item: object) -> Span | None:
    if isinstance(item, Token):
        return _tok_span(item)
    if isinstance(item, ast.Node):
        return item.span
    if isinstance(item, _Group):
        return item.span
    return None


_SPANNED = (ast.Node, _Group)  # the other items (a token aside) have no position


def _cover(children: Sequence[object]) -> Span:
    """The span from the first to the last child that has a position (the hottest
    function of the builder: a child's span, when it is the only one, is used as it is)."""
    for first in children:
        if isinstance(first, Token):
            line, column, start = first.line, first.column, first.start_pos
            break
        if isinstance(first, _SPANNED) and (span := first.span) is not None:
            line, column, start = span.line, span.column, span.start
            break
    else:
        return _span(_URI.get(), 1, 1, 1, 1, 0, 0)
    for last in reversed(children):
        if isinstance(last, Token):
            return _span(
                _URI.get(), line, column, last.end_line, last.end_column, start, last.end_pos
            )
        if isinstance(last, _SPANNED) and (end := last.span) is not None:
            if last is first:
                return end
            return _span(_URI.get(), line, column, end.end_line, end.end_column, start, end.end)
    raise AssertionError("unreachable: the first child with a position is found again")


def _nodes(children: Children, kind: type[_T]) -> tuple[_T, ...]:
    return tuple(c for c in children if isinstance(c, kind))


def _group(children: Children, kind: str) -> tuple[Any, ...]:
    for c in children:
        if isinstance(c, _Group) and c.kind == kind:
            return c.items
    return ()


@overload
def _first(children: Children, kind: type[_T]) -> _T | None: ...
@overload
def _first(children: Children, kind: tuple[type[_T], type[_U]]) -> _T | _U | None: ...
@overload
def _first(
    children: Children, kind: tuple[type[_T], type[_U], type[_V]]
) -> _T | _U | _V | None: ...
def _first(children: Children, kind: type[object] | tuple[type[object], ...]) -> object | None:
    for c in children:
        if isinstance(c, kind):
            return c
    return None


def _has(children: Children, token_type: str) -> bool:
    return any(isinstance(c, Token) and c.type == token_type for c in children)


def _report(span: Span, kind: str, number: NumberOutOfRange | None = None) -> None:
    problems = _PROBLEMS.get()
    if problems is not None:
        problems.append(BuildProblem(span, kind, number))


def _number(text: str, span: Span) -> int | Fraction | None:
    """The exact value of a literal's number, or None (reported) beyond the budget."""
    try:
        return exact_number(text)
    except NumberOutOfRange as exc:
        _report(span, "number", exc)
    except ValueError:  # inf, nan: no exact value
        pass
    return None


def _unescape(body: str) -> str:
    if "\\" not in body:
        return body
    out, i = [], 0
    while i < len(body):
        ch = body[i]
        if ch == "\\" and i + 1 < len(body):
            out.append(_ESCAPES.get(body[i + 1], body[i + 1]))
            i += 2
        else:
            out.append(ch)
            i += 1
    return "".join(out)


# Binding strength of binary operators; relations do not chain (`a < b < c`
# groups to the left and is then a type error, as in the standard's grammar).
_PRECEDENCE = {
    "=>": 1,
    "or": 2,
    "and": 3,
    "==": 5,
    "!=": 5,
    "<": 5,
    "<=": 5,
    ">": 5,
    ">=": 5,
    "in": 5,
    "+": 6,
    "-": 6,
    "*": 7,
    "/": 7,
    "%": 7,
}


def _group_chain(c: Children) -> ast.Expr:
    """Group ``operand (op operand)*`` by precedence, left-associative."""
    operands = c[0::2]
    ops = [str(t) or "+" for t in c[1::2]]
    return _climb(operands, ops, [0], 0)


def _climb(operands: Children, ops: list[str], pos: list[int], min_prec: int) -> ast.Expr:
    """Precedence climbing from ``operands[pos[0]]`` (a module function, not a nested
    recursive one: that would be a reference cycle holding the operands)."""
    left: ast.Expr = operands[pos[0]]
    while pos[0] < len(ops) and _PRECEDENCE.get(ops[pos[0]], 6) >= min_prec:
        op = ops[pos[0]]
        prec = _PRECEDENCE.get(op, 6)
        pos[0] += 1
        right = _climb(operands, ops, pos, prec + 1)
        left = ast.Binary(_cover([left, right]), op, left, right)
    return left


class Builder:
    """Parse callbacks that return ``ast`` nodes: the method named after a rule (or its
    alias) is called with the rule's children as lark's tree builder passes them
    (``tables.RuleShape``; lark's own recovering parser calls the same methods)."""

    # ---- names ---------------------------------------------------------------

    def name(self, c: Children) -> ast.Name:
        tok = c[0]
        return ast.Name(_tok_span(tok), tok.value)

    def plain_name(self, c: Children) -> ast.QualifiedName:
        return ast.QualifiedName(c[0].span, None, c[0])

    def prefixed_name(self, c: Children) -> ast.QualifiedName:
        return ast.QualifiedName(_cover(c), c[0].text, c[1])

    def global_name(self, c: Children) -> ast.QualifiedName:
        return ast.QualifiedName(c[0].span, "", c[0])

    def dotted_name(self, c: Children) -> _Group:
        return _Group("dotted", tuple(c), _cover(c))

    def behaviour_name(self, c: Children) -> ast.BehaviourName:
        if len(c) == 2 and c[1] is not None:
            return ast.BehaviourName(_cover(c), c[0], c[1])
        qn = c[0]
        return ast.BehaviourName(qn.span, None, qn.name, qn.namespace)

    def named_type(self, c: Children) -> ast.NamedType:
        return ast.NamedType(c[0].span, c[0])

    def list_type(self, c: Children) -> ast.ListType:
        return ast.ListType(_cover(c), c[-1])

    def range_type(self, c: Children) -> ast.RangeType:
        return ast.RangeType(_cover(c), c[-1])

    # ---- literals and expressions ------------------------------------------

    def int_literal(self, c: Children) -> ast.IntLiteral:
        tok = c[0]
        text, span = str(tok), _tok_span(tok)
        value = _number(text or "0", span)
        return ast.IntLiteral(span, value if isinstance(value, int) else 0, text)

    def float_literal(self, c: Children) -> ast.FloatLiteral:
        tok = c[0]
        text, span = str(tok) or "0", _tok_span(tok)
        if text[0].isdigit() or text[0] == ".":
            _number(text, span)  # reported beyond the budget (its value is inf or 0.0)
        return ast.FloatLiteral(span, float(text), str(tok))

    def physical_literal(self, c: Children) -> ast.PhysicalLiteral:
        tok = c[0]
        span = _tok_span(tok)
        m = _PHYSICAL.fullmatch(str(tok))
        number_text, unit_text = (m.group(1), m.group(2)) if m else ("0", str(tok))
        unit_start = tok.start_pos + len(number_text)
        unit_span = Span(
            span.uri,
            tok.line,
            tok.column + len(number_text),
            tok.end_line,
            tok.end_column,
            unit_start,
            tok.end_pos,
        )
        number = _number(number_text, span)
        return ast.PhysicalLiteral(
            span,
            number if number is not None else float("nan"),  # no exact value: not folded
            number_text,
            ast.Name(unit_span, unit_text),
        )

    def string_literal(self, c: Children) -> ast.StringLiteral:
        tok = c[0]
        text = str(tok)
        q = 3 if text[:3] in ('"""', "'''") else 1
        body = text[q:-q] if len(text) >= 2 * q and text[-q:] == text[:q] else text[q:]
        return ast.StringLiteral(_tok_span(tok), _unescape(body))

    def bool_literal(self, c: Children) -> ast.BoolLiteral:
        return ast.BoolLiteral(_tok_span(c[0]), c[0].type == "TRUE")

    def name_ref(self, c: Children) -> ast.NameRef:
        return ast.NameRef(c[0].span, c[0])

    def enum_ref(self, c: Children) -> ast.EnumRef:
        return ast.EnumRef(_cover(c), c[0], c[1])

    def member_access(self, c: Children) -> ast.MemberAccess:
        return ast.MemberAccess(_cover(c), c[0], c[1])

    def call(self, c: Children) -> ast.Call:
        args = c[1].items if isinstance(c[1], _Group) else ()
        return ast.Call(_cover(c), c[0], args)

    def index(self, c: Children) -> ast.Index:
        return ast.Index(_cover(c), c[0], c[1])

    def unary(self, c: Children) -> ast.Unary:
        return ast.Unary(_cover(c), str(c[0]) or "-", c[1])

    def logic(self, c: Children) -> ast.Expr:
        return _group_chain(c)

    def comparison(self, c: Children) -> ast.Expr:
        return _group_chain(c)

    def ternary(self, c: Children) -> ast.Ternary:
        return ast.Ternary(_cover(c), c[0], c[1], c[2])

    def list_literal(self, c: Children) -> ast.ListLiteral:
        items = tuple(x for x in c if x is not None and not isinstance(x, Token))
        return ast.ListLiteral(_cover(c), items)

    def range_literal(self, c: Children) -> ast.RangeLiteral:
        return ast.RangeLiteral(_cover(c), c[1], c[3])

    def arguments(self, c: Children) -> _Group:
        return _Group("args", tuple(c), _cover(c))

    def positional_argument(self, c: Children) -> ast.PositionalArgument:
        return ast.PositionalArgument(c[0].span, c[0])

    def named_argument(self, c: Children) -> ast.NamedArgument:
        return ast.NamedArgument(_cover(c), c[0], c[1])

    def event_argument(self, c: Children) -> ast.EventArgument:
        path = c[1].items
        return ast.EventArgument(_cover(c), path)

    def event_path(self, c: Children) -> _Group:
        return _Group("path", tuple(c), _cover(c))

    def event_reference(self, c: Children) -> ast.EventReference:
        path = c[1].items
        alias = condition = None
        rest = c[2:]
        for i, item in enumerate(rest):
            if isinstance(item, Token) and item.type == "AS" and i + 1 < len(rest):
                alias = rest[i + 1]
            elif isinstance(item, Token) and item.type == "IF" and i + 1 < len(rest):
                condition = rest[i + 1]
        return ast.EventReference(_cover(c), path, alias, condition)

    def event_condition(self, c: Children) -> ast.EventCondition:
        return ast.EventCondition(c[0].span, c[0])

    # ---- members -------------------------------------------------------------

    def member_end(self, c: Children) -> _Group:
        return _Group("with", c[0].items, c[0].span) if c else _Group("with", (), None)

    def with_block(self, c: Children) -> _Group:
        items = tuple(x for x in c if isinstance(x, ast.Node))
        return _Group("with", items, _cover(c))

    def field_decl(self, c: Children) -> ast.FieldDecl:
        names = _nodes(c, ast.Name)
        type_ref = _first(c, (ast.NamedType, ast.ListType, ast.RangeType))
        default = self._default(c, type_ref)
        return ast.FieldDecl(_cover(c), names, type_ref, default, _group(c, "with"), False)

    def var_decl(self, c: Children) -> ast.FieldDecl:
        names = _nodes(c, ast.Name)
        type_ref = _first(c, (ast.NamedType, ast.ListType, ast.RangeType))
        default = self._default(c, type_ref)
        return ast.FieldDecl(_cover(c), names, type_ref, default, _group(c, "with"), True)

    @staticmethod
    def _default(c: Children, type_ref: ast.TypeRef | None) -> ast.Expr | None:
        # The default is the expression after the type (names come first).
        seen_type = type_ref is None
        for item in c:
            if item is type_ref:
                seen_type = True
            elif seen_type and isinstance(item, ast.Expr):  # not a name, nor a `with` group
                return item
        return None

    def parameters(self, c: Children) -> _Group:
        return _Group("params", tuple(c), _cover(c))

    def parameter(self, c: Children) -> ast.Parameter:
        return ast.Parameter(_cover(c), c[0], c[1], c[2] if len(c) > 2 else None)

    def event_decl(self, c: Children) -> ast.EventDecl:
        name = _first(c, ast.Name)
        assert name is not None  # the grammar requires it (recovery inserts a missing one)
        spec = _first(c, (ast.EventReference, ast.EventCondition))
        return ast.EventDecl(_cover(c), name, _group(c, "params"), spec)

    def constraint_strength(self, c: Children) -> Token:
        strength: Token = c[0]
        return strength

    def keep_stmt(self, c: Children) -> ast.KeepConstraint:
        strength = "default" if _has(c, "DEFAULT") else "hard"
        nodes = [x for x in c if isinstance(x, ast.Expr)]
        expr = nodes[-1] if nodes else ast.Missing(_cover(c))
        return ast.KeepConstraint(_cover(c), strength, expr)

    def remove_default_stmt(self, c: Children) -> ast.RemoveDefault:
        nodes = [x for x in c if isinstance(x, ast.Expr)]
        return ast.RemoveDefault(_cover(c), nodes[-1] if nodes else ast.Missing(_cover(c)))

    def method_expression(self, c: Children) -> _MethodBody:
        return ("expression", c[-1], (), ())

    def method_undefined(self, c: Children) -> _MethodBody:
        return ("undefined", None, (), ())

    def method_external(self, c: Children) -> _MethodBody:
        args = _group(c, "args")
        return ("external", None, _group(c, "dotted"), args)

    def method_decl(self, c: Children) -> ast.MethodDecl:
        name = c[1]
        body = next(x for x in c if isinstance(x, tuple))
        return_type = _first(c, (ast.NamedType, ast.ListType, ast.RangeType))
        kind, expr, external, ext_args = body
        return ast.MethodDecl(
            _cover([c[0], *[x for x in c if not isinstance(x, tuple)], expr]),
            name,
            _group(c, "params"),
            return_type,
            _has(c, "ONLY"),
            kind,
            expr,
            external,
            ext_args,
        )

    def coverage_stmt(self, c: Children) -> ast.CoverageDecl:
        return ast.CoverageDecl(_cover(c), str(c[0]) or "cover", _group(c, "args"))

    def invocation_stmt(self, c: Children) -> ast.Invocation:
        expr, with_group = c[0], c[1]
        span = _cover([expr, with_group])
        if isinstance(expr, ast.Call):
            callee = expr.callee
            if isinstance(callee, ast.MemberAccess):
                return ast.Invocation(
                    span, callee.target, callee.member, expr.arguments, with_group.items
                )
            if isinstance(callee, ast.NameRef):
                return ast.Invocation(
                    span, None, callee.name.name, expr.arguments, with_group.items
                )
        _report(expr.span, "not-invocation")
        if isinstance(expr, ast.MemberAccess):  # `hero.dr` while typing: keep the actor
            return ast.Invocation(span, expr.target, expr.member, (), with_group.items)
        return ast.Invocation(span, None, ast.Name(expr.span, ""), (), with_group.items)

    def until_stmt(self, c: Children) -> ast.Until:
        return ast.Until(_cover(c), c[-1])

    def on_block(self, c: Children) -> ast.OnDirective:
        event = c[1]
        members = tuple(x for x in c[2:] if isinstance(x, (ast.Emit, ast.CallDirective)))
        return ast.OnDirective(_cover(c), event, members)

    # ---- behaviour -----------------------------------------------------------

    def do_block(self, c: Children) -> ast.DoDirective:
        return ast.DoDirective(_cover(c), c[-1])

    def do_member(self, c: Children) -> ast.DoMember:
        label, body = c[0], c[-1]
        return ast.DoMember(_cover([x for x in c if x is not None]), label, body)

    def composition_op(self, c: Children) -> Token:
        op: Token = c[0]
        return op

    def composition(self, c: Children) -> ast.Composition:
        op = c[0]
        members = _nodes(c, ast.DoMember)
        return ast.Composition(
            _cover(c), str(op) or "serial", _group(c, "args"), members, _group(c, "with")
        )

    def wait_stmt(self, c: Children) -> ast.Wait:
        return ast.Wait(_cover(c), c[-1])

    def emit_stmt(self, c: Children) -> ast.Emit:
        return ast.Emit(_cover(c), c[1], _group(c, "args"))

    def call_stmt(self, c: Children) -> ast.CallDirective:
        return ast.CallDirective(_cover(c), c[-1])

    # ---- declarations --------------------------------------------------------

    def import_file(self, c: Children) -> ast.ImportDecl:
        lit = self.string_literal([c[1]])
        return ast.ImportDecl(_cover(c), "file", lit.value, lit.span)

    def import_module(self, c: Children) -> ast.ImportDecl:
        dotted = c[1]
        target = ".".join(n.text for n in dotted.items)
        return ast.ImportDecl(_cover(c), "module", target, dotted.span)

    def use_stmt(self, c: Children) -> ast.UseStatement:
        names = tuple(g.items for g in c if isinstance(g, _Group))
        return ast.UseStatement(_cover(c), names)

    def namespace_stmt(self, c: Children) -> ast.NamespaceDecl:
        names = _nodes(c, ast.Name)
        return ast.NamespaceDecl(_cover(c), names[0], names[1:])

    def export_stmt(self, c: Children) -> ast.ExportDecl:
        return ast.ExportDecl(_cover(c), _nodes(c, ast.ExportItem))

    def export_name(self, c: Children) -> ast.ExportItem:
        return ast.ExportItem(c[0].span, "name", c[0], None)

    def export_namespace(self, c: Children) -> ast.ExportItem:
        return ast.ExportItem(_cover(c), "namespace", None, c[0])

    def export_all(self, c: Children) -> ast.ExportItem:
        return ast.ExportItem(_cover(c), "all", None, None)

    def si_spec(self, c: Children) -> _Group:
        return _Group("si", c[0].items if isinstance(c[0], _Group) else (), _cover(c))

    def type_decl(self, c: Children) -> ast.PhysicalTypeDecl:
        return ast.PhysicalTypeDecl(_cover(c), c[1], _group(c, "si"))

    def unit_decl(self, c: Children) -> ast.UnitDecl:
        return ast.UnitDecl(_cover(c), c[1], c[3], _group(c, "si"))

    def enum_members(self, c: Children) -> _Group:
        return _Group("enum", _nodes(c, ast.EnumMember), _cover(c))

    def enum_member(self, c: Children) -> ast.EnumMember:
        return ast.EnumMember(_cover(c), c[0], c[1] if len(c) > 1 else None)

    def enum_decl(self, c: Children) -> ast.EnumDecl:
        return ast.EnumDecl(_cover(c), c[1], _group(c, "enum"))

    def extend_enum(self, c: Children) -> ast.EnumExtension:
        return ast.EnumExtension(_cover(c), c[1], _group(c, "enum"))

    def extend_type(self, c: Children) -> ast.ExtendDecl:
        return ast.ExtendDecl(_cover(c), c[1], _group(c, "body"))

    def inherits(self, c: Children) -> ast.Inherits:
        condition = c[2] if len(c) > 2 and isinstance(c[2], ast.Expr) else None
        return ast.Inherits(_cover(c), c[1], condition)

    def body(self, c: Children) -> _Group:
        members = tuple(x for x in c if isinstance(x, ast.Node))
        return _Group("body", members, _cover(members) if members else None)

    def _structured(self, cls: type[_S], c: Children, **extra: ast.BehaviourName | None) -> _S:
        name = c[1]
        if isinstance(name, ast.QualifiedName):
            name = ast.BehaviourName(name.span, None, name.name, name.namespace)
        inherits = _first(c, ast.Inherits)
        members = _group(c, "body")
        return cls(_cover(c), name, inherits, members, bool(members), **extra)

    def struct_decl(self, c: Children) -> ast.StructDecl:
        if isinstance(c[1], ast.Name):
            c = [c[0], ast.QualifiedName(c[1].span, None, c[1]), *c[2:]]
        return self._structured(ast.StructDecl, c)

    def actor_decl(self, c: Children) -> ast.ActorDecl:
        return self._structured(ast.ActorDecl, c)

    def scenario_decl(self, c: Children) -> ast.ScenarioDecl:
        return self._structured(ast.ScenarioDecl, c)

    def action_decl(self, c: Children) -> ast.ActionDecl:
        return self._structured(ast.ActionDecl, c)

    def modifier_decl(self, c: Children) -> ast.ModifierDecl:
        names = _nodes(c, ast.BehaviourName)
        of = names[1] if len(names) > 1 else None
        return self._structured(ast.ModifierDecl, c, of=of)

    def global_decl(self, c: Children) -> ast.GlobalDecl:
        return ast.GlobalDecl(_cover(c), c[1])

    def start(self, c: Children) -> ast.File:
        decls = tuple(x for x in c if isinstance(x, ast.Declaration))
        return ast.File(_cover(decls), decls)
