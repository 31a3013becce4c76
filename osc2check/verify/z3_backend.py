"""Solve a ``ConstraintProblem`` with z3: satisfiability, minimal conflicts, defaults, samples.

``check`` decides a problem for the analysis: a model found by propagation
(``propagate``) settles a plainly satisfiable problem without z3 (z3 is not even
loaded); anything else goes to z3, which reports minimal conflicts.
``solve`` always asks z3, and with a seed returns a sample (the witness).

z3 state is never shared between analyses: the scenarios of one analysis share
a ``Session`` (one z3 context, made when first needed), and each witness is
drawn in a context of its own, so the same seed gives the same witness however
many scenarios were solved before. ``rlimit`` is z3's deterministic resource
budget: results do not depend on the machine's speed; the wall-clock timeout
is only a safety net. An undecided check is "unknown", never an error.
"""

from __future__ import annotations

import math
import random
import signal
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from osc2check import memory, results
from osc2check.verify import ir, propagate
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.terms import is_one_of_choice

DEFAULT_RLIMIT = 20_000_000
DEFAULT_TIMEOUT_MS = 10_000
MAX_CONFLICTS = 10
_USER_KINDS = ("keep", "default", "argument", "modifier", "declaration", "condition", "timing")
_IMPLICIT_KINDS = ("domain", "placement")
#: constraints that only define a variable (the timing model's starts and ends): always
#: asserted, never part of a conflict
DEFINITION = "definition"
FALLBACK = "fallback"  # the rule of an implicit constraint that only holds unmentioned

# z3 has no type stubs: the module, its contexts, solvers and expressions are Any.
Z3Context = Any
Z3Expr = Any


def load_z3() -> Any:
    """z3, imported when first needed (the import takes about 0.1 s)."""
    import z3

    return z3


#: z3's reason when its own SIGINT handler cancelled a call (``ctrl_c``, on by default)
_KEYBOARD = "interrupted from keyboard"


def decided(solver: Any, *assumptions: Any) -> Any:
    """``solver.check(*assumptions)``. While z3 solves, Ctrl-C is z3's: it cancels the call
    and answers unknown, and Python never sees the signal; that is raised here as the
    ``KeyboardInterrupt`` Python would have raised, so the command stops. A process that
    ignores SIGINT (a script's background job) asks again instead."""
    while True:
        result = solver.check(*assumptions)
        if result != load_z3().unknown or solver.reason_unknown() != _KEYBOARD:
            return result
        if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:
            raise KeyboardInterrupt


@dataclass
class Conflict:
    primary: ir.Constraint
    others: list[ir.Constraint]


@dataclass
class SolverOutcome:
    status: str  # "sat" | "unsat" | "unknown"
    values: dict[str, Fraction | bool] = field(default_factory=dict)
    conflicts: list[Conflict] = field(default_factory=list)
    overridden: list[tuple[ir.Constraint, ir.Constraint | None]] = field(default_factory=list)
    conflicting_defaults: list[tuple[ir.Constraint, ir.Constraint]] = field(default_factory=list)
    nonlinear: list[ir.Constraint] = field(default_factory=list)
    reason: str = ""
    method: str = "z3"  # "z3" | "propagation": what decided the status


def new_context() -> Z3Context:
    """A new z3 context, or ``MemoryError`` when the memory budget has no room for one
    (z3 does not check that its context was made, and crashes). A Ctrl-C while it is
    made is raised once it is whole: a context left half made reports an error when
    it is freed, at the process's exit."""
    memory.room_for_solver()
    z3 = load_z3()
    with _interrupt_after():
        return z3.Context()


@contextmanager
def _interrupt_after() -> Iterator[None]:
    """Hold SIGINT for the block; the ``KeyboardInterrupt`` it would have raised is raised
    when the block ends. Only in the main thread, with Python's own SIGINT handler."""
    received: list[int] = []
    previous: Any = None
    try:
        held = signal.getsignal(signal.SIGINT) is signal.default_int_handler
        if held:
            previous = signal.signal(signal.SIGINT, lambda signum, _: received.append(signum))
    except ValueError:  # not the main thread
        held = False
    try:
        yield
    finally:
        if held:
            signal.signal(signal.SIGINT, previous)
    if received:
        raise KeyboardInterrupt


