"""CARLA's forms in scenarios: what each means in standard OSC2 (see
:mod:`osc2check.dialects.carla`; the library forms are there).

Each rule edits the text of one form and reports it with its own D code.
Names that a rule gives another meaning (an actor alias, CARLA's speed strings)
are substituted in one last pass, so that rules that rewrite a larger piece of
text (a ``wait``) write those names already substituted.
"""

from __future__ import annotations

from collections.abc import Iterator

from osc2check import messages
from osc2check.dialects.carla_text import CARLA_TYPE_NAMES, CarlaText, Field
from osc2check.semantics.phases import time_zero
from osc2check.syntax import ast
from osc2check.syntax.walk import walk

__all__ = ["CARLA_MODELS", "behaviour_forms"]

#: CARLA's vehicle classes, the actor types of the toolkit's CARLA world
CARLA_MODELS = frozenset({"Car", "Model3", "Mkz2017", "Carlacola", "Rubicon"})
#: the actor types whose fields are actors (CARLA's and the standard's)
_ACTOR_TYPES = CARLA_MODELS | {"vehicle", "person", "physical_object", "movable_object"}
#: enum members CARLA's examples declare as events or globals for its parser
_MEMBER_NAMES = frozenset({"start", "end", "left", "right"})
_PATH_MODIFIERS = ("path_min_driving_lanes", "path_over_junction")


def behaviour_forms(text: CarlaText) -> None:
    """Apply every scenario-level rule to the file (see the module docstring)."""
    substitutions: dict[int, dict[str, str]] = {}
    globals_ = text.globals()
    _unused_names(text, None, globals_)
    for scenario in text.scenarios():  # first what is left out, then what is rewritten
        names = substitutions.setdefault(id(scenario), {})
        _aliases(text, scenario, names)
        _speed_names(text, scenario, names)
        _unused_names(text, scenario, globals_)
    _type_names(text)
    _static_methods(text)
    _external_python(text)
    for scenario in text.scenarios():
        names = substitutions[id(scenario)]
        _path(text, scenario, globals_)
        _drive_distance(text, scenario, names)
        _elapsed_ranges(text, scenario)
        durations = _phase_durations(scenario)
        for node in walk(scenario):
            if isinstance(node, ast.Invocation):
                fields = CarlaText.fields(scenario)
                _invocation(text, node, globals_, fields, durations.get(id(node)))
    _scenarios_of_dut(text)
    for scenario in text.scenarios():
        _substitute(text, scenario, substitutions[id(scenario)])
    for scenario in text.scenarios():  # last: it moves text that other rules edited
        _start_placements(text, scenario)


# ---- types --------------------------------------------------------------------------


def _type_names(text: CarlaText) -> None:
    """CARLA's ``velocity`` is the standard's ``speed`` and its ``Path`` the ``map``
    (D813, D815), where the file does not declare such a type itself."""
    declared = {
        d.name.text if isinstance(d, ast.PhysicalTypeDecl) else str(d.name)
        for d in text.file.declarations
        if isinstance(d, ast.PhysicalTypeDecl | ast.StructDecl | ast.ActorDecl)
        and not text.removed(d.span)
    }
    for node in walk(text.file):
        if not isinstance(node, ast.NamedType) or text.removed(node.span):
            continue
        name = node.name.name.text
        if name in CARLA_TYPE_NAMES and name not in declared and node.name.namespace is None:
            text.replace(node.name.span, CARLA_TYPE_NAMES[name])
            if name == "velocity":
                text.report(messages.carla_velocity(node.span))
            else:
                text.report(messages.carla_path(node.span, "type"))
    for decl in text.file.declarations:
        if isinstance(decl, ast.UnitDecl) and not text.removed(decl.span):
            name = decl.type.name.text
            if name == "velocity" and name not in declared:
                text.replace(decl.type.span, "speed")
                text.report(messages.carla_velocity(decl.type.span))


# ---- scenarios declared on CARLA's `dut` -------------------------------------------------


