"""Run-time values of OSC2 structs: one class per standard-library struct the runner
builds itself, and :class:`StructValue` for every other struct value.

The runner makes a struct value in two ways. It builds some itself from the
simulation (an actor's ``pose``, ``velocity``, ``bounding_box``, the weather, the
sun's position, a path through world points): those are the typed classes here,
named after their struct in ``stdlib/types.osc`` and ``stdlib/domain.osc`` and
holding exactly the members the runner fills (SI floats, enum members by name).
The checker's witness gives the others, any struct of any shape a scenario declares
(``osc2runner.instance.values``): a :class:`StructValue`, the struct's name and its
members by name.

Expressions read a member of either kind the same way, as an attribute
(``hero.pose.position.x``, ``p.points``). No member has a default here: the witness
or the simulation gives every value (the world is flat: ``z``, roll and pitch are 0
where the runner builds them).
"""

from __future__ import annotations

from dataclasses import dataclass, fields, is_dataclass
from typing import TYPE_CHECKING, SupportsFloat

if TYPE_CHECKING:
    from osc2runner.sim.tracking import Polyline

__all__ = [
    "Acceleration6d",
    "Air",
    "Angles3d",
    "BoundingBox",
    "CelestialPosition2d",
    "Clouds",
    "Fog",
    "HitchCoupler",
    "HitchReceiver",
    "Orientation3d",
    "OrientationAcceleration3d",
    "OrientationRate3d",
    "Path",
    "Pose3d",
    "Position3d",
    "Precipitation",
    "StructValue",
    "TranslationalAcceleration3d",
    "TranslationalVelocity3d",
    "Vector3d",
    "Velocity6d",
    "Weather",
    "Wind",
    "XyzPoint",
    "as_pose",
    "member_number",
    "struct_json",
    "struct_members",
]


class StructValue:
    """The value of a struct the runner knows only from its declaration (a witness's
    struct parameter, an event's arguments): ``struct`` names it, ``fields`` holds its
    members. A member reads and writes as an attribute (``value.position.x``;
    a ``var`` member such as a bulb's ``state`` is written while the run goes on)."""

    __slots__ = ("_fields", "_struct")
    _fields: dict[str, object]
    _struct: str

    def __init__(self, struct: str, fields: dict[str, object] | None = None) -> None:
        object.__setattr__(self, "_struct", struct)
        object.__setattr__(self, "_fields", {} if fields is None else fields)

    @property
    def struct(self) -> str:
        """The struct's name (``pose_3d``, ``traffic_light``, an event's name)."""
        return self._struct

    @property
    def fields(self) -> dict[str, object]:
        """The members given, by name."""
        return self._fields

    def __getattr__(self, member: str) -> object:
        if member in StructValue.__slots__:  # (copy and pickle ask before __init__ ran)
            raise AttributeError(member)
        try:
            return self._fields[member]
        except KeyError:
            raise AttributeError(f"`{self._struct}` has no member `{member}`") from None

    def __setattr__(self, member: str, value: object) -> None:
        self._fields[member] = value

    def __getstate__(self) -> tuple[str, dict[str, object]]:
        return self._struct, self._fields

    def __setstate__(self, state: tuple[str, dict[str, object]]) -> None:
        object.__setattr__(self, "_struct", state[0])
        object.__setattr__(self, "_fields", state[1])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, StructValue):
            return NotImplemented
        return self._struct == other._struct and self._fields == other._fields

    __hash__ = None  # type: ignore[assignment]  # mutable, as its members are

    def __repr__(self) -> str:
        members = ", ".join(f"{k}={v!r}" for k, v in self._fields.items())
        return f"{self._struct}({members})"


@dataclass(frozen=True, slots=True)
class Vector3d:
    """The members of the structs of three lengths, speeds or accelerations along x, y, z."""

    x: float
    y: float
    z: float


@dataclass(frozen=True, slots=True)
class Angles3d:
    """The members of the structs of three angles, rates or angular accelerations (about
    x, y, z)."""

    roll: float
    pitch: float
    yaw: float


@dataclass(frozen=True, slots=True)
class Position3d(Vector3d):
    """``position_3d``: world coordinates, m."""


@dataclass(frozen=True, slots=True)
class Orientation3d(Angles3d):
    """``orientation_3d``: angles, rad."""


@dataclass(frozen=True, slots=True)
class Pose3d:
    """``pose_3d``: a position and an orientation."""

    position: Position3d
    orientation: Orientation3d


@dataclass(frozen=True, slots=True)
class XyzPoint:
    """``xyz_point``: a point of the map given in world coordinates."""

    position: Position3d


@dataclass(frozen=True, slots=True)
class TranslationalVelocity3d(Vector3d):
    """``translational_velocity_3d``: m/s along x, y and z."""


@dataclass(frozen=True, slots=True)
class OrientationRate3d(Angles3d):
    """``orientation_rate_3d``: rad/s about x, y and z."""


