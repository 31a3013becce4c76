"""How evenly a campaign's runs cover each swept parameter, and when one piles up.

For each swept parameter (:mod:`osc2runner.campaign.parameters`) over the finished
runs:

* **continuous** (a ``real`` parameter, or an integer one with more values than
  :data:`osc2check.verify.domains.MAX_VALUES`): its range is its domain's bounds when the
  constraints give both, else the values the runs took (``observed``). Reported:
  the share of runs on each bound, the most common value's share, and the
  Kolmogorov-Smirnov statistic ``D`` of the values against a uniform spread over
  the range, with its p-value (the asymptotic Kolmogorov distribution with
  Stephens' small-sample factor). It **piles up** when more than
  :data:`PILE_SHARE` of the runs (at least two) share one value, on a bound or not:
  drawn from a continuous range, no two runs should.
* **discrete** (an integer, enum or boolean parameter, or one a set constrains):
  its ``K`` allowed values (the domain's, else those the runs took). Reported: the
  values hit and the most common value's share. It **piles up** when that share is
  improbable for ``K`` values hit evenly: the binomial chance of so many runs on
  one value, times ``K``, is below :data:`PILE_P`.

Constraints may make a parameter's spread uneven on purpose (``keep(a < b)``); the
statistics say how it came out, the warning only when runs pile on one value.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

from osc2runner.campaign.parameters import compact_text, numeric
from osc2runner.campaign.worker import RunRecord

__all__ = ["PILE_P", "PILE_SHARE", "Spread", "ks_p_value", "spread_of", "spreads"]

PILE_SHARE = 0.10  # of the runs on one value of a continuous parameter: a pile
PILE_P = 0.001  # a discrete value this improbably popular: a pile


@dataclass
class Spread:
    """One swept parameter's spread over the runs (see the module docstring)."""

    name: str
    unit: str
    kind: str  # continuous, discrete
    runs: int
    low: Any = None
    high: Any = None
    range: str = "constraints"  # where low and high come from: constraints, observed
    on_low: int = 0
    on_high: int = 0
    top_value: Any = None
    top_runs: int = 0
    ks: float | None = None  # Kolmogorov-Smirnov D against uniform over [low, high]
    ks_p: float | None = None
    allowed: int | None = None  # discrete: how many values the constraints allow
    hit: int | None = None  # discrete: how many of them the runs took
    piles: bool = False
    warning: str = ""

    def to_json(self) -> dict[str, Any]:
        return asdict(self)

    def text(self) -> str:
        """One line for the command's summary."""
        share = f"{100 * self.top_runs / self.runs:.0f} %" if self.runs else "–"
        unit = f" {self.unit}" if self.unit else ""
        if self.kind == "continuous":
            bounds = f"[{self.low:g}..{self.high:g}]{unit} ({self.range})"
            ks = f"; KS D = {self.ks:.2f} (p = {self.ks_p:.2g})" if self.ks is not None else ""
            return (
                f"{self.name} over {bounds}: {self.on_low} runs on the lower bound, "
                f"{self.on_high} on the upper{ks}; most at one value: {self.top_runs} ({share})"
            )
        return (
            f"{self.name}: {self.hit} of {self.allowed} values hit; most at one value: "
            f"{compact_text(self.top_value, self.unit)} in {self.top_runs} runs ({share})"
        )


def ks_p_value(d: float, n: int) -> float:
    """P(D >= d) for ``n`` values drawn uniformly: the Kolmogorov distribution with
    Stephens' factor ``sqrt(n) + 0.12 + 0.11 / sqrt(n)``."""
    if n <= 0 or d <= 0.0:
        return 1.0
    lam = (math.sqrt(n) + 0.12 + 0.11 / math.sqrt(n)) * d
    total: float = sum((-1) ** (k - 1) * math.exp(-2.0 * k * k * lam * lam) for k in range(1, 101))
    return min(max(2.0 * total, 0.0), 1.0)


def _binomial_tail(count: int, n: int, p: float) -> float:
    """P(X >= count) for X ~ Binomial(n, p)."""
    return sum(math.comb(n, k) * p**k * (1.0 - p) ** (n - k) for k in range(count, n + 1))


def _same(a: float, b: float) -> bool:
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)


def spread_of(name: str, values: Sequence[Any], domain: Mapping[str, Any]) -> Spread:
    """The spread of one parameter's ``values`` (one a run) in its ``domain`` (see
    :func:`osc2runner.campaign.parameters.parameter_domains`)."""
    unit = domain.get("unit", "")
    counts = Counter(str(v) for v in values)
    top_text, top_runs = counts.most_common(1)[0] if counts else ("", 0)
    top_value = next((v for v in values if str(v) == top_text), None)
    n = len(values)
    numbers = [numeric(v) for v in values]
    continuous = domain.get("sort") in ("real", "int") and not domain.get("values")
    if continuous and all(x is not None for x in numbers) and n:
        xs = sorted(x for x in numbers if x is not None)
        low, high = domain.get("low"), domain.get("high")
        where = "constraints"
        if low is None or high is None:
            low, high, where = xs[0], xs[-1], "observed"
        result = Spread(name, unit, "continuous", n, low, high, where, top_value=top_value,
                        top_runs=top_runs)  # fmt: skip
        result.on_low = sum(1 for x in xs if _same(x, low))
        result.on_high = sum(1 for x in xs if _same(x, high))
        if high > low:
            cdf = [min(max((x - low) / (high - low), 0.0), 1.0) for x in xs]
            result.ks = max(
                max((i + 1) / n - c for i, c in enumerate(cdf)),
                max(c - i / n for i, c in enumerate(cdf)),
            )
            result.ks_p = ks_p_value(result.ks, n)
        result.piles = top_runs >= 2 and top_runs > PILE_SHARE * n
        if result.piles:
            top = numeric(top_value)
            at = (
                ", its lower bound"
                if top is not None and _same(top, low)
                else ", its upper bound"
                if top is not None and _same(top, high)
                else ""
            )
            result.warning = (
                f"`{name}` piles up: {top_runs} of {n} runs at "
                f"{compact_text(top_value, ' ' + unit if unit else '')}{at}"
            )
        return result
    allowed = domain.get("values") or sorted(set(values), key=str)
    result = Spread(name, unit, "discrete", n, top_value=top_value, top_runs=top_runs)
    result.allowed, result.hit = len(allowed), len(counts)
    if allowed and n:
        chance = _binomial_tail(top_runs, n, 1.0 / len(allowed)) * len(allowed)
        result.piles = len(allowed) > 1 and chance < PILE_P
        if result.piles:
            result.warning = (
                f"`{name}` piles up: {top_runs} of {n} runs at "
                f"{compact_text(top_value, ' ' + unit if unit else '')} of its "
                f"{len(allowed)} values"
            )
    return result


def spreads(
    records: Sequence[RunRecord], swept: Sequence[str], domains: Mapping[str, Mapping[str, Any]]
) -> list[Spread]:
    """The spread of each swept parameter over the finished ``records``."""
    done = [r for r in records if r.finished]
    found = []
    for name in swept:
        values = [r.parameters[name].get("value") for r in done if name in r.parameters]
        found.append(spread_of(name, values, domains.get(name, {})))
    return found
