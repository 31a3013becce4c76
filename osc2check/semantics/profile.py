"""Which language a file is read as: the OSC2 version and the dialect.

The version chooses the standard library (:mod:`osc2check.semantics.stdlib`):
2.1 (ASAM OpenSCENARIO DSL 2.1.0, the default) or 2.2 (2.2.0, March 2026).
The dialect chooses how other tools' forms are read: ``standard`` reads the
standard only (the design paper's forms are warnings with D codes, as always);
``carla`` also reads CARLA scenario_runner's forms
(:mod:`osc2check.dialects.carla`); ``auto`` (the default) reads a file as
``carla`` when it imports CARLA's ``basic.osc`` or declares CARLA's
``Path.set_map``, else as ``standard``.

:class:`LibraryChoice` is the one value that names the analysed library a
program is built on; a cache of that work keys on :attr:`LibraryChoice.key`.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "DEFAULT_DIALECT",
    "DEFAULT_OSC_VERSION",
    "DIALECTS",
    "OSC_VERSIONS",
    "LibraryChoice",
]

#: the versions of the standard whose library the toolkit has, oldest first
OSC_VERSIONS = ("2.1", "2.2")
DEFAULT_OSC_VERSION = "2.1"
#: how other tools' forms are read (see the module docstring)
DIALECTS = ("auto", "standard", "carla")
DEFAULT_DIALECT = "auto"


@dataclass(frozen=True, slots=True)
class LibraryChoice:
    """The standard library a program is built on: its version.

    The dialect changes how files are read, not the library (CARLA's world is a
    module a file imports, ``osc2toolkit.carla``), so the library's analysis is
    the same for every dialect; :attr:`key` still names both, so that a cache
    of a file's reading (which the dialect changes) can key on it too.
    """

    version: str = DEFAULT_OSC_VERSION
    dialect: str = DEFAULT_DIALECT

    def __post_init__(self) -> None:
        if self.version not in OSC_VERSIONS:
            raise ValueError(f"unknown OSC2 version {self.version!r} (known: {OSC_VERSIONS})")
        if self.dialect not in DIALECTS:
            raise ValueError(f"unknown dialect {self.dialect!r} (known: {DIALECTS})")

    @property
    def key(self) -> str:
        """``2.1/auto``: what a cache of the library or of a file's reading keys on."""
        return f"{self.version}/{self.dialect}"
