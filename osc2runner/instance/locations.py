"""``stationary_object.location(pose: p)``: where a static object stands for the whole run.

The modifier is a member of the scenario (``box.location(pose: here)``). Its
``pose`` is a ``pose_3d`` parameter of the scenario, whose value is the
witness's (``instance.values``); the world builds the object there, at the
pose's world ``x``, ``y`` and yaw (the world is flat: ``z``, roll and pitch are
not used). A pose that is not a parameter of the scenario is an error before the
run, at the argument.
"""

from __future__ import annotations

from osc2check.semantics.constants import NotConstant
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2runner.errors import RunProblem
from osc2runner.instance.values import ScenarioValues

__all__ = ["object_locations"]


def object_locations(
    model: Model, scenario: Symbol, values: ScenarioValues
) -> tuple[dict[str, tuple[float, float, float]], list[RunProblem]]:
    """``actor name -> (x, y, yaw)`` of every ``location`` member of the scenario."""
    found: dict[str, tuple[float, float, float]] = {}
    problems: list[RunProblem] = []
    decl = scenario.decl
    if not isinstance(decl, ast.StructuredDecl):
        return found, problems
    for member in decl.members:
        if not isinstance(member, ast.Invocation) or member.name.text != "location":
            continue
        if not isinstance(member.actor, ast.NameRef) or not member.arguments:
            continue
        first = member.arguments[0]
        value = None if isinstance(first, ast.EventArgument) else first.value
        pose = _pose(model, values, value)
        if pose is None:
            problems.append(
                RunProblem(
                    "`location(pose: ...)` needs a pose_3d parameter of the scenario",
                    value.span if value is not None else member.span,
                )
            )
            continue
        found[member.actor.name.name.text] = pose
    return found, problems


def _pose(
    model: Model, values: ScenarioValues, value: ast.Node | None
) -> tuple[float, float, float] | None:
    if not isinstance(value, ast.NameRef):
        return None
    sym = model.references.get(value.name.name)
    if sym is None or sym.kind is not SymbolKind.FIELD:
        return None
    try:
        pose = values.value(sym)
        position, orientation = pose.position, pose.orientation  # type: ignore[union-attr]
        return (float(position.x), float(position.y), float(orientation.yaw))
    except (NotConstant, AttributeError):
        return None