class Session:
    """The z3 context that the scenarios of one analysis share, made when first needed."""

    def __init__(self) -> None:
        self._ctx: Z3Context | None = None

    @property
    def ctx(self) -> Z3Context:
        if self._ctx is None:
            self._ctx = new_context()
        return self._ctx


def _position(c: ir.Constraint) -> tuple[str, int, int]:
    return (c.span.uri, c.span.line, c.span.column)


def active_constraints(problem: ConstraintProblem, outcome: SolverOutcome) -> list[ir.Constraint]:
    """The constraints that hold after the override rule (see module ``parameters``).

    A default on a parameter yields to a hard constraint that has the parameter
    alone on the left of `==` or `in` (an argument is such a constraint), and to
    `remove_default`; these are recorded in ``outcome.overridden`` (C403). Of
    several defaults of one parameter the last in the list holds: the lowering
    orders them from the most general (a type's) to the most specific (the
    instance's). Two defaults written in one body with different values are
    recorded in ``outcome.conflicting_defaults`` (C404).
    """
    hard_subjects: dict[str, ir.Constraint] = {}
    for c in problem.constraints:
        if c.strength == "hard" and c.subject is not None:
            hard_subjects.setdefault(c.subject.name, c)
    last_default: dict[str, ir.Constraint] = {}
    in_body: dict[tuple[str, str], ir.Constraint] = {}
    for c in problem.constraints:
        if c.strength == "default" and c.subject is not None:
            last_default[c.subject.name] = c
            earlier = in_body.get((c.subject.name, c.origin))
            if earlier is not None and earlier.term != c.term:
                outcome.conflicting_defaults.append((c, earlier))
            in_body[(c.subject.name, c.origin)] = c
    mentioned: set[str] = set()  # variables that written constraints that hold mention
    active = []
    for c in problem.constraints:
        if c.strength != "default":
            active.append(c)
            if c.kind not in _IMPLICIT_KINDS:
                mentioned |= ir.names(c.term)
            continue
        subject = c.subject.name if c.subject is not None else None
        if subject is not None and subject in problem.removed_defaults:
            outcome.overridden.append((c, None))
        elif subject is not None and subject in hard_subjects:
            outcome.overridden.append((c, hard_subjects[subject]))
        elif subject is not None and last_default[subject] is not c:
            pass  # a later, more specific default of the same parameter holds instead
        else:
            active.append(c)
            mentioned |= ir.names(c.term)
    # a fallback holds only while nothing else that holds mentions its variable
    return [
        c
        for c in active
        if c.rule != FALLBACK or c.subject is None or c.subject.name not in mentioned
    ]


def giving_way(
    problem: ConstraintProblem,
    outcome: SolverOutcome,
    decide: Callable[[ConstraintProblem], SolverOutcome],
) -> tuple[ConstraintProblem, SolverOutcome]:
    """``problem`` and its ``outcome``, or, while the readings of open starts
    (``ir.Constraint.tentative``) take part in the outcome's conflicts, the problem without
    them (``ConstraintProblem.firm``) and what ``decide`` makes of it."""
    while outcome.status == "unsat":
        readings = {c.tentative for k in outcome.conflicts for c in (k.primary, *k.others)}
        firm = problem.firm(readings - {""})
        if firm is None:
            break
        problem, outcome = firm, decide(firm)
    return problem, outcome


def nonlinear(active: list[ir.Constraint]) -> list[ir.Constraint]:
    """The constraints of ``active`` that multiply or divide unknowns (C410). A parameter
    that equations fix to a constant (its declaration's ``ttc0: time = 4s`` while no
    keep overrides it, ``keep(ttc0 == 4s)``) is a constant, as the sampler takes it:
    ``gap == closing * ttc0`` is linear then."""
    # folding in constants never makes a term nonlinear: only the nonlinear ones are folded
    candidates = [c for c in active if ir.is_nonlinear(c.term)]
    if not candidates:
        return []
    fixed = propagate.determined([c.term for c in active])
    return [c for c in candidates if ir.is_nonlinear(propagate.fold(c.term, fixed))]


