"""The registry of diagnostic codes: every code is declared here once.

A code has a family letter and three digits (``N101``), a slug that names the
problem (``undefined-name``), a default severity and a one-line summary. Each
code has a documentation page in ``code_docs/<CODE>.md``; a test keeps the two
in step. Retired codes stay here with ``removed_in`` and are never reused.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum


class Severity(IntEnum):
    """Ordered so that ``min()`` gives the most severe."""

    ERROR = 1
    WARNING = 2
    INFO = 3

    @property
    def label(self) -> str:
        return self.name.lower()

    @property
    def letter(self) -> str:
        return self.name[0]


@dataclass(frozen=True, slots=True)
class Code:
    code: str
    slug: str
    severity: Severity
    summary: str
    since: str = "0.1.0"
    removed_in: str | None = None

    @property
    def family(self) -> str:
        return self.code[0]

    def __str__(self) -> str:
        return self.code


FAMILIES = {
    "P": "syntax",
    "N": "names and resolution",
    "T": "types and units",
    "A": "arguments and invocations",
    "C": "constraints",
    "L": "initial placement",
    "B": "behaviour flow",
    "D": "dialect (non-standard forms accepted for compatibility)",
    "S": "suppressions and tooling",
}

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFO

# --- P: syntax -------------------------------------------------------------
SYNTAX_ERROR = Code("P001", "syntax-error", E, "the text does not follow the OSC2 grammar")
INDENTATION_ERROR = Code(
    "P002", "indentation-error", E, "a line is indented to a level no enclosing block uses"
)
INVALID_LITERAL = Code(
    "P003", "invalid-literal", E, "a number, string or physical literal is malformed"
)
INVALID_ENCODING = Code("P004", "invalid-encoding", E, "the file is not valid UTF-8 text")
NESTING_TOO_DEEP = Code(
    "P005", "nesting-too-deep", E, "an expression or block is nested too deeply to analyse"
)

# --- N: names and resolution -----------------------------------------------
UNDEFINED_NAME = Code(
    "N101", "undefined-name", E, "a name is used that no visible declaration defines"
)
DUPLICATE_DEFINITION = Code(
    "N102", "duplicate-definition", E, "a name is declared twice in the same scope"
)
UNKNOWN_MEMBER = Code(
    "N103", "unknown-member", E, "a member is accessed that the type does not have"
)
UNKNOWN_UNIT = Code(
    "N104", "unknown-unit", E, "a physical literal names a unit that is not declared"
)
UNRESOLVED_IMPORT = Code(
    "N105", "unresolved-import", E, "an import names a file or module that cannot be found"
)
UNKNOWN_ENUM_MEMBER = Code(
    "N106", "unknown-enum-member", E, "an enum member is named that the enum does not have"
)
IMPORT_CYCLE = Code("N107", "import-cycle", W, "files import each other in a cycle")
AMBIGUOUS_ENUM_LITERAL = Code(
    "N108",
    "ambiguous-enum-literal",
    E,
    "a bare enum member belongs to several enums and the context does not decide",
)
INVALID_INHERITANCE = Code(
    "N109", "invalid-inheritance", E, "a declaration inherits from something it cannot inherit from"
)
RESERVED_NAME = Code(
    "N110", "reserved-name", W, "a declaration uses a name reserved by the standard"
)
INVALID_IMPLICIT_NAME = Code(
    "N111", "invalid-implicit-name", E, "`it` or `actor` is used where it has no meaning"
)
MISPLACED_MEMBER = Code(
    "N112",
    "misplaced-member",
    E,
    "a member that this kind of declaration cannot have, such as `do` in a struct or a second `do`",
)
AMBIGUOUS_NAME = Code(
    "N113",
    "ambiguous-name",
    E,
    "a name is exported by several used namespaces and nothing closer decides",
)
ENUM_VALUE_CYCLE = Code(
    "N114", "enum-value-cycle", E, "enum members take their values from each other in a cycle"
)
SHADOWED_ENUM_LITERAL = Code(
    "N115",
    "shadowed-enum-literal",
    W,
    "a declared name is also a member of the enum expected here; the member is taken",
)

# --- T: types and units ----------------------------------------------------
DIMENSION_MISMATCH = Code(
    "T201", "dimension-mismatch", E, "physical quantities of different dimensions are combined"
)
MISSING_UNIT = Code(
    "T202", "missing-unit", E, "a plain number is used where a physical quantity is expected"
)
TYPE_MISMATCH = Code(
    "T203", "type-mismatch", E, "a value has a type that the context does not accept"
)
FLOAT_TO_INT = Code(
    "T204", "float-to-int", W, "a float value is given where an integer is expected"
)
NON_BOOLEAN_CONDITION = Code(
    "T205", "non-boolean-condition", E, "a condition is not a boolean expression"
)
RANGE_BOUNDS_TYPE = Code(
    "T206", "range-bounds-type", E, "the two bounds of a range have different types"
)
INVALID_UNIT_DECLARATION = Code(
    "T207",
    "invalid-unit-declaration",
    E,
    "a unit declares SI exponents that differ from its type's",
)
NOT_CALLABLE = Code("T208", "not-callable", E, "something that is not a method is called")
NUMBER_OUT_OF_RANGE = Code(
    "T209",
    "number-out-of-range",
    E,
    "a number has more digits or a larger or smaller magnitude than any value can have",
)

# --- A: arguments and invocations ------------------------------------------
UNKNOWN_ACTION_OR_MODIFIER = Code(
    "A301",
    "unknown-action-or-modifier",
    E,
    "an invoked action, scenario or modifier is not declared for the actor",
)
UNKNOWN_ARGUMENT = Code("A302", "unknown-argument", E, "a named argument matches no parameter")
TOO_MANY_POSITIONAL = Code(
    "A304",
    "too-many-positional",
    E,
    "more positional arguments than parameters, or a positional after a named one",
)
DUPLICATE_ARGUMENT = Code("A305", "duplicate-argument", E, "a parameter is given twice")
EXCLUSIVE_ARGUMENTS = Code(
    "A306",
    "mutually-exclusive-arguments",
    E,
    "arguments that exclude each other are given together",
)
INCOMPLETE_ARGUMENTS = Code(
    "A307", "incomplete-argument-group", E, "an argument is given without the argument it needs"
)
NOT_EXECUTED = Code(
    "A308",
    "not-executed-by-runner",
    W,
    "a call or argument form that the reference runner does not execute",
)
MISSING_ARGUMENT = Code(
    "A303", "missing-argument", E, "a method call omits a parameter that has no default"
)

# --- C: constraints (keep, defaults, arguments) --------------------------------
UNSATISFIABLE_CONSTRAINTS = Code(
    "C401", "unsatisfiable-constraints", E, "constraints of a scenario cannot all hold"
)
REVERSED_RANGE = Code(
    "C402", "reversed-range", W, "a range is written from its upper to its lower bound"
)
DEFAULT_OVERRIDDEN = Code(
    "C403",
    "default-overridden",
    I,
    "a default constraint is replaced by a hard constraint or `remove_default`",
)
CONFLICTING_DEFAULTS = Code(
    "C404", "conflicting-defaults", W, "two defaults of one parameter give different values"
)
VACUOUS_CONSTRAINT = Code(
    "C405", "vacuous-constraint", W, "a constraint holds for every value its parameters can take"
)
SOLVER_INCONCLUSIVE = Code(
    "C408", "solver-inconclusive", I, "the solver could not decide within its budget"
)
NONLINEAR_CONSTRAINT = Code(
    "C410",
    "nonlinear-constraint",
    I,
    "a constraint multiplies or divides unknowns; it is solved with a budget",
)
UNVERIFIED_CONSTRAINT = Code(
    "C411",
    "unverified-constraint",
    W,
    "a constraint the solver cannot take is left out of the verdict and the witness",
)

# --- L: initial placement ------------------------------------------------------
INFEASIBLE_PLACEMENT = Code(
    "L501",
    "infeasible-initial-placement",
    E,
    "the start positions that the scenario asks for cannot all hold",
)
FOOTPRINT_OVERLAP = Code(
    "L502", "footprint-overlap-at-start", E, "actors would overlap at the start"
)
LANE_OUT_OF_RANGE = Code(
    "L503", "lane-out-of-range", E, "an actor is placed in a lane the road does not have"
)
REFERENCE_NOT_PLACED = Code(
    "L504",
    "reference-actor-not-placed",
    W,
    "an actor is placed relative to one that is not on the road at the start",
)
CYCLIC_PLACEMENT = Code(
    "L505", "cyclic-relative-placement", W, "actors are placed relative to each other in a cycle"
)
UNPLACED_ACTOR = Code(
    "L506", "unplaced-actor", I, "an actor has no start position; the solver picks one"
)
OFF_ROAD = Code("L507", "off-road-placement", E, "an actor would start beyond the ends of the road")
SPEED_ABOVE_MAX = Code(
    "L508", "speed-exceeds-vehicle-max", E, "a start speed is above what the vehicle can reach"
)
UNSAFE_GAP = Code(
    "L511",
    "unsafe-initial-gap",
    W,
    "a start gap is shorter than one second at the follower's speed",
)
UNKNOWN_MAP = Code("L513", "unknown-map", E, "a map is named that the toolkit does not know")
UNREADABLE_MAP = Code(
    "L516", "unreadable-map", E, "a map file is named that is missing or cannot be read"
)
ROAD_TOO_SHORT_FOR_MOTION = Code(
    "L514",
    "road-too-short-for-motion",
    E,
    "constant speeds and durations take an actor past the road's end from every start",
)
PERSON_FASTER_THAN_WALKING = Code(
    "L515",
    "person-faster-than-walking",
    W,
    "a person is asked to move faster than an adult walks",
)

# --- B: behaviour flow -----------------------------------------------------------
WAIT_WITHOUT_EMITTER = Code(
    "B601", "wait-without-emitter", E, "a `wait` for an event that nothing emits"
)
WAIT_BLOCKS_EMITTER = Code(
    "B602",
    "wait-blocks-own-emitter",
    E,
    "a `wait` comes before the only `emit` of its event in the same serial chain",
)
NEGATIVE_DURATION = Code("B604", "negative-duration", E, "a duration is negative")
EMPTY_ONE_OF = Code("B605", "empty-one-of", E, "a `one_of` has no members")
EMPTY_COMPOSITION = Code("B606", "empty-composition", W, "a `serial` or `parallel` has no members")
INFEASIBLE_TIMING = Code(
    "B608",
    "infeasible-timing",
    E,
    "no run can keep the durations and overlaps that the behaviour asks for",
)
CONSTANT_CONDITION = Code(
    "B609", "constant-condition", W, "a condition is always true or always false"
)
PARALLEL_MOVEMENTS = Code(
    "B610",
    "conflicting-parallel-movements",
    W,
    "one actor is given two movement actions at the same time",
)
RECURSIVE_SCENARIO = Code(
    "B611", "recursive-scenario", E, "a scenario invokes itself, directly or through others"
)

# --- D: dialect forms (the design paper's and the standard's own examples) --
USE_STATEMENT = Code(
    "D801",
    "use-statement",
    W,
    "`use` written as a statement instead of a `namespace ... use` clause",
)
UNDECLARED_EVENT = Code(
    "D802",
    "undeclared-event",
    W,
    "an event is emitted or awaited that no `event` declaration defines",
)
TOOLKIT_EXTENSION = Code(
    "D803",
    "toolkit-extension",
    W,
    "a member of the toolkit's own library is used; other tools may not have it",
)
STANDARD_FILE_IMPORT = Code(
    "D804",
    "standard-file-import",
    W,
    "the standard library is imported by file name instead of `import osc.standard`",
)
UNITLESS_PHYSICAL_LITERAL = Code(
    "D805",
    "unitless-physical-literal",
    W,
    "a plain number literal is given where a physical quantity is expected",
)
ONE_OF_RACE = Code(
    "D806", "one-of-race", W, "a `one_of` member is a `wait`: the toolkit runs `one_of` as a race"
)
SPEC_EXAMPLE_PARAMETER = Code(
    "D807",
    "nonstandard-parameter",
    W,
    "a parameter used in the standard's examples but not declared by its library",
)
UNQUOTED_FILE_IMPORT = Code(
    "D808",
    "unquoted-file-import",
    W,
    "a file is imported by its name without quotes (`import basic.osc`), as CARLA does",
)

STRUCT_CONSTRUCTOR_CALL = Code(
    "D809",
    "struct-constructor-call",
    W,
    "a struct value is built by calling the struct's name (`pose_3d(position_3d(x: 1m))`)",
)
TOOL_MODULE = Code(
    "D810",
    "tool-module",
    W,
    "a module under the standard's reserved name `osc` is another tool's library",
)

# CARLA scenario_runner's dialect (osc2check.dialects.carla)
CARLA_WORLD_IMPORT = Code(
    "D811",
    "carla-world-import",
    W,
    "CARLA's library `basic.osc` is imported: the toolkit reads it as its CARLA world",
)
CARLA_WORLD_DECLARATION = Code(
    "D812",
    "carla-world-declaration",
    W,
    "a declaration of CARLA's library is repeated: the CARLA world's is used",
)
CARLA_VELOCITY = Code(
    "D813",
    "carla-velocity",
    W,
    "CARLA's type `velocity` is used: it is the standard's `speed`",
)
CARLA_UNIT_DIMENSION = Code(
    "D814",
    "carla-unit-dimension",
    W,
    "a unit's SI exponents differ from its type's: CARLA takes the type's",
)
CARLA_PATH = Code(
    "D815",
    "carla-path",
    W,
    "CARLA's `Path` and `set_map` are used: they are the standard's `map` and `set_map_file`",
)
CARLA_PATH_CONDITION = Code(
    "D816",
    "carla-path-condition",
    W,
    "CARLA's path condition (`path_min_driving_lanes`, `path_over_junction`) is used",
)
CARLA_DRIVE_PATH = Code(
    "D817",
    "carla-drive-path",
    W,
    "`drive` is given CARLA's path or `adjust`: the standard's `drive` takes neither",
)
CARLA_LANE_NUMBERING = Code(
    "D818",
    "carla-lane-numbering",
    W,
    "a lane number without `from:`: CARLA counts lanes from the left",
)
CARLA_LANE_CHANGES = Code(
    "D819",
    "carla-lane-changes",
    W,
    "`change_lane(lane_changes: ...)` is CARLA's name of the standard's `lane:`",
)
CARLA_SCENARIO_OF_DUT = Code(
    "D820",
    "carla-scenario-of-dut",
    W,
    "a scenario is declared on CARLA's `dut` and shares the invoking scenario's actors by name",
)
CARLA_UNUSED_NAME = Code(
    "D821",
    "carla-unused-name",
    W,
    "an event or global named as an enum member is declared for CARLA's parser and never used",
)
CARLA_ACTOR_ALIAS = Code(
    "D822",
    "carla-actor-alias",
    W,
    "an actor field whose default is another actor: CARLA's second name for that actor",
)
CARLA_SPEED_NAME = Code(
    "D823",
    "carla-speed-name",
    W,
    "a speed field whose default is a string naming an actor: CARLA reads it as that actor's speed",
)
CARLA_DRIVE_DISTANCE = Code(
    "D824",
    "carla-drive-distance",
    W,
    "CARLA's hard-wired event `drive_distance` is awaited",
)
CARLA_ELAPSED_RANGE = Code(
    "D825",
    "carla-elapsed-range",
    W,
    "`elapsed` is given a range: CARLA waits a time drawn from it",
)
CARLA_STATIC_METHOD = Code(
    "D826",
    "carla-static-method",
    W,
    "a method is called on its struct's name instead of on a value",
)
CARLA_EXTERNAL_PYTHON = Code(
    "D827",
    "carla-external-python",
    W,
    "a method body is CARLA's `external python(module:, name:)`",
)
CARLA_WORLD_POSE = Code(
    "D828",
    "carla-world-pose",
    W,
    "CARLA's `set_position` places an actor at a pose of CARLA's world",
)
CARLA_TRAJECTORY_FILE = Code(
    "D829",
    "carla-trajectory-file",
    W,
    "CARLA's `follow_trajectory(input_file:)` follows a CSV file of CARLA's world",
)
CARLA_PHASE_DURATION = Code(
    "D831",
    "carla-phase-duration",
    W,
    "a drive in a composition with a duration: CARLA gives it the composition's duration",
)
CARLA_START_PLACEMENT = Code(
    "D832",
    "carla-start-placement",
    W,
    "`lane` or `position` `at: start` after time 0: CARLA sets the actor's transform there",
)
CARLA_MAP = Code(
    "D830",
    "carla-map",
    W,
    "a map of CARLA's is named that has no stand-in and no configured file",
)

# --- S: suppressions and tooling -------------------------------------------
UNUSED_SUPPRESSION = Code(
    "S001", "unused-suppression", W, "a suppression comment matches no diagnostic"
)
UNKNOWN_SUPPRESSION_CODE = Code(
    "S002", "unknown-suppression-code", W, "a suppression comment names a code that does not exist"
)
MEMORY_BUDGET = Code(
    "S003", "memory-budget", E, "the check of a file needs more memory than its budget"
)

ALL: tuple[Code, ...] = tuple(v for v in list(globals().values()) if isinstance(v, Code))
BY_CODE: dict[str, Code] = {c.code: c for c in ALL}
BY_SLUG: dict[str, Code] = {c.slug: c for c in ALL}
#: codes whose message may suggest a name ("did you mean ...?", ``semantics.suggest``)
#: from anywhere in the program: what such a finding says depends on every declaration
SUGGESTING: frozenset[Code] = frozenset(
    {
        UNDEFINED_NAME,
        UNKNOWN_MEMBER,
        UNKNOWN_UNIT,
        UNKNOWN_ENUM_MEMBER,
        UNKNOWN_ACTION_OR_MODIFIER,
        UNKNOWN_ARGUMENT,
    }
)


def lookup(name: str) -> Code | None:
    """The code named by its code (``N101``) or slug (``undefined-name``)."""
    return BY_CODE.get(name.upper()) or BY_SLUG.get(name.lower())


def select(patterns: list[str]) -> set[Code]:
    """Codes matched by prefixes such as ``N``, ``N1`` or ``N101``, or by slugs."""
    chosen: set[Code] = set()
    for pattern in patterns:
        p = pattern.strip()
        if p.upper() == "ALL":
            chosen.update(ALL)
            continue
        code = BY_SLUG.get(p.lower())
        if code:
            chosen.add(code)
            continue
        chosen.update(c for c in ALL if c.code.startswith(p.upper()))
    return chosen
