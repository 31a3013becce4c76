"""Shared pytest options, and where the tests' data lives."""

from __future__ import annotations

from pathlib import Path

import pytest

#: The design paper's scenarios, vendored (tests/data/README.md).
SEED_DIR = Path(__file__).resolve().parent / "data" / "seed"


def pytest_configure(config: pytest.Config) -> None:
    """Under ``-n`` (pytest-xdist) the default distribution is ``loadgroup``: the tests of
    one ``xdist_group`` share a worker, so a module fixture they share (a campaign, a long
    run) is built once, not once a worker (docs/testing.md)."""
    if getattr(config.option, "dist", "no") == "load":
        config.option.dist = "loadgroup"


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--update-goldens",
        action="store_true",
        default=False,
        help="rewrite the expectations of golden cases (markers, .expected files) from the "
        "checker's output; read the diff before committing",
    )


@pytest.fixture
def update_goldens(request: pytest.FixtureRequest) -> bool:
    """True under ``pytest --update-goldens``."""
    return bool(request.config.getoption("--update-goldens"))