def fallbacks(problem: ConstraintProblem, active: list[ir.Constraint]) -> list[ir.Constraint]:
    """The fallbacks (``rule == "fallback"``: a vehicle is a car when nothing says
    otherwise) that do not hold because constraints of ``active`` mention their variable.

    They hold again without those constraints: a conflict's core is looked for with
    them in the background, so a line is left out of it when the scenario without that
    line, fallback included, still has the conflict.
    """
    kept = {id(c) for c in active}
    return [c for c in problem.constraints if c.rule == FALLBACK and id(c) not in kept]


class Encoder:
    def __init__(self, problem: ConstraintProblem, ctx: Z3Context):
        z3 = load_z3()
        self.z3 = z3
        self.ctx = ctx
        self.vars: dict[str, Z3Expr] = {}
        for var in problem.variables.values():
            if var.sort == "real":
                self.vars[var.name] = z3.Real(var.name, ctx)
            elif var.sort == "bool":
                self.vars[var.name] = z3.Bool(var.name, ctx)
            else:
                self.vars[var.name] = z3.Int(var.name, ctx)

    def num_or_bool(self, value: Fraction | bool) -> Z3Expr:
        if isinstance(value, bool):
            return self.z3.BoolVal(value, self.ctx)
        return self.num(value)

    def num(self, value: Fraction) -> Z3Expr:
        if value.denominator == 1:
            return self.z3.IntVal(value.numerator, self.ctx)
        return self.z3.RealVal(f"{value.numerator}/{value.denominator}", self.ctx)

    def term(self, t: ir.Term) -> Z3Expr:
        z3 = self.z3
        if isinstance(t, ir.Const):
            if isinstance(t.value, bool):
                return z3.BoolVal(t.value, self.ctx)
            return self.num(t.value)
        if isinstance(t, ir.Ref):
            return self.vars[t.var.name]
        args = [self.term(a) for a in t.args]
        match t.op:
            case "+":
                return args[0] + args[1]
            case "-":
                return args[0] - args[1]
            case "*":
                return args[0] * args[1]
            case "/":
                return self._real(args[0]) / self._real(args[1])
            case "%":
                return self._remainder(args[0], args[1], t.args[1])
            case "neg":
                return -args[0]
            case "==":
                return args[0] == args[1]
            case "!=":
                return args[0] != args[1]
            case "<":
                return args[0] < args[1]
            case "<=":
                return args[0] <= args[1]
            case ">":
                return args[0] > args[1]
            case ">=":
                return args[0] >= args[1]
            case "and":
                return z3.And(*args)
            case "or":
                return z3.Or(*args) if args else z3.BoolVal(False, self.ctx)
            case "not":
                return z3.Not(args[0])
            case "=>":
                return z3.Implies(args[0], args[1])
            case "ite":
                return z3.If(args[0], args[1], args[2])
        raise ValueError(f"unknown operator {t.op}")

    def _real(self, e: Z3Expr) -> Z3Expr:
        return self.z3.ToReal(e) if e.is_int() else e

    def _remainder(self, a: Z3Expr, b: Z3Expr, divisor: ir.Term) -> Z3Expr:
        """``a % b`` floored (the sign of ``b``): z3's own ``mod`` where it agrees (an
        integer by a positive constant), else ``a - b * floor(a / b)``."""
        if (
            a.is_int()
            and isinstance(divisor, ir.Const)
            and not isinstance(divisor.value, bool)
            and divisor.value > 0
            and divisor.value.denominator == 1
        ):
            return a % b
        return a - b * self.z3.ToInt(self._real(a) / self._real(b))


