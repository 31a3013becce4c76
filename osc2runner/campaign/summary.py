"""What a campaign found, over its runs: pass rate, coverage, worst runs, KPI figures.

* **Pass rate**: runs whose outcome is ``success`` over the runs that finished
  (``interrupted`` runs are not counted: ``--resume`` does them again).
* **Coverage**: per ``cover`` item, each bucket's hits summed over the runs
  (a run counts once per bucket it hit) and the seeds that hit it; buckets the
  plan found unreachable are marked so, the others with no hit are *holes*.
* **Worst runs**: the runs that failed first (error, failure, timeout), then
  by smallest time to collision, then by smallest gap.
* **KPIs**: per numeric KPI, its minimum, median, mean and maximum over the
  finished runs that have it.
* **Parameters**: the scenario parameters the campaign swept and how evenly
  (:mod:`~osc2runner.campaign.parameters`, :mod:`~osc2runner.campaign.spread`);
  **failures**: the pass/fail map's pair, the failure boundary and the triage of
  the runs that did not pass (:mod:`~osc2runner.campaign.failures`).
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence
from typing import Any

from osc2runner.campaign.failures import best_pair, boundary, triage
from osc2runner.campaign.kpis import KPI_UNITS
from osc2runner.campaign.parameters import choose_axes
from osc2runner.campaign.plan import ItemPlan
from osc2runner.campaign.spread import spreads
from osc2runner.campaign.worker import RunRecord

__all__ = [
    "SEVERITY",
    "coverage_table",
    "findings",
    "kpi_figures",
    "summarize",
    "varying",
    "worst_runs",
]

#: outcomes from worst to best (the order of the worst runs)
SEVERITY = {"error": 0, "failure": 1, "timeout": 2, "interrupted": 3, "success": 4}


def finished(records: Sequence[RunRecord]) -> list[RunRecord]:
    return [r for r in records if r.finished]


def summarize(records: Sequence[RunRecord]) -> dict[str, Any]:
    """Counts per outcome and the pass rate."""
    done = finished(records)
    counts: dict[str, int] = {}
    for r in records:
        counts[r.status] = counts.get(r.status, 0) + 1
    passed = sum(1 for r in done if r.passed)
    return {
        "runs": len(records),
        "finished": len(done),
        "passed": passed,
        "failed": len(done) - passed,
        "outcomes": dict(sorted(counts.items(), key=lambda kv: SEVERITY.get(kv[0], 9))),
        "pass_rate": round(passed / len(done), 4) if done else None,
        "collisions": sum(1 for r in done if r.kpis.get("collision")),
    }


def coverage_table(records: Sequence[RunRecord], plans: Sequence[ItemPlan]) -> list[dict[str, Any]]:
    """Per cover item: every bucket with its status, hits and the seeds that hit it."""
    table: list[dict[str, Any]] = []
    for plan in plans:
        name, bucket_labels = plan.name, plan.labels
        hits = [0] * len(bucket_labels)
        seeds: list[list[int]] = [[] for _ in bucket_labels]
        for r in finished(records):
            for index in r.coverage.get(name, []):
                if 0 <= index < len(hits):
                    hits[index] += 1
                    seeds[index].append(r.seed)
        buckets = []
        for i, label in enumerate(bucket_labels):
            status = plan.status[i] if plan.status else "observed"
            state = "filled" if hits[i] else ("unreachable" if status == "unreachable" else "hole")
            buckets.append(
                {"label": label, "hits": hits[i], "state": state, "solver": status,
                 "seeds": seeds[i][:20]}
            )  # fmt: skip
        reachable = [b for b in buckets if b["state"] != "unreachable"]
        table.append(
            {
                "name": name,
                "steerable": plan.steerable,
                "reason": plan.reason or None,
                "filled": sum(1 for b in reachable if b["hits"]),
                "reachable": len(reachable),
                "unreachable": len(buckets) - len(reachable),
                "holes": [b["label"] for b in buckets if b["state"] == "hole"],
                "buckets": buckets,
            }
        )
    return table


def _badness(r: RunRecord) -> tuple[float, float, float, int]:
    ttc = r.kpis.get("min_ttc_s")
    gap = r.kpis.get("min_gap_m")
    return (
        SEVERITY.get(r.status, 9),
        ttc if isinstance(ttc, (int, float)) else float("inf"),
        gap if isinstance(gap, (int, float)) else float("inf"),
        r.seed,
    )


def worst_runs(records: Sequence[RunRecord], count: int = 10) -> list[RunRecord]:
    """The ``count`` worst finished runs (see the module docstring)."""
    return sorted(finished(records), key=_badness)[:count]


def kpi_figures(records: Sequence[RunRecord]) -> dict[str, dict[str, Any]]:
    """Per numeric KPI: unit, min, median, mean, max and how many runs have it."""
    figures: dict[str, dict[str, Any]] = {}
    for name, unit in KPI_UNITS.items():
        values = [
            float(r.kpis[name])
            for r in finished(records)
            if isinstance(r.kpis.get(name), (int, float)) and not isinstance(r.kpis.get(name), bool)
        ]
        if not values:  # none, or not numbers: collision (a bool), collision_with
            continue
        figures[name] = {
            "unit": unit,
            "runs": len(values),
            "min": round(min(values), 4),
            "median": round(statistics.median(values), 4),
            "mean": round(statistics.fmean(values), 4),
            "max": round(max(values), 4),
        }
    return figures


def varying(records: Sequence[RunRecord]) -> list[str]:
    """The parameters whose value differs between the finished runs, by name."""
    seen: dict[str, set[str]] = {}
    for r in finished(records):
        for name, p in r.parameters.items():
            seen.setdefault(name, set()).add(str(p.get("value")))
    return sorted(n for n, values in seen.items() if len(values) > 1)


def findings(
    records: Sequence[RunRecord],
    parameters: Mapping[str, Any],
    preferred: Sequence[str],
    replay: Mapping[int, str],
) -> tuple[dict[str, Any], dict[str, Any]]:
    """The parameters the campaign swept and their spread, and where its runs failed:
    ``campaign.json``'s ``parameters`` (``parameters`` holds its ``domains`` and
    ``equations``, which the check of the file gave) and ``failures``."""
    domains = parameters.get("domains", {})
    axes = choose_axes(records, domains, parameters.get("equations", []), preferred)
    units = {name: d.get("unit", "") for name, d in domains.items()}
    pair, pairs = best_pair(records, axes.swept)
    swept = {
        **parameters,
        **axes.to_json(),
        "spread": [s.to_json() for s in spreads(records, axes.swept, domains)],
    }
    failures = {
        "map": {"pair": list(pair) if pair else None, "pairs": pairs},
        "boundary": boundary(records, axes.swept, units),
        "triage": triage(records, axes.swept, units, replay),
    }
    return swept, failures
