"""How a run ends: its status (one of :data:`OUTCOME_STATUSES`) and why.

``success`` (the scenario's behaviour ended, or only open-ended actions were
still running at the time limit), ``failure`` (a failed phase, the ``fail``
event, a collision, an actor off the road), ``timeout`` (the time limit with
bounded phases still running), ``interrupted`` (a signal) and ``error`` (the
physics diverged, the system under test failed, or a bug). The same words are
written to ``run.json``, ``events.csv`` and a campaign's records.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, get_args

__all__ = ["OUTCOME_STATUSES", "OutcomeStatus", "RunOutcome"]

OutcomeStatus = Literal["success", "failure", "timeout", "interrupted", "error"]
OUTCOME_STATUSES: tuple[OutcomeStatus, ...] = get_args(OutcomeStatus)


@dataclass(frozen=True, slots=True)
class RunOutcome:
    """How a run ended: its ``status``, the ``reason``, the tick and time it ended at;
    ``signal`` names the signal that interrupted the run (``SIGTERM``), when one did.
    """

    status: OutcomeStatus
    reason: str
    tick: int
    time: float
    signal: str | None = None

    @property
    def ok(self) -> bool:
        return self.status == "success"
