"""The parser's tables: lark's LALR analysis of the grammar, as plain data.

Making them (lark reads and analyses ``grammar/osc2.lark``) takes about a second,
and importing lark a good part of a checker's start-up; the start-up cache
(``osc2check.cache``) keeps the tables, so a process that parses only sound text
never imports lark. :func:`drive` runs the LALR automaton over the tables and
calls the AST builder exactly as lark's own callbacks would: the tables carry,
for every rule, what lark's tree builder does before it calls the builder (the
``?rule`` pass-through, the filtering and inlining of children, the ``None`` of
an absent ``[optional]``), read from that tree builder when the tables are made.

On the first token the tables cannot take, parsing goes on in lark's interactive
parser (``recover``), made from the same stored analysis (:func:`lark_parser`),
so its states are the tables' states and the stacks carry over as they are.
"""

from __future__ import annotations

import pickle
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from operator import itemgetter
from typing import TYPE_CHECKING, Any

from osc2check import cache
from osc2check.syntax.grammar import grammar_key, grammar_text

if TYPE_CHECKING:
    from lark import Lark

__all__ = [
    "Automaton",
    "Inline",
    "ParseTables",
    "Reduction",
    "RuleShape",
    "automaton",
    "drive",
    "finish",
    "lark_parser",
    "parse_tables",
]

LARK_OPTIONS: dict[str, Any] = dict(parser="lalr", lexer="basic", maybe_placeholders=True)
START = "start"


@dataclass(frozen=True, slots=True)
class RuleShape:
    """One grammar rule, and how lark's tree builder turns its children into a value."""

    origin: str  # the rule's name, which the parser shifts after reducing it
    symbols: tuple[str, ...]  # what it expands to
    callback: str  # the builder method lark calls: the alias, else the rule's name
    passes: bool  # a `?rule` of one kept symbol: its value is that child's
    expand1: bool  # a `?rule`: one child left after filtering is the value
    include: tuple[tuple[int, bool, int], ...] | None  # kept: (index, inline, Nones before)
    nones_after: int  # Nones after the last kept child (absent `[optional]` parts)


@dataclass(frozen=True)
class ParseTables:
    """The automaton and the terminals, as lark made them from the grammar.

    ``rows[state][terminal]`` is the state to shift to (>= 0) or ``~rule`` (< 0), the
    index in ``rules`` of the rule to reduce. ``analysis`` is lark's own stored form
    of its parser (pickled), from which :func:`lark_parser` rebuilds it.
    """

    rows: dict[int, dict[str, int]]
    rules: tuple[RuleShape, ...]
    start: int
    end: int
    literals: dict[str, str]  # fixed-text terminals: name -> text
    patterns: dict[str, str]  # regular-expression terminals: name -> pattern
    analysis: bytes


class Inline:
    """The value of a rule that its parent inlines (``_rule``), as lark's ``Tree`` is read."""

    __slots__ = ("data", "children")

    def __init__(self, data: str, children: list[Any]) -> None:
        self.data = data
        self.children = children


_lock = threading.Lock()
_tables: ParseTables | None = None
_larks: dict[object, Lark] = {}


def parse_tables() -> ParseTables:
    """The tables: from the start-up cache, else made with lark and stored."""
    global _tables
    with _lock:
        if _tables is None:
            _tables = cache.cached("parse-tables", grammar_key(), _make)
        return _tables


def lark_parser(builder: object | None = None) -> Lark:
    """Lark's LALR parser over the tables' states, with ``builder``'s callbacks (or lark's
    tree callbacks); one per builder, made on first use."""
    tables = parse_tables()
    with _lock:
        found = _larks.get(builder)
        if found is None:
            data, memo = pickle.loads(tables.analysis)
            options = {"transformer": builder} if builder is not None else {}
            found = _larks[builder] = _load_lark(data, memo, **options)
        return found


# ---------------------------------------------------------------- driving the automaton

Callback = Callable[[list[Any]], Any] | None  # None: the rule's value is its only child
# What reducing a rule does: pop this many values, call this (None: keep the one value),
# then shift the rule's name (its ``origin``).
Reduction = tuple[int, Callback, str]


@dataclass(frozen=True, slots=True)
class Automaton:
    """The tables as :func:`drive` reads them, with a builder's callbacks: the rows in a
    list by state (an index instead of a hash), and what reducing each rule does."""

    rows: list[dict[str, int]]
    reductions: list[Reduction]
    end: int
    # (state under, state, terminal) -> the state a chain of `?rule: other` reductions
    # ends in: found on first use (a name in an expression reduces through seven)
    chains: dict[tuple[int, int, str], int] = field(default_factory=dict)


