"""The runs of a campaign: which seeds, and for ``cover`` which bins they fill.

* ``random``: seeds ``S .. S+N-1``; each is the seed's own witness, which the
  checker's sampler spreads over the constraint space.
* ``cover``: runs chosen to fill the scenario's ``cover`` bins. For each
  steerable item (:mod:`osc2runner.campaign.steering`) every bucket is checked
  with the solver: a bucket no instance reaches is *unreachable* (reported,
  never run). Then the witnesses of candidate seeds ``S, S+1, ...`` (up to
  :data:`CANDIDATES_PER_RUN` per run) are looked at, and seeds are taken
  greedily, each the one whose witness fills the most bins not yet filled; a
  reachable bin that no candidate lands in gets a run whose witness is drawn
  inside it (a *directed* run, replayed with ``--bin item=index``). Runs left
  over once every reachable bin is filled are the next unused seeds.

Every planned run is a :class:`~osc2runner.campaign.worker.RunTask`; the plan
also says, per item, which bins are unreachable and which the run budget leaves
untried.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from osc2check.verify import bins
from osc2runner.campaign.steering import BinRef, SteerableItem, scenario_result
from osc2runner.campaign.worker import RunTask
from osc2runner.runner import Checked

__all__ = ["CANDIDATES_PER_RUN", "CoverPlan", "ItemPlan", "item_plans", "plan_cover", "plan_random"]

CANDIDATES_PER_RUN = 4  # witnesses looked at per planned run (cover strategy)
MAX_CANDIDATES = 2000


@dataclass
class ItemPlan:
    """A ``cover`` item as the plan sees it: steerable or why not, each bucket's status
    (``reachable``, ``unreachable``, ``unknown``) and the planned runs per bucket."""

    name: str
    steerable: bool
    reason: str
    labels: list[str]
    status: list[str] = field(default_factory=list)
    planned: list[int] = field(default_factory=list)

    def to_json(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "steerable": self.steerable,
            "reason": self.reason or None,
            "buckets": [
                {"label": label, "status": status, "planned_runs": planned}
                for label, status, planned in zip(
                    self.labels,
                    self.status or ["observed"] * len(self.labels),
                    self.planned or [0] * len(self.labels),
                    strict=True,
                )
            ],
        }


@dataclass
class CoverPlan:
    """The planned tasks and, per cover item, its plan."""

    tasks: list[RunTask]
    items: list[ItemPlan] = field(default_factory=list)


def plan_random(first_seed: int, runs: int) -> CoverPlan:
    """Seeds ``first_seed .. first_seed + runs - 1``."""
    return CoverPlan([RunTask(first_seed + i) for i in range(runs)])


def item_plans(checked: Checked, items: list[SteerableItem]) -> list[ItemPlan]:
    """Every cover item's plan before any run is chosen: its bucket labels and, for an
    item that can be steered, each bucket's solver status."""
    plans: list[ItemPlan] = []
    for entry in items:
        labels = [b.label for b in entry.item.buckets]
        plan = ItemPlan(entry.item.name, entry.steerable, entry.reason, labels)
        plans.append(plan)
        if not entry.steerable:
            continue
        assert entry.problem is not None
        by_name = {p.name: p for p in plans}
        plan.status = [
            _status(entry, i, entry.bucket_term(checked, i), by_name) for i in range(len(labels))
        ]
        plan.planned = [0] * len(labels)
    return plans


def plan_cover(
    checked: Checked, items: list[SteerableItem], first_seed: int, runs: int
) -> CoverPlan:
    """The cover strategy's runs (see the module docstring)."""
    plans = item_plans(checked, items)
    terms = {
        e.item.name: [e.bucket_term(checked, i) for i in range(len(e.item.buckets))]
        for e in items
        if e.steerable
    }
    wanted = {
        (p.name, i)
        for p in plans
        if p.steerable
        for i, status in enumerate(p.status)
        if status == "reachable"
    }
    result = scenario_result(checked)
    steer = {e.item.name: e for e in items if e.steerable}
    candidates: list[tuple[int, set[tuple[str, int]]]] = []
    budget = min(MAX_CANDIDATES, max(runs, len(wanted)) * CANDIDATES_PER_RUN)
    for k in range(budget if wanted else 0):
        seed = first_seed + k
        witness = result.witness_for(seed)
        if witness is None:
            continue
        hits: set[tuple[str, int]] = set()
        for name, entry in steer.items():
            assert entry.problem is not None
            for index, term in enumerate(terms[name]):
                if bins.term_value(term, entry.problem, witness) is True:
                    hits.add((name, index))  # the bucket's own constraint holds
                    break
        candidates.append((seed, hits))
    tasks: list[RunTask] = []
    used: set[int] = set()
    by_name = {p.name: p for p in plans}

    def count(hits: set[tuple[str, int]]) -> None:
        for name, index in hits:
            by_name[name].planned[index] += 1

    def take(filling: bool) -> bool:
        """Take the candidate that fills the least-filled bins; False when none helps."""

        def score(c: tuple[int, set[tuple[str, int]]]) -> tuple[float, int]:
            hits = c[1] & wanted
            if filling:
                return (len([b for b in hits if by_name[b[0]].planned[b[1]] == 0]), -c[0])
            return (sum(1.0 / (1 + by_name[n].planned[i]) for n, i in hits), -c[0])

        best = max(candidates, key=score, default=None)
        if best is None or (filling and score(best)[0] == 0):
            return False
        candidates.remove(best)
        used.add(best[0])
        tasks.append(RunTask(best[0]))
        count(best[1] & wanted)
        return True

    def unfilled() -> list[tuple[str, int]]:
        return sorted(
            (b for b in wanted if by_name[b[0]].planned[b[1]] == 0), key=lambda b: (b[1], b[0])
        )

    while len(tasks) < runs and unfilled() and take(filling=True):
        pass
    next_seed = first_seed + budget
    for name, index in unfilled():  # no candidate lands there: draw the witness inside
        if len(tasks) >= runs:
            break
        while next_seed in used:
            next_seed += 1
        tasks.append(RunTask(next_seed, BinRef(name, index, by_name[name].labels[index])))
        used.add(next_seed)
        count({(name, index)})
    while len(tasks) < runs and take(filling=False):
        pass
    seed = first_seed
    while len(tasks) < runs:
        if seed not in used:
            tasks.append(RunTask(seed))
            used.add(seed)
        seed += 1
    tasks.sort(key=lambda t: t.seed)
    return CoverPlan(tasks, plans)


def _status(entry: SteerableItem, index: int, term: Any, plans: dict[str, ItemPlan]) -> str:
    """A bucket's solver status; a combination with an unreachable part is unreachable."""
    for part, i in entry.combination(index) if entry.components else ():
        if plans[part.item.name].status[i] == "unreachable":
            return "unreachable"
    assert entry.problem is not None
    return bins.bin_status(entry.problem, term)
