"""Text positions and file names, without the analysis (cheap to import).

Lines end at ``\r\n``, ``\r`` or ``\n``, as in the OSC2 lexer. Offsets and
columns count code points; ``convert.py`` turns them into the client's units.
"""

from __future__ import annotations

import bisect
import re
from pathlib import Path
from urllib.parse import quote, unquote, urlparse

_NEWLINE = re.compile(r"\r\n|\r|\n")


# ---- file names ---------------------------------------------------------------


def uri_to_key(uri: str) -> str:
    """The analysis name of a client URI: a path for ``file:`` URIs, else the URI."""
    if uri.startswith("file:"):
        parsed = urlparse(uri)
        path = unquote(parsed.path)
        if re.match(r"^/[A-Za-z]:", path):  # file:///c:/x on Windows
            path = path[1:]
        return str(Path(path)) if path else uri
    return uri


def key_to_uri(key: str) -> str:
    """The client URI of an analysis name (absolute paths become ``file:`` URIs)."""
    if "://" in key or key.startswith("untitled:"):
        return key
    path = Path(key)
    if path.is_absolute():
        return "file://" + quote(path.as_posix(), safe="/:")
    return key


# ---- lines and offsets --------------------------------------------------------


class LineIndex:
    """Offsets of line starts; lines end at ``\\r\\n``, ``\\r`` or ``\\n`` as in the lexer."""

    __slots__ = ("text", "starts")

    def __init__(self, text: str):
        self.text = text
        self.starts = [0] + [m.end() for m in _NEWLINE.finditer(text)]

    def __len__(self) -> int:
        return len(self.starts)

    def line_text(self, line: int) -> str:
        """Line ``line`` (0-based) with its line ending."""
        if line < 0 or line >= len(self.starts):
            return ""
        end = self.starts[line + 1] if line + 1 < len(self.starts) else len(self.text)
        return self.text[self.starts[line] : end]

    def line_content(self, line: int) -> str:
        """Line ``line`` (0-based) without its line ending."""
        return self.line_text(line).rstrip("\r\n")

    def lines(self) -> list[str]:
        return [self.line_text(i) for i in range(len(self.starts))]

    def offset(self, line: int, column: int) -> int:
        """The offset of 0-based (line, column in code points), clamped to the text."""
        if line < 0:
            return 0
        if line >= len(self.starts):
            return len(self.text)
        content = self.line_content(line)
        return self.starts[line] + max(0, min(column, len(content)))

    def position(self, offset: int) -> tuple[int, int]:
        """0-based (line, column in code points) of ``offset``."""
        offset = max(0, min(offset, len(self.text)))
        line = bisect.bisect_right(self.starts, offset) - 1
        return line, offset - self.starts[line]
