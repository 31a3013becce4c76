"""Finding a map by the name a scenario gives: a built-in name or an ``.xodr`` path.

``map_file`` in a scenario names either a built-in map (``Town06``,
``highway_4lane``, ...) or an OpenDRIVE file, relative to the scenario file.
:func:`load_map` tries the file first when the name ends in ``.xodr`` and the
file exists, then the built-in names (so ``Town06.xodr`` without a file gives
the Town06 stand-in, as before). Loaded files are cached by path and
modification time, so an editor asking on every keystroke reads a map once.
"""

from __future__ import annotations

from pathlib import Path

from osc2check.world.builtin import builtin_network
from osc2check.world.network import RoadNetwork
from osc2check.world.opendrive import load_opendrive

__all__ = ["load_map"]

_CACHE: dict[tuple[str, int], RoadNetwork] = {}
_CACHE_SIZE = 8


def load_map(name: str, relative_to: str | Path | None = None) -> RoadNetwork:
    """The road network ``name`` names (an ``.xodr`` path or a built-in map name).

    ``relative_to`` is the folder a relative path is taken from (the scenario's).

    Raises:
        MapError: the ``.xodr`` file exists but cannot be read.
        UnknownMapError: no such file and no built-in map of that name.
    """
    if name.lower().endswith(".xodr"):
        path = Path(name)
        if not path.is_absolute() and relative_to is not None:
            path = Path(relative_to) / path
        if path.is_file():
            key = (str(path.resolve()), path.stat().st_mtime_ns)
            network = _CACHE.get(key)
            if network is None:
                network = load_opendrive(path)
                if len(_CACHE) >= _CACHE_SIZE:
                    _CACHE.pop(next(iter(_CACHE)))
                _CACHE[key] = network
            return network
    return builtin_network(name)
