"""Syntax: lexer, tolerant indenter, LALR parser with recovery, AST builder."""

from osc2check.syntax.parser import ParseResult, parse
from osc2check.syntax.walk import dump, walk

__all__ = ["ParseResult", "dump", "parse", "walk"]
