"""The language's built-in vocabulary: what every OSC2 program has without declaring it.

The analysis types these names, the language server completes and explains
them, and the runner executes them; each of those reads this module.

* predefined events of every behaviour: ``start``, ``end``, ``fail`` (§7.3.10.4);
* event functions (§7.3.10.3): ``rise``, ``fall``, ``elapsed``, ``every``;
* value functions: ``sample`` (§7.3.6.6), ``range``;
* list methods (§7.2.4.2): ``size``, ``count``, ``has``, ``filter``, ``map``,
  ``first_index``; type tests ``as`` and ``is``;
* coverage (§7.5): ``cover`` and ``record`` and their parameters, the default
  sampling event;
* primitive types; ``parallel`` overlap kinds (§7.3.9.3.3); the structured
  imports of the standard library.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from osc2check.syntax import ast

__all__ = [
    "Builtin",
    "BuiltinParameter",
    "COVERAGE_KINDS",
    "COVERAGE_PARAMETERS",
    "DEFAULT_SAMPLING_EVENT",
    "EVENT_FUNCTIONS",
    "LIST_METHODS",
    "OVERLAP_KINDS",
    "PREDEFINED_EVENTS",
    "PRIMITIVE_TYPES",
    "STANDARD_MODULE_NAMES",
    "TYPE_TESTS",
    "VALUE_FUNCTIONS",
    "cover_item_expression",
    "coverage_directive",
]

PREDEFINED_EVENTS = ("start", "end", "fail")
PRIMITIVE_TYPES = ("bool", "int", "uint", "float", "string")
OVERLAP_KINDS = ("equal", "start", "end", "initial", "final", "inside", "full", "any")
TYPE_TESTS = ("as", "is")
#: The structured imports of the standard library (§7.7.5.1), then the toolkit's own
#: modules (CARLA's world, :mod:`osc2check.dialects.carla`).
STANDARD_MODULE_NAMES = (
    "osc.standard",
    "osc.standard.all",
    "osc.standard.types",
    "osc.standard.domain",
    "osc2toolkit.carla",
)


@dataclass(frozen=True, slots=True)
class BuiltinParameter:
    name: str
    type: str  # as written in OSC2: `bool`, `time`, `any`
    optional: bool = False

    @property
    def text(self) -> str:
        return f"{self.name}: {self.type}"


@dataclass(frozen=True, slots=True)
class Builtin:
    """A built-in function or method: its parameters, result and one line of documentation."""

    name: str
    parameters: tuple[BuiltinParameter, ...]
    result: str
    doc: str

    @property
    def signature(self) -> str:
        return f"{self.name}({', '.join(p.text for p in self.parameters)})"

    @property
    def names(self) -> tuple[str, ...]:
        """Its parameters' names, in order."""
        return tuple(p.name for p in self.parameters)


def _p(name: str, type_: str, optional: bool = False) -> BuiltinParameter:
    return BuiltinParameter(name, type_, optional)


EVENT_FUNCTIONS: dict[str, Builtin] = {
    b.name: b
    for b in (
        Builtin("rise", (_p("condition", "bool"),), "bool",
                "occurs when the condition becomes true"),
        Builtin("fall", (_p("condition", "bool"),), "bool",
                "occurs when the condition becomes false"),
        Builtin("elapsed", (_p("duration", "time"),), "bool",
                "occurs once the duration has passed since the enclosing phase started"),
        Builtin("every", (_p("period", "time"), _p("offset", "time", optional=True)), "bool",
                "occurs at the start of the enclosing context and then once per period "
                "(shifted by the offset when given)"),
    )
}  # fmt: skip

VALUE_FUNCTIONS: dict[str, Builtin] = {
    b.name: b
    for b in (
        Builtin("sample", (_p("expression", "any"), _p("event", "event"),
                           _p("default", "any", optional=True)), "any",
                "the expression's value when the event occurs (the default before it)"),
        Builtin("range", (_p("low", "any"), _p("high", "any")), "range",
                "the range from low to high"),
    )
}  # fmt: skip

LIST_METHODS: dict[str, Builtin] = {
    b.name: b
    for b in (
        Builtin("size", (), "int", "the number of elements"),
        Builtin("count", (_p("condition", "bool"),), "int",
                "the number of elements for which the condition (on `it`) holds"),
        Builtin("has", (_p("condition", "bool"),), "bool",
                "whether some element satisfies the condition (on `it`)"),
        Builtin("filter", (_p("condition", "bool"),), "list",
                "the elements for which the condition (on `it`) holds"),
        Builtin("map", (_p("expression", "any"),), "list",
                "the expression (on `it`) for each element"),
        Builtin("first_index", (_p("condition", "bool"),), "int",
                "the index of the first element for which the condition holds, else -1"),
    )
}  # fmt: skip

#: The coverage directives (§7.5): ``cover`` collects values into buckets, ``record``
#: only records them.
COVERAGE_KINDS = ("cover", "record")
#: The event a coverage item is sampled at when it names none: the end of the enclosing
#: scenario (§7.5).
DEFAULT_SAMPLING_EVENT = "end"

#: The parameters of ``cover(...)`` and ``record(...)`` (§7.5); ``record`` has all but
#: ``target``. The item's name may also be the first positional argument.
COVERAGE_PARAMETERS: dict[str, BuiltinParameter] = {
    p.name: p
    for p in (
        _p("name", "identifier", optional=True),
        _p("expression", "any", optional=True),
        _p("unit", "unit", optional=True),
        _p("range", "range", optional=True),
        _p("every", "any", optional=True),
        _p("event", "event", optional=True),
        _p("text", "string", optional=True),
        _p("items", "list", optional=True),
        _p("ignore", "bool", optional=True),
        _p("disable", "bool", optional=True),
        _p("buckets", "list", optional=True),
        _p("target", "uint", optional=True),
        _p("illegal", "bool", optional=True),
        _p("override", "identifier", optional=True),
    )
}


def cover_item_expression(
    named: Mapping[str, ast.Node], positional: Sequence[ast.Node]
) -> ast.Node | None:
    """The expression a ``cover``/``record`` item samples, given its named and positional
    arguments (§7.5): its ``expression:``, else its name (``name:`` or the first
    positional argument: the field it is named after); None when it has none, or when
    ``items:`` or ``override:`` make the name another item's. The checker types it and
    the runner collects it; one rule for both."""
    if "expression" in named:
        return named["expression"]
    if "items" in named or "override" in named:
        return None
    return named.get("name", positional[0] if positional else None)


def coverage_directive(kind: str) -> Builtin:
    """``cover`` or ``record`` as a built-in with its parameters (§7.5: ``record`` has no
    ``target``)."""
    params = tuple(p for p in COVERAGE_PARAMETERS.values() if kind == "cover" or p.name != "target")
    return Builtin(kind, params, "none", f"the coverage directive `{kind}`")
