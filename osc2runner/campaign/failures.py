"""Where a campaign's runs fail: the pass/fail map's pair, the failure boundary, triage.

All three read one small model: a **decision tree** over the swept parameters
that separates the runs that did not pass from those that did. A node splits on
the parameter and threshold (midway between two neighbouring runs' values; for
an enum or boolean, one value against the others) with the lowest Gini impurity,
and keeps the split only when it puts fewer runs on the wrong side of the
majority than the node did; it stops at :data:`DEPTH` levels or with fewer than
four runs. A threshold is written with as few digits as fall strictly between
its two neighbours (70.2 and 73.4 kph give 71.8 kph).

* **Pass/fail map** (:func:`best_pair`): of every pair of swept parameters, the
  one whose tree over those two alone leaves the fewest runs on the wrong side;
  ties go to the earlier pair in the order of the swept parameters (the cover
  items first).
* **Failure boundary** (:func:`boundary`): the tree over all swept parameters; each
  leaf where most runs fail, and at least two do, is a region where the scenario
  fails, said as its conditions ("fails where ego_speed is above 71.8 kph and
  offset below 0.2 m: 7 of 7 runs"), with the nearest runs on either side of each
  threshold. Without such a leaf, or when the tree cannot split, there is no
  boundary, and the page says why (every run failed, the failures are spread).
* **Triage** (:func:`triage`): the runs that did not pass, grouped by their reason
  (numbers left out, a source location kept) and the leaf of that tree they fall
  in; each group names a representative run (the one nearest the others, over the
  swept parameters scaled to their ranges) and the command that replays it.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from osc2runner.campaign.parameters import compact_text, numeric
from osc2runner.campaign.worker import RunRecord

__all__ = ["DEPTH", "Leaf", "Split", "best_pair", "boundary", "grow", "reason_class", "triage"]

DEPTH = 2  # levels of the tree: a region is said by two conditions at most
MAX_PAIRS = 28  # pairs looked at for the map (of the first eight swept parameters)


@dataclass(frozen=True)
class Split:
    """``name <= threshold`` (numeric) or ``name == value`` (an enum or boolean), with
    the neighbouring runs' values on either side of a threshold."""

    name: str
    threshold: float | None = None
    below: float | None = None  # the largest value at or under the threshold
    above: float | None = None  # the smallest value over it
    value: Any = None

    def holds(self, x: Any) -> bool:
        if self.threshold is None:
            return bool(x == self.value)
        number = numeric(x)
        return number is not None and number <= self.threshold


@dataclass
class Leaf:
    """A region of the parameters: the conditions on the way to it (``(split, holds)``)
    and the runs in it."""

    path: list[tuple[Split, bool]]
    runs: list[int] = field(default_factory=list)  # indices into the records
    failed: int = 0

    @property
    def passed(self) -> int:
        return len(self.runs) - self.failed


def _gini(failed: int, total: int) -> float:
    if total == 0:
        return 0.0
    p = failed / total
    return 2.0 * p * (1.0 - p)


def _wrong(failed: int, total: int) -> int:
    return min(failed, total - failed)


def _between(a: float, b: float) -> float:
    """The number with the fewest significant digits strictly between ``a`` and ``b``,
    nearest their middle."""
    middle = 0.5 * (a + b)
    for digits in range(1, 16):
        rounded = float(f"{middle:.{digits}g}")
        if a < rounded < b:
            return rounded
    return middle


def _splits(name: str, values: list[Any]) -> list[Split]:
    numbers = [numeric(v) for v in values]
    if all(x is not None for x in numbers):
        distinct = sorted({x for x in numbers if x is not None})
        return [
            Split(name, _between(a, b), a, b) for a, b in zip(distinct, distinct[1:], strict=False)
        ]
    return [Split(name, value=v) for v in sorted({v for v in values}, key=str)]