@dataclass(frozen=True, slots=True)
class Velocity6d:
    """``velocity_6d``: a translational velocity and an orientation rate."""

    translational: TranslationalVelocity3d
    angular: OrientationRate3d


@dataclass(frozen=True, slots=True)
class TranslationalAcceleration3d(Vector3d):
    """``translational_acceleration_3d``: m/s² along x, y and z."""


@dataclass(frozen=True, slots=True)
class OrientationAcceleration3d(Angles3d):
    """``orientation_acceleration_3d``: rad/s² about x, y and z."""


@dataclass(frozen=True, slots=True)
class Acceleration6d:
    """``acceleration_6d``: a translational and an angular acceleration."""

    translational: TranslationalAcceleration3d
    angular: OrientationAcceleration3d


@dataclass(frozen=True, slots=True)
class BoundingBox:
    """``bounding_box``: the body's box, m; ``center`` from the actor's reference point."""

    center: Position3d
    length: float
    width: float
    height: float


@dataclass(frozen=True, slots=True)
class HitchReceiver:
    """``hitch_receiver`` of a vehicle: its place from the rear axle (m), and whether it
    tows now."""

    position_x: float
    position_z: float
    is_towing: bool


@dataclass(frozen=True, slots=True)
class HitchCoupler:
    """``hitch_coupler`` of a trailer: its place from the trailer's axle (m), and whether it
    is towed now."""

    position_x: float
    position_z: float
    is_towed: bool


@dataclass(frozen=True, slots=True)
class CelestialPosition2d:
    """``celestial_position_2d``: a body on the sky, rad (azimuth clockwise from North)."""

    azimuth: float
    elevation: float


@dataclass(frozen=True, slots=True)
class Path:
    """A ``path`` (or, with ``time_stamps``, a ``trajectory``) the runner makes: world
    poses joined by ``interpolation``; ``line``, when it runs along the road, is that
    line (an ``osc2runner.sim`` polyline the path actions follow)."""

    points: tuple[Pose3d, ...]
    interpolation: str
    time_stamps: tuple[float, ...] | None = None
    line: Polyline | None = None


# ---------------------------------------------------------------------- weather
# ``env.weather`` is a ``var``: the environment actions write its parts while the run
# goes on, so these are not frozen. Their values before any action are
# ``osc2runner.execution.context.initial_weather``'s.


@dataclass(slots=True)
class Air:
    """``air``: K, Pa and a relative humidity in [0, 1]."""

    temperature: float
    pressure: float
    relative_humidity: float


@dataclass(slots=True)
class Precipitation:
    """``precipitation`` (rain, snow): its intensity, m/s of water."""

    intensity: float


@dataclass(slots=True)
class Wind:
    """``wind``: m/s, and the direction it blows from, rad clockwise from North."""

    speed: float
    direction: float


@dataclass(slots=True)
class Fog:
    """``fog``: the visual range, m."""

    visual_range: float


@dataclass(slots=True)
class Clouds:
    """``clouds``: okta, 0 clear to 8 overcast, 9 sky obscured."""

    cloudiness: int


@dataclass(slots=True)
class Weather:
    """``weather``: its parts."""

    air: Air
    rain: Precipitation
    snow: Precipitation
    wind: Wind
    fog: Fog
    clouds: Clouds


def as_pose(value: object) -> Pose3d:
    """A ``pose_3d`` value as a :class:`Pose3d` (the witness's is a :class:`StructValue`)."""
    if isinstance(value, Pose3d):
        return value
    position, orientation = _struct(value, "position"), _struct(value, "orientation")
    return Pose3d(
        Position3d(*(member_number(position, k) for k in ("x", "y", "z"))),
        Orientation3d(*(member_number(orientation, k) for k in ("roll", "pitch", "yaw"))),
    )


def _struct(value: object, member: str) -> StructValue:
    found = value.fields.get(member) if isinstance(value, StructValue) else None
    if not isinstance(found, StructValue):
        raise TypeError(f"`{value!r}` has no struct member `{member}`")
    return found


def member_number(value: object, member: str) -> float:
    """The number ``member`` of a struct value, typed or generic (``p.x``), or of the
    object a plug-in's method gave for one; TypeError when it has none."""
    members = struct_members(value)
    found = members.get(member) if members is not None else getattr(value, member, None)
    if not isinstance(found, SupportsFloat):
        raise TypeError(f"`{value!r}` has no number `{member}`")
    return float(found)


def struct_members(value: object) -> dict[str, object] | None:
    """The members of a struct value by name; None for a value that is no struct value."""
    if isinstance(value, StructValue):
        return dict(value.fields)
    if is_dataclass(value) and type(value).__module__ == __name__:  # a class of this module
        return {f.name: getattr(value, f.name) for f in fields(value)}
    return None


def struct_json(value: object) -> object:
    """A struct value as JSON-ready nested dicts (a list for a list)."""
    members = struct_members(value)
    if members is not None:
        return {k: struct_json(v) for k, v in members.items()}
    if isinstance(value, tuple):
        return [struct_json(v) for v in value]
    return value
