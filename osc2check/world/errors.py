"""The one error type of road-network loading, and the warnings kept beside a network.

Every problem with a map file (not XML, a missing or non-numeric attribute, an
unknown geometry, a link to a road that does not exist, a road without
geometry, ...) is raised as :class:`MapError`, whose message names the file,
the line and column (when known) and what is wrong, in the
``path:line:column: problem`` form the checker prints for scenario files. No
other exception escapes the readers for bad input, so callers need one
``except MapError`` and never show a traceback for a broken map.

Problems that do not stop a network from being used (a lane link naming a lane
that does not exist, say, which real files contain) are kept as
:class:`MapWarning` values on the network instead.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["MapError", "MapWarning", "UnknownMapError", "format_location"]


def format_location(file: str | None, line: int | None, column: int | None) -> str:
    """``file:line:column`` with the parts that are known (``<map>`` for no file)."""
    text = file if file else "<map>"
    if line is not None:
        text += f":{line}"
        if column is not None:
            text += f":{column}"
    return text


class MapError(ValueError):
    """A map that cannot be read: malformed, inconsistent or unsupported.

    Attributes:
        file: the map's path as given (None for maps built in code).
        line: 1-based line of the offending element, when known.
        column: 1-based column of the offending element, when known.
        problem: what is wrong, without the location.
    """

    def __init__(
        self,
        problem: str,
        file: str | None = None,
        line: int | None = None,
        column: int | None = None,
    ) -> None:
        self.problem = problem
        self.file = file
        self.line = line
        self.column = column
        super().__init__(f"{format_location(file, line, column)}: {problem}")


@dataclass(frozen=True, slots=True)
class MapWarning:
    """Something odd in a map that was skipped rather than refused."""

    problem: str
    file: str | None = None
    line: int | None = None
    column: int | None = None

    def __str__(self) -> str:
        return f"{format_location(self.file, self.line, self.column)}: {self.problem}"


class UnknownMapError(LookupError):
    """A map name that is neither a readable ``.xodr`` file nor a built-in map."""

    def __init__(self, name: str, known: tuple[str, ...]) -> None:
        self.name = name
        self.known = known
        super().__init__(f"unknown map `{name}`; known built-in maps: {', '.join(known)}")
