"""Which ``cover`` items a campaign can steer, their bins, and witnesses inside a bin.

The runner's coverage items (``compile/coverage.py``) define the buckets; the
checker (``osc2check.verify.bins``) turns a bucket into a constraint and draws
the witness with it. An item is *steerable* when its expression is over the
scenario's parameters (the solver chooses its value before the run); one over
run-time state (``hero.speed`` at the end) is only observed, and says why.

Cross coverage (``cover(grid, items: [a, b])``, §7.5), which the runner does
not collect, is the campaign's: its buckets are the combinations of the
buckets of ``a`` and ``b`` (``[7.5..12.5) × [87.5..112.5]``), steered by the
conjunction of their constraints, and a run hits a combination when it hits
both buckets.

A run drawn inside a bin is named by a :class:`BinRef` (``test_speed=3``: the
item's name and the bucket's index); ``osc2run FILE --seed k --bin test_speed=3``
replays it alone.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from osc2check.semantics.bindings import CoverItem
from osc2check.semantics.symbols import SymbolKind
from osc2check.syntax import ast
from osc2check.syntax.ast import NameRef as _NameRef
from osc2check.verify import bins, ir
from osc2check.verify.check import ScenarioResult, source_text
from osc2check.verify.witness import Witness
from osc2runner.errors import RunProblem, ScenarioError
from osc2runner.execution.coverage import CoverageBucket, CoverageItem
from osc2runner.options import DT_CONTROL
from osc2runner.runner import Checked, compile_checked

__all__ = [
    "BinRef",
    "SteerableItem",
    "bin_ref",
    "cover_items",
    "directed_witness",
    "scenario_result",
]

MAX_CROSS_BUCKETS = 10_000


@dataclass(frozen=True, slots=True)
class BinRef:
    """One bucket of one ``cover`` item: the item's name, the bucket's index and label."""

    item: str
    index: int
    label: str = ""

    @property
    def text(self) -> str:
        """``item=index``, as ``--bin`` takes it."""
        return f"{self.item}={self.index}"


@dataclass
class SteerableItem:
    """A ``cover`` item of the root scenario, with its solver term when it has one
    (``reason`` says why not otherwise)."""

    item: CoverageItem
    problem: ir.ConstraintProblem | None = None
    term: ir.Term | None = None
    reason: str = ""
    components: list[SteerableItem] = field(default_factory=list)  # of a cross item

    @property
    def steerable(self) -> bool:
        return self.term is not None

    def combination(self, index: int) -> list[tuple[SteerableItem, int]]:
        """The component buckets of bucket ``index`` of a cross item."""
        found = []
        for part in reversed(self.components):
            count = len(part.item.buckets)
            found.append((part, index % count))
            index //= count
        return found[::-1]

    def hits(self, coverage: dict[str, list[int]]) -> list[int]:
        """The buckets of this cross item a run hit, from its hits of the components."""
        result = [0]
        for part in self.components:
            count = len(part.item.buckets)
            result = [r * count + i for r in result for i in coverage.get(part.item.name, [])]
        return sorted(result)

    def bucket_term(self, checked: Checked, index: int) -> ir.Term:
        """The constraint of bucket ``index``."""
        assert self.term is not None
        if self.components:
            return ir.op("and", *(p.bucket_term(checked, i) for p, i in self.combination(index)))
        item = self.item
        bucket = item.buckets[index]
        if bucket.low is not None and bucket.high is not None:
            unit = (
                checked.analysis.programs[checked.uri].model.unit(item.unit) if item.unit else None
            )
            factor = Fraction(unit.factor) if unit is not None else Fraction(1)
            offset = Fraction(unit.offset) if unit is not None else Fraction(0)
            low = Fraction(repr(bucket.low)) * factor + offset
            high = Fraction(repr(bucket.high)) * factor + offset
            return bins.in_bucket(self.term, low, high, index == len(item.buckets) - 1)
        value = bucket.value
        if isinstance(value, bool):
            return bins.is_value(self.term, value)
        if isinstance(self.term, ir.Ref):
            number = next((v for n, v in self.term.var.enum if n == value), None)
            if number is not None:
                return bins.is_value(self.term, Fraction(number))
        raise ValueError(f"bucket `{bucket.label}` of `{item.name}` cannot be a constraint")


def scenario_result(checked: Checked) -> ScenarioResult:
    """The checker's result for the scenario ``checked`` runs (its constraint problem and
    witnesses)."""
    verified = checked.analysis.verified[checked.uri]
    return next(r for r in verified.scenarios if r.scenario is checked.scenario)


def cover_items(
    checked: Checked, *, seed: int = 0, dt_control: float = DT_CONTROL
) -> list[SteerableItem]:
    """The scenario's ``cover`` items (compiled for ``seed``) with their terms."""
    compiled = compile_checked(checked, seed=seed, dt_control=dt_control).compiled
    program = checked.analysis.programs[checked.uri]
    model = program.model
    result = scenario_result(checked)
    found: list[SteerableItem] = []
    for item, source in compiled.cover_items:
        if item.kind != "cover" or item.disabled:
            continue
        entry = SteerableItem(item)
        found.append(entry)
        crossed = _crossed(source)
        if crossed is not None:
            _cross(entry, crossed, found)
            continue
        if not item.buckets:
            entry.reason = "it has no buckets (give it a range, or make it an enum or boolean)"
            continue
        expr = source.expression
        owner = model.references.get(expr.name.name) if isinstance(expr, _NameRef) else None
        if expr is None or (owner is not None and owner.kind is SymbolKind.EVENT):
            entry.reason = "it has no expression the solver can read"
            continue
        try:
            entry.problem, entry.term = bins.cover_term(
                model, checked.scenario, result.problem, expr, source_text(program)
            )
        except bins.NotSteerable as exc:
            entry.reason = str(exc)
    return found


