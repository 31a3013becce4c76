"""One CARLA file as the dialect's rules read and edit it (:mod:`osc2check.dialects.carla`).

A rule asks for the source of a node, the standard library's name for a CARLA
name, the fields and globals a name may refer to, and it records edits (that
must not overlap) and findings. Text inside a declaration that a rule commented
out is left alone by later rules.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, replace

from osc2check.diagnostics import Diagnostic
from osc2check.dialects.rewrite import Edit, apply_edits
from osc2check.semantics.model import Context
from osc2check.semantics.stdlib import standard_library
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ParseResult, ast
from osc2check.syntax.walk import walk

__all__ = ["CARLA_TYPE_NAMES", "CarlaText", "Field"]

#: CARLA's names of standard types
CARLA_TYPE_NAMES = {"velocity": "speed", "Path": "map"}


@dataclass(frozen=True, slots=True)
class Field:
    """A field or global parameter as written: its name, type name, default and node."""

    name: str
    type: str | None
    default: ast.Expr | None
    decl: ast.FieldDecl


class CarlaText:
    """A CARLA file being read: its text and tree, and the edits and findings so far."""

    def __init__(self, result: ParseResult) -> None:
        self.result = result
        self.text = result.text
        self.file = result.ast
        self.edits: list[Edit] = []
        self.findings: list[Diagnostic] = []
        self._removed: list[tuple[int, int]] = []  # commented out
        self._claimed: list[tuple[int, int]] = []  # replaced whole by a rule

    # ---- the standard library

    def standard_type(self, name: str) -> Symbol | None:
        """The standard's physical type ``name`` (CARLA's names mapped first)."""
        return self._standard(CARLA_TYPE_NAMES.get(name, name), SymbolKind.PHYSICAL_TYPE)

    def standard_unit(self, name: str) -> Symbol | None:
        return standard_library().model.unit(name)

    @staticmethod
    def _standard(name: str, kind: SymbolKind) -> Symbol | None:
        found = standard_library().model.lookup(
            name, Context("", ("stdtypes", "std")), None, lambda s: s.kind is kind
        )
        return found[0] if found else None

    # ---- what the file declares

    def scenarios(self) -> Iterator[ast.ScenarioDecl]:
        for decl in self.file.declarations:
            if isinstance(decl, ast.ScenarioDecl):
                yield decl

    def globals(self) -> dict[str, Field]:
        found: dict[str, Field] = {}
        for decl in self.file.declarations:
            if isinstance(decl, ast.GlobalDecl):
                found.update((f.name, f) for f in _fields(decl.field))
        return found

    @staticmethod
    def fields(scenario: ast.ScenarioDecl) -> dict[str, Field]:
        found: dict[str, Field] = {}
        for member in scenario.members:
            if isinstance(member, ast.FieldDecl):
                found.update((f.name, f) for f in _fields(member))
        return found

    # ---- text

    def source(self, node: ast.Node | Span) -> str:
        span = node if isinstance(node, Span) else node.span
        return self.text[span.start : span.end]

    def line_start(self, offset: int) -> int:
        return self.text.rfind("\n", 0, offset) + 1

    def indent(self, offset: int) -> str:
        """The whitespace that begins the line of ``offset``."""
        start = self.line_start(offset)
        line = self.text[start:offset]
        return line[: len(line) - len(line.lstrip(" \t"))]

    def removed(self, span: Span) -> bool:
        """Whether ``span`` lies in text a rule commented out."""
        return any(a <= span.start and span.end <= b for a, b in self._removed)

    def claimed(self, span: Span) -> bool:
        """Whether ``span`` lies in text a rule replaced whole (its names already
        substituted)."""
        return any(a <= span.start and span.end <= b for a, b in self._claimed)

    def claim(self, span: Span) -> None:
        self._claimed.append((span.start, span.end))

    # ---- edits and findings

    def replace(self, span: Span, new: str) -> None:
        self.replace_between(span.start, span.end, new)

    def replace_between(self, start: int, end: int, new: str) -> None:
        self.edits.append(Edit(start, end, new))

    def insert(self, offset: int, new: str) -> None:
        self.edits.append(Edit(offset, offset, new))

    def comment_out(self, span: Span) -> None:
        """Make the lines of ``span`` comments (``# `` before their first character)."""
        start = offset = self.line_start(span.start)
        while True:
            end = self.text.find("\n", offset)
            end = len(self.text) if end < 0 else end
            line = self.text[offset:end]
            if line.strip():
                self.insert(offset + len(line) - len(line.lstrip(" \t")), "# ")
            if end >= span.end or end >= len(self.text):
                break
            offset = end + 1
        self._removed.append((start, span.end))

    def edited_between(self, start: int, end: int) -> str:
        """The text of ``start..end`` with the edits inside it made."""
        inside = [e for e in self.edits if start <= e.start and e.end <= end]
        new, _ = apply_edits(
            self.text[start:end],
            [replace(e, start=e.start - start, end=e.end - start) for e in inside],
        )
        return new

    def edited(self, span: Span) -> str:
        return self.edited_between(span.start, span.end)

    def rewrite(self, span: Span, new: str) -> None:
        """Replace ``span`` with ``new``, which was written from its edited text: the edits
        inside it are taken back."""
        self.edits = [e for e in self.edits if not (span.start <= e.start and e.end <= span.end)]
        self.replace(span, new)

    def report(self, finding: Diagnostic) -> None:
        self.findings.append(finding)

    def names(self, node: ast.Node, name: str) -> Iterator[ast.NameRef]:
        """The bare references to ``name`` below ``node``."""
        for n in walk(node):
            if isinstance(n, ast.NameRef) and n.name.namespace is None and n.name.name.text == name:
                yield n


def _fields(decl: ast.FieldDecl) -> Iterator[Field]:
    type_name = decl.type.name.name.text if isinstance(decl.type, ast.NamedType) else None
    for name in decl.names:
        yield Field(name.text, type_name, decl.default, decl)
