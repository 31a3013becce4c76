"""Solve a ``Problem`` with z3: satisfiability, minimal conflicts, defaults, samples.

One z3 context per solve, so analyses never share solver state and a thread
can interrupt its own. ``rlimit`` is z3's deterministic resource budget:
results do not depend on the machine's speed; the wall-clock timeout is only
a safety net. An undecided check is "unknown", never an error.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field
from fractions import Fraction

import z3

from osc2check.verify import ir

DEFAULT_RLIMIT = 20_000_000
DEFAULT_TIMEOUT_MS = 10_000
MAX_CONFLICTS = 10
_USER_KINDS = ("keep", "default", "argument", "modifier", "declaration")


@dataclass
class Conflict:
    primary: ir.Constraint
    others: list[ir.Constraint]


@dataclass
class Outcome:
    status: str  # "sat" | "unsat" | "unknown"
    values: dict[str, Fraction | bool] = field(default_factory=dict)
    conflicts: list[Conflict] = field(default_factory=list)
    overridden: list[tuple[ir.Constraint, ir.Constraint | None]] = field(default_factory=list)
    conflicting_defaults: list[tuple[ir.Constraint, ir.Constraint]] = field(default_factory=list)
    nonlinear: list[ir.Constraint] = field(default_factory=list)
    reason: str = ""


def _position(c: ir.Constraint) -> tuple:
    return (c.span.uri, c.span.line, c.span.column)


def active_constraints(problem: ir.Problem, outcome: Outcome) -> list[ir.Constraint]:
    """The constraints that hold after the override rule (see module ``lower``).

    A default on a parameter is overridden by a hard constraint that has the
    parameter alone on the left of `==` or `in`, by `remove_default`, or by a
    later default of the same form; the rest stay.
    """
    hard_subjects: dict[str, ir.Constraint] = {}
    for c in problem.constraints:
        if c.strength == "hard" and c.subject is not None:
            hard_subjects.setdefault(c.subject.name, c)
    last_default: dict[str, ir.Constraint] = {}
    for c in problem.constraints:
        if c.strength == "default" and c.subject is not None:
            last_default[c.subject.name] = c
    active = []
    for c in problem.constraints:
        if c.strength != "default":
            active.append(c)
            continue
        subject = c.subject.name if c.subject is not None else None
        if subject is not None and subject in problem.removed_defaults:
            outcome.overridden.append((c, None))
        elif subject is not None and subject in hard_subjects:
            outcome.overridden.append((c, hard_subjects[subject]))
        elif subject is not None and last_default[subject] is not c:
            later = last_default[subject]
            if later.term != c.term and later.span.uri == c.span.uri:
                outcome.conflicting_defaults.append((later, c))
            outcome.overridden.append((c, later))
        else:
            active.append(c)
    return active


class _Encoder:
    def __init__(self, problem: ir.Problem, ctx: z3.Context):
        self.ctx = ctx
        self.vars: dict[str, z3.ExprRef] = {}
        for var in problem.variables.values():
            if var.sort == "real":
                self.vars[var.name] = z3.Real(var.name, ctx)
            elif var.sort == "bool":
                self.vars[var.name] = z3.Bool(var.name, ctx)
            else:
                self.vars[var.name] = z3.Int(var.name, ctx)

    def num(self, value: Fraction) -> z3.ExprRef:
        if value.denominator == 1:
            return z3.IntVal(value.numerator, self.ctx)
        return z3.RealVal(f"{value.numerator}/{value.denominator}", self.ctx)

    def term(self, t: ir.Term) -> z3.ExprRef:
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


def _value(expr: z3.ExprRef) -> Fraction | bool:
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


def solve(problem: ir.Problem, *, seed: int | None = None, rlimit: int = DEFAULT_RLIMIT,
          timeout_ms: int = DEFAULT_TIMEOUT_MS) -> Outcome:
    """Check the problem; report conflicts, or a model (a sample picked by ``seed``)."""
    outcome = Outcome("sat")
    active = active_constraints(problem, outcome)
    outcome.nonlinear = [c for c in active if ir.is_nonlinear(c.term)]
    ctx = z3.Context()
    enc = _Encoder(problem, ctx)
    solver = z3.Solver(ctx=ctx)
    solver.set("core.minimize", True)
    solver.set("rlimit", rlimit)
    solver.set("timeout", timeout_ms)
    literals: dict[str, ir.Constraint] = {}
    enabled: list[z3.ExprRef] = []
    for i, c in enumerate(active):
        lit = z3.Bool(f"c{i}", ctx)
        solver.add(z3.Implies(lit, enc.term(c.term)))
        literals[str(lit)] = c
        enabled.append(lit)

    result = solver.check(*enabled)
    while result == z3.unsat and len(outcome.conflicts) < MAX_CONFLICTS:
        core = _minimal_core(solver, [lit for lit in solver.unsat_core()])
        members = sorted((literals[str(lit)] for lit in core), key=_position)
        users = [c for c in members if c.kind in _USER_KINDS]
        primary = users[-1] if users else members[-1]
        outcome.conflicts.append(Conflict(primary, [c for c in members if c is not primary]))
        primary_lit = next(lit for lit in core if literals[str(lit)] is primary)
        enabled = [lit for lit in enabled if not lit.eq(primary_lit)]
        result = solver.check(*enabled)
    if outcome.conflicts:
        outcome.status = "unsat"
        return outcome
    if result != z3.sat:
        outcome.status = "unknown"
        outcome.reason = solver.reason_unknown()
        return outcome
    model = solver.model()
    if seed is not None:
        sample = _sample(problem, enc, [literals[str(lit)] for lit in enabled], model, seed,
                         rlimit, timeout_ms)
        if sample is not None:
            model = sample
    for name, var in enc.vars.items():
        outcome.values[name] = _value(model.eval(var, model_completion=True))
    return outcome


def _minimal_core(solver: z3.Solver, core: list[z3.ExprRef]) -> list[z3.ExprRef]:
    """Drop core members one by one while the rest stays unsatisfiable."""
    needed = list(core)
    i = 0
    while i < len(needed) and len(needed) > 1:
        trial = needed[:i] + needed[i + 1:]
        if solver.check(*trial) == z3.unsat:
            needed = trial
        else:
            i += 1
    return needed


def _sample(problem: ir.Problem, enc: _Encoder, constraints: list[ir.Constraint],
            model: z3.ModelRef, seed: int, rlimit: int, timeout_ms: int):
    """A model near a random target: spread over the feasible space, fixed by ``seed``."""
    rng = random.Random(seed)
    opt = z3.Optimize(ctx=enc.ctx)
    opt.set("timeout", timeout_ms)
    for c in constraints:
        opt.add(enc.term(c.term))
    distance = []
    for var in sorted(problem.variables.values(), key=lambda v: v.name):
        if var.sort == "bool":
            continue
        expr = enc.vars[var.name]
        base = _value(model.eval(expr, model_completion=True))
        if var.enum:
            target = enc.num(Fraction(rng.choice(var.enum)[1]))
        else:
            spread = abs(base) + (10 if var.sort == "real" else 3)
            offset = Fraction(rng.randint(-1000, 1000), 1000) * spread
            if var.sort == "int":
                offset = Fraction(round(offset))
            target = enc.num(base + offset)
        d = z3.Real(f"d_{var.name}", enc.ctx)
        opt.add(d >= expr - target, d >= target - expr)
        distance.append(d)
    if not distance:
        return None
    opt.minimize(z3.Sum(*distance))
    if opt.check() != z3.sat:
        return None
    return opt.model()