def _value(expr: Z3Expr) -> Fraction | bool:
    z3 = load_z3()
    if z3.is_true(expr):
        return True
    if z3.is_false(expr):
        return False
    if z3.is_int_value(expr):
        return Fraction(expr.as_long())
    if z3.is_rational_value(expr):
        return Fraction(expr.numerator_as_long(), expr.denominator_as_long())
    if z3.is_algebraic_value(expr):
        return Fraction(expr.approx(20).as_fraction())
    return Fraction(0)


def check(
    problem: ConstraintProblem,
    *,
    rlimit: int = DEFAULT_RLIMIT,
    timeout_ms: int = DEFAULT_TIMEOUT_MS,
    session: Session | None = None,
) -> SolverOutcome:
    """Decide the problem: a model by propagation if an easy one exists, else z3.

    The values of a satisfiable outcome are a model, but not the seeded sample
    that ``solve`` gives: witnesses come from ``solve``.
    """
    outcome = SolverOutcome("sat")
    active = active_constraints(problem, outcome)
    outcome.nonlinear = nonlinear(active)
    model = propagate.find_model(problem.variables, [c.term for c in active])
    if model is not None:
        outcome.values = model
        outcome.method = "propagation"
        return outcome
    ctx = session.ctx if session is not None else new_context()
    return _solve(problem, outcome, active, None, rlimit, timeout_ms, ctx)


def solve(
    problem: ConstraintProblem,
    *,
    seed: int | None = None,
    rlimit: int = DEFAULT_RLIMIT,
    timeout_ms: int = DEFAULT_TIMEOUT_MS,
    ctx: Z3Context | None = None,
) -> SolverOutcome:
    """Check the problem with z3; report conflicts, or a model (a sample picked by
    ``seed``; without a seed, z3's first model)."""
    outcome = SolverOutcome("sat")
    active = active_constraints(problem, outcome)
    outcome.nonlinear = nonlinear(active)
    return _solve(
        problem,
        outcome,
        active,
        seed,
        rlimit,
        timeout_ms,
        ctx if ctx is not None else new_context(),
    )


def _solve(
    problem: ConstraintProblem,
    outcome: SolverOutcome,
    active: list[ir.Constraint],
    seed: int | None,
    rlimit: int,
    timeout_ms: int,
    ctx: Z3Context,
) -> SolverOutcome:
    z3 = load_z3()
    enc = Encoder(problem, ctx)
    solver = z3.Solver(ctx=ctx)
    solver.set("core.minimize", True)
    solver.set("rlimit", rlimit)
    solver.set("timeout", timeout_ms)
    exprs = [enc.term(c.term) for c in active]
    tracked = [(c, e) for c, e in zip(active, exprs, strict=True) if c.kind != DEFINITION]
    for c, expr in zip(active, exprs, strict=True):
        if c.kind == DEFINITION:
            solver.add(expr)
    literals = [z3.Bool(f"c{i}", ctx) for i in range(len(tracked))]
    constraint_of = {lit.get_id(): c for lit, (c, _) in zip(literals, tracked, strict=True)}
    for lit, (_, expr) in zip(literals, tracked, strict=True):
        solver.add(z3.Implies(lit, expr))
    for fallback in fallbacks(problem, active):
        assert fallback.subject is not None  # a fallback names its variable
        name = fallback.subject.name
        mentions = [
            lit
            for lit, (c, _) in zip(literals, tracked, strict=True)
            if c.kind not in _IMPLICIT_KINDS and name in ir.names(c.term)
        ]
        solver.add(z3.Or(*mentions, enc.term(fallback.term)))
    enabled = list(literals)

    result = decided(solver, *enabled)
    home = problem.span.uri
    while result == z3.unsat and len(outcome.conflicts) < MAX_CONFLICTS:
        core = _minimal_core(solver, list(solver.unsat_core()))
        members = sorted((constraint_of[lit.get_id()] for lit in core), key=_position)
        users = [c for c in members if c.kind in _USER_KINDS]
        at_home = [c for c in users if c.span.uri == home]
        primary = (at_home or users or members)[-1]
        outcome.conflicts.append(Conflict(primary, [c for c in members if c is not primary]))
        primary_id = next(lit.get_id() for lit in core if constraint_of[lit.get_id()] is primary)
        enabled = [lit for lit in enabled if lit.get_id() != primary_id]
        result = decided(solver, *enabled)
    if outcome.conflicts:
        outcome.status = "unsat"
        return outcome
    if result != z3.sat:
        outcome.status = "unknown"
        outcome.reason = solver.reason_unknown()
        if "resource limit" not in outcome.reason:  # a timeout: the machine's load decided
            results.not_repeatable(f"the solver stopped: {outcome.reason}")
        return outcome
    model = solver.model()
    values = {
        name: _value(model.eval(var, model_completion=True)) for name, var in enc.vars.items()
    }
    if seed is not None:  # satisfiable without dropping anything: every constraint holds
        sample = Sampler(
            problem, active, values, timeout_ms=timeout_ms, rlimit=rlimit, enc=enc
        ).sample(seed)
        if sample is not None:
            values = sample
    outcome.values = values
    return outcome


