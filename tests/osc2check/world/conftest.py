"""Fixtures for the road-network tests."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest


@pytest.fixture
def write_map(tmp_path: Path) -> Callable[..., Path]:
    """Write OpenDRIVE text to a file and return its path."""

    def write(text: str, name: str = "map.xodr") -> Path:
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path

    return write