def automaton(tables: ParseTables, builder: object) -> Automaton:
    """The automaton of ``tables`` whose reductions call ``builder``'s methods as lark's
    tree builder calls them (a rule without a method makes an ``Inline``)."""
    return Automaton(
        [tables.rows[state] for state in range(len(tables.rows))],
        [(len(shape.symbols), _callback(shape, builder), shape.origin) for shape in tables.rules],
        tables.end,
    )


def _callback(shape: RuleShape, builder: object) -> Callback:
    """The builder's method for ``shape``, called as lark's tree builder calls it: one
    closure per rule, picking the kept children without a loop where none is inlined
    (a reduction is the commonest step of a parse)."""
    if shape.passes:
        return None
    method = getattr(builder, shape.callback, None)
    if method is None:
        name = shape.callback

        def method(children: list[Any]) -> Any:
            return Inline(name, children)

    call = method
    if shape.expand1:

        def call(children: list[Any]) -> Any:
            return children[0] if len(children) == 1 else method(children)

    include, after = shape.include, shape.nones_after
    if include is None:
        return call
    if any(inline for _, inline, _ in include):
        return _filtered(include, after, call)
    picks: list[int] = []  # the index of each kept child, -1 for a None
    for i, _, nones in include:
        picks += [-1] * nones
        picks.append(i)
    picks += [-1] * after
    return _picked(picks, call)


def _picked(picks: list[int], call: Callable[[list[Any]], Any]) -> Callback:
    """``call`` on the children at ``picks`` (-1: a ``None``, appended to the children,
    which are the parser's own slice of its stack), by ``itemgetter``."""
    if not picks:
        return lambda children: call([])
    if len(picks) == 1:
        (at,) = picks
        if at < 0:
            return lambda children: call([None])
        return lambda children: call([children[at]])
    get = itemgetter(*picks)
    if -1 not in picks:
        return lambda children: call([*get(children)])

    def padded(children: list[Any]) -> Any:
        children.append(None)
        return call([*get(children)])

    return padded


def _filtered(
    include: tuple[tuple[int, bool, int], ...], after: int, call: Callable[[list[Any]], Any]
) -> Callback:
    """``call`` on the kept children of a rule that inlines some, as lark's
    ``ChildFilterLALR`` keeps them."""

    def filtered(children: list[Any]) -> Any:
        kept: list[Any] = []
        for i, inline, nones in include:
            if nones:
                kept += [None] * nones
            if inline:
                if kept:
                    kept += children[i].children
                else:  # lark reuses the inlined list (a left-recursive rule's items)
                    kept = children[i].children
            else:
                kept.append(children[i])
        if after:
            kept += [None] * after
        return call(kept)

    return filtered


def drive(automaton: Automaton, states: list[int], values: list[Any], tokens: Sequence[Any]) -> int:
    """Feed ``tokens`` (anything with a ``type``) until one cannot be taken; returns how
    many were. ``states`` and ``values`` are the parser's stacks, changed in place."""
    rows, reductions, chains = automaton.rows, automaton.reductions, automaton.chains
    row = rows[states[-1]]
    push_state, push_value = states.append, values.append
    consumed = 0
    for tok in tokens:
        ttype = tok.type
        while True:
            entry = row.get(ttype)
            if entry is None:
                return consumed
            if entry >= 0:
                push_state(entry)
                push_value(tok)
                row = rows[entry]
                break
            size, call, origin = reductions[~entry]
            if call is None:  # `?rule: other`: the child is the value, the stack is as it was
                key = (states[-2], states[-1], ttype)
                goto = chains.get(key)
                if goto is None:
                    goto = chains[key] = _chain(rows, reductions, states[-2], origin, ttype)
                states[-1] = goto
                row = rows[goto]
                continue
            if size == 1:  # the commonest reduction: the value is replaced in place
                values[-1] = call([values[-1]])
                del states[-1]
            elif size:
                children = values[-size:]
                del states[-size:]
                del values[-size:]
                push_value(call(children))
            else:
                push_value(call([]))
            goto = rows[states[-1]][origin]
            push_state(goto)
            row = rows[goto]
        consumed += 1
    return consumed


def _chain(
    rows: list[dict[str, int]], reductions: list[Reduction], under: int, origin: str, ttype: str
) -> int:
    """The state after reducing to ``origin`` over state ``under`` and then every
    `?rule: other` reduction that ``ttype`` asks for next (each one over ``under`` too)."""
    goto = rows[under][origin]
    while (entry := rows[goto].get(ttype)) is not None and entry < 0:
        _, call, then = reductions[~entry]
        if call is not None:
            break
        goto = rows[under][then]
    return goto