def _minimal_core(solver: Any, core: list[Z3Expr]) -> list[Z3Expr]:
    """Drop core members one by one while the rest stays unsatisfiable."""
    z3 = load_z3()
    needed = list(core)
    i = 0
    while i < len(needed) and len(needed) > 1:
        trial = needed[:i] + needed[i + 1 :]
        if decided(solver, *trial) == z3.unsat:
            needed = trial
        else:
            i += 1
    return needed


def bounds(active: list[ir.Constraint]) -> dict[str, tuple[Fraction | None, Fraction | None]]:
    """Lower and upper bounds that constraints on one variable alone give it."""
    found: dict[str, list[Fraction | None]] = {}
    conjuncts: list[ir.Term] = []
    for constraint in active:
        propagate.split_conjuncts(constraint.term, conjuncts)
    for term in conjuncts:
        atom = propagate.atom_of(term)
        if len(atom.names) != 1:
            continue
        name = atom.names[0]
        low, high = found.setdefault(name, [None, None])
        if atom.kind == "set" and atom.values and not any(isinstance(v, bool) for v in atom.values):
            values = [Fraction(v) for v in atom.values]
            candidates = [(min(values), ">="), (max(values), "<=")]
        elif atom.kind in ("cmp", "eq"):
            assert atom.form is not None  # a comparison has its linear form
            coeffs, constant = atom.form
            c = coeffs[name]
            bound = -constant / c
            op = atom.op if c > 0 else propagate.FLIPPED[atom.op]
            candidates = (
                [(bound, ">="), (bound, "<=")]
                if op == "=="
                else [(bound, ">=")]
                if op in (">", ">=")
                else [(bound, "<=")]
                if op in ("<", "<=")
                else []
            )
        else:
            continue
        for bound, op in candidates:
            if op == ">=" and (low is None or bound > low):
                low = bound
            elif op == "<=" and (high is None or bound < high):
                high = bound
        found[name] = [low, high]
    return {name: (low, high) for name, (low, high) in found.items()}