def grow(
    records: Sequence[RunRecord], names: Sequence[str], depth: int = DEPTH
) -> tuple[list[Leaf], bool]:
    """The leaves of the tree over ``names`` (see the module docstring) of the finished
    runs that have a value of each, and whether it split at all."""
    rows = [
        i
        for i, r in enumerate(records)
        if r.finished and all(_value(r, n) is not None for n in names)
    ]
    leaves: list[Leaf] = []
    split_any = False

    def node(indices: list[int], path: list[tuple[Split, bool]], level: int) -> None:
        nonlocal split_any
        failed = sum(1 for i in indices if not records[i].passed)
        best: tuple[float, Split, list[int], list[int]] | None = None
        if level < depth and len(indices) >= 4 and 0 < failed < len(indices):
            for name in names:
                for split in _splits(name, [_value(records[i], name) for i in indices]):
                    yes = [i for i in indices if split.holds(_value(records[i], name))]
                    no = [i for i in indices if not split.holds(_value(records[i], name))]
                    if not yes or not no:
                        continue
                    f_yes = sum(1 for i in yes if not records[i].passed)
                    f_no = failed - f_yes
                    impurity = (
                        len(yes) * _gini(f_yes, len(yes)) + len(no) * _gini(f_no, len(no))
                    ) / len(indices)
                    kept = _wrong(f_yes, len(yes)) + _wrong(f_no, len(no)) < _wrong(
                        failed, len(indices)
                    )
                    if kept and (best is None or impurity < best[0] - 1e-12):
                        best = (impurity, split, yes, no)
        if best is None:
            leaves.append(Leaf(path, indices, failed))
            return
        split_any = True
        _, split, yes, no = best
        node(yes, [*path, (split, True)], level + 1)
        node(no, [*path, (split, False)], level + 1)

    node(rows, [], 0)
    return leaves, split_any


def _value(r: RunRecord, name: str) -> Any:
    return r.parameters.get(name, {}).get("value")


def best_pair(
    records: Sequence[RunRecord], swept: Sequence[str]
) -> tuple[tuple[str, str] | None, list[dict[str, Any]]]:
    """The pair of swept parameters the map shows first, and every pair with the runs
    its tree leaves on the wrong side (``wrong``) and the runs it judges (``runs``)."""
    pairs = [(a, b) for i, a in enumerate(swept[:8]) for b in swept[i + 1 : 8]][:MAX_PAIRS]
    scored: list[dict[str, Any]] = []
    for a, b in pairs:
        leaves, _ = grow(records, [a, b])
        wrong = sum(_wrong(leaf.failed, len(leaf.runs)) for leaf in leaves)
        scored.append({"x": a, "y": b, "wrong": wrong, "runs": sum(len(x.runs) for x in leaves)})
    if not scored:
        return None, []
    best = min(range(len(scored)), key=lambda k: (scored[k]["wrong"], k))
    return pairs[best], scored


def _conditions(path: list[tuple[Split, bool]], units: Mapping[str, str]) -> list[str]:
    """The path's conditions, one per parameter (two thresholds on one make a range)."""
    lows: dict[str, Split] = {}
    highs: dict[str, Split] = {}
    equal: dict[str, list[str]] = {}
    for split, holds in path:
        if split.threshold is None:
            text = compact_text(split.value, "")
            equal.setdefault(split.name, []).append(text if holds else f"not {text}")
        elif holds:  # <= threshold: an upper bound; the tighter of two wins
            high = highs.get(split.name)
            if high is None or high.threshold is None or split.threshold < high.threshold:
                highs[split.name] = split
        else:
            low = lows.get(split.name)
            if low is None or low.threshold is None or split.threshold > low.threshold:
                lows[split.name] = split
    texts = []
    for name in dict.fromkeys([s.name for s, _ in path]):
        unit = f" {units.get(name, '')}".rstrip()
        low, high = lows.get(name), highs.get(name)
        if name in equal:
            texts.append(f"{name} is {' and '.join(equal[name])}")
        elif low is not None and high is not None:
            texts.append(f"{name} is between {low.threshold:g} and {high.threshold:g}{unit}")
        elif low is not None:
            texts.append(f"{name} is above {low.threshold:g}{unit}")
        elif high is not None:
            texts.append(f"{name} is below {high.threshold:g}{unit}")
    return texts


def _brackets(path: list[tuple[Split, bool]], units: Mapping[str, str]) -> list[str]:
    texts = []
    for split, _ in path:
        if split.threshold is not None:
            unit = f" {units.get(split.name, '')}".rstrip()
            texts.append(
                f"{split.name}: runs at {split.below:.4g} and {split.above:.4g}{unit} on either "
                "side"
            )
    return texts