def _scenarios_of_dut(text: CarlaText) -> None:
    """``scenario dut.x`` invoked as ``dut.x()``: an unassociated scenario whose actor
    fields are the invoking scenario's actors of the same names (D820)."""
    scenarios = list(text.scenarios())
    of_dut = {
        s.name.name.text: s
        for s in scenarios
        if s.name.actor is not None and s.name.actor.name.text == "dut"
    }
    if not of_dut:
        return
    callers: dict[str, list[ast.ScenarioDecl]] = {name: [] for name in of_dut}
    invocations: list[tuple[ast.Invocation, ast.ScenarioDecl]] = []
    for scenario in scenarios:
        for node in walk(scenario):
            if (
                isinstance(node, ast.Invocation)
                and isinstance(node.actor, ast.NameRef)
                and node.actor.name.name.text == "dut"
                and node.name.text in of_dut
                and "dut" not in CarlaText.fields(scenario)
            ):
                invocations.append((node, scenario))
                callers[node.name.text].append(scenario)
    top = next((s for s in scenarios if str(s.name) == "top"), None)
    shared: dict[str, list[Field]] = {}
    for name, scenario in of_dut.items():
        text.replace(scenario.name.span, name)
        text.report(messages.carla_scenario_of_dut(scenario.name.span, name))
        actors = _actor_fields(callers[name] or ([top] if top is not None else []))
        own = CarlaText.fields(scenario)
        used = {ref.name.name.text for ref in _refs(scenario)}
        missing = [f for n, f in actors.items() if n in used and n not in own]
        if missing:
            first = next((m for m in scenario.members), None)
            at = text.line_start(first.span.start) if first is not None else scenario.span.end
            indent = text.indent(first.span.start) if first is not None else "    "
            text.insert(at, "".join(f"{indent}{f.name}: {f.type}\n" for f in missing))
        shared[name] = [f for n, f in actors.items() if n in own or n in used]
    for inv, caller in invocations:
        own_actors = _actor_fields([caller])
        args = [f"{f.name}: {f.name}" for f in shared[inv.name.text] if f.name in own_actors]
        args += [text.source(a) for a in inv.arguments]
        assert inv.actor is not None  # as chosen above
        head_end = _arguments_end(text, inv)
        text.replace_between(inv.actor.span.start, head_end, f"{inv.name.text}({', '.join(args)})")
        text.report(messages.carla_scenario_of_dut(inv.span, inv.name.text, shared=args))


def _actor_fields(scenarios: list[ast.ScenarioDecl]) -> dict[str, Field]:
    found: dict[str, Field] = {}
    for scenario in scenarios:
        for name, f in CarlaText.fields(scenario).items():
            if f.type in _ACTOR_TYPES and f.default is None:
                found.setdefault(name, f)
    return found


def _refs(node: ast.Node) -> Iterator[ast.NameRef]:
    for n in walk(node):
        if isinstance(n, ast.NameRef) and n.name.namespace is None:
            yield n
        elif isinstance(n, ast.Invocation) and isinstance(n.actor, ast.NameRef):
            continue


def _arguments_end(text: CarlaText, inv: ast.Invocation) -> int:
    """The offset just past the closing parenthesis of an invocation's arguments."""
    start = inv.arguments[-1].span.end if inv.arguments else inv.name.span.end
    return text.text.index(")", start) + 1


# ---- fields that name something else ------------------------------------------------------


def _aliases(text: CarlaText, scenario: ast.ScenarioDecl, names: dict[str, str]) -> None:
    """``other_car: Rubicon = npc``: CARLA's name for the actor ``npc`` (D822)."""
    fields = CarlaText.fields(scenario)
    for name, f in fields.items():
        if (
            f.type in _ACTOR_TYPES
            and isinstance(f.default, ast.NameRef)
            and f.default.name.name.text in fields
            and len(f.decl.names) == 1
        ):
            target = f.default.name.name.text
            names[name] = names.get(target, target)
            text.comment_out(f.decl.span)
            text.report(messages.carla_actor_alias(f.decl.names[0].span, name, target))


def _speed_names(text: CarlaText, scenario: ast.ScenarioDecl, names: dict[str, str]) -> None:
    """``x: velocity = "ego_vehicle_speed"``: CARLA reads the string as the speed of the
    actor it begins with (D823)."""
    fields = CarlaText.fields(scenario)
    actors = sorted((n for n, f in fields.items() if f.type in _ACTOR_TYPES), key=len)
    for name, f in fields.items():
        if not isinstance(f.default, ast.StringLiteral) or f.type not in ("velocity", "speed"):
            continue
        owner = next((a for a in reversed(actors) if f.default.value.startswith(a)), None)
        if owner is None or len(f.decl.names) != 1:
            continue
        names[name] = f"{owner}.speed"
        text.comment_out(f.decl.span)
        text.report(messages.carla_speed_name(f.decl.span, name, f.default.value, owner))


