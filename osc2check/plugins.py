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
:class:`PluginRegistry`. The installed ones are looked up when the registry is
first asked (finding them reads every installed distribution's metadata: tens of
milliseconds that a file calling no behaviour of the user's libraries never needs).

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
import threading
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
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
    """The marked implementations of the plug-in modules loaded, by (kind, owner, name).

    ``installed``: a function naming more modules (the installed distributions'), imported
    when the registry is first asked (``find``, iterating, ``len``, ``modules``). A module
    among them that cannot be imported leaves the registry with what was loaded before it
    and is kept in ``failure``; ``load_installed`` raises it."""

    def __init__(self, installed: Callable[[], Iterable[str]] | None = None) -> None:
        self._entries: dict[tuple[str, str | None, str], Implementation] = {}
        self._modules: list[str] = []
        self._installed = installed
        self._lock = threading.Lock()
        self.failure: PluginError | None = None

    @property
    def modules(self) -> list[str]:
        """The names of the modules loaded, in order."""
        self._settle()
        return self._modules

    def collect(self, module: Any) -> None:
        """Register what ``module`` marks (what it defines, not what it imports)."""
        for value in list(vars(module).values()):
            if getattr(value, "__module__", None) != module.__name__:
                continue
            for kind, owner, name in getattr(value, _MARK, ()):
                self._add(Implementation(kind, owner, name, value, module.__name__))
        self._modules.append(module.__name__)

    def load_installed(self) -> None:
        """Import the installed plug-in modules now, if not done yet; ``PluginError`` when one
        cannot be imported (this call and every later one)."""
        self._settle()
        if self.failure is not None:
            raise self.failure

    def _settle(self) -> None:
        if self._installed is None:
            return
        with self._lock:  # another thread reads the entries once they are all there
            names = self._installed
            if names is None:
                return
            try:
                for name in names():
                    if name not in self._modules:
                        self.collect(_load(name))
            except PluginError as exc:
                self.failure = exc
            finally:
                self._installed = None

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
        self._settle()
        for owner in owners:
            found = self._entries.get((kind, owner, name))
            if found is not None:
                return found
        return None

    def __iter__(self) -> Iterator[Implementation]:
        self._settle()
        return iter(self._entries.values())

    def __len__(self) -> int:
        self._settle()
        return len(self._entries)


def entry_points(group: str) -> list[Any]:
    """The entry points installed distributions declare in ``group`` (``importlib.metadata``
    is imported here only: about 20 ms)."""
    from importlib import metadata

    return list(metadata.entry_points(group=group))


def _installed_modules() -> list[str]:
    return [ep.value.split(":")[0] for ep in entry_points(group=ENTRY_POINT_GROUP)]


_loaded: dict[tuple[tuple[str, ...], bool], PluginRegistry] = {}


def load_plugins(modules: Iterable[str] = (), *, installed: bool = True) -> PluginRegistry:
    """The registry of the plug-in ``modules`` (imported by name, now) and, with
    ``installed``, of the modules installed distributions name in
    :data:`ENTRY_POINT_GROUP` (imported when the registry is first asked:
    ``PluginRegistry``); made once per process for the same modules."""
    names = tuple(dict.fromkeys(modules))
    key = (names, installed)
    found = _loaded.get(key)
    if found is not None:
        return found
    registry = PluginRegistry(_installed_modules if installed else None)
    for name in names:
        registry.collect(_load(name))
    _loaded[key] = registry
    return registry


def _load(name: str) -> ModuleType:
    """The plug-in module ``name``; ``PluginError`` saying why it cannot be imported."""
    try:
        return _import(name)
    except PluginError:
        raise
    except Exception as exc:  # the user's module: said with its name, never a traceback
        raise PluginError(
            f"plug-in `{name}` cannot be imported: {type(exc).__name__}: {exc}"
        ) from None


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