def region_text(leaf: Leaf, units: Mapping[str, str]) -> str:
    """A leaf's conditions as words (``anywhere`` for the root)."""
    return " and ".join(_conditions(leaf.path, units)) or "anywhere"


def boundary(
    records: Sequence[RunRecord], swept: Sequence[str], units: Mapping[str, str]
) -> dict[str, Any]:
    """The failure boundary (see the module docstring): ``regions`` (each with its
    ``text``, ``conditions``, ``runs``, ``failed`` and ``brackets``) and, without
    one, ``why``."""
    done = [r for r in records if r.finished]
    failed = sum(1 for r in done if not r.passed)
    if not swept:
        return {"regions": [], "why": "no parameter varies between the runs"}
    if failed == 0:
        return {"regions": [], "why": "no run failed"}
    if failed == len(done):
        return {"regions": [], "why": "every run failed"}
    leaves, split = grow(records, swept)
    regions = [
        {
            "text": f"fails where {region_text(leaf, units)}: {leaf.failed} of "
            f"{len(leaf.runs)} runs",
            "conditions": _conditions(leaf.path, units),
            "runs": len(leaf.runs),
            "failed": leaf.failed,
            "brackets": _brackets(leaf.path, units),
        }
        for leaf in leaves
        if split and leaf.failed >= 2 and leaf.failed > leaf.passed
    ]
    why = "" if regions else "the failures are spread over the parameters: no region of them fails"
    return {"regions": regions, "why": why}


_LOCATION = re.compile(r"[^\s:()]+:\d+:\d+")
_NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e-?\d+)?")


def reason_class(reason: str) -> str:
    """A run's reason without its numbers (times, ticks, positions), source locations
    kept: runs that failed alike share it."""
    places = iter(_LOCATION.findall(reason))
    text = _NUMBER.sub("#", _LOCATION.sub("\0", reason))
    return re.sub("\0", lambda _: next(places), text)


def _scaled(records: Sequence[RunRecord], swept: Sequence[str]) -> dict[str, Any]:
    spans: dict[str, tuple[float, float]] = {}
    for name in swept:
        numbers = [x for r in records if (x := numeric(_value(r, name))) is not None]
        if numbers:
            spans[name] = (min(numbers), max(numbers))
    return spans


def _distance(
    a: RunRecord, b: RunRecord, swept: Sequence[str], spans: Mapping[str, tuple[float, float]]
) -> float:
    total = 0.0
    for name in swept:
        x, y = _value(a, name), _value(b, name)
        if name in spans and numeric(x) is not None and numeric(y) is not None:
            low, high = spans[name]
            total += ((float(x) - float(y)) / (high - low if high > low else 1.0)) ** 2
        else:
            total += 0.0 if x == y else 1.0
    return math.sqrt(total)


def triage(
    records: Sequence[RunRecord],
    swept: Sequence[str],
    units: Mapping[str, str],
    replay: Mapping[int, str],
) -> list[dict[str, Any]]:
    """The runs that did not pass, grouped (see the module docstring): per group its
    ``reason``, ``region``, ``seeds``, ``statuses`` and ``representative`` (seed and
    ``replay`` command); the largest groups first."""
    leaves, _ = grow(records, swept) if swept else ([], False)
    leaf_of = {i: k for k, leaf in enumerate(leaves) for i in leaf.runs}
    groups: dict[tuple[str, int], list[int]] = {}
    for i, r in enumerate(records):
        if r.finished and not r.passed:
            groups.setdefault((reason_class(r.reason), leaf_of.get(i, -1)), []).append(i)
    spans = _scaled(records, swept)
    rows: list[dict[str, Any]] = []
    for (reason, leaf), members in groups.items():
        runs = [records[i] for i in members]
        middle = min(runs, key=lambda r: (sum(_distance(r, o, swept, spans) for o in runs), r.seed))
        rows.append(
            {
                "reason": reason,
                "region": region_text(leaves[leaf], units) if leaf >= 0 else "–",
                "seeds": sorted(r.seed for r in runs),
                "statuses": sorted({r.status for r in runs}),
                "representative": middle.seed,
                "replay": replay.get(middle.seed, ""),
            }
        )
    rows.sort(key=lambda row: (-len(row["seeds"]), row["seeds"][0]))
    return rows
