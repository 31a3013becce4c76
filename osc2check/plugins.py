"""User-defined actions, modifiers and methods: the plug-in API.

A user's ``.osc`` library declares a behaviour (``action log: msg: string``,
``action vehicle.accelerate_to: target: speed``); a Python module implements it,
marking the implementation with a decorator of this module::

    # my_plugin.py
    from osc2check.plugins import action

    @action("log")
    def log(run, msg):                  # an instant action: called once, when it starts
        run.log(msg)

    @action("accelerate_to", actor="vehicle")
    class AccelerateTo:                 # a lasting action: one object per invocation
        def start(self, run, actor, target): ...
        def step(self, run, actor) -> bool: ...   # True when it is done

Marking changes nothing global: :func:`load_plugins` imports the modules named
with ``--plugin MODULE`` (``osc2run``, ``osc2check``; a module name or a ``.py``
file), in the configuration (``plugins = ["my_plugin"]`` under
``[tool.osc2check]``, a file relative to the configuration file) and by
installed distributions in the entry point group ``osc2toolkit.plugins`` (an
entry point names a module), and collects what they mark into a
:class:`PluginRegistry`.

The checker reads the registry to know which declared behaviours run (the
capability table, :mod:`osc2check.capabilities`); the runner executes them
(:mod:`osc2runner.plugin_behaviours`, which says what ``run`` and ``actor`` are
and how arguments arrive). This module imports nothing of the runner, so that a
plug-in module and the checker stay light.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from importlib.metadata import entry_points
from pathlib import Path
from types import ModuleType
from typing import Any, Literal, TypeVar

__all__ = [
    "ENTRY_POINT_GROUP",
    "Implementation",
    "PluginError",
    "PluginRegistry",
    "action",
    "load_plugins",
    "method",
    "modifier",
]

#: installed distributions name their plug-in modules in this entry point group
ENTRY_POINT_GROUP = "osc2toolkit.plugins"
_MARK = "__osc2_plugin__"
Kind = Literal["action", "modifier", "method"]
_T = TypeVar("_T")


class PluginError(Exception):
    """A plug-in module cannot be imported, or two implement one behaviour."""


@dataclass(frozen=True, slots=True)
class Implementation:
    """One marked implementation: what it implements (kind, ``owner``: the actor of an
    action or modifier, the type of a method, None for an unassociated behaviour) and the
    function or class, from ``module``."""

    kind: Kind
    owner: str | None
    name: str
    target: Any
    module: str

    @property
    def label(self) -> str:
        return f"{self.owner}.{self.name}" if self.owner else self.name

    @property
    def lasting(self) -> bool:
        """Whether it is a class of objects that start and step (else a function called
        once)."""
        return isinstance(self.target, type)


def _mark(kind: Kind, name: str, owner: str | None) -> Callable[[_T], _T]:
    def mark(target: _T) -> _T:
        marks = getattr(target, _MARK, ())
        setattr(target, _MARK, (*marks, (kind, owner, name)))
        return target

    return mark


def action(name: str, *, actor: str | None = None) -> Callable[[_T], _T]:
    """Mark the implementation of the action ``name`` (of actors of type ``actor`` and its
    subtypes; None: an action declared without an actor, ``action log:``)."""
    return _mark("action", name, actor)


def modifier(name: str, *, actor: str | None = None) -> Callable[[_T], _T]:
    """Mark the implementation of the modifier ``name`` (``actor``: its associated actor)."""
    return _mark("modifier", name, actor)


def method(owner: str, name: str) -> Callable[[_T], _T]:
    """Mark the function implementing ``owner.name()``, a method declared ``is undefined``."""
    return _mark("method", name, owner)


class PluginRegistry:
    """The marked implementations of the plug-in modules loaded, by (kind, owner, name)."""

    def __init__(self) -> None:
        self._entries: dict[tuple[str, str | None, str], Implementation] = {}
        self.modules: list[str] = []

    def collect(self, module: Any) -> None:
        """Register what ``module`` marks (what it defines, not what it imports)."""
        for value in list(vars(module).values()):
            if getattr(value, "__module__", None) != module.__name__:
                continue
            for kind, owner, name in getattr(value, _MARK, ()):
                self._add(Implementation(kind, owner, name, value, module.__name__))
        self.modules.append(module.__name__)

    def _add(self, entry: Implementation) -> None:
        key = (entry.kind, entry.owner, entry.name)
        known = self._entries.get(key)
        if known is not None and known.target is not entry.target:
            raise PluginError(
                f"{entry.kind} `{entry.label}` is implemented twice: in `{known.module}` and "
                f"in `{entry.module}`"
            )
        self._entries[key] = entry

    def find(self, kind: Kind, owners: Iterable[str | None], name: str) -> Implementation | None:
        """The implementation of ``name`` for the first of ``owners`` that has one (an
        actor type and its supertypes, nearest first)."""
        for owner in owners:
            found = self._entries.get((kind, owner, name))
            if found is not None:
                return found
        return None

    def __iter__(self) -> Iterator[Implementation]:
        return iter(self._entries.values())

    def __len__(self) -> int:
        return len(self._entries)


_loaded: dict[tuple[tuple[str, ...], bool], PluginRegistry] = {}


def load_plugins(modules: Iterable[str] = (), *, installed: bool = True) -> PluginRegistry:
    """The registry of the plug-in ``modules`` (imported by name) and, with ``installed``,
    of the modules installed distributions name in :data:`ENTRY_POINT_GROUP`; loaded once
    per process for the same modules."""
    names = tuple(dict.fromkeys(modules))
    key = (names, installed)
    found = _loaded.get(key)
    if found is not None:
        return found
    registry = PluginRegistry()
    wanted = list(names)
    if installed:
        wanted += [ep.value.split(":")[0] for ep in entry_points(group=ENTRY_POINT_GROUP)]
    for name in dict.fromkeys(wanted):
        try:
            module = _import(name)
        except PluginError:
            raise
        except Exception as exc:  # the user's module: said with its name, never a traceback
            raise PluginError(
                f"plug-in `{name}` cannot be imported: {type(exc).__name__}: {exc}"
            ) from None
        registry.collect(module)
    _loaded[key] = registry
    return registry


def _import(name: str) -> ModuleType:
    """A module by name (``my_plugin``, ``pkg.plugin``) or by file (``plugins/log.py``)."""
    if not name.endswith(".py"):
        return importlib.import_module(name)
    path = Path(name)
    if not path.is_file():
        raise PluginError(f"plug-in `{name}`: no such file")
    module_name = f"osc2_plugin_{path.stem}"
    spec = importlib.util.spec_from_file_location(module_name, path)
    if spec is None or spec.loader is None:  # pragma: no cover - a .py file always has one
        raise PluginError(f"plug-in `{name}` cannot be loaded")
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module  # the module's own classes name it
    spec.loader.exec_module(module)
    return module