class Sampler:
    """Models of one problem spread over its feasible space, one per seed.

    A seed draws a random target for every variable: inside the bounds that constraints
    on the variable alone give (the road, the vehicle, a range), else around 0. A
    variable that only such constraints mention (or none) takes a drawn value that
    satisfies them; one that equations fix keeps its value, and is a constant in the
    other constraints (``ttc0: time = 4s`` makes ``gap == closing * ttc0`` linear). The
    others ("linked") are drawn by propagation, each at random inside the bounds that
    the values drawn before leave it (``propagate.find_model`` with a seeded generator: no
    solver, and checked exactly); a variable that an equation defines from others
    (``gap`` there) is drawn last, so it follows from the values drawn for the others
    instead of cornering them on a bound. Only when that fails does z3 come in:
    ``z3.Optimize`` puts the real ones as near to their targets as possible (the sum of
    distances is minimised, for one variable of each equation between unknowns) and the
    integer ones at their targets where they can be (soft constraints; integer distances
    would make it a slow mixed-integer problem). One ``Optimize``, made when first
    needed, serves every sample: a sample only fixes the targets, inside
    ``push``/``pop``. The same seed gives the same sample.
    """

    TRIES = 3  # draws by propagation before asking z3

    def __init__(
        self,
        problem: ConstraintProblem,
        active: list[ir.Constraint],
        base: dict[str, Fraction | bool],
        *,
        timeout_ms: int = DEFAULT_TIMEOUT_MS,
        rlimit: int = DEFAULT_RLIMIT,
        enc: Encoder | None = None,
    ):
        self.problem = problem
        self.active = active
        self.base = base
        self.timeout_ms, self.rlimit = timeout_ms, rlimit
        self.enc = enc  # the problem's variables in a z3 context (made when first needed)
        self.opt: Any = None  # a z3 Optimize
        self.order = sorted(problem.variables)
        self.bounds = bounds(active)
        self.alone: dict[str, list[ir.Term]] = {}  # constraints on one variable only
        linked: set[str] = set()
        for c in active:
            names = ir.names(c.term)
            if len(names) == 1:
                self.alone.setdefault(next(iter(names)), []).append(c.term)
            else:
                linked.update(names)
        fixed = self.fixed = propagate.determined([c.term for c in active])
        self.linked = [n for n in self.order if n in linked and n not in fixed]
        self.linked_set = set(self.linked)
        # constants (a field's `= value`, `keep(p == 4s)`) are folded in: a product with
        # one is linear, for the propagation and for z3
        self.folded = [propagate.fold(c.term, fixed) for c in active]
        # an equation between unknowns makes one of them follow from the others: only
        # the others get a target (fewer terms to minimise, the same spread), and they
        # are drawn first
        follows = _dependent(self.folded, fixed)
        self.aimed = [n for n in self.linked if n not in follows]
        # which `one_of` member runs is drawn first: the start it needs follows from it
        choices = [n for n in self.order if is_one_of_choice(n)]
        self.terms = propagate.Prepared(self.folded, first=choices)

    def _optimizer(self) -> Any:
        """The ``Optimize`` of the fallback, with |x - target| for each aimed real x."""
        if self.opt is not None:
            return self.opt
        z3 = load_z3()
        if self.enc is None:
            self.enc = Encoder(self.problem, new_context())
        enc = self.enc
        opt = self.opt = z3.Optimize(ctx=enc.ctx)
        opt.set("timeout", self.timeout_ms)
        opt.set("rlimit", self.rlimit)
        for term in self.folded:
            opt.add(enc.term(term))
        self.target: dict[str, Z3Expr] = {}
        distances = []
        for name in self.aimed:
            if self.problem.variables[name].sort != "real":
                continue
            x = enc.vars[name]
            t = self.target[name] = z3.Real(f"target {name}", enc.ctx)
            d = z3.Real(f"distance {name}", enc.ctx)
            opt.add(d >= x - t, d >= t - x)
            distances.append(d)
        if distances:
            opt.minimize(z3.Sum(*distances))
        return opt

    def _target(self, var: ir.Var, rng: random.Random) -> Fraction | bool:
        if var.sort == "bool":
            return rng.random() < 0.5
        if var.enum:
            wanted = self.problem.preferred.get(var.name)
            members = [v for _, v in var.enum if wanted is None or wanted[0] <= v <= wanted[1]]
            return Fraction(rng.choice(members or [v for _, v in var.enum]))
        low, high = self.bounds.get(var.name, (None, None))
        plausible = self.problem.preferred.get(var.name)
        if plausible is not None:  # draw in the plausible part of the bounds when there is one
            lo_p = plausible[0] if low is None else max(low, plausible[0])
            hi_p = plausible[1] if high is None else min(high, plausible[1])
            if lo_p <= hi_p:
                low, high = lo_p, hi_p
        spread = Fraction(10 if var.sort == "real" else 3)
        if low is None and high is None:
            low, high = -spread, spread
        elif low is None:
            assert high is not None  # not both None
            low = high - spread - abs(high)
        elif high is None:
            high = low + spread + abs(low)
        if var.sort == "int":
            lo, hi = math.ceil(low), math.floor(high)
            return Fraction(rng.randint(lo, hi)) if lo <= hi else Fraction(lo)
        return low + (high - low) * Fraction(rng.randint(0, 1_000_000), 1_000_000)

    def sample(self, seed: int) -> dict[str, Fraction | bool] | None:
        """A model drawn with ``seed``, or None if none is found."""
        rng = random.Random(seed)
        targets = {name: self._target(self.problem.variables[name], rng) for name in self.order}
        values = dict(self.base)
        for name in self.order:
            if name in self.linked_set or name in self.fixed:
                continue  # drawn below, or fixed by equations: keeps its value
            if name not in self.terms.by_var:  # no constraint mentions it
                is_string = self.problem.variables[name].is_string
                values[name] = Fraction(-1) if is_string else targets[name]  # -1: any string
                continue
            own = self.alone.get(name, ())
            if all(propagate.evaluate(t, {name: targets[name]}) is True for t in own):
                values[name] = targets[name]
        if not self.linked:
            return values
        for attempt in range(self.TRIES):
            drawn = propagate.find_model(
                self.problem.variables,
                self.terms,
                random.Random(f"{seed}/{attempt}"),
                self.problem.preferred,
            )
            if drawn is not None:
                values.update((name, drawn[name]) for name in self.linked)
                return values
        z3 = load_z3()
        opt = self._optimizer()
        assert self.enc is not None  # made with the optimizer
        opt.push()
        try:
            for name in self.aimed:
                t = self.enc.num_or_bool(targets[name])
                if name in self.target:
                    opt.add(self.target[name] == t)
                else:
                    opt.add_soft(self.enc.vars[name] == t)
            if decided(opt) != z3.sat:
                return None
            model = opt.model()
            for name in self.linked:
                values[name] = _value(model.eval(self.enc.vars[name], model_completion=True))
        finally:
            opt.pop()
        return values