def _substitute(text: CarlaText, scenario: ast.ScenarioDecl, names: dict[str, str]) -> None:
    for ref in _refs(scenario):
        new = names.get(ref.name.name.text)
        if new is not None and not text.removed(ref.span) and not text.claimed(ref.span):
            text.replace(ref.span, new)


def rendered(text: CarlaText, node: ast.Node, names: dict[str, str]) -> str:
    """The source of ``node`` with ``names`` substituted."""
    refs = sorted((r for r in _refs(node) if r.name.name.text in names), key=lambda r: r.span.start)
    out, last = [], node.span.start
    for ref in refs:
        out += [text.text[last : ref.span.start], names[ref.name.name.text]]
        last = ref.span.end
    out.append(text.text[last : node.span.end])
    return "".join(out)


# ---- CARLA's Path ------------------------------------------------------------------------


def _path(text: CarlaText, scenario: ast.ScenarioDecl, globals_: dict[str, Field]) -> None:
    """``path.set_map(m)`` -> ``path.set_map_file(m)`` (D815); the path conditions
    ``path_min_driving_lanes`` and ``path_over_junction`` apply to the path (D816);
    written without it, they apply to the scenario's path, declared where there is none."""
    fields = CarlaText.fields(scenario)
    visible = {**globals_, **fields}
    path = next((n for n, f in visible.items() if f.type == "Path"), None)
    for member in scenario.members:
        if not isinstance(member, ast.Invocation) or text.removed(member.span):
            continue
        name = member.name.text
        if name not in ("set_map", *_PATH_MODIFIERS):
            continue
        head = f"{text.source(member.actor)}." if member.actor is not None else ""
        if member.actor is None and path is None:
            path = "path" if "path" not in visible else "carla_path"
            indent = text.indent(member.span.start)
            head = f"{path}: map\n{indent}{path}."
        elif member.actor is None:
            head = f"{path}."
        new_name = "set_map_file" if name == "set_map" else name
        start = member.actor.span.start if member.actor is not None else member.name.span.start
        text.replace_between(start, member.name.span.end, f"{head}{new_name}")
        if name == "set_map":
            text.report(messages.carla_path(member.name.span, "set_map"))
        else:
            text.report(messages.carla_path_condition(member.name.span, name))


# ---- invocations and modifiers --------------------------------------------------------------


def _phase_durations(scenario: ast.ScenarioDecl) -> dict[int, ast.Expr]:
    """The ``drive`` invocations directly in a composition with a ``duration`` and none of
    their own, by id, with that duration: CARLA gives each behaviour of a composition the
    composition's duration (its timeout; srunner/scenarios/osc2_scenario.py)."""
    found: dict[int, ast.Expr] = {}
    for node in walk(scenario):
        if not isinstance(node, ast.Composition):
            continue
        duration = next(
            (
                a.value
                for a in node.arguments
                if isinstance(a, ast.NamedArgument) and a.name.text == "duration"
            ),
            None,
        )
        for member in node.members if duration is not None else ():
            inv = member.body
            if (
                isinstance(inv, ast.Invocation)
                and inv.name.text == "drive"
                and not any(
                    isinstance(a, ast.NamedArgument) and a.name.text == "duration"
                    for a in inv.arguments
                )
            ):
                found[id(inv)] = duration  # type: ignore[assignment]  # set above
    return found


def _invocation(
    text: CarlaText,
    inv: ast.Invocation,
    globals_: dict[str, Field],
    fields: dict[str, Field],
    duration: ast.Expr | None,
) -> None:
    if text.removed(inv.span) or text.claimed(inv.span):
        return
    visible = {**globals_, **fields}
    name = inv.name.text
    if name == "drive":
        _drive(text, inv, visible, duration)
    elif name == "lane":
        _lane(text, inv)
    elif name == "change_lane":
        _renamed(text, inv, "lane_changes", "lane", messages.carla_lane_changes)
    elif name == "set_position":
        text.report(messages.carla_world_pose(inv.name.span))
    elif name == "follow_trajectory" and _named(inv, "input_file") is not None:
        text.report(messages.carla_trajectory_file(inv.name.span))


