"""``compile_scenario``: one scenario of an analysed program -> a py_trees tree.

One method per OSC2 construct. Every invocation is looked up in the method
registry; what the registry lacks, or what the runner cannot evaluate, is
collected as a :class:`~osc2runner.errors.RunProblem` with its location, and the
run does not start. Expressions become closures over the execution context
(:mod:`osc2runner.compile.expressions`).

A node's name is its OSC2 text and line, e.g. ``hero.drive() [34]``, so that
``py_trees.display.unicode_tree`` shows the scenario as written.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from typing import Any

import py_trees

from osc2check.capabilities import TRAILER_ACTIONS
from osc2check.semantics.bindings import CoverItem
from osc2check.semantics.builtins import PREDEFINED_EVENTS
from osc2check.semantics.constants import NotConstant, evaluate, to_runtime
from osc2check.semantics.members import declaration_bodies, do_labels, last_do, scenario_members
from osc2check.semantics.phases import is_acting, time_zero
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2check.verify.terms import invocation_path, join_path, one_of_choice
from osc2check.verify.timeline import PhaseKey
from osc2runner.behaviours.base import ActionUse, Modifier, ModifierUse
from osc2runner.compile.arguments import (
    call_arguments,
    checked_binding,
    instance_field,
    overlap_kind,
    scenario_arguments,
)
from osc2runner.compile.composites import (
    DurationBound,
    InvokedScenario,
    Labelled,
    OneOf,
    Parallel,
    ScenarioRoot,
    Serial,
)
from osc2runner.compile.conditions import (
    CallDirective,
    Emit,
    NamedEventWatch,
    OnHandler,
    Until,
    Wait,
    Watch,
    calls,
    compile_watch,
    emits,
    emits_now,
)
from osc2runner.compile.coverage import compile_coverage
from osc2runner.compile.environment import CompileEnvironment
from osc2runner.compile.expressions import (
    Bindings,
    Closure,
    Frame,
    constant,
    is_constant,
)
from osc2runner.compile.preparation import Choices, drop_concurrent_preparations, prepare_starts
from osc2runner.compile.sampling import is_sample, on_occurrence
from osc2runner.compile.text import node_name, unparse
from osc2runner.errors import CompileProblem, RunProblem
from osc2runner.execution.coverage import CoverageItem
from osc2runner.instance.actors import Actor
from osc2runner.instance.values import scenario_fields

__all__ = ["CompiledScenario", "compile_scenario"]

log = logging.getLogger(__name__)


@dataclass
class CompiledScenario:
    """The tree and what the initializer and the runner need besides it."""

    root: py_trees.behaviour.Behaviour
    start_uses: list[ActionUse] = field(default_factory=list)
    problems: list[RunProblem] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    #: each run-time coverage item with the checker's reading of its ``cover``/``record``
    cover_items: list[tuple[CoverageItem, CoverItem]] = field(default_factory=list)
    #: which acting member each ``one_of`` runs, by its instance's name (``Choices``)
    choices: dict[str, int] = field(default_factory=dict)


def compile_scenario(
    env: CompileEnvironment, scenario: Symbol, texts: dict[str, str] | None = None
) -> CompiledScenario:
    """Compile ``scenario`` against ``env``; problems are collected, not raised."""
    return TreeCompiler(env, texts or {}).scenario(scenario)


class TreeCompiler:
    """Walks one scenario's declarations and behaviour (see the module docstring)."""

    def __init__(self, env: CompileEnvironment, texts: dict[str, str]) -> None:
        self.env = env
        self.run = env.run
        self.model = env.model
        self.texts = texts
        self.problems: list[RunProblem] = []
        self.notes: list[str] = []
        self.cover_items: list[tuple[CoverageItem, CoverItem]] = []
        self.uses: dict[ast.Invocation, tuple[ActionUse, type]] = {}
        self.waits: dict[ast.Wait, Wait] = {}  # the last compiled node of each wait
        self.labels: dict[int, ast.Name] = {}  # the label of an invocation, by node id
        self.invoking: list[Symbol] = []  # the scenarios being compiled, outermost first
        self.bodies = declaration_bodies(self.model)
        self.choices = Choices(self.run.seed)

    # ---- helpers

    def _problem(self, exc: CompileProblem) -> None:
        self.problems.append(exc.problem)

    def _text(self, node: ast.Node, limit: int = 60) -> str:
        """The node's OSC2 text, shortened (display names, messages)."""
        if isinstance(
            node, (ast.Expr, ast.Argument, ast.EventReference, ast.EventCondition, ast.Emit)
        ):
            piece = unparse(node)
        else:
            text = self.texts.get(node.span.uri)
            if text is None:
                return type(node).__name__
            piece = " ".join(text[node.span.start : node.span.end].split())
        return piece if len(piece) <= limit else piece[: limit - 3] + "..."

    def _failed(self, name: str) -> py_trees.behaviour.Behaviour:
        return py_trees.behaviours.Failure(name=name)

    # ---- scenario

    def scenario(self, scenario: Symbol) -> CompiledScenario:
        run = self.run
        for name in PREDEFINED_EVENTS:
            run.declare_event(name)
        events = self._event_names(scenario)
        for name in events:
            run.declare_event(name)
        self._variables(scenario)
        self._declared_events(scenario)
        members = scenario_members(self.model, self.bodies, scenario)
        do = last_do(members)
        frame = Frame(
            "",
            scenario,
            at_start=frozenset(time_zero(do.member.body).starts) if do else frozenset(),
            events=events,
            labels=do_labels(do),
        )
        scope = Bindings(frame=frame)
        handlers: list[py_trees.behaviour.Behaviour] = []
        for member in members:
            match member:
                case ast.OnDirective():
                    handler = self._guard(partial(self.on, member, scope), member)
                    if handler is not None:
                        handlers.append(handler)
                case ast.Invocation():
                    self._scenario_modifier(member)
                case ast.CoverageDecl():
                    self._guard(partial(self.coverage, member), member)
        self.invoking.append(scenario)
        if do is None:
            main: py_trees.behaviour.Behaviour = Serial("do (empty)")
        else:
            main = self._guard(lambda: self.do_member(do.member, scope), do) or self._failed("do")
        root = ScenarioRoot(
            node_name(f"scenario {scenario.name}", scenario.decl or do or ast.Missing(_no_span())),
            main,
            handlers,
        )
        return CompiledScenario(
            root,
            self._start_uses(do),
            self.problems,
            self.notes,
            self.cover_items,
            self.choices.finish(),
        )

    def _event_names(self, scenario: Symbol) -> frozenset[str]:
        return frozenset(
            m.name for m in self.model.all_members(scenario) if m.kind is SymbolKind.EVENT
        )

    def _guard(self, build: Callable[[], Any], node: ast.Node) -> Any:
        try:
            return build()
        except CompileProblem as exc:
            self._problem(exc)
            return None

    def _variables(self, scenario: Symbol) -> None:
        """``var`` fields with an initialiser: a constant one (over the parameters' values)
        is set now; one that holds a ``sample(...)`` is live (it reads the sample's value
        at the last occurrence of its event so far, :mod:`osc2runner.compile.sampling`);
        another is evaluated at tick 0, over the live state. A ``var`` is never read from
        the checker's witness: the witness gives parameters only."""
        env = self.env
        values = env.values
        for sym in scenario_fields(self.model, scenario):
            if sym.kind is not SymbolKind.VARIABLE or sym.name in env.actors:
                continue
            default = sym.default
            env.variable_symbols.add(sym)
            if default is None:
                continue
            if any(is_sample(node) for node in walk(default)):
                try:
                    env.compiler.live_variables[sym] = env.compile(default)
                except CompileProblem as exc:
                    self._problem(exc)
                continue
            try:
                value = evaluate(default, self.model, lambda field, node: _parameter(values, field))
                env.run.variables[sym.name] = to_runtime(value)
                continue
            except NotConstant:
                pass
            try:
                fn = env.compile(default)
            except CompileProblem as exc:
                self._problem(exc)
                continue
            env.variable_inits.append((sym.name, fn))

    def _event_specs(self, scenario: Symbol) -> list[tuple[Symbol, ast.EventDecl, ast.Node]]:
        """The ``event e is <spec>`` members of ``scenario`` (§7.3.10.2): each event's
        symbol, declaration and spec."""
        found: list[tuple[Symbol, ast.EventDecl, ast.Node]] = []
        for sym in self.model.all_members(scenario):
            decl = sym.decl
            if sym.kind is SymbolKind.EVENT and isinstance(decl, ast.EventDecl):
                if decl.spec is not None:
                    found.append((sym, decl, decl.spec))
        return found

    def _declared_events(self, scenario: Symbol) -> None:
        """``event e is <spec>`` of the root scenario: ``e`` occurs whenever its spec
        occurs, watched from the scenario's start (its event context) through
        :func:`on_occurrence` (an ``@x`` spec occurs at once with ``x``, also when ``x``
        is emitted later in the tick than the scenario's handlers run); logged as kind
        ``event``."""
        run = self.run
        for sym, _, spec in self._event_specs(scenario):
            try:
                watch = self.watch(spec, Bindings())
            except CompileProblem as exc:
                self._problem(exc)
                continue
            on_occurrence(run, watch, partial(run.emit, sym.name, kind="event"))

    def _declared_event_handlers(
        self, scenario: Symbol, scope: Bindings
    ) -> list[py_trees.behaviour.Behaviour]:
        """``event e is <spec>`` of an invoked scenario: ``e`` of the instance occurs
        whenever its spec does while the instance runs (its event context)."""
        run = self.run
        handlers: list[py_trees.behaviour.Behaviour] = []
        for sym, decl, spec in self._event_specs(scenario):
            name = scope.event((sym.name,))
            watch = self.watch(spec, scope)
            handlers.append(
                OnHandler(
                    node_name(f"event {sym.name}", decl),
                    watch,
                    [emits(run, name)],
                )
            )
        return handlers

    def _scenario_modifier(self, member: ast.Invocation) -> None:
        sym = self.model.references.get(member.name)
        if (
            sym is not None
            and sym.kind is SymbolKind.MODIFIER
            and self.env.registry.find_modifier(self.model, sym) is not None
            and sym.actor is not None
            and sym.actor.name in ("map", "stationary_object")
        ):
            return  # the road, an object's location: chosen before compiling (instance)
        self._problem(
            CompileProblem(
                f"`{self._text(member)}`: modifiers applied to the whole scenario are not "
                "supported by the runner",
                member,
            )
        )

    # ---- behaviour

    def do_member(self, member: ast.DoMember, scope: Bindings) -> py_trees.behaviour.Behaviour:
        body = member.body
        node: py_trees.behaviour.Behaviour
        if member.label is not None and not member.label.missing:
            self.labels[id(body)] = member.label
        try:
            match body:
                case ast.Composition():
                    node = self.composition(body, scope)
                case ast.Invocation():
                    node = self.invocation(body, scope)
                case ast.Wait():
                    node = self.wait(body, scope)
                case ast.Emit():
                    node = self.emit(body, scope)
                case ast.CallDirective():
                    node = self.call(body, scope)
                case _:
                    raise CompileProblem("the runner cannot run this member", body)
        except CompileProblem as exc:
            self._problem(exc)
            node = self._failed(node_name(self._text(body), body))
        if member.label is not None and not member.label.missing:
            label = member.label.text
            qualified = scope.frame.qualified(label) if scope.frame is not None else label
            for suffix in PREDEFINED_EVENTS:
                self.run.declare_event(f"{qualified}.{suffix}")
            node = Labelled(node_name(f"{label}:", member), node, qualified)
        return node

    def composition(self, comp: ast.Composition, scope: Bindings) -> py_trees.behaviour.Behaviour:
        args = {b.name: b.value for b in checked_binding(self.env, comp).extras}
        children = [self.do_member(m, scope) for m in comp.members]
        name = node_name(comp.op, comp)
        node: py_trees.behaviour.Behaviour
        if comp.op == "serial":
            node = Serial(name, children)
            prepare_starts(comp, self.uses, self.waits, self.choices, self.model)
        elif comp.op == "parallel":
            overlap = "start"
            if "overlap" in args:
                overlap = overlap_kind(args["overlap"])
            for key in ("start_to_start", "end_to_end"):
                if key in args:
                    raise CompileProblem(
                        f"parallel({key}: ...) is not supported by the runner: it starts every "
                        "member with the composition",
                        args[key],
                    )
            span = comp.span
            plans = [self.run.schedule.get(_phase_key(scope, m.body)) for m in comp.members]
            node = Parallel(name, children, overlap, f"{span.uri}:{span.line}:{span.column}", plans)
            drop_concurrent_preparations(comp, self.uses, self.waits)
        elif comp.op == "one_of":
            acting = [is_acting(m.body) for m in comp.members]
            node = OneOf(name, children, acting)
            path = scope.frame.path if scope.frame is not None else ""
            choice = one_of_choice(path, comp)
            self.choices.add(comp, choice, node, self._chosen_member(choice))
        else:
            raise CompileProblem(f"unknown composition `{comp.op}`", comp)
        node.phase_key = _phase_key(scope, comp)
        untils = self._untils(comp.with_members, "a composition")
        return self._wrap(node, comp, args.get("duration"), untils, scope)

    def _chosen_member(self, name: str) -> int | None:
        """The acting member of a ``one_of`` the witness chose (the placement placed the
        actors for it: ``verify.terms.one_of_choice``), or None (the seed chooses)."""
        chosen = self.env.values.witness.parameter(name)
        if chosen is None or isinstance(chosen.value, bool):
            return None
        return int(chosen.value)

    def _untils(self, with_members: tuple[ast.WithMember, ...], what: str) -> list[ast.Until]:
        """The ``until``s of the ``with:`` block of ``what`` (a composition, a scenario
        invocation), which takes no modifiers in the runner; its ``keep``s are the
        solver's."""
        untils: list[ast.Until] = []
        for wm in with_members:
            if isinstance(wm, ast.Until):
                untils.append(wm)
            elif isinstance(wm, ast.Invocation):
                raise CompileProblem(
                    f"`{self._text(wm)}`: modifiers on {what} are not supported by the runner",
                    wm,
                )
            else:
                self.notes.append(
                    f"line {wm.span.line}: a constraint on {what} is left to the solver"
                )
        return untils

    def _wrap(
        self,
        node: py_trees.behaviour.Behaviour,
        owner: ast.Node,
        duration: ast.Node | None,
        untils: list[ast.Until],
        scope: Bindings,
    ) -> py_trees.behaviour.Behaviour:
        # `until` ends the phase whenever its event occurs, also before a `duration`'s
        # lower bound: it wraps the duration's bound
        if duration is not None:
            bounds = self._bounds(self.env.compile(duration, scope))
            span = owner.span
            node = DurationBound(
                node_name(f"duration: {self._text(duration)}", duration),
                node,
                bounds,
                f"{span.uri}:{span.line}:{span.column}",
            )
        for until in untils:
            watch = self.watch(until.event, scope)
            node = Until(node_name(f"until {self._text(until.event)}", until), node, watch)
        return node

    @staticmethod
    def _bounds(fn: Closure) -> Callable[[], tuple[float | None, float | None]]:
        def bounds() -> tuple[float | None, float | None]:
            value = fn()
            if isinstance(value, tuple):
                lo, hi = sorted(float(v) for v in value)
                return lo, hi
            return float(value), float(value)

        return bounds

    # ---- invocations

    def invocation(self, inv: ast.Invocation, scope: Bindings) -> py_trees.behaviour.Behaviour:
        sym = self.model.references.get(inv.name)
        if sym is None:
            raise CompileProblem(f"`{inv.name.text}` is not a behaviour the runner knows", inv)
        if sym.kind is SymbolKind.SCENARIO:
            return self.scenario_invocation(inv, sym, scope)
        if sym.kind is not SymbolKind.ACTION:
            raise CompileProblem(f"`{inv.name.text}` is a {sym.kind.value}, not an action", inv)
        if sym.actor is None and inv.actor is None:
            return self._unbound_action(inv, sym, scope)
        actor = self._actor(inv, scope)
        if not isinstance(actor, Actor):
            raise CompileProblem(
                "the actor of an action must be an actor field of the scenario", inv.actor
            )
        entry = self.env.registry.find_action(self.model, actor.type, sym)
        label = f"{actor.type.name}.{sym.name}"
        if entry is None:
            raise CompileProblem(
                f"action `{label}` has no runner behaviour (see "
                "docs/coverage.md for what the runner supports)",
                inv.name,
            )
        if actor.kind == "trailer" and sym.name not in TRAILER_ACTIONS:
            raise CompileProblem(
                f"`{actor.name}` is a trailer: it has no engine or driver and moves only when "
                f"a vehicle tows it (`connect_trailer`), so `{sym.name}` cannot act on it",
                inv.name,
            )
        # the arguments, modifiers and `until` of an action are written in the scenario's
        # scope: `actor` there is the scenario's actor, not the action's
        inner = scope
        path = invocation_path(
            scope.frame.path if scope.frame is not None else "",
            actor.name,
            self.labels.get(id(inv)),
            sym.name,
            inv,
        )
        arguments, duration = call_arguments(
            self.env, inv, inner, path, defaults=getattr(entry.target, "with_defaults", False)
        )
        modifiers: list[Modifier] = []
        untils: list[ast.Until] = []
        for wm in inv.with_members:
            if isinstance(wm, ast.Invocation):
                modifiers.append(self.modifier(wm, actor, inner, path))
            elif isinstance(wm, ast.Until):
                untils.append(wm)
            else:
                self.notes.append(
                    f"line {wm.span.line}: `{self._text(wm)}` is left to the "
                    "solver (not enforced at run time)"
                )
        key = _phase_key(scope, inv)
        use = ActionUse(
            inv,
            sym,
            actor,
            arguments,
            modifiers,
            self._bounds(self.env.compile(duration, inner)) if duration else None,
            starts_scenario=scope.frame is not None and inv in scope.frame.at_start,
            binding=self.model.binding(inv),
            key=key,
            plan=self.run.schedule.get(key),
        )
        cls = entry.target
        use.behaviour = cls
        behaviour = cls(node_name(f"{actor.name}.{sym.name}()", inv), use)
        behaviour.open_ended = not cls.finite and duration is None and not untils
        behaviour.endless = not cls.finite
        self.uses[inv] = (use, cls)
        return self._wrap(behaviour, inv, duration, untils, inner)

    def _unbound_action(
        self, inv: ast.Invocation, sym: Symbol, scope: Bindings
    ) -> py_trees.behaviour.Behaviour:
        """An action declared without an actor (``action log:``), which a plug-in
        implements: it takes arguments, ``duration`` and ``until``, no modifiers."""
        entry = self.env.registry.find_action(self.model, None, sym)
        if entry is None:
            raise CompileProblem(
                f"action `{sym.name}` has no runner behaviour (docs/plugins.md)", inv.name
            )
        path = invocation_path(
            scope.frame.path if scope.frame is not None else "",
            None,
            self.labels.get(id(inv)),
            sym.name,
            inv,
        )
        arguments, duration = call_arguments(self.env, inv, scope, path, defaults=True)
        untils = [wm for wm in inv.with_members if isinstance(wm, ast.Until)]
        for wm in inv.with_members:
            if isinstance(wm, ast.Invocation):
                raise CompileProblem(f"`{sym.name}` has no actor: it takes no modifiers", wm)
        behaviour = entry.target(node_name(f"{sym.name}()", inv), inv, arguments)
        return self._wrap(behaviour, inv, duration, untils, scope)

    def _actor(self, inv: ast.Invocation, scope: Bindings) -> Actor:
        """The actor an invocation is of: written, or the actor of the enclosing
        actor-associated scenario."""
        if inv.actor is None:
            implicit = scope.lookup("actor")
            value = implicit() if implicit is not None and is_constant(implicit) else None
            if not isinstance(value, Actor):
                raise CompileProblem(
                    f"`{inv.name.text}()` needs an actor (`hero.{inv.name.text}()`)", inv
                )
            return value
        actor = self.env.compiler.constant_value(inv.actor, scope)
        if not isinstance(actor, Actor):
            raise CompileProblem(
                "the actor of an action must be an actor field of the scenario", inv.actor
            )
        return actor

    def _actor_type(self, node: ast.Node) -> bool:
        """Whether ``node`` names an actor type, not an actor (``dut.cut_in()`` with
        ``actor dut``): the scenario of that type is invoked with no actor of its own,
        as the checker reads it (docs/runner.md)."""
        if not isinstance(node, ast.NameRef):
            return False
        sym = self.model.references.get(node.name.name)
        return isinstance(sym, Symbol) and sym.kind is SymbolKind.ACTOR

    def scenario_invocation(
        self, inv: ast.Invocation, sym: Symbol, scope: Bindings
    ) -> py_trees.behaviour.Behaviour:
        """An invoked scenario, compiled in place as an instance of its own (§7.3.8).

        Its parameters take the witness's values at the instance's path; its actor
        parameters are the actors its arguments pass; ``actor`` is the invoking actor
        of an actor-associated scenario; its events, labels and variables are the
        instance's own (qualified by its path); its ``var``s are initialised when it
        starts. ``duration``, ``until`` and the invocation's label apply as to any
        invocation; recursion is refused with its cycle.
        """
        if sym in self.invoking:
            cycle = " -> ".join(s.name for s in [*self.invoking[self.invoking.index(sym) :], sym])
            raise CompileProblem(f"scenario `{sym.name}` invokes itself ({cycle})", inv)
        outer = scope.frame
        assert outer is not None
        actor: Actor | None = None
        if inv.actor is not None and not self._actor_type(inv.actor):
            actor = self._actor(inv, scope)
        elif sym.actor is not None:
            implicit = scope.lookup("actor")
            value = implicit() if implicit is not None and is_constant(implicit) else None
            actor = value if isinstance(value, Actor) else None
        label = self.labels.get(id(inv))
        path = invocation_path(outer.path, actor.name if actor else None, label, sym.name, inv)
        given, duration = scenario_arguments(self.env, inv)
        members = scenario_members(self.model, self.bodies, sym)
        do = last_do(members)
        at_start: frozenset[ast.Node] = frozenset()
        if do is not None and inv in outer.at_start:
            at_start = frozenset(time_zero(do.member.body).starts)
        events = self._event_names(sym)
        frame = Frame(
            path,
            sym,
            {},
            constant(actor) if actor else None,
            at_start,
            parent=outer,
            events=events,
            labels=do_labels(do),
        )
        inner = Bindings(frame=frame, bindings={"actor": constant(actor)} if actor else None)
        initialisers: list[Callable[[], None]] = []
        for param in self.model.all_members(sym):
            if param.kind in (SymbolKind.FIELD, SymbolKind.VARIABLE):
                frame.fields[param] = instance_field(
                    self.env, param, frame, given, inv, scope, inner, initialisers
                )
        for event in (*PREDEFINED_EVENTS, *events):
            self.run.declare_event(frame.qualified(event))
        for m in members:
            if isinstance(m, ast.CoverageDecl):
                raise CompileProblem(
                    f"`{sym.name}` is invoked: the runner collects `{m.kind}` items of the root "
                    "scenario only",
                    m,
                )
            if isinstance(m, ast.Invocation):
                self._scenario_modifier(m)
        self.invoking.append(sym)
        try:
            main = (
                self.do_member(do.member, inner)
                if do is not None
                else Serial(node_name(f"{sym.name} (empty)", inv))
            )
            handlers = [
                self.on(m, inner) for m in members if isinstance(m, ast.OnDirective)
            ] + self._declared_event_handlers(sym, inner)
        finally:
            self.invoking.pop()
        labelled_as = outer.qualified(label.text) if label is not None else None
        invoked = InvokedScenario(
            node_name(f"{actor.name + '.' if actor else ''}{sym.name}()", inv),
            main,
            handlers,
            path,
            initialisers,
            emits_events=labelled_as != path,
        )
        invoked.phase_key = _phase_key(scope, inv)
        untils = self._untils(inv.with_members, "a scenario invocation")
        return self._wrap(invoked, inv, duration, untils, scope)

    def modifier(self, wm: ast.Invocation, actor: Actor, scope: Bindings, path: str) -> Modifier:
        """A modifier applied in an action's ``with:`` (``path``: the action's instance)."""
        sym = self.model.references.get(wm.name)
        if sym is None or sym.kind is not SymbolKind.MODIFIER:
            raise CompileProblem(f"`{wm.name.text}` is not a modifier the runner knows", wm)
        entry = self.env.registry.find_modifier(self.model, sym)
        if entry is None:
            raise CompileProblem(
                f"modifier `{sym.qualified_name}` has no runner behaviour (see "
                "docs/coverage.md for what the runner supports)",
                wm.name,
            )
        arguments, _ = call_arguments(
            self.env,
            wm,
            scope,
            join_path(path, f"{sym.name}@{wm.span.line}"),
            defaults=getattr(entry.target, "with_defaults", False),
        )
        arguments.setdefault("at", constant("all"))
        if wm.with_members:
            self.notes.append(f"line {wm.span.line}: the with: block of a modifier is ignored")
        modifier: Modifier = entry.target(
            ModifierUse(wm, sym, arguments, actor, self.model.binding(wm))
        )
        return modifier

    # ---- events

    def wait(self, wait: ast.Wait, scope: Bindings) -> py_trees.behaviour.Behaviour:
        """``wait <event>``: its event context is the wait (§7.3.10.3)."""
        node = self.waits[wait] = Wait(
            node_name(f"wait {self._text(wait.event)}", wait), self.watch(wait.event, scope)
        )
        key = node.phase_key = _phase_key(scope, wait)
        node.plan = self.run.schedule.get(key)  # (a wait's companions plan against its end)
        return node

    def emit(self, emit: ast.Emit, scope: Bindings) -> py_trees.behaviour.Behaviour:
        name, key, args = self._emission(emit, scope)
        return Emit(node_name(self._text(emit), emit), name, key, args)

    def _emission(self, emit: ast.Emit, scope: Bindings) -> tuple[str, str, dict[str, Closure]]:
        """The event, its blackboard key and its argument closures, by parameter name in
        declaration order: positional arguments in order, then named ones; a parameter
        not given takes its default (an input error when it has none)."""
        name = scope.event((emit.event.text,))
        key = self.run.declare_event(name)
        binding = self.model.binding(emit)
        sym = self.model.references.get(emit.event)
        args: dict[str, Closure] = {}
        for p in sym.parameters if sym is not None else ():
            bound = binding.argument(p.name) if binding is not None else None
            if bound is None:
                raise CompileProblem(f"`emit {name}` needs its argument `{p.name}`", emit)
            args[p.name] = self.env.compile(bound.value, Bindings() if bound.is_default else scope)
        return name, key, args

    def call(self, call: ast.CallDirective, scope: Bindings) -> py_trees.behaviour.Behaviour:
        """``call m(args)`` as a member of ``do``: the call is evaluated once."""
        return CallDirective(
            node_name(f"call {self._text(call.call)}", call), self.env.compile(call.call, scope)
        )

    def on(self, on: ast.OnDirective, scope: Bindings) -> py_trees.behaviour.Behaviour:
        """``on <event>: emit ... / call ...``: the event context is the scenario (its
        instance, ``scope``); an ``as`` alias of the event is visible in the members."""
        watch = self.watch(on.event, scope)
        event = on.event
        if isinstance(event, ast.EventReference) and event.alias is not None:
            cell = watch.cell if isinstance(watch, NamedEventWatch) else None
            scope = scope.child(**{event.alias.text: lambda c=cell: c[0] if c else None})
        members: list[Callable[[Any], None]] = []
        keys: list[str] = []
        env, run = self.env, self.run
        for member in on.members:
            if isinstance(member, ast.Emit):
                name, key, args = self._emission(member, scope)
                keys.append(key)
                members.append(emits_now(run, name, key, args))
            elif isinstance(member, ast.CallDirective):
                call = env.compile(member.call, scope)
                members.append(calls(call))
        return OnHandler(node_name(f"on {self._text(on.event)}", on), watch, members, keys)

    def coverage(self, decl: ast.CoverageDecl) -> None:
        """``cover(...)`` / ``record(...)``: an item of the run's coverage, sampled at its
        event (:mod:`osc2runner.compile.coverage`)."""
        source = self.model.cover_item(decl)
        if source is None:
            raise CompileProblem(f"`{decl.kind}` was not read by the checker", decl)
        item = compile_coverage(self.env, source, self.notes)
        self.run.coverage.items.append(item)
        self.cover_items.append((item, source))

    def watch(self, spec: ast.Node, scope: Bindings) -> Watch:
        """The watch of an event spec (:func:`osc2runner.compile.conditions.compile_watch`)."""
        return compile_watch(self.env, spec, scope)

    # ---- the phases that start the scenario

    def _start_uses(self, do: ast.DoDirective | None) -> list[ActionUse]:
        """The compiled invocations that begin at time 0 (``semantics.phases``)."""
        if do is None:
            return []
        found = []
        for inv in time_zero(do.member.body).starts:
            entry = self.uses.get(inv)
            if entry is not None:
                found.append(entry[0])
        return found


def _phase_key(scope: Bindings, node: ast.Node) -> PhaseKey:
    """The schedule's name of the phase ``node`` runs (``osc2check.verify.schedule``)."""
    return (scope.frame.path if scope.frame is not None else "", node.span)


def _parameter(values: Any, field: Symbol) -> Any:
    """A parameter's value from the witness; a ``var`` is not constant (not a parameter)."""
    if field.kind is SymbolKind.VARIABLE:
        raise NotConstant(f"`{field.name}` is a variable")
    return values.value(field)


def _no_span() -> Any:
    from osc2check.source import Span

    return Span("", 0, 0, 0, 0)