def _dependent(terms: list[ir.Term], fixed: dict[str, Fraction | bool]) -> set[str]:
    """Variables that equations express through other unknowns, one per equation: of a
    linear one, its left side when that is a variable, else its last unknown; of one that
    is not linear (``gap == closing * headway``, ``t == d / v``), the variable alone on
    one side that the other side does not mention."""
    conjuncts: list[ir.Term] = []
    for t in terms:
        propagate.split_conjuncts(t, conjuncts)
    dependent: set[str] = set()
    for term in conjuncts:
        if not (isinstance(term, ir.Op) and term.op == "=="):
            continue
        atom = propagate.atom_of(term)
        free = [n for n in atom.names if n not in fixed and n not in dependent]
        if not free:  # none left: it follows from unknowns that follow from others
            continue
        left, right = term.args
        if atom.kind == "eq":
            on_left = isinstance(left, ir.Ref) and left.var.name in free
            dependent.add(left.var.name if isinstance(left, ir.Ref) and on_left else free[-1])
            continue
        for side, other in ((left, right), (right, left)):
            if (
                isinstance(side, ir.Ref)
                and side.var.name in free
                and side.var.name not in ir.names(other)
            ):
                dependent.add(side.var.name)
                break
    return dependent


def never_holds(
    problem: ConstraintProblem,
    active: list[ir.Constraint],
    term: ir.Term,
    rlimit: int = DEFAULT_RLIMIT,
) -> bool:
    """Whether ``term`` is false in every model of the active constraints."""
    z3 = load_z3()
    ctx = new_context()
    enc = Encoder(problem, ctx)
    solver = z3.Solver(ctx=ctx)
    solver.set("rlimit", rlimit)
    for c in active:
        solver.add(enc.term(c.term))
    solver.add(enc.term(term))
    return bool(decided(solver) == z3.unsat)
