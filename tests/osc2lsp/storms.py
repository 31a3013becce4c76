"""Edit storms: random incremental edits as an LSP client sends them.

The model here is written from the LSP specification, independently of the
server: lines end at CR LF, LF or CR only (never at a form feed, VT, the
information separators, NEL or the Unicode line/paragraph separators), and a
character is counted in the client's units. ``SEPARATORS`` are the characters
``str.splitlines()`` breaks at although LSP does not.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from hypothesis import strategies as st

SEPARATORS = "\f\x0b\x1c\x1d\x1e\x85\u2028\u2029"
_BREAK = re.compile(r"\r\n|\r|\n")


def lsp_lines(text: str) -> list[tuple[int, int]]:
    """``(start, end)`` offsets of each line's content, LSP's way."""
    lines, start = [], 0
    for m in _BREAK.finditer(text):
        lines.append((start, m.start()))
        start = m.end()
    lines.append((start, len(text)))
    return lines


def units(text: str, encoding: str) -> int:
    if encoding == "utf-8":
        return len(text.encode("utf-8"))
    if encoding == "utf-32":
        return len(text)
    return len(text.encode("utf-16-le")) // 2


def lsp_position(text: str, offset: int, encoding: str = "utf-16") -> dict:
    """The LSP position (a JSON object) of a code-point offset of ``text``."""
    for number, (start, end) in enumerate(lsp_lines(text)):
        if offset <= end:
            return {"line": number, "character": units(text[start:offset], encoding)}
    raise ValueError(offset)


@dataclass(frozen=True)
class Edit:
    start: int  # code-point offsets of the text before the edit
    end: int
    text: str

    def apply(self, text: str) -> str:
        return text[: self.start] + self.text + text[self.end :]

    def change(self, before: str, encoding: str = "utf-16") -> dict:
        """The edit as a ``TextDocumentContentChangePartial`` (JSON)."""
        return {
            "range": {
                "start": lsp_position(before, self.start, encoding),
                "end": lsp_position(before, self.end, encoding),
            },
            "text": self.text,
        }


PIECES = [
    *SEPARATORS,
    "\n",
    "\r\n",
    "\r",
    " ",
    "    ",
    "x",
    "é",
    "😀",
    ":",
    "(",
    ")",
    "hero",
    "keep(",
    "# ",
    "scenario t:\n    a: int\n",
    "\n    y: speed = 3kph\n",
]


@st.composite
def storms(draw, base: str, max_edits: int = 12) -> list[Edit]:
    """Edits to apply one after the other to ``base``; each sits at a valid
    position (never inside a surrogate pair: offsets are code points)."""
    text, edits = base, []
    for _ in range(draw(st.integers(1, max_edits))):
        # Edits never split a CR LF pair: a client's document model cannot address
        # the position between them (it is the end of the line).
        starts = [i for i in range(len(text) + 1) if not (text[i - 1 : i + 1] == "\r\n")]
        start = draw(st.sampled_from(starts))
        ends = [i for i in starts if start <= i <= start + 12]
        end = draw(st.sampled_from(ends))
        inserted = "".join(draw(st.lists(st.sampled_from(PIECES), max_size=3)))
        edit = Edit(start, end, inserted)
        edits.append(edit)
        text = edit.apply(text)
    return edits


def final_text(base: str, edits: list[Edit]) -> str:
    for edit in edits:
        base = edit.apply(base)
    return base
