"""The lock-free cached property: one instance computing never holds up another."""

from __future__ import annotations

import threading

from osc2lsp.lazy import cached_property


class Slow:
    def __init__(self, gate: threading.Event | None = None):
        self.gate = gate
        self.calls = 0

    @cached_property
    def value(self) -> int:
        """The doc of the property."""
        self.calls += 1
        if self.gate is not None:
            assert self.gate.wait(10)
        return 42


def test_computed_once_then_read_from_the_instance():
    slow = Slow()
    assert slow.value == 42 and slow.value == 42 and slow.calls == 1
    assert vars(slow)["value"] == 42
    assert Slow.value.__doc__ == "The doc of the property."


def test_an_instance_computing_does_not_block_another():
    """``functools.cached_property`` of Python 3.11 holds one lock per property for the
    whole class: the second instance would wait for the first one's gate."""
    gate = threading.Event()
    first = Slow(gate)
    worker = threading.Thread(target=lambda: first.value)
    worker.start()
    try:
        while first.calls == 0:
            worker.join(0.001)
        done = threading.Event()
        second = Slow()
        reader = threading.Thread(target=lambda: (second.value, done.set()))
        reader.start()
        assert done.wait(5), "the second instance waited for the first"
        reader.join()
    finally:
        gate.set()
        worker.join()
    assert first.value == 42 and second.value == 42
