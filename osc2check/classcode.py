"""Compiled code of the methods that ``dataclasses`` generates, from the start-up cache.

``@dataclass`` writes each class's ``__init__``, ``__repr__``, ``__eq__``,
``__setattr__``... as source text and compiles it while the class is created:
about a fifth of the checker's start-up went to compiling those few hundred
texts, the same ones in every process. ``install`` gives the ``dataclasses``
module an ``exec`` of its own that compiles each text of the toolkit's classes
once and keeps the code by its text; the code is stored in the start-up cache
(``osc2check.cache``, one entry per package) when the process ends, and read
back by the next one when it declares its first class of that package. Code compiled from the same
text is the same code, so nothing but the time changes; a text not seen before
is compiled as usual. Python's versions 3.11 to 3.13 call ``exec`` on the
generated text (3.13 once per class); a version that does not simply never asks.

``dataclasses`` is patched when it is first imported, not before: the ``osc2check``
command's first steps (a stored result, the resident checker) need neither it nor the
cache, and importing them would cost those steps a good part of their time.
"""

from __future__ import annotations

import atexit
import builtins
import marshal
import sys
import threading

TYPE_CHECKING = False  # typing's, without importing it (the command's first module)
if TYPE_CHECKING:
    from types import CodeType, ModuleType
    from typing import Any

__all__ = ["install"]

_KIND = "dataclass-code"
_PACKAGES = ("osc2check", "osc2lsp", "osc2runner")  # whose classes' code is kept
_lock = threading.Lock()
_code: dict[str, dict[str, CodeType]] = {}  # package -> source text -> code
_compiled: set[str] = set()  # packages with code compiled in this process (stored at exit)
_installed = False


def _package(globals: Any) -> str | None:
    name = globals.get("__name__", "") if isinstance(globals, dict) else ""
    top = name.partition(".")[0]
    return top if top in _PACKAGES else None


def _exec(source: object, globals: Any = None, locals: Any = None, /) -> None:
    """``exec`` as ``dataclasses`` calls it, with our classes' source texts compiled once."""
    package = _package(globals) if isinstance(source, str) else None
    if package is not None:
        assert isinstance(source, str)
        known = _code.get(package)
        if known is None:
            known = _load(package)
        code = known.get(source)
        if code is None:
            code = compile(source, "<string>", "exec")
            with _lock:
                known[source] = code
                _compiled.add(package)
        source = code
    builtins.exec(source, globals, locals)  # type: ignore[arg-type]


def _load(package: str) -> dict[str, CodeType]:
    """A package's stored code (an empty table when there is none, or it is unusable)."""
    from osc2check import cache

    loaded: object = None
    stored = cache.load(_KIND, {"package": package})
    if isinstance(stored, bytes):
        try:
            loaded = marshal.loads(stored)
        except (EOFError, ValueError, TypeError):
            loaded = None
    table = loaded if isinstance(loaded, dict) else {}
    with _lock:
        return _code.setdefault(package, table)


def install() -> None:
    """Route ``dataclasses``' compiling through the stored code (once per process)."""
    global _installed
    with _lock:
        if _installed:
            return
        _installed = True
    atexit.register(_store)
    module = sys.modules.get("dataclasses")
    if module is not None:
        _patch(module)
    else:
        sys.meta_path.insert(0, _WhenImported())


def _patch(dataclasses: ModuleType) -> None:
    dataclasses.exec = _exec  # type: ignore[attr-defined]  # shadows the builtin there


class _WhenImported:
    """A module finder that finds nothing itself: it has ``dataclasses`` patched as the
    other finders' loader runs it, then leaves."""

    def find_spec(self, name: str, path: object = None, target: object = None) -> Any:
        if name != "dataclasses":
            return None
        sys.meta_path.remove(self)
        for finder in sys.meta_path:
            find = getattr(finder, "find_spec", None)
            spec = find(name, path, target) if find is not None else None
            if spec is not None and spec.loader is not None:
                spec.loader = _PatchingLoader(spec.loader)
                return spec
        return None


class _PatchingLoader:
    """``loader``, patching the module once it has run."""

    def __init__(self, loader: Any) -> None:
        self._loader = loader

    def create_module(self, spec: Any) -> Any:
        return self._loader.create_module(spec)

    def exec_module(self, module: ModuleType) -> None:
        self._loader.exec_module(module)
        _patch(module)

    def __getattr__(self, name: str) -> Any:  # get_source, is_package, ...
        return getattr(self._loader, name)


def _store() -> None:
    if not _compiled:
        return
    from osc2check import cache

    if not cache.enabled():
        return
    for package in sorted(_compiled):
        with _lock:
            code = dict(_code[package])
        cache.store(_KIND, {"package": package}, marshal.dumps(code))
