"""The OSC2 abstract syntax tree: immutable, typed nodes, each with its span.

Nodes are plain data. Analysis results never go onto nodes; passes keep them
in side tables keyed by node identity. A name whose ``text`` is empty was
inserted by error recovery (the source lacks it; a syntax error says so).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from osc2check.source import Span


@dataclass(frozen=True, slots=True, eq=False)
class Node:
    span: Span


# ---- names and types ---------------------------------------------------------


@dataclass(frozen=True, slots=True, eq=False)
class Name(Node):
    text: str

    @property
    def missing(self) -> bool:
        return not self.text


@dataclass(frozen=True, slots=True, eq=False)
class QualifiedName(Node):
    """``name``, ``ns::name`` or ``::name`` (``namespace`` is "" for the null namespace)."""

    namespace: str | None
    name: Name

    def __str__(self) -> str:
        if self.namespace is None:
            return self.name.text
        return f"{self.namespace}::{self.name.text}"


@dataclass(frozen=True, slots=True, eq=False)
class BehaviourName(Node):
    """``vehicle.drive`` (actor and behaviour), ``drive`` or ``ns::drive`` (no actor)."""

    actor: QualifiedName | None
    name: Name
    namespace: str | None = None

    def __str__(self) -> str:
        if self.actor:
            return f"{self.actor}.{self.name.text}"
        return self.name.text if self.namespace is None else f"{self.namespace}::{self.name.text}"


@dataclass(frozen=True, slots=True, eq=False)
class NamedType(Node):
    name: QualifiedName


@dataclass(frozen=True, slots=True, eq=False)
class ListType(Node):
    element: TypeRef


@dataclass(frozen=True, slots=True, eq=False)
class RangeType(Node):
    element: TypeRef


TypeRef = NamedType | ListType | RangeType


# ---- expressions -------------------------------------------------------------


@dataclass(frozen=True, slots=True, eq=False)
class IntLiteral(Node):
    value: int
    text: str


@dataclass(frozen=True, slots=True, eq=False)
class FloatLiteral(Node):
    value: float
    text: str


@dataclass(frozen=True, slots=True, eq=False)
class PhysicalLiteral(Node):
    """``10kph``: the number exactly as written and the unit name."""

    number: Fraction | float
    number_text: str
    unit: Name


@dataclass(frozen=True, slots=True, eq=False)
class StringLiteral(Node):
    value: str


@dataclass(frozen=True, slots=True, eq=False)
class BoolLiteral(Node):
    value: bool


@dataclass(frozen=True, slots=True, eq=False)
class NameRef(Node):
    name: QualifiedName


@dataclass(frozen=True, slots=True, eq=False)
class EnumRef(Node):
    """``color!red``."""

    enum: QualifiedName
    member: Name


@dataclass(frozen=True, slots=True, eq=False)
class MemberAccess(Node):
    target: Expr
    member: Name


@dataclass(frozen=True, slots=True, eq=False)
class Call(Node):
    callee: Expr
    arguments: tuple[Argument, ...]

    @property
    def callee_name(self) -> Name | None:
        """The name the callee ends with (``m`` of ``a.b.m(...)`` and of ``m(...)``)."""
        if isinstance(self.callee, MemberAccess):
            return self.callee.member
        if isinstance(self.callee, NameRef):
            return self.callee.name.name
        return None


@dataclass(frozen=True, slots=True, eq=False)
class Index(Node):
    target: Expr
    index: Expr


@dataclass(frozen=True, slots=True, eq=False)
class Unary(Node):
    op: str  # "-", "+", "not"
    operand: Expr


@dataclass(frozen=True, slots=True, eq=False)
class Binary(Node):
    op: str  # "+", "-", "*", "/", "%", "==", "!=", "<", "<=", ">", ">=", "in", "and", "or", "=>"
    left: Expr
    right: Expr


@dataclass(frozen=True, slots=True, eq=False)
class Ternary(Node):
    condition: Expr
    then: Expr
    otherwise: Expr


@dataclass(frozen=True, slots=True, eq=False)
class ListLiteral(Node):
    items: tuple[Expr, ...]


@dataclass(frozen=True, slots=True, eq=False)
class RangeLiteral(Node):
    low: Expr
    high: Expr


@dataclass(frozen=True, slots=True, eq=False)
class Missing(Node):
    """An expression that error recovery had to assume."""


Expr = (
    IntLiteral
    | FloatLiteral
    | PhysicalLiteral
    | StringLiteral
    | BoolLiteral
    | NameRef
    | EnumRef
    | MemberAccess
    | Call
    | Index
    | Unary
    | Binary
    | Ternary
    | ListLiteral
    | RangeLiteral
    | Missing
)


@dataclass(frozen=True, slots=True, eq=False)
class PositionalArgument(Node):
    value: Expr


@dataclass(frozen=True, slots=True, eq=False)
class NamedArgument(Node):
    name: Name
    value: Expr


@dataclass(frozen=True, slots=True, eq=False)
class EventArgument(Node):
    """``@path`` given as an argument (``sample(x, @e)``)."""

    path: tuple[Name, ...]


Argument = PositionalArgument | NamedArgument | EventArgument


# ---- events ------------------------------------------------------------------


@dataclass(frozen=True, slots=True, eq=False)
class EventReference(Node):
    """``@a.b [as x] [if cond]``."""

    path: tuple[Name, ...]
    alias: Name | None
    condition: Expr | None


@dataclass(frozen=True, slots=True, eq=False)
class EventCondition(Node):
    """A condition used as an event: a boolean, ``rise``, ``fall``, ``elapsed``, ``every``."""

    expr: Expr


EventSpec = EventReference | EventCondition


# ---- members -----------------------------------------------------------------


@dataclass(frozen=True, slots=True, eq=False)
class Parameter(Node):
    name: Name
    type: TypeRef
    default: Expr | None


@dataclass(frozen=True, slots=True, eq=False)
class FieldDecl(Node):
    """``a, b: T [= v] [with: ...]``; ``var`` fields are variables, the rest parameters."""

    names: tuple[Name, ...]
    type: TypeRef | None
    default: Expr | None
    with_members: tuple[WithMember, ...]
    is_var: bool


@dataclass(frozen=True, slots=True, eq=False)
class EventDecl(Node):
    name: Name
    parameters: tuple[Parameter, ...]
    spec: EventSpec | None


@dataclass(frozen=True, slots=True, eq=False)
class KeepConstraint(Node):
    strength: str  # "hard" | "default"
    expr: Expr


@dataclass(frozen=True, slots=True, eq=False)
class RemoveDefault(Node):
    target: Expr


@dataclass(frozen=True, slots=True, eq=False)
class MethodDecl(Node):
    name: Name
    parameters: tuple[Parameter, ...]
    return_type: TypeRef | None
    only: bool
    kind: str  # "expression" | "undefined" | "external"
    body: Expr | None
    external: tuple[Name, ...] = ()
    external_arguments: tuple[Argument, ...] = ()


@dataclass(frozen=True, slots=True, eq=False)
class CoverageDecl(Node):
    kind: str  # "cover" | "record"
    arguments: tuple[Argument, ...]


@dataclass(frozen=True, slots=True, eq=False)
class Invocation(Node):
    """``[actor.]name(args) [with: ...]``: a behaviour invocation or a modifier application."""

    actor: Expr | None
    name: Name
    arguments: tuple[Argument, ...]
    with_members: tuple[WithMember, ...]


@dataclass(frozen=True, slots=True, eq=False)
class Until(Node):
    event: EventSpec


WithMember = KeepConstraint | RemoveDefault | Invocation | Until


@dataclass(frozen=True, slots=True, eq=False)
class Wait(Node):
    event: EventSpec


@dataclass(frozen=True, slots=True, eq=False)
class Emit(Node):
    event: Name
    arguments: tuple[Argument, ...]


@dataclass(frozen=True, slots=True, eq=False)
class CallDirective(Node):
    call: Expr


@dataclass(frozen=True, slots=True, eq=False)
class Composition(Node):
    op: str  # "serial" | "parallel" | "one_of"
    arguments: tuple[Argument, ...]
    members: tuple[DoMember, ...]
    with_members: tuple[WithMember, ...]


@dataclass(frozen=True, slots=True, eq=False)
class DoMember(Node):
    label: Name | None
    body: Composition | Invocation | Wait | Emit | CallDirective


@dataclass(frozen=True, slots=True, eq=False)
class DoDirective(Node):
    member: DoMember


@dataclass(frozen=True, slots=True, eq=False)
class OnDirective(Node):
    event: EventSpec
    members: tuple[Emit | CallDirective, ...]


Member = (
    FieldDecl
    | EventDecl
    | KeepConstraint
    | RemoveDefault
    | MethodDecl
    | CoverageDecl
    | Invocation
    | OnDirective
    | DoDirective
)


# ---- declarations ------------------------------------------------------------


@dataclass(frozen=True, slots=True, eq=False)
class ImportDecl(Node):
    kind: str  # "file" | "module"
    target: str
    target_span: Span


@dataclass(frozen=True, slots=True, eq=False)
class UseStatement(Node):
    """``use a.b`` written as a statement (the design paper's dialect)."""

    names: tuple[tuple[Name, ...], ...]


@dataclass(frozen=True, slots=True, eq=False)
class NamespaceDecl(Node):
    name: Name
    uses: tuple[Name, ...]


@dataclass(frozen=True, slots=True, eq=False)
class ExportItem(Node):
    kind: str  # "name" | "namespace" (ns::*) | "all" (*)
    name: QualifiedName | None
    namespace: Name | None


@dataclass(frozen=True, slots=True, eq=False)
class ExportDecl(Node):
    items: tuple[ExportItem, ...]


@dataclass(frozen=True, slots=True, eq=False)
class PhysicalTypeDecl(Node):
    name: Name
    si: tuple[Argument, ...]


@dataclass(frozen=True, slots=True, eq=False)
class UnitDecl(Node):
    name: Name
    type: QualifiedName
    si: tuple[Argument, ...]


@dataclass(frozen=True, slots=True, eq=False)
class EnumMember(Node):
    name: Name
    value: Expr | None


@dataclass(frozen=True, slots=True, eq=False)
class EnumDecl(Node):
    name: Name
    members: tuple[EnumMember, ...]


@dataclass(frozen=True, slots=True, eq=False)
class EnumExtension(Node):
    target: BehaviourName
    members: tuple[EnumMember, ...]


@dataclass(frozen=True, slots=True, eq=False)
class Inherits(Node):
    target: BehaviourName
    condition: Expr | None


@dataclass(frozen=True, slots=True, eq=False)
class StructuredDecl(Node):
    """Common shape of struct, actor, scenario, action and modifier declarations."""

    name: BehaviourName
    inherits: Inherits | None
    members: tuple[Member, ...]
    has_body: bool


@dataclass(frozen=True, slots=True, eq=False)
class StructDecl(StructuredDecl):
    pass


@dataclass(frozen=True, slots=True, eq=False)
class ActorDecl(StructuredDecl):
    pass


@dataclass(frozen=True, slots=True, eq=False)
class ScenarioDecl(StructuredDecl):
    pass


@dataclass(frozen=True, slots=True, eq=False)
class ActionDecl(StructuredDecl):
    pass


@dataclass(frozen=True, slots=True, eq=False)
class ModifierDecl(StructuredDecl):
    of: BehaviourName | None = None


@dataclass(frozen=True, slots=True, eq=False)
class ExtendDecl(Node):
    target: BehaviourName
    members: tuple[Member, ...]


@dataclass(frozen=True, slots=True, eq=False)
class GlobalDecl(Node):
    field: FieldDecl


Declaration = (
    ImportDecl
    | UseStatement
    | NamespaceDecl
    | ExportDecl
    | PhysicalTypeDecl
    | UnitDecl
    | EnumDecl
    | EnumExtension
    | StructDecl
    | ActorDecl
    | ScenarioDecl
    | ActionDecl
    | ModifierDecl
    | ExtendDecl
    | GlobalDecl
)


@dataclass(frozen=True, slots=True, eq=False)
class File(Node):
    declarations: tuple[Declaration, ...]
