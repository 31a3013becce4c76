"""The documentation page of each code, and ``docs/checks.md`` built from them.

Every code in ``codes.ALL`` has a page ``code_docs/<CODE>.md`` shipped inside the
package, so ``osc2check rule N101`` works from an installed wheel. A page has a
title line (``# N101 undefined-name``), the summary, and the sections named in
``SECTIONS``. The *Example* section holds a small OSC2 file (an ``osc`` fence)
that reports exactly that code; the *Fix* section holds the corrected file.

Two conventions let an example be more than one UTF-8 file:

* a fence whose first line is ``# file: NAME`` is the file ``NAME`` (the first
  fence of a section is the file that is checked; the others sit beside it);
* ``<!-- example-encoding: latin-1 -->`` in a section encodes its files so.

Regenerate ``docs/checks.md`` with ``python -m osc2check.rules docs/checks.md``.
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass
from importlib import resources

from osc2check import codes
from osc2check.codes import Code

__all__ = [
    "DEFAULT_EXAMPLE_NAME",
    "SECTIONS",
    "ExampleFile",
    "anchor",
    "doc_url",
    "example_files",
    "page_sections",
    "page_text",
    "render_checks_md",
]

SECTIONS = ("What it finds", "Why it matters", "Example", "Fix", "Options", "Since")
DEFAULT_EXAMPLE_NAME = "example.osc"
DOCS_PATH = "docs/checks.md"

_FILE_LINE = re.compile(r"#\s*file:\s*(\S+)")
_ENCODING = re.compile(r"<!--\s*example-encoding:\s*([\w-]+)\s*-->")


@dataclass(frozen=True, slots=True)
class ExampleFile:
    """One file of a page's example: its name and its exact bytes."""

    name: str
    data: bytes


def _code(code: Code | str) -> Code:
    if isinstance(code, Code):
        return code
    found = codes.lookup(code)
    if found is None:
        raise KeyError(f"unknown code {code!r}")
    return found


def page_text(code: Code | str) -> str:
    """The Markdown page of ``code`` (a ``Code``, a code such as ``N101`` or a slug).

    Raises ``KeyError`` for an unknown code and ``FileNotFoundError`` when the
    code has no page.
    """
    c = _code(code)
    return resources.files("osc2check").joinpath("code_docs", f"{c.code}.md").read_text("utf-8")


def _heading(line: str, level: int) -> str | None:
    prefix = "#" * level + " "
    return line[len(prefix) :].strip() if line.startswith(prefix) else None


def page_sections(text: str) -> dict[str, str]:
    """Split a page into ``{"title": ..., "summary": ..., <section>: body}``.

    Headings inside code fences are not headings.
    """
    result: dict[str, str] = {}
    current = "summary"
    body: list[str] = []
    in_fence = False
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            in_fence = not in_fence
        if not in_fence:
            title = _heading(line, 1)
            section = _heading(line, 2)
            if title is not None and "title" not in result:
                result["title"] = title
                continue
            if section is not None:
                result[current] = "\n".join(body).strip()
                current, body = section, []
                continue
        body.append(line)
    result[current] = "\n".join(body).strip()
    return result


def _fences(body: str, lang: str = "osc") -> list[str]:
    fences: list[str] = []
    lines: list[str] | None = None
    for line in body.splitlines():
        stripped = line.strip()
        if lines is None and stripped == f"```{lang}":
            lines = []
        elif lines is not None and stripped == "```":
            fences.append("\n".join(lines) + "\n")
            lines = None
        elif lines is not None:
            lines.append(line)
    return fences


def example_files(code: Code | str, section: str = "Example") -> list[ExampleFile]:
    """The files of the example in ``section`` (``"Example"`` or ``"Fix"``) of a page.

    The first file is the one to check. Names come from a ``# file: NAME`` first
    line, else ``example.osc``.
    """
    body = page_sections(page_text(code)).get(section, "")
    match = _ENCODING.search(body)
    encoding = match.group(1) if match else "utf-8"
    files = []
    for text in _fences(body):
        first = text.split("\n", 1)[0]
        named = _FILE_LINE.fullmatch(first.strip())
        name = named.group(1) if named else DEFAULT_EXAMPLE_NAME
        files.append(ExampleFile(name, text.encode(encoding)))
    return files


def anchor(code: Code) -> str:
    """The Markdown anchor of the code's section in ``docs/checks.md``."""
    return f"{code.code.lower()}-{code.slug}"


def doc_url(code: Code) -> str:
    """The link to the code's documentation, relative to the repository root."""
    return f"{DOCS_PATH}#{anchor(code)}"


def _demote(text: str, levels: int) -> str:
    out = []
    in_fence = False
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            in_fence = not in_fence
        if not in_fence and re.match(r"#{1,6} ", line):
            line = "#" * levels + line
        out.append(line)
    return "\n".join(out).rstrip("\n")


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def _order(code: Code) -> tuple[int, str]:
    families = list(codes.FAMILIES)
    rank = families.index(code.family) if code.family in families else len(families)
    return rank, code.code


def render_checks_md() -> str:
    """The text of ``docs/checks.md``: a table of every code, then every page."""
    ordered = sorted(codes.ALL, key=_order)
    active = [c for c in ordered if c.removed_in is None]
    lines = [
        "# Checks",
        "",
        "<!-- Generated from osc2check/code_docs/*.md by osc2check.rules; do not edit.",
        "     Regenerate with: python -m osc2check.rules docs/checks.md -->",
        "",
        "Every finding of `osc2check` has a code (a family letter and three digits) and a",
        "name. Select, ignore and suppress findings by either; `osc2check rule CODE` prints",
        "the page of one code. D codes are dialect forms the toolkit accepts with a warning;",
        "`--strict` makes them errors.",
        "",
        "| Code | Name | Severity | Summary |",
        "|---|---|---|---|",
    ]
    for c in active:
        lines.append(
            f"| [{c.code}](#{anchor(c)}) | `{c.slug}` | {c.severity.label} | {_cell(c.summary)} |"
        )
    for family, title in codes.FAMILIES.items():
        members = [c for c in ordered if c.family == family]
        if not members:
            continue
        lines += ["", f"## {family}: {title}"]
        for c in members:
            lines += ["", _demote(page_text(c), 2)]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    """Write ``docs/checks.md`` (or print it when no path is given)."""
    args = sys.argv[1:] if argv is None else argv
    text = render_checks_md()
    if not args:
        sys.stdout.write(text)
        return 0
    with open(args[0], "w", encoding="utf-8", newline="\n") as out:
        out.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
