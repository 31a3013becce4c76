"""What ``osc2run`` executes: one table for the checker, the runner and ``docs/coverage.md``.

Everything the bundled library declares runs, except what this table lists:

* ``NOT_EXECUTED``: actions, modifiers and ``is undefined`` methods the runner has
  no implementation of (``owner.name``), each with the reason;
* ``FORMS``: argument forms and placements of otherwise executed calls that the
  runner does not carry out (``parallel(start_to_start: ...)``, a modifier on a
  composition, ``orientation(measured_by: absolute)``, ...).

The checker reports each use as A308 (``not_executed``, a warning by default, so
the editor shows it); the runner refuses a file with such a finding before tick 0
with the same code and message, and never meets one of these forms otherwise. The
runner's registry is tested against ``NOT_EXECUTED`` (each library entry either
has an implementation or is listed here, never both), and ``docs/coverage.md``
is generated from both.

Behaviours of the user's own libraries (an ``action``, a ``modifier``, a method
``is undefined``) run when a plug-in implements them (:mod:`osc2check.plugins`):
each call of one that no loaded plug-in implements is A308 too.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.plugins import Implementation, PluginRegistry
from osc2check.semantics import types as T
from osc2check.semantics.members import MemberList, declaration_bodies
from osc2check.semantics.model import Model
from osc2check.semantics.phases import enum_word, modifier_timing
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.syntax.walk import walk

__all__ = [
    "BODY_TYPES",
    "FORMS",
    "NOT_EXECUTED",
    "TRAILER_ACTIONS",
    "Form",
    "absent_reason",
    "label_of",
    "not_executed",
    "plugin_of",
]

_NO_PLUGIN = "no plug-in implements it (docs/plugins.md: --plugin, plugins in [tool.osc2check])"
_CARLA_WORLD = (
    "it needs CARLA's world coordinates of the map, which its built-in stand-ins do not have"
)

#: The library's actions, modifiers and ``is undefined`` methods the runner does not
#: execute (``owner.name``), and why.
NOT_EXECUTED: dict[str, str] = {
    "physical_object.set_bm": (
        "behavioural models are implementation-defined (and gone in DSL 2.2): each actor "
        "kind has one driver model"
    ),
    # CARLA's world (osc2toolkit.carla): the poses and trajectory files of CARLA's maps
    "vehicle.set_position": _CARLA_WORLD,
    "follow_trajectory": _CARLA_WORLD,
}


@dataclass(frozen=True, slots=True)
class Form:
    """A form of an executed call that the runner does not carry out."""

    key: str
    written: str  # how it looks (``parallel(start_to_start: ...)``), as messages show it
    reason: str


#: The forms of calls the runner does not carry out, by key.
FORMS: dict[str, Form] = {
    f.key: f
    for f in (
        Form(
            "start_to_start",
            "`parallel(start_to_start: ...)`",
            "the runner starts every member of a `parallel` with the composition",
        ),
        Form(
            "end_to_end",
            "`parallel(end_to_end: ...)`",
            "the runner starts every member of a `parallel` with the composition",
        ),
        Form(
            "composition_modifier",
            "a modifier of a composition",
            "the runner applies modifiers to actions only; put it on the actions inside",
        ),
        Form(
            "scenario_modifier",
            "a modifier of a scenario invocation",
            "the runner applies modifiers to actions only; put it on the scenario's actions",
        ),
        Form(
            "modifier_with",
            "a `with:` block of a modifier",
            "a modifier's own constraints are not applied by the runner",
        ),
        Form(
            "invoked_coverage",
            "`cover`/`record` of an invoked scenario",
            "the runner collects the coverage items of the root scenario only",
        ),
        Form(
            "event_argument",
            "an event argument of an action or modifier",
            "actions and modifiers take values, not events",
        ),
        Form(
            "yaw_relative_to",
            "`yaw(relative_to: ...)`",
            "a heading relative to another actor is not executed: give it from the road",
        ),
        Form(
            "orientation_relative_to",
            "`orientation(relative_to: ...)`",
            "a heading relative to another actor is not executed: give it from the road",
        ),
        Form(
            "heading_frame",
            "a heading measured other than `relative_to_road`",
            "headings are executed from the road's direction (`relative_to_road`) only",
        ),
        Form(
            "pitch_roll",
            "`orientation(pitch: ..., roll: ...)`",
            "the world is flat: pitch and roll are 0",
        ),
        Form(
            "vehicle_heading",
            "`yaw`/`orientation` of a vehicle at `end` or `all`",
            "the runner steers vehicles along their lanes or path: give the heading `at: start`",
        ),
        Form(
            "trailer_action",
            "an action of a trailer other than "
            + " and ".join(f"`{a}`" for a in ("assign_position", "assign_orientation")),
            "a trailer has no engine or driver: it moves when a vehicle tows it "
            "(`connect_trailer`)",
        ),
        Form(
            "bodiless_actor",
            "an action of an actor that is no vehicle, person or animal",
            "the world builds a body for vehicles, persons, animals and stationary objects "
            "only: give the actor one of those types",
        ),
        Form(
            "track_projected",
            "`track: projected`",
            "a reference's motion is followed as it is (`track: actual`); extrapolating it "
            "from the phase's start is not executed",
        ),
        Form(
            "modifier_shape",
            "a movement modifier's `shape`",
            "shapes (`any_shape`) are not followed: the runner's profiles shape each change",
        ),
        Form(
            "relative_acceleration",
            "`acceleration(faster_than|slower_than|same_as: ...)`",
            "an acceleration relative to another actor's is not executed: give it absolute",
        ),
        Form(
            "change_at_start",
            "`change_speed`, `change_lane`, `distance` or `acceleration` `at: start`",
            "each is about the motion during its phase, and the world starts every actor at "
            "a steady speed in its lane: leave `at` out or give `end`",
        ),
        Form(
            "invoked_actor_field",
            "an actor field of an invoked scenario that the invocation does not pass",
            "the runner builds the actors of the scenario it runs: pass each actor field of "
            "the invoked scenario as an argument (`ego: hero`)",
        ),
        Form(
            "position_along_road",
            "`position(...)` without `ahead_of` or `behind`, other than a distance `at: start`",
            "a distance along the road places an actor when the scenario starts (or checks "
            "it when a later phase starts); a time headway needs the actor it is measured to",
        ),
    )
}

#: the actions a trailer takes (it has no engine or driver); the runner refuses others
TRAILER_ACTIONS = ("assign_position", "assign_orientation")
#: the library actor types whose actors the world builds a body for (their subtypes too)
BODY_TYPES = ("vehicle", "person", "animal", "stationary_object")
#: the reference parameters of `acceleration`, which the runner does not execute
_RELATIVE = ("faster_than", "slower_than", "same_as")
#: the modifiers of a change over the phase (no constraint at an instant)
_CHANGES = ("change_speed", "change_lane", "distance", "acceleration")


def absent_reason(label: str) -> str:
    """Why the library's ``label`` (``owner.name``) is not executed ('' when it is)."""
    return NOT_EXECUTED.get(label, "")


