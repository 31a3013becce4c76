"""``cover(...)`` and ``record(...)`` (§7.5): compiled into collectors that sample at run time.

Each item becomes a :class:`~osc2runner.execution.coverage.CoverageItem` in the
run context, and a collector that takes a sample at every occurrence of the
item's sampling event (``event:``, by default the end of the enclosing
scenario), from the scenario's start (:func:`osc2runner.compile.sampling.on_occurrence`):

* the value is the expression's (``expression:``, else the field the item is
  named after) at the occurrence's tick, converted to ``unit:`` when given
  (else SI units) and made JSON-ready (enum members by name, actors by name,
  lists as lists, a non-finite number as ``null``);
* ``ignore:`` and ``illegal:`` are evaluated with the item's name bound to the
  value (in SI units, as every run-time number): an ignored sample is kept but
  counts in no bucket; an illegal one is kept, logged, and fails the run
  (§7.5: an illegal value is an error);
* ``cover`` buckets: ``range: [a..b]`` split every ``every:`` (one bucket for
  the whole range without ``every``), bounds written as plain numbers in the
  item's unit or as physical values; an enum or a boolean without a range has
  a bucket per value; a number without a range has none.

``disable: true`` lists the item without sampling it. ``items:`` (cross
coverage), ``buckets:`` and ``override:`` are not collected by the runner: a
note in the run's metadata says so.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

from osc2check.semantics import types as T
from osc2check.semantics.bindings import CoverItem
from osc2check.semantics.builtins import COVERAGE_PARAMETERS, DEFAULT_SAMPLING_EVENT
from osc2check.semantics.constants import NotConstant, Quantity, RangeValue, evaluate
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2runner.compile.conditions import NamedEventWatch, compile_watch
from osc2runner.compile.expressions import Bindings, Environment
from osc2runner.compile.sampling import on_occurrence
from osc2runner.compile.text import unparse
from osc2runner.errors import CompileProblem
from osc2runner.execution.coverage import (
    CoverageBucket,
    CoverageItem,
    CoverageSample,
    SourceLocation,
)
from osc2runner.external import python_value
from osc2runner.structs import struct_members

__all__ = ["compile_coverage"]

_NOT_COLLECTED = ("items", "buckets", "override")
_MAX_BUCKETS = 10_000


def compile_coverage(env: Environment, source: CoverItem, notes: list[str]) -> CoverageItem:
    """The item of one ``cover``/``record`` (as the checker read it) and its collector
    (registered with the run); raises CompileProblem for what cannot be collected as
    written."""
    decl = source.decl
    named = dict(source.parameters)
    for key, given in source.parameters:
        if key not in COVERAGE_PARAMETERS or (key == "target" and decl.kind == "record"):
            raise CompileProblem(f"`{decl.kind}` has no parameter `{key}`", given)
    if not source.name:
        raise CompileProblem(f"`{decl.kind}` needs a name (its first argument or `name:`)", decl)
    name = source.name
    line = f"line {decl.span.line}"
    for key in _NOT_COLLECTED:
        if key in named:
            notes.append(
                f"{line}: `{decl.kind}({name}, {key}: ...)`: {key} is not collected by the runner"
            )
    expression_node = source.expression
    if expression_node is None:
        notes.append(f"{line}: `{decl.kind}({name})` has no expression: not collected")
    model = env.model
    value_type = model.type_of(expression_node) if expression_node is not None else None
    unit = _unit(env, named.get("unit"), value_type)
    item = CoverageItem(
        name=name,
        kind=decl.kind,
        location=SourceLocation(decl.span.uri, decl.span.line, decl.span.column),
        expression=unparse(expression_node) if expression_node is not None else "",
        event=DEFAULT_SAMPLING_EVENT,
        unit=unit.name if unit is not None else None,
        si_unit=(
            T.dimension_text(value_type.dimension)
            if value_type is not None
            and value_type.kind is T.Kind.PHYSICAL
            and value_type.dimension is not None
            else None
        ),
    )
    if "text" in named:
        item.text = str(env.compiler.constant_value(named["text"]))
    if "disable" in named:
        item.disabled = bool(env.compiler.constant_value(named["disable"]))
    if "target" in named:
        target = env.compiler.constant_value(named["target"])
        if not isinstance(target, int) or isinstance(target, bool) or target < 0:
            raise CompileProblem("`target:` takes a whole number of samples", named["target"])
        item.target = target
    if decl.kind == "cover":
        _buckets(env, item, named, value_type, unit)
    if expression_node is None or item.disabled:
        return item
    value = env.compile(expression_node)
    cell: list[Any] = [None]
    inner = Bindings(None, bindings={name: lambda: cell[0]})
    ignore = env.compile(named["ignore"], inner) if "ignore" in named else None
    illegal = env.compile(named["illegal"], inner) if "illegal" in named else None
    event_node = named.get("event")
    if event_node is not None:
        watch = compile_watch(env, event_node, Bindings())
        item.event = watch.name if isinstance(watch, NamedEventWatch) else unparse(event_node)
    else:
        watch = NamedEventWatch(env.run, DEFAULT_SAMPLING_EVENT)
    to_unit = _converter(unit)
    ctx = env.run

    def take() -> None:
        raw = value()
        cell[0] = raw
        ignored = bool(ignore()) if ignore is not None else False
        bad = bool(illegal()) if illegal is not None else False
        shown = to_unit(raw)
        bucket = _bucket_of(item, shown) if item.buckets else None
        item.add(CoverageSample(ctx.tick, ctx.time, shown, bucket, ignored, bad))
        if bad:
            where = f"{item.location.uri}:{item.location.line}:{item.location.column}"
            text = f"illegal value {shown}" + (f" {item.unit}" if item.unit else "")
            ctx.record("coverage", name, text)
            ctx.fail(f"{where}: {decl.kind} `{name}`: {text}")

    on_occurrence(ctx, watch, take)
    return item


def _unit(env: Environment, node: ast.Node | None, value_type: T.Type | None) -> Any:
    """The unit symbol of ``unit:`` (its dimension must be the value's)."""
    if node is None:
        return None
    if not isinstance(node, ast.NameRef):
        raise CompileProblem("`unit:` takes a unit name (`unit: kph`)", node)
    unit = env.model.unit(node.name.name.text)
    if unit is None or unit.kind is not SymbolKind.UNIT:
        raise CompileProblem(f"unknown unit `{node.name.name.text}`", node)
    if (
        value_type is not None
        and value_type.kind is T.Kind.PHYSICAL
        and value_type.dimension is not None
        and unit.dimension != value_type.dimension
    ):
        raise CompileProblem(
            f"`{unit.name}` is not a unit of the value ({T.dimension_text(value_type.dimension)})",
            node,
        )
    return unit


def _converter(unit: Symbol | None) -> Any:
    """Run-time value -> JSON-ready value in ``unit`` (numbers in SI when no unit)."""
    factor = float(unit.factor) if unit is not None else 1.0
    offset = float(unit.offset) if unit is not None else 0.0

    def convert(value: Any) -> Any:
        value = python_value(value)
        if isinstance(value, bool) or value is None or isinstance(value, str):
            return value
        if isinstance(value, int):
            return value if unit is None else (value - offset) / factor
        if isinstance(value, float):
            if not math.isfinite(value):
                return None
            return value if unit is None else (value - offset) / factor
        if isinstance(value, tuple):
            return [convert(v) for v in value]
        members = struct_members(value)
        if members is not None:
            return {k: convert(v) for k, v in members.items()}
        if hasattr(value, "__dict__"):  # another object: its attributes
            return {k: convert(v) for k, v in vars(value).items()}
        return str(value)

    return convert


def _in_unit(env: Environment, node: ast.Node, unit: Symbol | None) -> float:
    """A constant bound or width: a physical value converted to ``unit`` (SI without one),
    a plain number taken as written in the item's unit."""
    value = _constant(env, node)
    return _number_in_unit(value, unit, node)


def _number_in_unit(value: Any, unit: Symbol | None, node: ast.Node) -> float:
    if isinstance(value, Quantity):
        if not value.physical:
            return float(value.si)
        si = value.si
        if unit is None:
            return float(si)
        return float((si - unit.offset) / unit.factor)
    if isinstance(value, (int, Fraction)) and not isinstance(value, bool):
        return float(value)
    raise CompileProblem("a coverage bound must be a number or a physical value", node)


def _constant(env: Environment, node: ast.Node) -> Any:
    values = env.values

    def lookup(field: Symbol, ref: ast.Node) -> Any:
        if field.kind is SymbolKind.VARIABLE:
            raise NotConstant(f"`{field.name}` is a variable", ref)
        return values.value(field)

    try:
        return evaluate(node, env.model, lookup)
    except NotConstant as exc:
        raise CompileProblem(
            f"must be known before the run starts: {exc}", exc.node or node
        ) from None


def _buckets(
    env: Environment,
    item: CoverageItem,
    named: dict[str, ast.Node],
    value_type: T.Type | None,
    unit: Symbol | None,
) -> None:
    span = named.get("range")
    every = named.get("every")
    if span is None:
        if every is not None:
            raise CompileProblem("`every:` needs a `range:` to split", every)
        if value_type is not None and value_type.kind is T.Kind.ENUM and value_type.symbol:
            for member in env.model.enum_values(value_type.symbol):
                item.buckets.append(CoverageBucket(member.name, value=member.name))
        elif value_type is not None and value_type.kind is T.Kind.BOOL:
            item.buckets.extend(
                [CoverageBucket("false", value=False), CoverageBucket("true", value=True)]
            )
        return
    bounds = _constant(env, span)
    if not isinstance(bounds, RangeValue):
        raise CompileProblem("`range:` takes a range (`range: [10..130]`)", span)
    low = _number_in_unit(bounds.low, unit, span)
    high = _number_in_unit(bounds.high, unit, span)
    low, high = min(low, high), max(low, high)
    item.range = (low, high)
    if every is None:
        item.buckets.append(CoverageBucket(f"[{low:g}..{high:g}]", low, high))
        return
    width = _in_unit(env, every, unit)
    if not width > 0.0:
        raise CompileProblem("`every:` must be positive", every)
    count = max(1, math.ceil((high - low) / width - 1e-9))
    if count > _MAX_BUCKETS:
        raise CompileProblem(f"`every:` makes {count} buckets (at most {_MAX_BUCKETS})", every)
    item.every = width
    for i in range(count):
        lo = low + i * width
        hi = min(low + (i + 1) * width, high)
        last = i == count - 1
        item.buckets.append(CoverageBucket(f"[{lo:g}..{hi:g}" + ("]" if last else ")"), lo, hi))


def _bucket_of(item: CoverageItem, value: Any) -> int | None:
    """The index of the bucket holding ``value`` (in the item's unit), or None."""
    if item.range is None:
        for i, bucket in enumerate(item.buckets):
            if bucket.value == value and type(bucket.value) is type(value):
                return i
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    low, high = item.range
    tolerance = 1e-9 * max(1.0, abs(low), abs(high))
    if value < low - tolerance or value > high + tolerance:
        return None
    if item.every is None:
        return 0
    index = math.floor((value - low) / item.every + 1e-9)
    return min(max(index, 0), len(item.buckets) - 1)
