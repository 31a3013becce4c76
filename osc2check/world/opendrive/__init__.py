"""OpenDRIVE (``.xodr``) files as :class:`~osc2check.world.network.RoadNetwork` values.

Reading is two steps: :mod:`.xmltree` parses the XML with the standard
library's expat (line and column for every element), :mod:`.reader` turns the
elements into road records, and :mod:`osc2check.world.layout` samples and links
them, the same step the built-in maps go through.
"""

from __future__ import annotations

from pathlib import Path

from osc2check.world.layout import build_network
from osc2check.world.network import RoadNetwork
from osc2check.world.opendrive.reader import read_spec

__all__ = ["load_opendrive"]


def load_opendrive(path: str | Path) -> RoadNetwork:
    """The road network of the OpenDRIVE file at ``path``.

    Raises:
        MapError: the file cannot be read, is not OpenDRIVE 1.x XML, or is
        inconsistent; the message names the file, line and column.
    """
    return build_network(read_spec(path))