def label_of(symbol: Symbol) -> str:
    """``owner.name`` of a library action, modifier or method (the table's key; ``name``
    of one without an owner)."""
    owner = symbol.owner if symbol.kind is SymbolKind.METHOD else symbol.actor
    return f"{owner.name}.{symbol.name}" if owner is not None else symbol.name


def not_executed(
    model: Model,
    scenario: Symbol,
    invoked: bool,
    plugins: PluginRegistry | None = None,
    bodies: Mapping[Symbol, Sequence[MemberList]] | None = None,
) -> list[Diagnostic]:
    """A308 for each call of ``scenario``'s own members that the runner does not execute
    (``invoked``: the scenario is invoked by another, whose run collects no coverage of
    it; ``plugins``: the plug-ins loaded, which implement behaviours of the user's
    libraries). ``bodies``: ``declaration_bodies(model)``, when the caller has it (a
    file's scenarios share it: made once per scenario, it is quadratic in the file's
    size)."""
    found: list[Diagnostic] = []
    registry = plugins if plugins is not None else PluginRegistry()
    if bodies is None:
        bodies = declaration_bodies(model)
    for members in bodies.get(scenario, ()):
        for member in members:
            if invoked and isinstance(member, ast.CoverageDecl):
                _form(found, member.span, "invoked_coverage")
            for node in walk(member):
                _node(model, node, found, registry)
    found.sort(key=lambda d: d.sort_key)
    return found


