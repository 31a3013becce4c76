"""External functions for test_methods.py, registered as docs/runner.md describes.

Not a test module: the scenarios in scenarios/methods*.osc name these functions
(``is external demo_externals.faster_than(...)``); the test puts this folder on
``sys.path`` so that the runner can import the module by that name.
"""

from __future__ import annotations

from osc2runner.external import external

#: What ``note`` was called with, in order (the test clears it before each run).
CALLS: list[tuple[float, str]] = []


@external("demo_externals.faster_than")
def faster_than(speed: float, limit: float) -> bool:
    """Whether ``speed`` is above ``limit`` (both in m/s)."""
    return speed > limit


@external
def note(value: float, label: str = "") -> None:
    """Remember a value (registered under its own name, ``demo_externals.note``)."""
    CALLS.append((value, label))


@external("demo_externals.broken")
def broken(value: float) -> float:
    """Always raises: a run calling it fails with the call's location."""
    raise ValueError(f"cannot handle {value}")