def _named(inv: ast.Invocation, name: str) -> ast.NamedArgument | None:
    return next(
        (a for a in inv.arguments if isinstance(a, ast.NamedArgument) and a.name.text == name),
        None,
    )


def _drive(
    text: CarlaText, inv: ast.Invocation, visible: dict[str, Field], duration: ast.Expr | None
) -> None:
    """``drive(path)``, ``drive(path, adjust: true)``: CARLA's path is the map's road the
    actors are placed on, and ``adjust`` CARLA ignores (D817). Directly in a composition
    with a duration, the drive lasts that duration, as in CARLA (D831)."""
    dropped = [
        a
        for a in inv.arguments
        if (
            isinstance(a, ast.PositionalArgument)
            and isinstance(a.value, ast.NameRef)
            and visible.get(a.value.name.name.text, None) is not None
            and visible[a.value.name.name.text].type == "Path"
        )
        or (isinstance(a, ast.NamedArgument) and a.name.text == "adjust")
    ]
    if not dropped and duration is None:
        return
    kept = [text.source(a) for a in inv.arguments if a not in dropped]
    if duration is not None:
        kept.append(f"duration: {text.source(duration)}")
        text.report(messages.carla_phase_duration(inv.name.span, text.source(duration)))
    if dropped:
        span = dropped[0].span.cover(dropped[-1].span)
        text.report(messages.carla_drive_path(span, [text.source(a) for a in dropped]))
    if inv.arguments:
        start, end = inv.arguments[0].span.start, inv.arguments[-1].span.end
    else:
        start = end = text.text.index("(", inv.name.span.end) + 1
    text.replace_between(start, end, ", ".join(kept))


def _lane(text: CarlaText, inv: ast.Invocation) -> None:
    """``lane(1)``: CARLA counts lanes from the left (D818); ``lane(right_of: x)`` is
    ``lane(side_of: x, side: right)`` (D807)."""
    for side in ("left_of", "right_of"):
        arg = _named(inv, side)
        if arg is not None:
            word = side.removesuffix("_of")
            text.replace(arg.span, f"side_of: {text.source(arg.value)}, side: {word}")
            text.report(messages.carla_lane_side(arg.name.span, side, word))
    relative = any(_named(inv, n) for n in ("same_as", "side_of", "left_of", "right_of"))
    number: ast.Argument | None = next(
        (a for a in inv.arguments if isinstance(a, ast.PositionalArgument)), None
    )
    number = number or _named(inv, "lane")
    if number is None or relative or _named(inv, "from") is not None:
        return
    text.insert(number.span.end, ", from: left")
    text.report(messages.carla_lane_numbering(number.span))


def _renamed(text: CarlaText, inv: ast.Invocation, old: str, new: str, message: object) -> None:
    arg = _named(inv, old)
    if arg is None:
        return
    text.replace(arg.name.span, new)
    text.report(message(arg.name.span))  # type: ignore[operator]


# ---- events, globals, waits -----------------------------------------------------------------


def _unused_names(
    text: CarlaText, scenario: ast.ScenarioDecl | None, globals_: dict[str, Field]
) -> None:
    """``event start``, ``event left``, ``global start: string``: CARLA's parser wants them,
    nothing uses them, and they would hide the enum members of their names (D821)."""
    if scenario is None:
        for name, f in globals_.items():
            if name in _MEMBER_NAMES and not _used(text.file, name):
                text.comment_out(f.decl.span)
                text.report(messages.carla_unused_name(f.decl.names[0].span, "global", name))
        return
    for member in scenario.members:
        if (
            isinstance(member, ast.EventDecl)
            and member.name.text in _MEMBER_NAMES
            and not member.parameters
            and member.spec is None
            and not _used(scenario, member.name.text)
        ):
            text.comment_out(member.span)
            text.report(messages.carla_unused_name(member.name.span, "event", member.name.text))


def _used(node: ast.Node, name: str) -> bool:
    """Whether ``name`` is used below ``node`` other than as an enum member (the value of
    ``at:``, ``side:`` or ``from:``), an event waited for or emitted."""
    enum_values = {
        id(a.value)
        for n in walk(node)
        if isinstance(n, ast.Invocation)
        for a in n.arguments
        if isinstance(a, ast.NamedArgument) and a.name.text in ("at", "side", "from")
    }
    for n in walk(node):
        if isinstance(n, ast.NameRef) and n.name.name.text == name and id(n) not in enum_values:
            return True
        if isinstance(n, ast.EventReference) and n.path and n.path[-1].text == name:
            return True
        if isinstance(n, ast.Emit) and n.event.text == name:
            return True
    return False