def _form(found: list[Diagnostic], span: Span, key: str) -> None:
    form = FORMS[key]
    found.append(messages.not_executed(span, form.written, form.reason))


def _node(model: Model, node: ast.Node, found: list[Diagnostic], plugins: PluginRegistry) -> None:
    binding = model.binding(node)
    if isinstance(node, ast.Composition):
        for key in ("start_to_start", "end_to_end"):
            given = binding.extra(key) if binding is not None else None
            if given is not None:
                _form(found, given.span, key)
        for item in node.with_members:
            if isinstance(item, ast.Invocation):
                _form(found, item.span, "composition_modifier")
        return
    if isinstance(node, ast.Call):
        method = binding.callee if binding is not None else None
        if isinstance(method, Symbol) and _undefined(method):
            # a library method the runner lacks (set_bm), or a program's without a plug-in
            _implemented(model, method, node.callee.span, found, plugins)
        return
    if not isinstance(node, ast.Invocation) or binding is None:
        return
    callee = binding.callee
    if not isinstance(callee, Symbol):
        return
    _implemented(model, callee, node.name.span, found, plugins)
    if binding.events:
        _form(found, binding.events[0].span, "event_argument")
    if callee.kind is SymbolKind.SCENARIO:
        _invoked_actors(model, node, callee, found)
        for item in node.with_members:
            if isinstance(item, ast.Invocation):
                _form(found, item.span, "scenario_modifier")
    if callee.kind is SymbolKind.MODIFIER:
        if node.with_members:
            _form(found, node.with_members[0].span, "modifier_with")
    if callee.kind is SymbolKind.ACTION:
        _actor_forms(model, node, callee, found)
        for item in node.with_members:
            if isinstance(item, ast.Invocation):
                _heading(model, node, item, found)
                _movement(model, item, found)


def _invoked_actors(
    model: Model, node: ast.Invocation, callee: Symbol, found: list[Diagnostic]
) -> None:
    """An invoked scenario's actor fields that the invocation leaves without an actor."""
    binding = model.binding(node)
    assert binding is not None  # as `_node` found it
    for param in model.all_members(callee):
        t = param.type
        if (
            param.kind is SymbolKind.FIELD
            and t is not None
            and t.kind is T.Kind.COMPOUND
            and t.symbol is not None
            and t.symbol.kind is SymbolKind.ACTOR
            and binding.given(param.name) is None
        ):
            _form(found, node.span, "invoked_actor_field")
            return


def _actor_forms(
    model: Model, action: ast.Invocation, callee: Symbol, found: list[Diagnostic]
) -> None:
    """Actions of actors the world cannot move: trailers, actors without a body."""
    symbol = _actor_type(model, action)
    if symbol is None or not callee.library:
        return
    names = {a.name for a in model.ancestors(symbol) if a.library}
    movable = callee.actor is not None and any(
        a.name == "movable_object" for a in model.ancestors(callee.actor)
    )
    if "trailer" in names and callee.name not in TRAILER_ACTIONS:
        _form(found, action.name.span, "trailer_action")
    elif movable and not names & set(BODY_TYPES):
        _form(found, action.name.span, "bodiless_actor")