class _End:
    type = "$END"


def finish(automaton: Automaton, states: list[int], values: list[Any]) -> tuple[bool, Any]:
    """Feed the end of input: (True, the start rule's value), or (False, None) when the
    input cannot end here (the stacks are then as they were)."""
    saved_states, saved_values = list(states), list(values)
    drive(automaton, states, values, (_End,))  # reduces up to the end state, or stops
    if states[-1] == automaton.end:
        return True, values[-1]
    states[:], values[:] = saved_states, saved_values
    return False, None


# ---------------------------------------------------------------- making the tables


def _load_lark(data: Any, memo: Any, **options: Any) -> Lark:
    """Lark's parser from its stored form (``Lark.save`` writes it; ``Lark.load`` reads it
    from a file, this from the data itself, as lark's standalone parsers do)."""
    from lark import Lark

    loaded: Lark = Lark._load_from_dict(data, memo, **options)  # type: ignore[no-untyped-call]
    return loaded


def _make() -> ParseTables:
    from lark.lexer import PatternStr
    from lark.parse_tree_builder import (
        ChildFilterLALR,
        ChildFilterLALR_NoPlaceholders,
        ExpandSingleChild,
    )
    from lark.parsers.lalr_analysis import Shift

    # lark's analysis of the grammar (about a second) depends on the grammar and lark
    # only: it is kept across versions of the toolkit, as lark's own cache would be
    key = {**grammar_key(), "options": repr(sorted(LARK_OPTIONS.items()))}
    analysis = cache.cached("lark-analysis", key, _analyse, toolkit=False)
    data, memo = pickle.loads(analysis)
    # the tables are read from the stored form, loaded back: their states are then the
    # ones every later process's lark parser has
    lark = _load_lark(data, memo)
    index = {rule: i for i, rule in enumerate(lark.rules)}
    shapes: list[RuleShape] = []
    for rule, chain in lark._parse_tree_builder.rule_builders:
        expand1 = False
        include: tuple[tuple[int, bool, int], ...] | None = None
        after = 0
        for wrapper in chain:
            kind = getattr(wrapper, "func", wrapper)
            if kind is ExpandSingleChild:
                expand1 = True
            elif kind is ChildFilterLALR:
                include = tuple((i, bool(x), n) for i, x, n in wrapper.args[0])
                after = wrapper.args[1]
            elif kind is ChildFilterLALR_NoPlaceholders:
                include = tuple((i, bool(x), 0) for i, x in wrapper.args[0])
            else:
                raise TypeError(f"lark's tree builder wraps a rule in {wrapper!r}, unknown here")
        symbols = tuple(str(s.name) for s in rule.expansion)
        kept = len(rule.expansion) == 1 and not (
            rule.expansion[0].is_term and getattr(rule.expansion[0], "filter_out", False)
        )
        shapes.append(
            RuleShape(
                origin=str(rule.origin.name),
                symbols=symbols,
                callback=str(rule.alias or rule.options.template_source or rule.origin.name),
                passes=bool(rule.options.expand1)
                and not rule.alias
                and kept
                and (include is None or (include == ((0, False, 0),) and after == 0)),
                expand1=expand1,
                include=include,
                nones_after=after,
            )
        )
    order = [index[rule] for rule, _ in lark._parse_tree_builder.rule_builders]
    if order != list(range(len(order))):
        raise AssertionError("lark's tree builder lists the rules in another order")
    conf = lark.parse_interactive(start=START).parser_state.parse_conf
    rows = {
        int(state): {
            str(ttype): int(arg) if action is Shift else ~index[arg]
            for ttype, (action, arg) in row.items()
        }
        for state, row in conf.states.items()
    }
    literals: dict[str, str] = {}
    patterns: dict[str, str] = {}
    for term in lark.terminals:
        value = str(term.pattern.value)
        (literals if isinstance(term.pattern, PatternStr) else patterns)[str(term.name)] = value
    return ParseTables(
        rows=rows,
        rules=tuple(shapes),
        start=int(conf.start_state),
        end=int(conf.end_state),
        literals=literals,
        patterns=patterns,
        analysis=analysis,
    )


def _analyse() -> bytes:
    """lark's LALR analysis of the grammar, in lark's own stored form (``Lark.save``)."""
    from lark import Lark
    from lark.grammar import Rule
    from lark.lexer import TerminalDef

    made = Lark(grammar_text(), **LARK_OPTIONS)
    return pickle.dumps(made.memo_serialize([TerminalDef, Rule]), protocol=pickle.HIGHEST_PROTOCOL)
