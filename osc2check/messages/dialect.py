"""The messages of the D codes (dialect): non-standard forms accepted for compatibility,
those of the design paper and the standard's examples, then CARLA scenario_runner's."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from osc2check import codes
from osc2check.diagnostics import Diagnostic, Fix, TextEdit
from osc2check.messages.parts import (
    callee_name,
    diagnostic,
    example_unit,
)
from osc2check.source import Span

if TYPE_CHECKING:
    from osc2check.semantics.symbols import Symbol
    from osc2check.semantics.types import Type


def tool_module(span: Span, target: str, path: str) -> Diagnostic:
    """``import osc.helpers`` found in a search path (the module map says so without one)."""
    return diagnostic(
        codes.TOOL_MODULE,
        f"`{target}` is no module of the standard library (names under `osc` are the "
        f"standard's); read from `{path}`, found by its name: name the file in the module "
        f"map (`[tool.osc2check.modules]`) to say it is meant",
        span,
    )


def struct_constructor_call(span: Span, struct: Symbol) -> Diagnostic:
    return diagnostic(
        codes.STRUCT_CONSTRUCTOR_CALL,
        f"`{struct.name}(...)` builds a `{struct.name}` from its fields, as scenario_execution "
        "does; the standard has no struct constructor (give a field the value with `keep`)",
        span,
    )


def unitless_literal(span: Span, expected: Type) -> Diagnostic:
    return diagnostic(
        codes.UNITLESS_PHYSICAL_LITERAL,
        f"a plain number where `{expected}` is expected; the toolkit reads it in SI "
        f"units, the standard needs a unit such as `{example_unit(expected)}`",
        span,
    )


def use_statement(span: Span, text: str) -> Diagnostic:
    return diagnostic(
        codes.USE_STATEMENT,
        f"`use {text}` as a statement is not standard; write `namespace <name> use "
        "...` or import `osc.standard`",
        span,
    )


def undeclared_event(span: Span, name: str) -> Diagnostic:
    return diagnostic(
        codes.UNDECLARED_EVENT,
        f"event `{name}` is emitted without a declaration; add `event {name}` to the scenario",
        span,
    )


def toolkit_extension(span: Span, symbol: Symbol) -> Diagnostic:
    return diagnostic(
        codes.TOOLKIT_EXTENSION,
        f"`{symbol.name}` comes from the toolkit's own library, not the ASAM standard; "
        "other tools may not have it",
        span,
    )


def standard_file_import(span: Span, target: str) -> Diagnostic:
    return diagnostic(
        codes.STANDARD_FILE_IMPORT,
        f'`import "{target}"` names no file here and is read as the standard '
        "library; write `import osc.standard`",
        span,
        fix=Fix("write `import osc.standard`", (TextEdit(span, "import osc.standard"),), False),
    )


def unquoted_file_import(span: Span, target: str, beside: bool) -> Diagnostic:
    """``import basic.osc`` read as the file ``basic.osc``; ``beside``: found beside the
    importing file, so that ``import "basic.osc"`` names the same file."""
    module_file = target.removesuffix(".osc").replace(".", "/") + "/osc.osc"
    quoted = f'"{target}"'
    fix = Fix(f"write `import {quoted}`", (TextEdit(span, quoted),)) if beside else None
    return diagnostic(
        codes.UNQUOTED_FILE_IMPORT,
        f"`import {target}` is read as the file `{target}`, as CARLA does; the standard "
        f"reads it as the module file `{module_file}`: write `import {quoted}`",
        span,
        fix=fix,
    )


def one_of_race(span: Span) -> Diagnostic:
    return diagnostic(
        codes.ONE_OF_RACE,
        "this `one_of` has a `wait` member: the toolkit runs the members side by side "
        "and keeps the first to finish; the standard picks exactly one member",
        span,
    )


def spec_example_parameter(span: Span, callee: Symbol, name: str) -> Diagnostic:
    return diagnostic(
        codes.SPEC_EXAMPLE_PARAMETER,
        f"`{name}` is used in the standard's examples but {callee_name(callee)} does not "
        "declare it",
        span,
    )


# --- CARLA scenario_runner's dialect (osc2check.dialects.carla) --------------------

_MIGRATE = "`osc2check migrate` writes the standard form"


def carla_world_import(span: Span, target: str) -> Diagnostic:
    return diagnostic(
        codes.CARLA_WORLD_IMPORT,
        f"`import {target}` is CARLA's library; it is read as `import osc2toolkit.carla`, the "
        "toolkit's CARLA world on the standard library (the file itself is not read); " + _MIGRATE,
        span,
    )


def carla_world_declaration(span: Span, what: str, note: str = "") -> Diagnostic:
    return diagnostic(
        codes.CARLA_WORLD_DECLARATION,
        f"{what} repeats CARLA's library; the CARLA world's (on the standard library) is "
        f"used{note}",
        span,
    )


def carla_velocity(span: Span) -> Diagnostic:
    return diagnostic(
        codes.CARLA_VELOCITY,
        "`velocity` is CARLA's name of the standard's type `speed`; read as `speed`",
        span,
        fix=Fix("write `speed`", (TextEdit(span, "speed"),)),
    )


def carla_unit_dimension(span: Span, unit: str, type_name: str) -> Diagnostic:
    return diagnostic(
        codes.CARLA_UNIT_DIMENSION,
        f"the SI exponents of unit `{unit}` are not those of `{type_name}`; CARLA takes a "
        f"unit's dimension from its type, and so does this reading (the standard reports it)",
        span,
    )


def carla_path(span: Span, form: str) -> Diagnostic:
    if form == "type":
        text = "CARLA's `Path` is the map the scenario runs on: read as the standard's `map`"
    else:
        text = "CARLA's `set_map` chooses the map: read as the standard's `set_map_file`"
    return diagnostic(codes.CARLA_PATH, text, span)


def carla_path_condition(span: Span, name: str) -> Diagnostic:
    meaning = {
        "path_min_driving_lanes": "the actors start on a road with at least that many driving "
        "lanes in their direction",
        "path_over_junction": "the actors start before a junction that their road crosses",
    }.get(name, "a condition on the road")
    return diagnostic(
        codes.CARLA_PATH_CONDITION,
        f"`{name}` is CARLA's path condition, not the standard's: {meaning} (the CARLA "
        "world's modifier of the map)",
        span,
    )


def carla_drive_path(span: Span, dropped: Sequence[str]) -> Diagnostic:
    return diagnostic(
        codes.CARLA_DRIVE_PATH,
        f"`drive({', '.join(dropped)})` is CARLA's: its path is the map's road the actors are "
        "placed on, and it ignores `adjust`; read as `drive()`",
        span,
    )


def carla_phase_duration(span: Span, duration: str) -> Diagnostic:
    return diagnostic(
        codes.CARLA_PHASE_DURATION,
        f"CARLA gives each behaviour of a composition the composition's duration (its "
        f"timeout): this `drive` lasts {duration}, as if written `drive(duration: {duration})`",
        span,
    )


def carla_start_placement(span: Span, actor: str) -> Diagnostic:
    return diagnostic(
        codes.CARLA_START_PLACEMENT,
        f"in a phase that may begin after time 0, CARLA sets `{actor}`'s transform where "
        f"its `at: start` modifiers say when the phase starts: read as "
        f"`{actor}.assign_position()` with them, then the phase's behaviour",
        span,
    )


def carla_lane_numbering(span: Span) -> Diagnostic:
    return diagnostic(
        codes.CARLA_LANE_NUMBERING,
        "CARLA counts lanes from the left (1 = the leftmost in the direction of travel); the "
        "standard from the right by default: read as `from: left`",
        span,
    )


def carla_lane_side(span: Span, name: str, side: str) -> Diagnostic:
    return diagnostic(
        codes.SPEC_EXAMPLE_PARAMETER,
        f"`{name}` is not a parameter of the standard's `lane` (CARLA's and the standard's "
        f"examples use it): read as `side_of: ..., side: {side}`",
        span,
    )


def carla_lane_changes(span: Span) -> Diagnostic:
    return diagnostic(
        codes.CARLA_LANE_CHANGES,
        "`lane_changes` is CARLA's name of the standard `change_lane` modifier's `lane` (how "
        "many lanes to change); read as `lane`",
        span,
        fix=Fix("write `lane`", (TextEdit(span, "lane"),)),
    )


def carla_scenario_of_dut(span: Span, name: str, shared: Sequence[str] | None = None) -> Diagnostic:
    if shared is None:
        text = (
            f"`{name}` is declared on CARLA's `dut` and invoked through the type: read as a "
            "scenario of no actor whose actors are the invoking scenario's of the same names"
        )
    else:
        given = ", ".join(shared) if shared else "nothing"
        text = (
            f"`dut.{name}()` invokes CARLA's scenario through its actor type, its actors shared "
            f"by name: read as `{name}({given})`"
        )
    return diagnostic(codes.CARLA_SCENARIO_OF_DUT, text, span)


def carla_unused_name(span: Span, kind: str, name: str) -> Diagnostic:
    return diagnostic(
        codes.CARLA_UNUSED_NAME,
        f"{kind} `{name}` is declared for CARLA's parser and nothing uses it; left out, so "
        f"that `{name}` is the enum member it names where one is expected",
        span,
    )


def carla_actor_alias(span: Span, name: str, target: str) -> Diagnostic:
    return diagnostic(
        codes.CARLA_ACTOR_ALIAS,
        f"`{name}` is CARLA's second name for the actor `{target}`; read as `{target}` (a field "
        "of an actor type is an actor of its own in the standard)",
        span,
    )


def carla_speed_name(span: Span, name: str, value: str, actor: str) -> Diagnostic:
    return diagnostic(
        codes.CARLA_SPEED_NAME,
        f'`{name}` is CARLA\'s "{value}": the speed of `{actor}` while it runs; read as '
        f"`{actor}.speed`",
        span,
    )


def carla_drive_distance(span: Span) -> Diagnostic:
    return diagnostic(
        codes.CARLA_DRIVE_DISTANCE,
        "CARLA hard-wires `drive_distance(other_car, distance)`: the wait ends when its "
        "condition holds and then `other_car` has driven `distance`; read as a `wait` for the "
        "condition and that car's `drive()` with `distance(...)`",
        span,
    )


def carla_elapsed_range(span: Span, name: str) -> Diagnostic:
    return diagnostic(
        codes.CARLA_ELAPSED_RANGE,
        f"`elapsed` takes a time; CARLA waits a time drawn from the range: read as the "
        f"parameter `{name}` kept in the range (chosen by the seed)",
        span,
    )


def carla_static_method(span: Span, method: str, dropped: bool) -> Diagnostic:
    if dropped:
        text = (
            f"`{method}` is called on its struct's name and its value is dropped (CARLA "
            "evaluates it and forgets it): left out"
        )
    else:
        text = (
            f"`{method}` is called on its struct's name; the standard calls methods on a "
            "value: read as a call on the scenario's field of that struct"
        )
    return diagnostic(codes.CARLA_STATIC_METHOD, text, span)


def carla_external_python(span: Span, target: str) -> Diagnostic:
    return diagnostic(
        codes.CARLA_EXTERNAL_PYTHON,
        f"`external python(module:, name:)` is CARLA's call of a Python function: read as "
        f"the standard's `external {target}(...)`",
        span,
    )


def carla_world_pose(span: Span) -> Diagnostic:
    return diagnostic(
        codes.CARLA_WORLD_POSE,
        "`set_position` places the vehicle at a pose of CARLA's world (degrees whatever the "
        "unit): it needs CARLA's map in CARLA's coordinates, which the toolkit's stand-ins "
        "are not; osc2run does not execute it (A308)",
        span,
    )


def carla_trajectory_file(span: Span) -> Diagnostic:
    return diagnostic(
        codes.CARLA_TRAJECTORY_FILE,
        "`follow_trajectory(input_file:)` follows the positions of a CSV file in CARLA's "
        "world: it needs CARLA's map in CARLA's coordinates, which the toolkit's stand-ins "
        "are not; osc2run does not execute it (A308)",
        span,
    )


def carla_map(span: Span, name: str, known: Sequence[str]) -> Diagnostic:
    return diagnostic(
        codes.CARLA_MAP,
        f"CARLA's map `{name}` has no stand-in (built-in: {', '.join(known)}): give its "
        f'OpenDRIVE file in `[tool.osc2check.maps]` (`{name} = "maps/{name}.xodr"`); until '
        "then the scenario is placed on the default road and the runner refuses it",
        span,
    )
