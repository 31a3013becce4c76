"""Every example runs in full once, exports, and the exports hold what ran.

For each runnable example in ``examples/`` (one run each, module-scoped): the
OpenSCENARIO export passes ASAM's checker (schema and rules), its road network
(the built-in road written out, or the map copied) passes ASAM's OpenDRIVE checker,
a replay of the exported trajectories at the control rate lands where the run's
telemetry says (1 cm, 0.5°), and the OSI trace read back with the OSI library has
the same ticks, actors and poses.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("scenariogeneration")
pytest.importorskip("osi3")
pytest.importorskip("osi_utilities")

from osc2runner.export import ExportTargets  # noqa: E402
from osc2runner.runner import Prepared, RunResult, check_file, execute, prepare_checked  # noqa: E402
from tests.osc2runner.export.asam_checks import assert_valid  # noqa: E402
from tests.osc2runner.export.replay import heading_error, read_replay  # noqa: E402

ROOT = Path(__file__).parents[3]
EXAMPLES = sorted(
    p
    for p in [*ROOT.glob("examples/*.osc"), *ROOT.glob("examples/ncap/*.osc")]
    if p.name != "unsafe_typos.osc"  # mistakes on purpose: the checker refuses it
)
POSITION_TOLERANCE = 0.01  # m
HEADING_TOLERANCE = math.radians(0.5)


@dataclass
class Exported:
    prepared: Prepared
    result: RunResult
    xosc: Path
    osi: Path


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2runner/export/test_export_examples")


@pytest.fixture(scope="module", params=EXAMPLES, ids=lambda p: p.stem)
def exported(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Exported:
    path: Path = request.param
    folder = tmp_path_factory.mktemp(path.stem)
    prepared = prepare_checked(check_file(path))
    targets = ExportTargets(folder / f"{path.stem}.xosc", folder / f"{path.stem}.osi")
    result = execute(prepared, export=targets)
    assert targets.xosc is not None and targets.osi is not None
    assert [p.name for p in result.outputs] == [
        f"{path.stem}.xodr",
        f"{path.stem}.xosc",
        f"{path.stem}.osi",
    ]
    return Exported(prepared, result, targets.xosc, targets.osi)


def test_every_example_but_the_broken_one_is_exported():
    assert len(EXAMPLES) >= 12
    assert all(p.name != "unsafe_typos.osc" for p in EXAMPLES)


def test_export_passes_asam_openscenario_checker(exported: Exported):
    assert_valid(exported.xosc)


def test_road_network_beside_the_export_passes_asam_opendrive_checker(exported: Exported):
    road = exported.xosc.with_suffix(".xodr")
    logic = ET.parse(exported.xosc).getroot().find("RoadNetwork/LogicFile")
    assert logic is not None and logic.get("filepath") == road.name
    source = exported.prepared.world.network.source
    if source is not None:  # an OpenDRIVE map: copied as it is
        assert road.read_bytes() == Path(source).read_bytes()
    assert_valid(road)


def test_replay_of_the_trajectories_matches_the_telemetry(exported: Exported):
    entities, stop = read_replay(exported.xosc)
    telemetry = exported.result.telemetry
    assert set(entities) == set(telemetry)
    for name, channels in telemetry.items():
        times = channels["time"]
        assert stop == pytest.approx(float(times[-1]), abs=1e-6)
        replayed = entities[name]
        x, y, h = replayed.pose(times)  # the control rate: every recorded tick
        error = np.hypot(x - channels["x"], y - channels["y"])
        assert error.max() <= POSITION_TOLERANCE, (name, float(error.max()))
        turn = heading_error(h, channels["yaw"])
        assert turn.max() <= HEADING_TOLERANCE, (name, float(turn.max()))
        sx, sy, sh = replayed.start  # the Init teleport is where the run started
        start_x = sx + replayed.centre_x * math.cos(sh)
        start_y = sy + replayed.centre_x * math.sin(sh)
        assert math.hypot(start_x - channels["x"][0], start_y - channels["y"][0]) <= 1e-5
        if len(replayed.times):
            assert np.all(np.diff(replayed.times) > 0)
            assert np.all(np.abs(np.diff(replayed.h)) < math.pi)  # unwrapped


def test_replay_between_ticks_stays_near_the_path(exported: Exported):
    """Halfway between two ticks a player interpolates: within a tick's travel of both."""
    entities, _ = read_replay(exported.xosc)
    for name, channels in exported.result.telemetry.items():
        times = channels["time"]
        if len(times) < 2:
            continue
        middle = 0.5 * (times[1:] + times[:-1])
        x, y, _ = entities[name].pose(middle)
        step = np.hypot(np.diff(channels["x"]), np.diff(channels["y"]))
        to_ends = np.minimum(
            np.hypot(x - channels["x"][:-1], y - channels["y"][:-1]),
            np.hypot(x - channels["x"][1:], y - channels["y"][1:]),
        )
        assert np.all(to_ends <= step + POSITION_TOLERANCE), name


def test_osi_trace_reads_back_with_the_actors_poses_and_ticks(exported: Exported):
    from osi3trace.osi_trace import OSITrace

    trace = OSITrace(str(exported.osi), "GroundTruth")
    messages = list(trace)
    trace.close()
    telemetry = exported.result.telemetry
    world = exported.prepared.world
    ticks = next(iter(telemetry.values()))["tick"]
    assert len(messages) == len(ticks)
    moving = [n for n in telemetry if world.specs[world.names.index(n)].kind != "obstacle"]
    still = [n for n in telemetry if n not in moving]
    dt = world.dt_control
    for k, gt in enumerate(messages):
        stamp = gt.timestamp.seconds + gt.timestamp.nanos * 1e-9
        assert stamp == pytest.approx(int(ticks[k]) * dt, abs=1e-9)
        assert len(gt.moving_object) == len(moving)
        assert len(gt.stationary_object) == len(still)
        by_name = {o.source_reference[0].identifier[0]: o for o in gt.moving_object}
        assert set(by_name) == set(moving)
        for name, obj in by_name.items():
            channels = telemetry[name]
            assert obj.base.position.x == pytest.approx(channels["x"][k], abs=1e-9)
            assert obj.base.position.y == pytest.approx(channels["y"][k], abs=1e-9)
            assert obj.base.orientation.yaw == pytest.approx(channels["yaw"][k], abs=1e-9)
    assert (len(messages[0].lane) > 0) == bool(world.network.roads)
    assert all(len(gt.lane) == 0 for gt in messages[1:])  # lanes once, in the first message
