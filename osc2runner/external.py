"""Python functions that scenarios call as ``is external`` methods (§7.3.7, methods).

A scenario declares a method whose body is a Python function::

    def gap_ok(gap: length, limit: length) -> bool is external my_checks.gaps.gap_ok(gap, limit)

and the function is marked where it is written::

    # my_checks/gaps.py
    from osc2runner.external import external

    @external("my_checks.gaps.gap_ok")
    def gap_ok(gap: float, limit: float) -> bool:
        return gap > limit

:func:`external` only marks (nothing global changes when a module is imported).
When the compiler meets ``is external a.b.c(...)`` it asks an
:class:`ExternalRegistry` for ``a.b.c``: a name registered already (by
:meth:`ExternalRegistry.load` or :meth:`ExternalRegistry.add`) is used; otherwise
the registry imports the modules the name starts with, longest first
(``a.b``, then ``a``), and registers the functions marked in them, so the usual
name ``<module>.<function>`` needs no set-up. A name no marked function has is
an input error at the method's declaration, before the run.

The function is called with SI values (``10kph`` arrives as ``2.777...`` m/s;
booleans, integers and strings as themselves, enum members by name, actors by
name, ranges as ``(low, high)``, lists as tuples) each time the expression that
calls the method is evaluated, and its result is taken as the method's type
(``bool``, ``int``, a float in SI units for physical types). A function that
raises fails the run with the call's location.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from types import ModuleType
from typing import Any, TypeVar, overload

from osc2check.syntax import ast
from osc2runner.execution.context import RunFault
from osc2runner.instance.actors import Actor

__all__ = ["ExternalFunction", "ExternalLoadError", "ExternalRegistry", "external", "python_value"]

_MARK = "__osc2_external__"

_F = TypeVar("_F", bound=Callable[..., Any])


@overload
def external(name: _F) -> _F: ...
@overload
def external(name: str | None = None) -> Callable[[_F], _F]: ...


def external(name: str | Callable[..., Any] | None = None) -> Any:
    """Mark a Python function as the body of ``is external <name>(...)`` methods.

    ``@external("pkg.mod.fn")`` names it explicitly; ``@external`` or
    ``@external()`` names it ``<its module>.<its qualified name>``. A function may
    carry several names (stacked decorators).
    """

    def mark(fn: _F, given: str | None) -> _F:
        full = given or f"{fn.__module__}.{fn.__qualname__}"
        setattr(fn, _MARK, (*getattr(fn, _MARK, ()), full))
        return fn

    if callable(name):
        return mark(name, None)
    return lambda fn: mark(fn, name)


class ExternalLoadError(Exception):
    """A module named by an external method could not be imported, or registers a name
    twice."""


@dataclass(frozen=True, slots=True)
class ExternalFunction:
    """A registered external function: the name scenarios use and the Python function."""

    name: str
    function: Callable[..., Any]

    def closure(
        self,
        positional: list[Callable[[], Any]],
        keywords: dict[str, Callable[[], Any]],
        convert: Callable[[Any], Any],
        node: ast.Node,
    ) -> Callable[[], Any]:
        """A closure calling the function with the arguments' values (see the module
        docstring); a raised exception fails the run as a RunFault at ``node``."""
        fn, name = self.function, self.name

        def call() -> Any:
            args = [python_value(a()) for a in positional]
            kwargs = {k: python_value(f()) for k, f in keywords.items()}
            try:
                return convert(fn(*args, **kwargs))
            except RunFault:
                raise
            except Exception as exc:  # the user's code: reported with the call's place
                raise RunFault(
                    f"the external function `{name}` raised {type(exc).__name__}: {exc}", node
                ) from exc

        return call


def python_value(value: Any) -> Any:
    """A run-time value as an external function receives it: actors (and an actor's
    ``position``) by the actor's name, tuples item by item, the rest as it is."""
    if isinstance(value, Actor):
        return value.name
    if isinstance(getattr(value, "actor", None), Actor):  # `npc.position`
        return value.actor.name
    if isinstance(value, tuple):
        return tuple(python_value(v) for v in value)
    return value


class ExternalRegistry:
    """External functions by name (see the module docstring)."""

    def __init__(self) -> None:
        self._functions: dict[str, ExternalFunction] = {}
        self._imported: set[str] = set()

    def add(self, name: str, function: Callable[..., Any]) -> None:
        """Register ``function`` under ``name`` (an error when another has the name)."""
        known = self._functions.get(name)
        if known is not None and known.function is not function:
            raise ExternalLoadError(f"two external functions are registered as `{name}`")
        self._functions[name] = ExternalFunction(name, function)

    def collect(self, module: ModuleType) -> None:
        """Register every function marked in ``module`` (also ones it imports)."""
        for value in list(vars(module).values()):
            for name in getattr(value, _MARK, ()) if callable(value) else ():
                self.add(name, value)

    def load(self, *modules: str) -> ExternalRegistry:
        """Import ``modules`` and register what is marked in them; returns self."""
        for module in modules:
            self.collect(importlib.import_module(module))
            self._imported.add(module)
        return self

    def find(self, name: str) -> ExternalFunction | None:
        """The function registered as ``name``, importing the modules it names if needed."""
        found = self._functions.get(name)
        if found is not None:
            return found
        parts = name.split(".")
        for end in range(len(parts) - 1, 0, -1):
            module_name = ".".join(parts[:end])
            if module_name in self._imported:
                continue
            self._imported.add(module_name)
            try:
                module = importlib.import_module(module_name)
            except ModuleNotFoundError as exc:
                missing = exc.name or ""
                if module_name == missing or module_name.startswith(missing + "."):
                    continue  # no such module: a shorter prefix may be the module
                raise ExternalLoadError(
                    f"importing `{module_name}` for the external `{name}` failed: {exc}"
                ) from None
            except Exception as exc:  # the user's module failed to import: say so
                raise ExternalLoadError(
                    f"importing `{module_name}` for the external `{name}` failed: "
                    f"{type(exc).__name__}: {exc}"
                ) from None
            self.collect(module)
            found = self._functions.get(name)
            if found is not None:
                return found
        return None

    def names(self) -> list[str]:
        """The registered names, sorted."""
        return sorted(self._functions)
