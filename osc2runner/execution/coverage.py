"""The coverage data of a run: every ``cover``/``record`` item with its samples (§7.5).

This is what a run returns (``RunResult.coverage``), writes (``coverage.json``,
:mod:`osc2runner.output.coverage`) and what a campaign aggregates over runs:

* :class:`RunCoverage`: the run (scenario, source, seed) and its items, in
  declaration order;
* :class:`CoverageItem`: one item — its name, kind (``cover`` or ``record``),
  where it is declared, the expression, the unit its values are in (``None``:
  SI units, named by ``si_unit`` when the value is physical), the sampling
  event, its text; for ``cover`` the range, the bucket width (``every``), the
  buckets with their hit counts and the target;
* :class:`CoverageSample`: one sample — tick, time, the value (JSON-ready, in
  the item's unit), the index of its bucket (``None``: no bucket holds it),
  whether ``ignore`` or ``illegal`` held for it.

A bucket counts the samples that are neither ignored nor illegal. Everything
here is plain data: ``to_json()`` and ``from_json()`` round-trip exactly, so a
campaign can merge the ``coverage.json`` of many runs with :meth:`RunCoverage.from_json`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

__all__ = [
    "COVERAGE_FORMAT",
    "CoverageBucket",
    "CoverageItem",
    "CoverageSample",
    "RunCoverage",
    "SourceLocation",
]

#: Version of the ``coverage.json`` layout (raised when it changes incompatibly).
COVERAGE_FORMAT = 1

JsonValue = None | bool | int | float | str | list[Any]


@dataclass(frozen=True, slots=True)
class SourceLocation:
    """Where an item is declared (1-based line and column)."""

    uri: str
    line: int
    column: int

    def to_json(self) -> dict[str, Any]:
        return {"uri": self.uri, "line": self.line, "column": self.column}

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> SourceLocation:
        return cls(data["uri"], data["line"], data["column"])


@dataclass(slots=True)
class CoverageBucket:
    """One bucket of a ``cover`` item: a numeric interval ``[low, high)`` (the last one
    closed) in the item's unit, or one value (an enum member, a boolean); ``hits`` counts
    the samples it holds that are neither ignored nor illegal."""

    label: str
    low: float | None = None
    high: float | None = None
    value: JsonValue = None
    hits: int = 0

    def to_json(self) -> dict[str, Any]:
        return {
            "label": self.label,
            "low": self.low,
            "high": self.high,
            "value": self.value,
            "hits": self.hits,
        }

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> CoverageBucket:
        return cls(data["label"], data["low"], data["high"], data["value"], data["hits"])


@dataclass(frozen=True, slots=True)
class CoverageSample:
    """One sample of an item: when, the value in the item's unit, its bucket."""

    tick: int
    time: float
    value: JsonValue
    bucket: int | None = None
    ignored: bool = False
    illegal: bool = False

    def to_json(self) -> dict[str, Any]:
        return {
            "tick": self.tick,
            "time": self.time,
            "value": self.value,
            "bucket": self.bucket,
            "ignored": self.ignored,
            "illegal": self.illegal,
        }

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> CoverageSample:
        return cls(
            data["tick"], data["time"], data["value"], data["bucket"], data["ignored"],
            data["illegal"],
        )  # fmt: skip


@dataclass(slots=True)
class CoverageItem:
    """One ``cover`` or ``record`` item of the scenario and its samples."""

    name: str
    kind: str  # "cover" | "record"
    location: SourceLocation
    expression: str
    event: str
    unit: str | None = None  # the unit of values, range and buckets; None: SI
    si_unit: str | None = None  # SI unit of a physical value (``m*s^-1``)
    text: str | None = None
    range: tuple[float, float] | None = None
    every: float | None = None
    target: int | None = None
    disabled: bool = False
    buckets: list[CoverageBucket] = field(default_factory=list)
    samples: list[CoverageSample] = field(default_factory=list)

    def add(self, sample: CoverageSample) -> None:
        """Record a sample (and count it in its bucket unless ignored or illegal)."""
        self.samples.append(sample)
        if sample.bucket is not None and not (sample.ignored or sample.illegal):
            self.buckets[sample.bucket].hits += 1

    def values(self) -> list[JsonValue]:
        """The sampled values, in order (ignored and illegal ones included)."""
        return [s.value for s in self.samples]

    def to_json(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "kind": self.kind,
            "location": self.location.to_json(),
            "expression": self.expression,
            "event": self.event,
            "unit": self.unit,
            "si_unit": self.si_unit,
            "text": self.text,
            "range": list(self.range) if self.range is not None else None,
            "every": self.every,
            "target": self.target,
            "disabled": self.disabled,
            "buckets": [b.to_json() for b in self.buckets],
            "samples": [s.to_json() for s in self.samples],
        }

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> CoverageItem:
        span = data["range"]
        return cls(
            name=data["name"],
            kind=data["kind"],
            location=SourceLocation.from_json(data["location"]),
            expression=data["expression"],
            event=data["event"],
            unit=data["unit"],
            si_unit=data["si_unit"],
            text=data["text"],
            range=(span[0], span[1]) if span is not None else None,
            every=data["every"],
            target=data["target"],
            disabled=data["disabled"],
            buckets=[CoverageBucket.from_json(b) for b in data["buckets"]],
            samples=[CoverageSample.from_json(s) for s in data["samples"]],
        )


@dataclass(slots=True)
class RunCoverage:
    """The coverage items of one run (see the module docstring)."""

    scenario: str = ""
    source: str = ""
    seed: int = 0
    items: list[CoverageItem] = field(default_factory=list)

    def item(self, name: str) -> CoverageItem:
        """The item named ``name`` (KeyError when there is none)."""
        for item in self.items:
            if item.name == name:
                return item
        raise KeyError(name)

    def to_json(self) -> dict[str, Any]:
        return {
            "format": COVERAGE_FORMAT,
            "scenario": self.scenario,
            "source": self.source,
            "seed": self.seed,
            "items": [i.to_json() for i in self.items],
        }

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> RunCoverage:
        if data.get("format") != COVERAGE_FORMAT:
            raise ValueError(f"coverage format {data.get('format')!r} is not {COVERAGE_FORMAT}")
        return cls(
            data["scenario"],
            data["source"],
            data["seed"],
            [CoverageItem.from_json(i) for i in data["items"]],
        )
