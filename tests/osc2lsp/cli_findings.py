"""What ``osc2check`` reports for a text, as LSP diagnostics would show it: the
reference the server's diagnostics are compared with."""

from __future__ import annotations

from osc2check.analysis import SourceInput, analyze
from osc2check.config import Config
from osc2lsp.text import uri_to_key
from tests.osc2lsp.storms import lsp_lines, units


def cli_findings(
    uri: str, text: str, encoding: str = "utf-16", verify: bool = False
) -> list[tuple]:
    """``(code, start, end, message)`` of the checker's findings (the solver's too with
    ``verify``), positions as LSP ``(line, character)`` pairs, sorted."""
    key = uri_to_key(uri)
    analysis = analyze([SourceInput(key, text)], Config().analysis_options(verify=verify))
    lines = [text[start:end] for start, end in lsp_lines(text)]

    def position(line: int, column: int) -> tuple[int, int]:
        if line - 1 >= len(lines):
            return (len(lines), 0)
        content = lines[line - 1]
        return (line - 1, units(content[: max(column - 1, 0)], encoding))

    found = []
    for d in analysis.diagnostics:
        if d.span.uri == key:
            s = d.span
            start, end = position(s.line, s.column), position(s.end_line, s.end_column)
            found.append((d.code.code, start, end, d.message))
    return sorted(found)


def lsp_findings(diagnostics: list) -> list[tuple]:
    """The same tuples from LSP diagnostics (JSON dicts or lsprotocol objects)."""
    found = []
    for d in diagnostics:
        if isinstance(d, dict):
            r = d["range"]
            found.append(
                (
                    d["code"],
                    (r["start"]["line"], r["start"]["character"]),
                    (r["end"]["line"], r["end"]["character"]),
                    d["message"],
                )
            )
        else:
            r = d.range
            found.append(
                (
                    d.code,
                    (r.start.line, r.start.character),
                    (r.end.line, r.end.character),
                    d.message,
                )
            )
    return sorted(found)
