"""Which SUT class drives which actor: ``--sut``, ``--sut-actor`` and ``[tool.osc2run]``.

* :class:`SutSpec` names the class (``module:Class``, a module importable from
  the current folder or installed, or ``path/to/file.py:Class``) and, optionally,
  the actor. It is plain data, so a campaign hands it to its workers.
* The actor is ``actor`` when given, else the scenario's field named ``sut``,
  else the one named ``ego``; it must be a vehicle.
* :func:`configured_sut` reads ``sut`` and ``sut-actor`` from ``[tool.osc2run]`` in
  the nearest ``pyproject.toml`` above the scenario file (a file path there is
  relative to that ``pyproject.toml``); the command line wins.

A name that does not import (whatever its import raised, ``SystemExit``
included), a class that is not there or has no ``step``, or a scenario without
the actor is a :class:`SutError` (a ``ValueError``), which the command reports as
a one-line usage error before anything runs.

``step_timeout`` is the wall-clock budget of each call into the SUT (its
construction, ``reset`` and every ``step``): ``osc2run --step-timeout``, default
``DEFAULT_STEP_TIMEOUT`` (60 s: generous for a controller that answers in
milliseconds, short beside a campaign's run limit).
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import sys
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from osc2runner.execution.signals import SignalInterrupt, genuine

__all__ = [
    "DEFAULT_STEP_TIMEOUT",
    "SUT_FIELDS",
    "SutError",
    "SutSpec",
    "choose_actor",
    "configured_sut",
]

DEFAULT_STEP_TIMEOUT = 60.0  # wall-clock seconds of one call into the SUT

#: the scenario fields that mark the system under test, in order of preference
SUT_FIELDS = ("sut", "ego")
_SECTION = ("tool", "osc2run")


class SutError(ValueError):
    """A SUT that cannot be used (the message says why)."""


@dataclass(frozen=True, slots=True)
class SutSpec:
    """The SUT class (``target``: ``module:Class`` or ``file.py:Class``), the actor
    it drives (None: the field named ``sut``, else ``ego``) and the wall-clock budget
    of each call into it (None: no limit)."""

    target: str
    actor: str | None = None
    step_timeout: float | None = DEFAULT_STEP_TIMEOUT

    def __post_init__(self) -> None:
        module, sep, name = self.target.rpartition(":")
        if not sep or not module or not name.isidentifier():
            raise SutError(f"`{self.target}` is not `module:Class` or `path/file.py:Class`")

    @property
    def is_file(self) -> bool:
        module = self.target.rpartition(":")[0]
        return module.endswith(".py") or os.sep in module or "/" in module

    def resolved(self, base: Path | None = None) -> SutSpec:
        """The spec with a file path made absolute (relative to ``base``, else the
        current folder), so that workers in other folders load the same file."""
        if not self.is_file:
            return self
        module, _, name = self.target.rpartition(":")
        path = Path(module)
        if not path.is_absolute():
            path = (base or Path.cwd()) / path
        return SutSpec(f"{path.resolve()}:{name}", self.actor, self.step_timeout)

    def load(self) -> type[Any]:
        """The class (SutError when it cannot be imported or is not a SUT)."""
        module_name, _, name = self.target.rpartition(":")
        try:
            if self.is_file:
                module = _load_file(Path(module_name))
            else:
                if os.getcwd() not in sys.path:  # as `python -m` does: the current folder
                    sys.path.append(os.getcwd())
                module = importlib.import_module(module_name)
        except SutError:
            raise
        except SignalInterrupt as exc:
            if genuine(exc):  # the command was interrupted while it imported
                raise
            raise SutError(f"cannot import `{module_name}`: it raised KeyboardInterrupt") from None
        except BaseException as exc:  # an import that fails, whatever it raised (SystemExit)
            raise SutError(f"cannot import `{module_name}`: {type(exc).__name__}: {exc}") from None
        cls = getattr(module, name, None)
        if not isinstance(cls, type):
            raise SutError(f"`{module_name}` has no class `{name}`")
        if not callable(getattr(cls, "step", None)):
            raise SutError(f"`{name}` has no `step(observation)` method")
        return cls

    def make(self) -> Any:
        """A new instance of the class (SutFault when constructing it fails: a run error)."""
        from osc2runner.sut.driver import call_sut

        cls = self.load()
        return call_sut(cls.__name__, "its construction", self.step_timeout, cls)


def _load_file(path: Path) -> Any:
    if not path.is_file():
        raise SutError(f"{path}: no such file")
    name = f"osc2run_sut_{abs(hash(str(path.resolve())))}"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise SutError(f"{path}: not a Python module")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    return module


def choose_actor(fields: Mapping[str, str], wanted: str | None) -> str:
    """The SUT actor among the scenario's actor fields (``name -> kind``): ``wanted``,
    else the field named ``sut``, else ``ego``; SutError when there is none or it
    is not a vehicle."""
    if wanted is not None:
        if wanted not in fields:
            known = ", ".join(fields) or "none"
            raise SutError(f"the scenario has no actor `{wanted}` (actors: {known})")
        chosen = wanted
    else:
        found = next((n for n in SUT_FIELDS if n in fields), None)
        if found is None:
            raise SutError(
                "the scenario marks no system under test: name its field `sut` or `ego`, "
                "or give --sut-actor NAME"
            )
        chosen = found
    if fields[chosen] != "vehicle":
        raise SutError(f"the system under test `{chosen}` is a {fields[chosen]}, not a vehicle")
    return chosen


def configured_sut(scenario_file: str | Path) -> tuple[SutSpec | None, Path | None]:
    """``[tool.osc2run]``'s ``sut`` and ``sut-actor`` from the nearest ``pyproject.toml``
    above ``scenario_file`` that has the table (None when none has), and that file."""
    folder = Path(scenario_file).resolve().parent
    for candidate in (folder, *folder.parents):
        path = candidate / "pyproject.toml"
        if not path.is_file():
            continue
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
            raise SutError(f"{path}: cannot read: {exc}") from None
        table: Any = data
        for key in _SECTION:
            table = table.get(key) if isinstance(table, dict) else None
        if not isinstance(table, dict):
            continue
        unknown = sorted(set(table) - {"sut", "sut-actor"})
        if unknown:
            raise SutError(
                f"{path}: [tool.osc2run] has no key `{unknown[0]}` (keys: sut, sut-actor)"
            )
        target, actor = table.get("sut"), table.get("sut-actor")
        if target is None:
            return None, path
        if not isinstance(target, str) or (actor is not None and not isinstance(actor, str)):
            raise SutError(f"{path}: [tool.osc2run] sut and sut-actor are strings")
        return SutSpec(target, actor).resolved(path.parent), path
    return None, None
