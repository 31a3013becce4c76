"""The CompileEnvironment: what compiling a scenario reads, apart from the run it compiles for.

The model (names, types), the parameter values of the instance (the witness),
the method registry, and the :class:`~osc2runner.execution.context.RunContext`
whose live state the compiled closures will read. Compiling never runs
anything: it builds the behaviour tree and the closures, declares the events
and the edge detectors in the run context, and records which ``var`` fields are
initialised when the run starts.
"""

from __future__ import annotations

import math

from osc2check.semantics.constants import to_runtime
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol
from osc2check.syntax import ast
from osc2runner.compile.expressions import (
    Bindings,
    Closure,
    ExpressionCompiler,
    PositionOf,
    constant,
)
from osc2runner.compile.registry import MethodRegistry
from osc2runner.compile.sampling import Sampler, compile_sample
from osc2runner.errors import CompileProblem
from osc2runner.execution.context import RunContext, RunFault
from osc2runner.instance.actors import Actor
from osc2runner.instance.values import ScenarioValues
from osc2runner.sim import ActorState, VehicleParams
from osc2runner.sim.sky import LightSource
from osc2runner.sim.trailer import TrailerParams
from osc2runner.structs import (
    Acceleration6d,
    BoundingBox,
    HitchCoupler,
    HitchReceiver,
    Orientation3d,
    OrientationAcceleration3d,
    OrientationRate3d,
    Pose3d,
    Position3d,
    TranslationalAcceleration3d,
    TranslationalVelocity3d,
    Velocity6d,
)

__all__ = ["CompileEnvironment"]


class CompileEnvironment:
    """Model, values, registry and the run context a scenario is compiled against.

    Parameters:
        model: the program's model.
        values: the parameter values of the scenario instance (the witness).
        registry: the method registry (actions, modifiers, methods).
        run: the run context the compiled tree and closures belong to.
    """

    def __init__(
        self, model: Model, values: ScenarioValues, registry: MethodRegistry, run: RunContext
    ) -> None:
        self.model = model
        self.values = values
        self.registry = registry
        self.run = run
        self.variable_symbols: set[Symbol] = set()
        self.variable_inits: list[tuple[str, Closure]] = []
        self.compiler = ExpressionCompiler(self)

    @property
    def actors(self) -> dict[str, Actor]:
        return self.run.actors

    def compile(self, expr: ast.Node, scope: Bindings | None = None) -> Closure:
        """Compile an expression to a closure over the run context."""
        return self.compiler.compile(expr, scope)

    def sample(self, call: ast.Call, scope: Bindings, text: str) -> tuple[Closure, Sampler]:
        """The closure reading ``sample(...)`` and its sampler (registered with the run)."""
        return compile_sample(self, call, scope, text)

    def actor_member(
        self, actor: Actor, member: str, sym: Symbol | None, node: ast.Node
    ) -> Closure:
        """A closure for ``actor.member`` (live state or a constant attribute)."""
        states = self.run.states
        n = actor.name
        if member == "position" and sym is not None and sym.toolkit:
            return constant(PositionOf(actor))
        if actor.has_body:
            if member == "speed":
                return lambda: states[n].speed
            if member == "velocity":
                return lambda: _velocity(states[n])
            if member == "acceleration":
                return lambda: _acceleration(states[n])
            if member == "pose":
                return lambda: _pose(states[n])
            if member == "bounding_box" and actor.params is not None:
                p = actor.params
                box = BoundingBox(Position3d(0.0, 0.0, 0.0), p.length, p.width, p.height)
                return constant(box)
            hitch = self._hitch_member(actor, member, node)
            if hitch is not None:
                return hitch
        if actor.kind == "environment" and member == "weather":
            run = self.run
            return lambda: run.weather
        if actor.kind == "environment" and member in ("sun", "moon"):
            # its position is read live; one nothing gives is a run fault here
            return constant(LightSource(member, self.run.sky, lambda why: RunFault(why, node)))
        if actor.kind == "environment" and member == "datetime":
            # the world's clock runs with the simulation (sim.sky, one home)
            return self.run.sky.now
        if member in actor.attributes:
            return constant(to_runtime(actor.attributes[member]))
        if member == "name":
            return constant(actor.name)
        if member == "model" and actor.blueprint is not None:
            return constant(actor.blueprint)
        raise CompileProblem(f"the runner cannot read `{actor.name}.{member}`", node)

    def _hitch_member(self, actor: Actor, member: str, node: ast.Node) -> Closure | None:
        """``v.trailer_receiver`` (a vehicle's: ``is_towing``, its place from the rear axle),
        ``t.coupler`` (a trailer's: ``is_towed``, its place from its axle) and
        ``t.tow_vehicle``, live."""
        run, n, p = self.run, actor.name, actor.params

        def tow() -> str | None:
            return run.attached_world.hitched.get(n)

        def towing() -> bool:
            return run.attached_world.towing(n) is not None

        if member == "trailer_receiver" and isinstance(p, VehicleParams):
            if p.receiver_x is None:
                raise CompileProblem(f"`{n}` has no hitch receiver: it tows nothing", node)
            x, z = p.receiver_x - p.rear_axle_x, p.hitch_height
            return lambda: HitchReceiver(x, z, is_towing=towing())
        if member == "coupler" and isinstance(p, TrailerParams):
            x, z = p.wheelbase, p.coupler_height
            return lambda: HitchCoupler(x, z, is_towed=tow() is not None)
        if member == "tow_vehicle" and isinstance(p, TrailerParams):

            def tow_vehicle() -> Actor:
                name = tow()
                if name is None:
                    raise RunFault(f"`{n}.tow_vehicle` has no value: `{n}` is not towed", node)
                return run.actors[name]

            return tow_vehicle
        return None


def _velocity(s: ActorState) -> Velocity6d:
    c, sn = math.cos(s.yaw), math.sin(s.yaw)
    vx = s.speed * c - s.lateral_speed * sn
    vy = s.speed * sn + s.lateral_speed * c
    return Velocity6d(
        TranslationalVelocity3d(x=vx, y=vy, z=0.0),
        OrientationRate3d(roll=0.0, pitch=0.0, yaw=s.yaw_rate),
    )


def _acceleration(s: ActorState) -> Acceleration6d:
    ax, ay = s.accel * math.cos(s.yaw), s.accel * math.sin(s.yaw)
    return Acceleration6d(
        TranslationalAcceleration3d(x=ax, y=ay, z=0.0),
        OrientationAcceleration3d(roll=0.0, pitch=0.0, yaw=0.0),
    )


def _pose(s: ActorState) -> Pose3d:
    return Pose3d(Position3d(x=s.x, y=s.y, z=0.0), Orientation3d(roll=0.0, pitch=0.0, yaw=s.yaw))
