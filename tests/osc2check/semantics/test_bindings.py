"""The call checker's bindings (``Model.binding``) and cover items (``Model.cover_item``):
one reading of every call, which every later stage reads."""

from __future__ import annotations

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.semantics.bindings import Binding
from osc2check.semantics.builtins import Builtin
from osc2check.semantics.model import Model
from osc2check.syntax import ast
from osc2check.syntax.walk import walk

TEXT = """import osc.standard

scenario top:
    npc: vehicle
    ego: vehicle
    event seen(distance: length, urgent: bool = false)
    gap: length = 10m
    keep(gap < twice(6m))
    def twice(x: length, scale: float = 2.0) -> length is expression x * scale
    cover(gap, unit: m, range: [0..30], every: 10)
    record(passing, expression: gap * 2)
    do parallel(overlap: equal, duration: [4s..6s]):
        npc.drive() with:
            speed([30kmph..31kmph], at: start)
            lane(1, side: left, side_of: ego)
            until elapsed(3s)
        serial:
            wait every(1s, offset: 3s)
            emit seen(5m)
"""


def _model() -> tuple[Model, ast.File]:
    analysis = analyze([SourceInput("t.osc", TEXT)], AnalysisOptions())
    program = analysis.programs["t.osc"]
    assert not [d for d in analysis.diagnostics if d.severity.name == "ERROR"]
    return program.model, program.files["t.osc"].ast


def _binding(model: Model, tree: ast.File, name: str) -> Binding:
    for node in walk(tree):
        if isinstance(node, ast.Invocation) and node.name.text == name:
            found = model.binding(node)
            assert found is not None
            return found
    raise AssertionError(name)


def test_positional_and_named_arguments_are_one_table_with_defaults_marked():
    model, tree = _model()
    speed = _binding(model, tree, "speed")
    assert speed.callee.name == "speed"
    assert speed.given("speed") is not None and speed.given("speed").positional
    assert speed.given("at") is not None and not speed.given("at").positional
    at = speed.argument("at")
    assert at is not None and isinstance(at.value, ast.NameRef) and not at.is_default
    lane = _binding(model, tree, "lane")
    assert lane.given("lane") is not None and lane.given("lane").positional
    assert lane.given("side_of") is not None
    defaulted = lane.argument("at")
    assert defaulted is not None and defaulted.is_default
    assert defaulted.value is defaulted.parameter.default


def test_a_range_given_for_a_scalar_is_marked():
    model, tree = _model()
    speed = _binding(model, tree, "speed")
    assert [b.name for b in speed.ranges] == ["speed"]
    assert not _binding(model, tree, "lane").ranges


def test_extras_until_and_compositions():
    model, tree = _model()
    drive = _binding(model, tree, "drive")
    assert len(drive.until) == 1
    comp = next(n for n in walk(tree) if isinstance(n, ast.Composition) and n.op == "parallel")
    binding = model.binding(comp)
    assert binding is not None
    assert {b.name for b in binding.extras} == {"overlap", "duration"}
    assert isinstance(binding.value("duration"), ast.RangeLiteral)


def test_emit_method_and_builtin_calls_are_bound():
    model, tree = _model()
    emit = next(n for n in walk(tree) if isinstance(n, ast.Emit))
    binding = model.binding(emit)
    assert binding is not None
    assert binding.given("distance") is not None
    assert binding.argument("urgent") is not None and binding.argument("urgent").is_default
    calls = {
        n.callee.name.name.text: model.binding(n)
        for n in walk(tree)
        if isinstance(n, ast.Call) and isinstance(n.callee, ast.NameRef)
    }
    every = calls["every"]
    assert every is not None and isinstance(every.callee, Builtin)
    assert [b.name for b in every.arguments] == ["period", "offset"]
    twice = calls["twice"]
    assert twice is not None and twice.argument("scale").is_default


def test_every_written_argument_is_bound_or_rejected():
    """No argument of a resolved call is lost: each is bound to one parameter, or is in
    the binding's rejected ones (the checker reported it)."""
    text = TEXT.replace("lane(1, side: left, side_of: ego)", "lane(1, nope: 1, 2)")
    analysis = analyze([SourceInput("t.osc", text)])
    program = analysis.programs["t.osc"]
    tree = program.files["t.osc"].ast
    lane = _binding(program.model, tree, "lane")
    node = lane.node
    assert isinstance(node, ast.Invocation)
    for arg in node.arguments:
        assert (lane.parameter_of(arg) is not None) != any(arg is r for r in lane.rejected)
    assert len(lane.rejected) == 2


def test_cover_items_are_read_once():
    model, tree = _model()
    top = next(s for s in model.symbols if s.name == "top")
    items = model.cover_items_of(top)
    assert [(i.kind, i.name) for i in items] == [("cover", "gap"), ("record", "passing")]
    gap, passing = items
    assert isinstance(gap.expression, ast.NameRef) and gap.has("range")
    assert isinstance(gap.get("unit"), ast.NameRef)
    assert isinstance(passing.expression, ast.Binary)
    assert model.cover_item(gap.decl) is gap
