"""What each call gives to each parameter, as the call checker bound it.

The call checker (``calls.py``) binds every invocation, modifier application,
method call, built-in function call, ``emit`` and composition once: positional
and named arguments unified, parameter defaults applied (and marked as such),
the language-level extras (``duration`` of every behaviour and composition,
``overlap``, ``start_to_start``, ``end_to_end`` of ``parallel``, an
invocation's ``until``), event arguments, and which arguments are ranges
given where a scalar is expected (``speed([30kph..31kph])``: the standard's
``keep(p in range)``, one value chosen from it). The result is a frozen
:class:`Binding` in the model's ``bindings`` side table, keyed by the call's
node; placement, timing, lowering, bins, the runner's compiler and the
language server read it (``Model.binding``) and bind nothing themselves.

Cover and record items (§7.5) have their own table, ``Model.cover_items``:
each item's name, the expression it samples and its named parameters, as
the checker read them.

Whether every bound argument is *used* is checked by recording reads
(:func:`recording_reads`): the stages that realise a call — the start placement
(the witness the world is built from) and the runner's behaviours — read its
arguments through :class:`ReadArguments`, which notes each parameter read, and
the runner notes each action whose phase started. An argument of a started call
that nothing read was dropped in silence (``tests/osc2runner/differential``).
Outside :func:`recording_reads` nothing is noted.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, TypeVar

from osc2check.semantics.builtins import Builtin
from osc2check.syntax import ast

if TYPE_CHECKING:
    from osc2check.semantics.symbols import Symbol
    from osc2check.source import Span

__all__ = [
    "EXTRAS",
    "ArgumentReads",
    "Binding",
    "BoundArgument",
    "CoverItem",
    "ReadArguments",
    "argument_values",
    "named_given",
    "note_read",
    "note_started",
    "python_arguments",
    "recording_reads",
]

#: The language-level arguments, which no library declaration lists: ``duration`` of
#: every behaviour invocation and composition, and ``parallel``'s overlap and offsets.
EXTRAS = ("duration", "overlap", "start_to_start", "end_to_end")


@dataclass(frozen=True, slots=True)
class BoundArgument:
    """One parameter's value in one call."""

    name: str
    value: ast.Expr
    #: the declared parameter; None for a language-level extra, a built-in function's
    #: parameter, or a parameter the standard's examples use but its library lacks
    parameter: Symbol | None = None
    #: the argument as written; None when the parameter's default was applied
    written: ast.PositionalArgument | ast.NamedArgument | None = None
    #: a range given where a scalar is expected: one value is chosen from it
    range: bool = False

    @property
    def is_default(self) -> bool:
        """Whether the value is the parameter's default, not an argument."""
        return self.written is None

    @property
    def positional(self) -> bool:
        return isinstance(self.written, ast.PositionalArgument)

    @property
    def span(self) -> Span:
        """Where the argument is written (the default's own span when none is)."""
        return self.written.span if self.written is not None else self.value.span


@dataclass(frozen=True, slots=True)
class Binding:
    """One call's arguments, bound to its callee's parameters by the call checker."""

    node: ast.Node  # the call: an Invocation, Call, Emit or Composition
    callee: Symbol | Builtin  # a composition's callee is a symbol named after its operator
    #: the callee's parameters that have a value (given, or by default), in declaration
    #: order, then arguments for parameters the standard's examples use (``left_of``)
    arguments: tuple[BoundArgument, ...] = ()
    extras: tuple[BoundArgument, ...] = ()  # ``duration``, ``overlap``, ... as given
    events: tuple[ast.EventArgument, ...] = ()  # ``@e`` given as an argument
    until: tuple[ast.Until, ...] = ()  # an invocation's ``until`` (its ``with:`` block)
    #: arguments that bind to nothing (the checker reported each)
    rejected: tuple[ast.Argument, ...] = ()

    @property
    def name(self) -> str:
        return self.callee.name

    def argument(self, name: str) -> BoundArgument | None:
        """The value of parameter or extra ``name``: given, or its default; None when it
        has none."""
        for bound in self.arguments:
            if bound.name == name:
                return bound
        for bound in self.extras:
            if bound.name == name:
                return bound
        return None

    def extra(self, name: str) -> BoundArgument | None:
        """The language-level argument ``name`` (``duration``, ``overlap``, ...) as given."""
        for bound in self.extras:
            if bound.name == name:
                return bound
        return None

    def value(self, name: str) -> ast.Expr | None:
        """The expression parameter or extra ``name`` takes, default included."""
        bound = self.argument(name)
        return bound.value if bound is not None else None

    def given(self, name: str) -> BoundArgument | None:
        """The argument written for ``name``; None when it was not given."""
        bound = self.argument(name)
        return bound if bound is not None and not bound.is_default else None

    def written(self) -> Iterator[BoundArgument]:
        """The arguments as written (parameters and extras), in source order."""
        found = [b for b in (*self.arguments, *self.extras) if b.written is not None]
        yield from sorted(found, key=lambda b: b.span.start)

    def values(self, defaults: bool = True) -> dict[str, ast.Expr]:
        """Each parameter's expression by name (extras left out)."""
        return {b.name: b.value for b in self.arguments if defaults or not b.is_default}

    @property
    def ranges(self) -> tuple[BoundArgument, ...]:
        """The arguments that are ranges given where a scalar is expected."""
        return tuple(b for b in self.arguments if b.range)

    def parameter_of(self, argument: ast.Node) -> str | None:
        """The name of the parameter ``argument`` (a node of this call) gives a value to."""
        for bound in (*self.arguments, *self.extras):
            if bound.written is argument:
                return bound.name
        return None


