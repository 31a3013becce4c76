"""What runs a campaign's tasks: an :class:`Engine` (the local process pool,
:class:`~osc2runner.campaign.pool.LocalPool`, or a Ray cluster,
:class:`~osc2runner.campaign.ray_engine.RayEngine`).

``run_campaign`` starts the engine's workers while it plans the runs, hands it
the tasks with a callback for each record, stops it on a signal and closes it
at the end, whatever happened.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Literal, Protocol

if TYPE_CHECKING:
    from osc2runner.campaign.worker import RunRecord, RunTask

__all__ = ["Engine", "EngineName"]

#: the engines ``--engine`` chooses from
EngineName = Literal["local", "ray"]


class Engine(Protocol):
    """Runs tasks on workers, each of which checked the campaign's file once."""

    #: what ``campaign.json`` says ran the campaign
    name: EngineName

    def start(self, count: int) -> None:
        """Start the workers for ``count`` runs (they start while the runs are planned)."""

    def run(self, tasks: Iterable[RunTask], on_record: Callable[[RunRecord], None]) -> None:
        """Run ``tasks``, calling ``on_record`` with each record as it arrives (in the
        caller's thread); returns when every task has its record, or after :meth:`stop`."""

    def stop(self) -> None:
        """No new run starts; the runs in progress end at a tick boundary (a signal)."""

    def close(self) -> None:
        """Release the workers (after the last record, or after an error)."""
