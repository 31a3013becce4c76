"""Code actions for the diagnostics in a range.

* the checker's own fixes ("did you mean" names and units, `import
  osc.standard` for a library file import...), preferred when safe;
* add a missing ``import osc.standard`` when an undefined name is declared by
  the standard library;
* suppress a finding on its line with ``# osc2check: ignore[CODE]`` (merged
  into an existing suppression comment of that line).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from osc2check.diagnostics import Diagnostic, TextEdit
from osc2check.semantics.stdlib import STANDARD_MODULES, standard_library
from osc2check.source import Span
from osc2check.syntax import ast
from osc2lsp.snapshot import Snapshot

_SUPPRESSION = re.compile(r"osc2check\s*:\s*ignore\s*\[(?P<codes>[^\]]*)\]", re.IGNORECASE)
_UNSUPPRESSIBLE = frozenset({"S001", "S002"})
_NAME_CODES = frozenset({"N101"})
IMPORT_STANDARD = "import osc.standard"


@dataclass
class Action:
    title: str
    kind: str  # "quickfix"
    edits: dict[str, list[TextEdit]]
    diagnostics: list[Diagnostic] = field(default_factory=list)
    preferred: bool = False


def code_actions(snapshot: Snapshot, start: int, end: int) -> list[Action]:
    """Actions for the diagnostics of the document that touch lines ``start``..``end``."""
    first_line, _ = snapshot.lines.position(start)
    last_line, _ = snapshot.lines.position(end)
    found = [
        d
        for d in snapshot.diagnostics
        if d.span.line - 1 <= last_line and d.span.end_line - 1 >= first_line
    ]
    actions: list[Action] = []
    import_added = False
    for d in found:
        if d.fix is not None and d.fix.edits:
            title = d.fix.message[:1].upper() + d.fix.message[1:]
            edits: dict[str, list[TextEdit]] = {}
            for edit in d.fix.edits:
                edits.setdefault(edit.span.uri, []).append(edit)
            actions.append(Action(title, "quickfix", edits, [d], preferred=d.fix.safe))
        if not import_added and d.code.code in _NAME_CODES and _needs_standard_import(snapshot, d):
            actions.append(
                Action(
                    f"Add `{IMPORT_STANDARD}`",
                    "quickfix",
                    {snapshot.key: [_import_edit(snapshot)]},
                    [d],
                    preferred=d.fix is None,
                )
            )
            import_added = True
    for d in found:
        if d.code.code in _UNSUPPRESSIBLE:
            continue
        edit = suppression_edit(snapshot, d)
        actions.append(
            Action(
                f"Suppress {d.code.code} ({d.code.slug}) on this line",
                "quickfix",
                {snapshot.key: [edit]},
                [d],
            )
        )
    return actions


def _needs_standard_import(snapshot: Snapshot, d: Diagnostic) -> bool:
    if _imports_standard(snapshot):
        return False
    name = snapshot.text[d.span.start : d.span.end].split("::")[-1].strip()
    if not name:
        return False
    library = standard_library().model
    for ns in STANDARD_MODULES["osc.standard"][0]:
        part = library.namespaces.get(ns)
        if part is not None and name in part.symbols:
            return True
    return False


def _imports_standard(snapshot: Snapshot) -> bool:
    for decl in snapshot.ast.declarations:
        if (
            isinstance(decl, ast.ImportDecl)
            and decl.kind == "module"
            and decl.target in ("osc.standard", "osc.standard.all", "osc.standard.domain")
        ):
            return True
    return False


def _import_edit(snapshot: Snapshot) -> TextEdit:
    """Insert the import after the file's leading comments and existing imports."""
    lines = snapshot.lines
    line = 0
    for decl in snapshot.ast.declarations:
        if isinstance(decl, ast.ImportDecl):
            line = decl.span.end_line  # after the last import (1-based end → next 0-based)
    if line == 0:
        while line < len(lines) and lines.line_content(line).lstrip().startswith("#"):
            line += 1
    offset = lines.offset(line, 0) if line < len(lines) else len(snapshot.text)
    prefix = "" if offset == 0 or snapshot.text[offset - 1 : offset] == "\n" else "\n"
    span = Span(snapshot.key, line + 1, 1, line + 1, 1, offset, offset)
    return TextEdit(span, f"{prefix}{IMPORT_STANDARD}\n")


def suppression_edit(snapshot: Snapshot, d: Diagnostic) -> TextEdit:
    """Add ``CODE`` to the suppression comment of the diagnostic's first line."""
    line = d.span.line - 1
    content = snapshot.lines.line_content(line)
    line_start = snapshot.lines.offset(line, 0)
    comment = next(
        (c for c in snapshot.parse.comments if line_start <= c.offset <= line_start + len(content)),
        None,
    )
    code = d.code.code
    if comment is not None:
        match = _SUPPRESSION.search(comment.text)
        if match is not None:
            inner_end = comment.offset + match.end("codes")
            existing = match.group("codes").strip()
            text = f", {code}" if existing else code
            line0, col0 = snapshot.lines.position(inner_end)
            at = Span(snapshot.key, line0 + 1, col0 + 1, line0 + 1, col0 + 1, inner_end, inner_end)
            return TextEdit(at, text)
    end = line_start + len(content.rstrip())
    trimmed = line_start + len(content)
    line0, col0 = snapshot.lines.position(end)
    line1, col1 = snapshot.lines.position(trimmed)
    return TextEdit(
        Span(snapshot.key, line0 + 1, col0 + 1, line1 + 1, col1 + 1, end, trimmed),
        f"  # osc2check: ignore[{code}]",
    )