def _drive_distance(text: CarlaText, scenario: ast.ScenarioDecl, names: dict[str, str]) -> None:
    """``wait @drive_distance if c``: CARLA's hard-wired event (srunner/osc2_stdlib/
    event.py) waits for ``c`` and then for its ``other_car`` to drive ``distance`` (D824)."""
    event = next(
        (
            m
            for m in scenario.members
            if isinstance(m, ast.EventDecl) and m.name.text == "drive_distance" and m.spec is None
        ),
        None,
    )
    if event is None:
        return
    defaults = {p.name.text: p.default for p in event.parameters}
    car, distance = defaults.get("other_car"), defaults.get("distance")
    if car is None or distance is None:
        return
    for node in walk(scenario):
        if not isinstance(node, ast.Composition) or node.op != "serial":
            continue
        for member in node.members:
            wait = member.body
            if not (
                isinstance(wait, ast.Wait)
                and isinstance(wait.event, ast.EventReference)
                and [n.text for n in wait.event.path] == ["drive_distance"]
            ):
                continue
            indent = text.indent(member.span.start)
            lines = []
            if wait.event.condition is not None:
                lines.append(f"wait {rendered(text, wait.event.condition, names)}")
            lines.append(f"{rendered(text, car, names)}.drive() with:")
            lines.append(f"    distance({rendered(text, distance, names)})")
            text.replace(wait.span, f"\n{indent}".join(lines))
            text.claim(wait.span)
            text.report(messages.carla_drive_distance(wait.event.span))
    text.comment_out(event.span)


def _elapsed_ranges(text: CarlaText, scenario: ast.ScenarioDecl) -> None:
    """``wait elapsed([10s..20s])``: CARLA waits a time drawn from the range; the standard
    way is a parameter kept in the range (D825)."""
    do = next((m for m in scenario.members if isinstance(m, ast.DoDirective)), None)
    if do is None:
        return
    count = 0
    for node in walk(do):
        if not isinstance(node, ast.DoMember) or not isinstance(node.body, ast.Wait):
            continue
        condition = node.body.event
        if not isinstance(condition, ast.EventCondition):
            continue
        call = condition.expr
        if not (
            isinstance(call, ast.Call)
            and isinstance(call.callee, ast.NameRef)
            and call.callee.name.name.text == "elapsed"
            and len(call.arguments) == 1
            and isinstance(call.arguments[0], ast.PositionalArgument)
            and isinstance(call.arguments[0].value, ast.RangeLiteral)
        ):
            continue
        count += 1
        label = node.label.text if node.label is not None else f"wait{count}"
        name = f"{label}_time"
        bounds = call.arguments[0].value
        indent = text.indent(do.span.start)
        text.insert(
            text.line_start(do.span.start),
            f"{indent}{name}: time with:\n{indent}    keep(it in {text.source(bounds)})\n",
        )
        text.replace(bounds.span, name)
        text.report(messages.carla_elapsed_range(bounds.span, name))


# ---- methods -------------------------------------------------------------------------------


def _static_methods(text: CarlaText) -> None:
    """``speeds.compute(x: 2, y: 3)``: a method called on its struct's name. The standard
    calls a method on a value: the scenario's field of that struct, declared where there is
    none; a call as a scenario member (evaluated, its value dropped) is left out (D826)."""
    structs = {str(d.name) for d in text.file.declarations if isinstance(d, ast.StructDecl)}
    if not structs:
        return
    for scenario in text.scenarios():
        fields = CarlaText.fields(scenario)
        instances = {f.type: n for n, f in fields.items() if f.type in structs}
        added: list[str] = []
        for member in scenario.members:
            if (
                isinstance(member, ast.Invocation)
                and isinstance(member.actor, ast.NameRef)
                and member.actor.name.name.text in structs
                and member.actor.name.name.text not in fields
            ):
                text.comment_out(member.span)
                text.report(messages.carla_static_method(member.span, str(member.name.text), True))
        for node in walk(scenario):
            if not (
                isinstance(node, ast.Call)
                and isinstance(node.callee, ast.MemberAccess)
                and isinstance(node.callee.target, ast.NameRef)
                and node.callee.target.name.name.text in structs
                and node.callee.target.name.name.text not in fields
            ) or text.removed(node.span):
                continue
            struct = node.callee.target.name.name.text
            instance = instances.get(struct)
            if instance is None:
                instance = instances[struct] = f"carla_{struct}"
                added.append(f"{instance}: {struct}")
            text.replace(node.callee.target.span, instance)
            text.report(messages.carla_static_method(node.span, node.callee.member.text, False))
        if added:
            first = scenario.members[0]
            indent = text.indent(first.span.start)
            text.insert(text.line_start(first.span.start), "".join(f"{indent}{a}\n" for a in added))


