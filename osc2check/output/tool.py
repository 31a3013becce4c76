"""The tool's name and version, as machine-readable outputs report them."""

from __future__ import annotations

NAME = "osc2check"
DISTRIBUTION = "osc2-toolkit"


def version() -> str:
    """The installed version of the distribution, or ``0+unknown`` when not installed."""
    from importlib import metadata  # about 20 ms to import: only when a version is asked

    try:
        return metadata.version(DISTRIBUTION)
    except metadata.PackageNotFoundError:
        return "0+unknown"
