"""What the message builders of several families share: the one way to make a
``Diagnostic`` from a code and its text, and the phrases more than one family writes
(a list of quoted names, "did you mean", a symbol's kind and name, a callee, an example
unit, where a name is first declared)."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING

from osc2check.codes import Code
from osc2check.diagnostics import Diagnostic, Fix, Related, TextEdit
from osc2check.source import Span

if TYPE_CHECKING:
    from osc2check.semantics.builtins import Builtin
    from osc2check.semantics.symbols import Symbol
    from osc2check.semantics.types import Type


def diagnostic(
    code: Code,
    message: str,
    span: Span,
    related: Sequence[Related] = (),
    fix: Fix | None = None,
    **data: object,
) -> Diagnostic:
    """The finding of ``code`` (at its default severity) with ``message`` at ``span``."""
    return Diagnostic(code, message, span, code.severity, tuple(related), fix, data)


def quote_list(items: Iterable[str], limit: int = 6, conj: str = "or") -> str:
    """Each item in backticks, joined by commas and ``conj``; past ``limit`` items, how many
    more."""
    items = list(items)
    shown = [f"`{i}`" for i in items[:limit]]
    if len(items) > limit:
        shown.append(f"{len(items) - limit} more")
    if len(shown) == 1:
        return shown[0]
    return ", ".join(shown[:-1]) + f" {conj} " + shown[-1]


def did_you_mean(suggestion: str | None) -> str:
    """The tail that suggests ``suggestion`` (empty without one)."""
    return f"; did you mean `{suggestion}`?" if suggestion else ""


def replace_fix(span: Span, suggestion: str | None) -> Fix | None:
    """The fix that writes ``suggestion`` over ``span`` (None without one)."""
    if not suggestion:
        return None
    return Fix(f"replace with `{suggestion}`", (TextEdit(span, suggestion),))


def kind_and_name(symbol: Symbol) -> str:
    """What ``symbol`` is and its qualified name in backticks, as in scenario `cut_in`."""
    return f"{symbol.kind.value} `{symbol.qualified_name}`"


def first_declared(previous: Symbol | None) -> list[Related]:
    """The note pointing at the first declaration of a name (none without a span)."""
    if previous is None or previous.name_span is None:
        return []
    return [Related(previous.name_span, f"`{previous.name}` is first declared here")]


def example_unit(expected: Type) -> str:
    """A literal with a unit of ``expected``'s quantity, to show in a hint."""
    while expected.element is not None:  # range of time -> time
        expected = expected.element
    examples = {
        "speed": "50kph",
        "length": "10m",
        "time": "2s",
        "acceleration": "2mpsps",
        "angle": "90deg",
        "mass": "1000kg",
        "temperature": "20celsius",
    }
    name = expected.symbol.name if expected.symbol is not None else ""
    return examples.get(name, "1" + ("m" if name == "" else "<unit>"))


def callee_name(symbol: Symbol | Builtin) -> str:
    """The name of what is invoked, quoted."""
    return f"`{symbol.name}`"