def _external_python(text: CarlaText) -> None:
    """``is external python(module: "math", name: "sin", param: x)`` is CARLA's Python call
    ``math.sin(x)``: the standard's ``is external math.sin(x)`` (D827)."""
    for node in walk(text.file):
        if not (
            isinstance(node, ast.MethodDecl)
            and node.kind == "external"
            and [n.text for n in node.external] == ["python"]
        ):
            continue
        given = {
            a.name.text: a.value
            for a in node.external_arguments
            if isinstance(a, ast.NamedArgument)
        }
        module, name = given.get("module"), given.get("name")
        if not isinstance(module, ast.StringLiteral) or not isinstance(name, ast.StringLiteral):
            continue
        rest = [
            text.source(a.value) if isinstance(a, ast.NamedArgument) else text.source(a)
            for a in node.external_arguments
            if not (isinstance(a, ast.NamedArgument) and a.name.text in ("module", "name"))
        ]
        start = node.external[0].span.start
        end = text.text.index(")", node.external_arguments[-1].span.end) + 1
        target = f"{module.value}.{name.value}"
        text.replace_between(start, end, f"{target}({', '.join(rest)})")
        span = node.external[0].span.cover(node.external_arguments[-1].span)
        text.report(messages.carla_external_python(span, target))


# ---- `at: start` after time 0 -------------------------------------------------------------

_PLACING = ("lane", "position")


def _start_placements(text: CarlaText, scenario: ast.ScenarioDecl) -> None:
    """``npc.drive() with: lane(..., at: start)`` in a phase that is not known to begin
    at time 0 (a later phase, a ``one_of`` member): CARLA sets the actor's transform there
    when the phase starts (scenario_runner's ActorTransformSetter). Read as the standard's
    exact ``assign_position`` with those modifiers, then the invocation (D832). At time 0
    the checker's placement puts the actors there already."""
    do = next((m for m in scenario.members if isinstance(m, ast.DoDirective)), None)
    if do is None:
        return
    zero = time_zero(do.member.body)
    at_zero = {id(inv) for inv in zero.starts}
    for node in walk(do):
        if (
            not isinstance(node, ast.Invocation)
            or id(node) in at_zero
            or node.actor is None
            or text.removed(node.span)
        ):
            continue
        placing = [m for m in node.with_members if _places_at_start(m)]
        if not placing:
            continue
        rest = [m for m in node.with_members if m not in placing]
        indent = text.indent(node.span.start)
        inner, deeper = indent + "    ", indent + "        "
        actor = text.edited(node.actor.span)
        head_end = _arguments_end(text, node)
        lines = [
            "serial:",
            f"{inner}{actor}.assign_position() with:",
            *(f"{deeper}{text.edited(m.span)}" for m in placing),
            f"{inner}{text.edited_between(node.span.start, head_end)}" + (" with:" if rest else ""),
            *(f"{deeper}{text.edited(m.span)}" for m in rest),
        ]
        text.rewrite(node.span, "\n".join(lines))
        text.report(messages.carla_start_placement(placing[0].span, actor))


def _places_at_start(member: ast.Node) -> bool:
    return (
        isinstance(member, ast.Invocation)
        and member.name.text in _PLACING
        and any(
            isinstance(a, ast.NamedArgument)
            and a.name.text == "at"
            and isinstance(a.value, ast.NameRef | ast.EnumRef)
            and (
                a.value.name.name.text if isinstance(a.value, ast.NameRef) else a.value.member.text
            )
            == "start"
            for a in member.arguments
        )
    )
