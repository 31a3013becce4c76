"""Finding a map by the name a scenario gives: a built-in name or an ``.xodr`` path.

``map_file`` in a scenario names either a built-in map (``Town06``,
``highway_4lane``, ...) or an OpenDRIVE file, relative to the scenario file.
:func:`load_map` reads the file when the name ends in ``.xodr`` and the file
exists; a name that is not a file is looked up among the built-in names (so
``Town06.xodr`` without a file gives the Town06 stand-in, as CARLA scenarios
expect), and an ``.xodr`` name that is neither is a :class:`MapError` ("no such
file or directory"); a folder, FIFO or device of that name is one too, saying what it
is (it is never opened). Loaded files are cached by path and modification time, so an editor
asking on every keystroke reads a map once.
"""

from __future__ import annotations

import re
from pathlib import Path
from urllib.parse import unquote, urlparse

from osc2check.inputs import InputError, not_regular, probe
from osc2check.world.builtin import builtin_network
from osc2check.world.errors import MapError, UnknownMapError
from osc2check.world.network import RoadNetwork
from osc2check.world.opendrive import load_opendrive

__all__ = ["is_carla_town", "load_map", "map_path", "scenario_folder"]

# CARLA's maps: Town01 .. Town15, Town10HD and their `_Opt` (layered) variants
_CARLA_TOWN = re.compile(r"Town\d{2}(HD)?(_Opt)?")


def is_carla_town(name: str) -> bool:
    """Whether ``name`` is one of CARLA's maps (``Town04``, ``Town10HD_Opt``)."""
    return _CARLA_TOWN.fullmatch(name.removesuffix(".xodr")) is not None


_CACHE: dict[tuple[str, int], RoadNetwork] = {}
_CACHE_SIZE = 8


def scenario_folder(uri: str) -> Path | None:
    """The folder of a scenario file, from its analysis name (a path or ``file:`` URI);
    None for a name that is no file (``<stdin>``, ``untitled:1``)."""
    if uri.startswith("file://"):
        return Path(unquote(urlparse(uri).path)).parent
    if not uri or uri.startswith("<") or re.match(r"[A-Za-z][A-Za-z0-9+.-]+:", uri):
        return None
    return Path(uri).parent


def map_path(name: str, relative_to: str | Path | None = None) -> Path | None:
    """The file an ``.xodr`` map name stands for (None for other names)."""
    if not name.lower().endswith(".xodr"):
        return None
    path = Path(name)
    if not path.is_absolute() and relative_to is not None:
        path = Path(relative_to) / path
    return path


def load_map(name: str, relative_to: str | Path | None = None) -> RoadNetwork:
    """The road network ``name`` names (an ``.xodr`` path or a built-in map name).

    ``relative_to`` is the folder a relative path is taken from (the scenario's).

    Raises:
        MapError: the ``.xodr`` file cannot be read, or there is no such file and no
            built-in map of that name.
        UnknownMapError: a name that is not an ``.xodr`` path and no built-in map.
    """
    path = map_path(name, relative_to)
    if path is None:
        return builtin_network(name)
    try:
        status = probe(path)
    except InputError as missing:
        try:
            return builtin_network(name)
        except UnknownMapError:
            raise MapError(f"{missing} (looked for `{path}`)", name) from None
    why = not_regular(status)  # a folder, a FIFO, a device: there, but no map file
    if why is not None:
        raise MapError(f"cannot read the map file: {why}", str(path))
    resolved = path.resolve()
    key = (str(resolved), status.st_mtime_ns)
    network = _CACHE.get(key)
    if network is None:
        network = load_opendrive(resolved)  # its source is the file's absolute path
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = network
    return network
