"""XML to a small element tree that remembers where each element starts.

The standard library's ``xml.parsers.expat`` reports the line and column of
every start tag, which ``xml.etree`` drops (and lxml keeps only the line), so
the OpenDRIVE reader builds its own tree here: :class:`Element` is a tag, its
attributes, its children and its position. Text content is not kept: OpenDRIVE
puts its data in attributes (the one exception, ``<geoReference>``'s CDATA, is
not needed). Anything expat refuses, a file that cannot be read at all, and one
beyond the size or element limits of :mod:`osc2check.world.budget`, becomes a
:class:`~osc2check.world.errors.MapError` at the position expat gives.

The attribute helpers (:meth:`Element.number`, :meth:`Element.text`, ...) raise
``MapError`` naming the element's line and column and the attribute, so the
reader above never formats a location itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat

from osc2check.inputs import InputError, read_bytes
from osc2check.world.budget import MAX_MAP_BYTES, MAX_MAP_ELEMENTS
from osc2check.world.errors import MapError

__all__ = ["Element", "parse_xml", "read_xml"]


@dataclass(slots=True)
class Element:
    """One XML element: tag, attributes, children in document order, start position."""

    tag: str
    attrib: dict[str, str]
    line: int
    column: int
    file: str | None
    children: list[Element] = field(default_factory=list)

    def error(self, problem: str) -> MapError:
        """A :class:`MapError` located at this element."""
        return MapError(problem, self.file, self.line, self.column)

    def find(self, tag: str) -> Element | None:
        """The first child called ``tag``, or None."""
        for child in self.children:
            if child.tag == tag:
                return child
        return None

    def findall(self, tag: str) -> list[Element]:
        """Every child called ``tag``, in document order."""
        return [child for child in self.children if child.tag == tag]

    def text(self, name: str, default: str | None = None) -> str:
        """The attribute ``name`` as text; a missing attribute without a default raises."""
        value = self.attrib.get(name)
        if value is None:
            if default is None:
                raise self.error(f"<{self.tag}> has no `{name}` attribute")
            return default
        return value.strip()

    def optional_text(self, name: str) -> str | None:
        """The attribute ``name`` stripped, or None when absent."""
        value = self.attrib.get(name)
        return None if value is None else value.strip()

    def number(self, name: str, default: float | None = None) -> float:
        """The attribute ``name`` as a finite float; missing (without default) or bad raises."""
        raw = self.attrib.get(name)
        if raw is None:
            if default is None:
                raise self.error(f"<{self.tag}> has no `{name}` attribute")
            return default
        try:
            value = float(raw)
        except ValueError:
            raise self.error(
                f"<{self.tag}> attribute `{name}` is not a number: {raw.strip()!r}"
            ) from None
        if not math.isfinite(value):
            raise self.error(f"<{self.tag}> attribute `{name}` is not finite: {raw.strip()!r}")
        return value

    def optional_number(self, name: str) -> float | None:
        """The attribute ``name`` as a float, or None when absent or empty."""
        raw = self.attrib.get(name)
        if raw is None or not raw.strip():
            return None
        return self.number(name)

    def integer(self, name: str, default: int | None = None) -> int:
        """The attribute ``name`` as an int (``"2"``, ``"-1"``, ``"2.0"``); bad raises."""
        raw = self.attrib.get(name)
        if raw is None:
            if default is None:
                raise self.error(f"<{self.tag}> has no `{name}` attribute")
            return default
        try:
            return int(raw)
        except ValueError:
            pass
        value = self.number(name)
        if value != int(value):
            raise self.error(f"<{self.tag}> attribute `{name}` is not an integer: {raw!r}")
        return int(value)


class _Builder:
    """Expat callbacks building :class:`Element` objects with their start positions."""

    def __init__(self, parser: expat.XMLParserType, file: str | None) -> None:
        self.parser = parser
        self.file = file
        self.stack: list[Element] = []
        self.root: Element | None = None
        self.left = MAX_MAP_ELEMENTS  # elements still allowed

    def start(self, tag: str, attrib: dict[str, str]) -> None:
        self.left -= 1
        if self.left < 0:
            raise MapError(
                f"the map has more than {MAX_MAP_ELEMENTS:,} elements (a map's limit)",
                self.file,
                self.parser.CurrentLineNumber,
                self.parser.CurrentColumnNumber + 1,
            )
        element = Element(
            tag,
            attrib,
            self.parser.CurrentLineNumber,
            self.parser.CurrentColumnNumber + 1,
            self.file,
        )
        if self.stack:
            self.stack[-1].children.append(element)
        else:
            self.root = element
        self.stack.append(element)

    def end(self, tag: str) -> None:
        self.stack.pop()


def parse_xml(data: bytes, file: str | None = None) -> Element:
    """Parse XML bytes into an :class:`Element` tree; anything malformed raises MapError."""
    parser = expat.ParserCreate()
    builder = _Builder(parser, file)
    parser.StartElementHandler = builder.start
    parser.EndElementHandler = builder.end
    parser.buffer_text = True
    try:
        parser.Parse(data, True)
    except expat.ExpatError as exc:
        message = expat.errors.messages.get(exc.code, str(exc)) if exc.code else str(exc)
        raise MapError(
            f"not well-formed XML: {message}", file, exc.lineno, exc.offset + 1
        ) from None
    if builder.root is None:
        raise MapError("no XML element in the file", file, 1, 1)
    return builder.root


def read_xml(path: Path) -> Element:
    """Read and parse the file at ``path``; an unreadable file raises MapError.

    It is read as the checker reads its sources (``osc2check.inputs``): a regular file
    of at most ``MAX_MAP_BYTES``, never a FIFO or a device, never blocking.
    """
    try:
        data = read_bytes(path, MAX_MAP_BYTES)
    except InputError as exc:
        raise MapError(f"cannot read the map file: {exc}", str(path)) from None
    return parse_xml(data, str(path))