def _movement(model: Model, item: ast.Invocation, found: list[Diagnostic]) -> None:
    """The forms of the library's movement modifiers the runner does not carry out."""
    binding = model.binding(item)
    if binding is None or not isinstance(binding.callee, Symbol) or not binding.callee.library:
        return
    given = binding.values(defaults=False)
    if enum_word(given.get("track")) == "projected":
        _form(found, binding.argument("track").span, "track_projected")  # type: ignore[union-attr]
    if "shape" in given:
        _form(found, binding.argument("shape").span, "modifier_shape")  # type: ignore[union-attr]
    name = binding.callee.name
    if name in _CHANGES and modifier_timing(given) == "start":
        _form(found, item.span, "change_at_start")
    if name == "acceleration" and any(k in given for k in _RELATIVE):
        _form(found, item.span, "relative_acceleration")
    if name == "position" and not ("ahead_of" in given or "behind" in given):
        if "time" in given or modifier_timing(given) != "start":
            _form(found, item.span, "position_along_road")


def _implemented(
    model: Model, callee: Symbol, span: Span, found: list[Diagnostic], plugins: PluginRegistry
) -> None:
    """A308 when the runner has no implementation of ``callee`` and no plug-in has one."""
    if callee.library or callee.toolkit:
        reason = absent_reason(label_of(callee))
    elif callee.kind in (SymbolKind.ACTION, SymbolKind.MODIFIER) or _undefined(callee):
        reason = _NO_PLUGIN
    else:
        return
    if reason and plugin_of(model, callee, plugins) is None:
        found.append(messages.not_executed(span, f"`{label_of(callee)}`", reason))


def _undefined(symbol: Symbol) -> bool:
    """Whether ``symbol`` is a method declared ``is undefined``."""
    decl = symbol.decl
    return (
        symbol.kind is SymbolKind.METHOD
        and isinstance(decl, ast.MethodDecl)
        and decl.kind == "undefined"
    )


def plugin_of(model: Model, callee: Symbol, plugins: PluginRegistry) -> Implementation | None:
    """The plug-in implementation of the action, modifier or method ``callee``: registered
    for its actor (its declaring type) or a supertype, or for no actor when it has none."""
    kinds = {SymbolKind.ACTION: "action", SymbolKind.MODIFIER: "modifier"}
    kind = kinds.get(callee.kind, "method" if callee.kind is SymbolKind.METHOD else None)
    if kind is None or not len(plugins):
        return None
    owner = callee.owner if callee.kind is SymbolKind.METHOD else callee.actor
    owners = [s.name for s in model.ancestors(owner)] if owner is not None else [None]
    return plugins.find(kind, owners, callee.name)  # type: ignore[arg-type]


def _heading(
    model: Model, action: ast.Invocation, item: ast.Invocation, found: list[Diagnostic]
) -> None:
    """The forms of ``yaw``/``orientation`` the runner does not carry out."""
    binding = model.binding(item)
    if binding is None or not isinstance(binding.callee, Symbol):
        return
    name = binding.callee.name
    if name not in ("yaw", "orientation") or not binding.callee.library:
        return
    given = binding.values(defaults=False)
    if "relative_to" in given:
        _form(found, item.span, f"{name}_relative_to")
    frame = "measure_by" if name == "yaw" else "measured_by"
    if enum_word(given.get(frame)) not in (None, "relative_to_road"):
        _form(found, item.span, "heading_frame")
    if name == "orientation" and ("pitch" in given or "roll" in given):
        _form(found, item.span, "pitch_roll")
    if modifier_timing(given) != "start" and _is_vehicle(model, action):
        _form(found, item.span, "vehicle_heading")


def _actor_type(model: Model, action: ast.Invocation) -> Symbol | None:
    """The actor type of the actor ``action`` is invoked on (None when not known)."""
    actor_type = model.type_of(action.actor) if action.actor is not None else None
    if actor_type is None or actor_type.kind is not T.Kind.COMPOUND:
        return None
    return actor_type.symbol


def _is_vehicle(model: Model, action: ast.Invocation) -> bool:
    """Whether the actor of ``action`` is a vehicle (persons turn at once)."""
    symbol = _actor_type(model, action)
    return symbol is not None and any(a.name == "vehicle" for a in model.ancestors(symbol))