def _crossed(source: CoverItem) -> list[str] | None:
    """The item names of ``items: [a, b]``, or None when the item is not a cross."""
    value = source.get("items")
    if value is None:
        return None
    if isinstance(value, ast.ListLiteral):
        return [v.name.name.text if isinstance(v, ast.NameRef) else "" for v in value.items]
    return []


def _cross(entry: SteerableItem, names: list[str], found: list[SteerableItem]) -> None:
    """Make ``entry`` the cross of the items ``names`` declared before it."""
    parts = [next((e for e in found if e.item.name == n and not e.components), None) for n in names]
    missing = [n for n, p in zip(names, parts, strict=True) if p is None or not p.item.buckets]
    if len(names) < 2 or missing:
        entry.reason = (
            f"its items {', '.join(f'`{n}`' for n in missing)} are not cover items with buckets "
            "declared before it"
            if missing
            else "cross coverage needs two items or more"
        )
        return
    components = [p for p in parts if p is not None]
    entry.components = components
    labels = [""]
    for part in components:
        labels = [f"{a} × {b.label}" if a else b.label for a in labels for b in part.item.buckets]
    entry.item.buckets = [CoverageBucket(label) for label in labels]
    if len(labels) > MAX_CROSS_BUCKETS:
        entry.reason = f"it has {len(labels)} combinations (at most {MAX_CROSS_BUCKETS})"
        return
    unsteered = [p for p in components if not p.steerable]
    if unsteered:
        entry.reason = f"`{unsteered[0].item.name}` cannot be steered: {unsteered[0].reason}"
        return
    entry.problem = components[0].problem
    entry.term = ir.const(True)


def bin_ref(text: str) -> BinRef:
    """``item=index`` as a BinRef (ValueError when it is not that)."""
    name, sep, index = text.partition("=")
    if not sep or not name or not index.isdigit():
        raise ValueError(f"`{text}` is not ITEM=INDEX (a cover item and a bucket number)")
    return BinRef(name, int(index))


def directed_witness(
    checked: Checked, items: list[SteerableItem], ref: BinRef, seed: int
) -> Witness:
    """The witness of ``seed`` inside bin ``ref``; ScenarioError when the item is not a
    steerable cover item, the bucket does not exist, or no instance lands in it."""
    span = checked.scenario.name_span
    entry = next((e for e in items if e.item.name == ref.item), None)
    if entry is None:
        known = ", ".join(e.item.name for e in items) or "none"
        raise ScenarioError(
            [RunProblem(f"--bin: no cover item `{ref.item}` (items: {known})", span)]
        )
    if not entry.steerable:
        raise ScenarioError(
            [RunProblem(f"--bin: `{ref.item}` cannot be steered: {entry.reason}", span)]
        )
    if not 0 <= ref.index < len(entry.item.buckets):
        raise ScenarioError(
            [
                RunProblem(
                    f"--bin: `{ref.item}` has buckets 0 to {len(entry.item.buckets) - 1}", span
                )
            ]
        )
    assert entry.problem is not None
    term = entry.bucket_term(checked, ref.index)
    witness = bins.witness_in(entry.problem, term, seed)
    if witness is None:
        label = entry.item.buckets[ref.index].label
        raise ScenarioError(
            [RunProblem(f"--bin: no instance of the scenario has `{ref.item}` in {label}", span)]
        )
    return witness
