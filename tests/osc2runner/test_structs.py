"""Run-time struct values (osc2runner.structs): the typed classes the runner builds and the
generic StructValue the witness gives read alike, and convert to JSON alike."""

from __future__ import annotations

import copy
import pickle

import pytest

from osc2runner.structs import (
    Orientation3d,
    Path,
    Pose3d,
    Position3d,
    StructValue,
    as_pose,
    member_number,
    struct_json,
    struct_members,
)


def _witness_pose(x: float, y: float, yaw: float) -> StructValue:
    return StructValue(
        "pose_3d",
        {
            "position": StructValue("position_3d", {"x": x, "y": y, "z": 0.0}),
            "orientation": StructValue("orientation_3d", {"roll": 0.0, "pitch": 0.0, "yaw": yaw}),
        },
    )


def test_a_struct_value_reads_and_writes_its_members_as_attributes():
    bulb = StructValue("traffic_light_bulb", {"color": "red", "icon": "circle"})
    assert bulb.struct == "traffic_light_bulb" and bulb.color == "red"
    bulb.state = "is_on"  # a `var` member, written while the run goes on
    assert bulb.fields == {"color": "red", "icon": "circle", "state": "is_on"}
    with pytest.raises(AttributeError, match="`traffic_light_bulb` has no member `size`"):
        _ = bulb.size
    assert repr(bulb) == "traffic_light_bulb(color='red', icon='circle', state='is_on')"


def test_a_struct_value_compares_by_struct_and_members_and_survives_copy_and_pickle():
    pose = _witness_pose(1.0, 2.0, 0.5)
    assert pose == _witness_pose(1.0, 2.0, 0.5) and pose != _witness_pose(1.0, 2.0, 0.0)
    assert StructValue("a", {"x": 1}) != StructValue("b", {"x": 1})
    for again in (copy.deepcopy(pose), pickle.loads(pickle.dumps(pose))):
        assert again == pose and again.position.x == 1.0
    with pytest.raises(TypeError):
        hash(pose)  # mutable, as its members are


def test_typed_and_generic_values_convert_to_the_same_json_and_pose():
    typed = Pose3d(Position3d(1.0, 2.0, 0.0), Orientation3d(0.0, 0.0, 0.5))
    generic = _witness_pose(1.0, 2.0, 0.5)
    assert struct_json(typed) == struct_json(generic)
    assert struct_json(generic) == {
        "position": {"x": 1.0, "y": 2.0, "z": 0.0},
        "orientation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.5},
    }
    assert as_pose(generic) == typed and as_pose(typed) is typed
    assert member_number(typed.position, "y") == member_number(generic.position, "y") == 2.0
    assert struct_members(3.0) is None and struct_json((generic.position,))[0]["x"] == 1.0


def test_a_member_that_is_not_there_or_not_a_number_is_a_type_error():
    with pytest.raises(TypeError, match="no number `x`"):
        member_number(StructValue("fog", {"visual_range": 100.0}), "x")
    with pytest.raises(TypeError, match="no number `interpolation`"):
        member_number(Path((), "smooth"), "interpolation")
    with pytest.raises(TypeError, match="no struct member `position`"):
        as_pose(StructValue("pose_3d", {}))
