"""What may come next at a point: lark's LALR table driven over a token prefix.

The language server completes with it; it is a question about the syntax, so it
lives here beside the parser. Only the state stack is kept (no values, no tree
callbacks), so a prefix of a few hundred tokens is fed in well under a
millisecond. Tokens the parser cannot take are repaired as the checker's
recovery (``recover.py``) repairs them, with its alphabet and depth: at a
statement boundary the shortest sequence of missing terminals (a `)`, a `:`) is
inserted, else the statement that cannot be completed is popped; other tokens
are dropped; an unexpected indented block is skipped.
"""

from __future__ import annotations

import re
from functools import cache
from typing import Literal

from osc2check.syntax.tables import parse_tables

# Terminals a repair may insert, tried in this order, at most MAX_REPAIR of them (the
# checker's recovery, ``recover.py``, repairs with the same alphabet and depth).
REPAIR_ALPHABET = ("RPAR", "RSQB", "COLON", "NAME", "INT", "_NL", "_INDENT", "_DEDENT")
MAX_REPAIR = 3
_BOUNDARIES = frozenset({"_NL", "_DEDENT"})
_MAX_TRIALS = 400  # repair candidates tried at one boundary (as recovery's fork limit)
_IDENTIFIER = re.compile(r"[^\W\d]\w*")

# A table entry: a shift and the state shifted to, or a reduction (rule size, rule name).
_Entry = tuple[Literal[True], int] | tuple[Literal[False], tuple[int, str]]


@cache
def _table() -> tuple[dict[int, dict[str, _Entry]], int]:
    tables = parse_tables()
    rules = tables.rules
    states: dict[int, dict[str, _Entry]] = {}
    for state, row in tables.rows.items():
        states[state] = {
            ttype: (True, entry)
            if entry >= 0
            else (False, (len(rules[~entry].symbols), rules[~entry].origin))
            for ttype, entry in row.items()
        }
    return states, tables.start


@cache
def keywords() -> dict[str, str]:
    """Keyword terminals (``SCENARIO``) and their text (``scenario``)."""
    return {
        name: value
        for name, value in parse_tables().literals.items()
        if _IDENTIFIER.fullmatch(value)
    }


@cache
def soft_keywords() -> frozenset[str]:
    """Keywords that may also be names (the alternatives of the grammar rule ``name``)."""
    return frozenset(
        r.symbols[0]
        for r in parse_tables().rules
        if r.origin == "name" and len(r.symbols) == 1 and r.symbols[0] != "NAME"
    )


class GrammarState:
    """A parser state stack that tokens are fed into."""

    __slots__ = ("stack",)

    def __init__(self, stack: list[int] | None = None):
        self.stack = stack if stack is not None else [_table()[1]]

    def copy(self) -> GrammarState:
        return GrammarState(list(self.stack))

    def feed(self, ttype: str) -> bool:
        """Feed one terminal; on failure the state is left unchanged."""
        states = _table()[0]
        stack = list(self.stack)
        while True:
            entry = states[stack[-1]].get(ttype)
            if entry is None:
                return False
            if entry[0]:
                stack.append(entry[1])
                self.stack = stack
                return True
            size, origin = entry[1]
            if size:
                del stack[-size:]
            goto = states[stack[-1]].get(origin)
            if goto is None or not goto[0]:  # a rule's name is only ever shifted
                return False
            stack.append(goto[1])

    def accepts(self) -> frozenset[str]:
        """Terminals that can come next."""
        states = _table()[0]
        return frozenset(t for t in states[self.stack[-1]] if t.isupper() and self.copy().feed(t))

    def keyword_use(self, ttype: str) -> bool:
        """Whether keyword ``ttype`` is accepted as itself, not only as a name."""
        trial = self.copy()
        if not trial.feed(ttype):
            return False
        if ttype not in soft_keywords():
            return True
        row = _table()[0][trial.stack[-1]]
        return not all(not entry[0] and entry[1][1] == "name" for entry in row.values())


def run(types: list[str]) -> GrammarState:
    """The state after feeding ``types`` (terminal names), repairing what does not fit."""
    state = GrammarState()
    i, n = 0, len(types)
    while i < n:
        t = types[i]
        if state.feed(t):
            i += 1
            continue
        if t in _BOUNDARIES or t == "_INDENT":
            repaired = _repair(state, t)
            if repaired is not None:
                state = repaired
                i += 1
                continue
            if t == "_INDENT":  # an unexpected block: skip it
                depth = 0
                while i < n:
                    depth += types[i] == "_INDENT"
                    depth -= types[i] == "_DEDENT"
                    i += 1
                    if depth == 0:
                        break
                continue
            popped = _pop_until(state, t)
            if popped is not None:
                state = popped
                i += 1
                continue
        i += 1  # drop the token
    return state


def _repair(state: GrammarState, boundary: str) -> GrammarState | None:
    """The state after the shortest repair sequence that makes ``boundary`` acceptable."""
    frontier = [state]
    trials = 0
    for _depth in range(MAX_REPAIR):
        following: list[GrammarState] = []
        for base in frontier:
            for kind in REPAIR_ALPHABET:
                if kind == boundary or trials >= _MAX_TRIALS:
                    continue
                trials += 1
                trial = base.copy()
                if not trial.feed(kind):
                    continue
                done = trial.copy()
                if done.feed(boundary):
                    return done
                following.append(trial)
        frontier = following
    return None


def _pop_until(state: GrammarState, ttype: str) -> GrammarState | None:
    for pops in range(1, len(state.stack)):
        trial = GrammarState(state.stack[:-pops])
        if trial.feed(ttype):
            return trial
    return None