@dataclass(frozen=True, slots=True)
class CoverItem:
    """One ``cover``/``record`` (§7.5) as the checker read it."""

    decl: ast.CoverageDecl
    owner: Symbol | None  # the scenario (or type) it is a member of
    name: str  # "" when it has none
    name_node: ast.Node | None  # ``name:`` or the first positional argument
    #: the value it samples: its ``expression:``, else the field it is named after; None
    #: when it has neither, or when ``items:``/``override:`` make the name another item's
    expression: ast.Node | None
    parameters: tuple[tuple[str, ast.Node], ...]  # its named arguments, as written
    positional: tuple[ast.Node, ...]  # positional arguments after the name

    @property
    def kind(self) -> str:
        return self.decl.kind

    def get(self, name: str) -> ast.Node | None:
        """The named argument ``name`` (``unit``, ``range``, ``event``, ...), or None."""
        for key, value in self.parameters:
            if key == name:
                return value
        return None

    def has(self, name: str) -> bool:
        return any(key == name for key, _ in self.parameters)


def python_arguments(
    arguments: tuple[ast.Argument, ...],
) -> tuple[list[ast.Expr], dict[str, ast.Expr], list[ast.EventArgument]]:
    """The arguments of ``is external pkg.fn(x, limit: 3kph)`` as a Python call takes
    them: positional values, keyword values, and event arguments (which it cannot take).
    They bind to the Python function's parameters, not to OSC2 ones: nothing to bind."""
    positional: list[ast.Expr] = []
    keywords: dict[str, ast.Expr] = {}
    events: list[ast.EventArgument] = []
    for arg in arguments:
        if isinstance(arg, ast.NamedArgument):
            keywords[arg.name.text] = arg.value
        elif isinstance(arg, ast.PositionalArgument):
            positional.append(arg.value)
        else:
            events.append(arg)
    return positional, keywords, events


def argument_values(arguments: Iterable[ast.Node]) -> list[ast.Expr]:
    """The value expressions of ``arguments`` (events left out), for code that reads
    every value whichever parameter it binds to (type checks of a call that resolves to
    nothing, value hints)."""
    return [
        a.value for a in arguments if isinstance(a, (ast.PositionalArgument, ast.NamedArgument))
    ]


def named_given(arguments: Iterable[ast.Argument], name: str) -> bool:
    """Whether the language-level argument ``name`` (``duration``) is written, which only a
    name can give; for syntax-level classification that needs no model (``phases``)."""
    return any(isinstance(a, ast.NamedArgument) and a.name.text == name for a in arguments)


# ---------------------------------------------------------------------- reads


@dataclass
class ArgumentReads:
    """What was read while recording: ``(id(call), parameter)`` pairs, and the action
    invocations whose phase started (by ``id``; the calls outlive the recording)."""

    read: set[tuple[int, str]] = field(default_factory=set)
    started: set[int] = field(default_factory=set)

    def was_read(self, call: ast.Node, name: str) -> bool:
        return (id(call), name) in self.read


_READS: ContextVar[ArgumentReads | None] = ContextVar("argument_reads", default=None)


@contextmanager
def recording_reads(reads: ArgumentReads | None = None) -> Iterator[ArgumentReads]:
    """Record which arguments are read while the block runs (see the module docstring),
    into ``reads`` when given (to go on recording), else into a new record."""
    reads = reads if reads is not None else ArgumentReads()
    token = _READS.set(reads)
    try:
        yield reads
    finally:
        _READS.reset(token)


def note_read(call: ast.Node, name: str) -> None:
    """Parameter ``name`` of ``call`` was read (realised), when reads are recorded."""
    reads = _READS.get()
    if reads is not None:
        reads.read.add((id(call), name))


def note_started(call: ast.Node) -> None:
    """The phase of action invocation ``call`` started, when reads are recorded."""
    reads = _READS.get()
    if reads is not None:
        reads.started.add(id(call))


_V = TypeVar("_V")


class ReadArguments(dict[str, _V]):
    """A call's arguments by parameter name; reading one (``[name]``, ``get``, or all of
    them with ``items``/``values``) notes it (:func:`note_read`). ``name in args``
    notes nothing: knowing an argument is given is not using it."""

    __slots__ = ("call",)

    def __init__(self, call: ast.Node, values: Mapping[str, _V] | None = None) -> None:
        super().__init__(values or {})
        self.call = call

    def __getitem__(self, name: str) -> _V:
        note_read(self.call, name)
        return super().__getitem__(name)

    def get(self, name: str, default: Any = None) -> Any:  # noqa: D102 - dict's
        if name in self:
            note_read(self.call, name)
        return super().get(name, default)

    def items(self) -> Any:
        for name in self:
            note_read(self.call, name)
        return super().items()

    def values(self) -> Any:
        for name in self:
            note_read(self.call, name)
        return super().values()
