"""The parts of an export: built-in roads as OpenDRIVE, lights, the environment, events,
OSI lanes, the command line and campaigns."""

from __future__ import annotations

import math
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("scenariogeneration")
pytest.importorskip("osi3")
pytest.importorskip("osi_utilities")

from osc2check.world.builtin import BUILTIN_MAPS, builtin_network  # noqa: E402
from osc2check.world.network import LaneRef  # noqa: E402
from osc2check.world.opendrive import load_opendrive  # noqa: E402
from osc2runner.export import ExportTargets, missing_extra  # noqa: E402
from osc2runner.export.recording import LightTrack, run_recording  # noqa: E402
from osc2runner.export.xodr import builtin_opendrive  # noqa: E402
from osc2runner.export.xosc import scenario_xosc, write_xosc, xml_bytes  # noqa: E402
from osc2runner.runner import check_file, execute, prepare_checked  # noqa: E402
from tests.osc2runner.export.asam_checks import asam_check, assert_valid  # noqa: E402

ROOT = Path(__file__).parents[3]
HEADER = "import osc.standard\n\nscenario s:\n"


def _run(tmp_path: Path, body: str, **targets: Path):
    source = tmp_path / "s.osc"
    source.write_text(HEADER + body)
    prepared = prepare_checked(check_file(source))
    return prepared, execute(prepared, export=ExportTargets(**targets))


# ---------------------------------------------------------------------- built-in roads


@pytest.mark.parametrize("name", sorted(BUILTIN_MAPS))
def test_builtin_road_written_as_opendrive_has_the_runners_lanes(name: str, tmp_path: Path):
    row, network = BUILTIN_MAPS[name], builtin_network(name)
    path = tmp_path / f"{name}.xodr"
    path.write_bytes(xml_bytes(builtin_opendrive(row, network, (), "2000-01-01T00:00:00")))
    assert_valid(path)
    read = load_opendrive(path)
    road, ours = read.roads["0"], network.roads["0"]
    assert road.length == ours.length
    n = row.lane_count
    assert [lane.id for lane in road.sections[0].lanes] == [-k for k in range(1, n + 1)]
    assert read.roads["0"].speed_limit == pytest.approx(row.speed_limit)
    for lane_id in range(-1, -row.lane_count - 1, -1):
        ref = LaneRef("0", 0, lane_id)
        for s in (0.0, 0.5 * row.length, row.length):
            assert read.width(ref, np.array([s]))[0] == pytest.approx(row.lane_width)
            a, b = read.lane_to_world(ref, s), network.lane_to_world(ref, s)
            assert (a.x, a.y, a.yaw) == pytest.approx((b.x, b.y, b.yaw), abs=1e-9)
        # lane k counted from the right is the same OpenDRIVE lane in both
        assert read.osc2_lane_index(ref) == network.osc2_lane_index(ref) == n + 1 + lane_id


def test_a_light_placed_by_its_pose_is_a_signal_with_that_pose(tmp_path: Path):
    row, network = BUILTIN_MAPS["default"], builtin_network("default")
    lights = (
        LightTrack("facing_traffic", "", 150.0, -0.5, math.pi, ((0, 0.0, "off", ()),)),
        LightTrack("turned", "", 90.0, 12.0, 0.3, ((0, 0.0, "off", ()),)),
    )
    path = tmp_path / "lit.xodr"
    path.write_bytes(xml_bytes(builtin_opendrive(row, network, lights, "2000-01-01T00:00:00")))
    assert_valid(path)
    read = load_opendrive(path)
    signals = {s.id: s for s in read.signals}
    assert signals["facing_traffic"].orientation == "+"  # faces cars driving along s
    for light in lights:
        signal = signals[light.name]
        assert signal.dynamic
        pose = read.signal_pose(signal)
        assert (pose.x, pose.y) == pytest.approx((light.x, light.y), abs=1e-9)
        assert math.cos(pose.yaw - light.yaw) == pytest.approx(1.0)


# ---------------------------------------------------------------------- asam's checker


def test_asam_checker_finds_a_broken_reference(tmp_path: Path):
    """The checks the tests rely on can fail: an action for an entity that does not exist."""
    _, result = _run(
        tmp_path,
        """\
    car: vehicle
    do car.drive(duration: 1s) with:
        speed(20kph)
""",
        xosc=tmp_path / "ok.xosc",
    )
    good = tmp_path / "ok.xosc"
    assert_valid(good)
    broken = tmp_path / "broken.xosc"
    broken.write_text(good.read_text().replace('entityRef="car"', 'entityRef="nobody"'))
    (tmp_path / "broken.xodr").write_bytes((tmp_path / "ok.xodr").read_bytes())
    assert any(r.issues for r in asam_check(broken))


# ---------------------------------------------------------------------- world changes


def _by_time(root: ET.Element, tag: str) -> list[tuple[float, ET.Element]]:
    """(start time, action element) of every timed event holding a ``tag`` action."""
    found = []
    for event in root.iter("Event"):
        action = event.find(f".//{tag}")
        time = event.find("StartTrigger//SimulationTimeCondition")
        if action is not None and time is not None:
            found.append((float(time.get("value", "nan")), action))
    return found


def test_environment_changes_are_environment_actions_at_their_times(tmp_path: Path):
    _run(
        tmp_path,
        """\
    car: vehicle
    env: environment
    do parallel:
        car.drive(duration: 3s) with:
            speed(20kph)
        serial:
            wait elapsed(1s)
            env.rain(intensity: 20mmph)
            env.fog(visual_range: 300m)
            env.wind(speed: 6mps, direction: 270deg)
            env.clouds(cloudiness: 5)
            env.air(temperature: 280K, pressure: 99000Pa, relative_humidity: 0.8)
            env.assign_celestial_position(azimuth: 90deg, elevation: 30deg)
            wait elapsed(1s)
            env.set_road_friction(value: 0.4)
""",
        xosc=tmp_path / "env.xosc",
    )
    assert_valid(tmp_path / "env.xosc")
    root = ET.parse(tmp_path / "env.xosc").getroot()
    start = root.find("Storyboard/Init//EnvironmentAction/Environment")
    assert start is not None
    assert start.find("RoadCondition").get("frictionScaleFactor") == "1.0"  # type: ignore[union-attr]
    changes = _by_time(root, "EnvironmentAction")
    assert [round(t, 6) for t, _ in changes] == [1.0] * 6 + [2.0]
    weather = changes[5][1].find(".//Weather")  # after the sun
    assert weather is not None
    assert weather.find("Precipitation").get("precipitationType") == "rain"  # type: ignore[union-attr]
    assert float(weather.find("Precipitation").get("precipitationIntensity")) == pytest.approx(20)  # type: ignore[union-attr,arg-type]
    assert float(weather.find("Fog").get("visualRange")) == pytest.approx(300)  # type: ignore[union-attr,arg-type]
    # blowing from the west (270deg): towards the east, yaw 0
    wind = weather.find("Wind")
    assert wind is not None and float(wind.get("speed", "0")) == pytest.approx(6)
    assert math.cos(float(wind.get("direction", "nan"))) == pytest.approx(1.0)
    assert weather.get("fractionalCloudCover") == "fiveOktas"
    assert float(weather.get("temperature", "0")) == pytest.approx(280)
    assert float(weather.get("atmosphericPressure", "0")) == pytest.approx(99000)
    sun = weather.find("Sun")
    assert sun is not None and float(sun.get("azimuth", "0")) == pytest.approx(math.pi / 2)
    assert float(sun.get("elevation", "0")) == pytest.approx(math.pi / 6)
    # rain sets the friction of the runner's model (0.58 at 20 mm/h), then set_road_friction
    friction = [float(a.find(".//RoadCondition").get("frictionScaleFactor")) for _, a in changes]  # type: ignore[union-attr,arg-type]
    assert friction[0] == pytest.approx(0.58) and friction[-1] == pytest.approx(0.4)


LIGHTS = """\
    car: vehicle
    ctrl: traffic_light_controller
    light: traffic_light with:
        keep(it.pose.position.x == 150m)
        keep(it.pose.position.y == -0.5m)
    do parallel:
        car.drive(duration: 4s) with:
            speed(20kph)
        serial:
            ctrl.set_semantic_state(traffic_light: light, state: go)
            wait elapsed(1s)
            ctrl.set_semantic_state(traffic_light: light, state: attention)
            wait elapsed(2s)
            ctrl.set_semantic_state(traffic_light: light, state: caution)
"""


def test_light_changes_are_signal_state_actions_on_the_written_signal(tmp_path: Path):
    _run(tmp_path, LIGHTS, xosc=tmp_path / "lit.xosc")
    assert_valid(tmp_path / "lit.xosc")  # resolves the signal id in the written road
    root = ET.parse(tmp_path / "lit.xosc").getroot()
    init = root.find("Storyboard/Init//TrafficSignalStateAction")
    assert init is not None and (init.get("name"), init.get("state")) == ("light", "off;off;on")
    changes = [(round(t, 6), a.get("state")) for t, a in _by_time(root, "TrafficSignalStateAction")]
    assert changes == [(1.0, "off;on;off"), (3.0, "off;flashing;off")]
    signal = ET.parse(tmp_path / "lit.xodr").getroot().find(".//signal")
    assert signal is not None and signal.get("id") == "light" and signal.get("dynamic") == "yes"


def test_lights_on_a_map_name_its_signals_and_lights_by_pose_are_left_out(tmp_path: Path):
    junction = (ROOT / "examples" / "maps" / "four_way_junction.xodr").as_posix()
    _run(
        tmp_path,
        f"""\
    town: map with:
        keep(it.map_file == "{junction}")
    ctrl: traffic_light_controller
    east: traffic_light with:
        keep(it.map_id == "tl1")
    loose: traffic_light with:
        keep(it.pose.position.x == 20m)
        keep(it.pose.position.y == 20m)
    do serial:
        ctrl.set_semantic_state(traffic_light: east, state: stop)
        ctrl.set_semantic_state(traffic_light: loose, state: stop)
        wait elapsed(1s)
        ctrl.set_semantic_state(traffic_light: east, state: go)
        ctrl.set_semantic_state(traffic_light: loose, state: go)
        wait elapsed(1s)
""",
        xosc=tmp_path / "map.xosc",
    )
    assert_valid(tmp_path / "map.xosc")  # tl1 resolves in the copied map
    root = ET.parse(tmp_path / "map.xosc").getroot()
    named = [a.get("name") for a in root.iter("TrafficSignalStateAction")]
    assert named == ["tl1", "tl1"]


def test_emitted_events_are_storyboard_events_that_count_them(tmp_path: Path):
    _run(
        tmp_path,
        """\
    car: vehicle
    event ping
    do parallel:
        car.drive(duration: 2s) with:
            speed(20kph)
        serial:
            wait elapsed(0.5s)
            emit ping
            wait elapsed(1s)
            emit ping
""",
        xosc=tmp_path / "ev.xosc",
    )
    assert_valid(tmp_path / "ev.xosc")
    root = ET.parse(tmp_path / "ev.xosc").getroot()
    events = {e.get("name"): e for e in root.iter("Event")}
    assert {"emit ping #1", "emit ping #2"} <= set(events)
    second = events["emit ping #2"]
    assert second.find(".//VariableAction").get("variableRef") == "event_ping"  # type: ignore[union-attr]
    assert second.find(".//SetAction").get("value") == "2"  # type: ignore[union-attr]
    time = second.find("StartTrigger//SimulationTimeCondition")
    assert time is not None and float(time.get("value", "0")) == pytest.approx(1.5)


def test_one_run_exports_the_same_bytes(tmp_path: Path):
    prepared, result = _run(tmp_path, LIGHTS)
    recording = run_recording(prepared, result)
    first = [p.read_bytes() for p in write_xosc(recording, tmp_path / "a.xosc")]
    again = [p.read_bytes() for p in write_xosc(recording, tmp_path / "a.xosc")]
    assert first == again
    assert b"2000-01-01T00:00:00" in first[0]  # the road's header: no wall clock
    assert scenario_xosc(recording, "a.xodr").header.creation_date.year == 2000


# ---------------------------------------------------------------------- OSI lanes


def _distance_to_polyline(px, py, x, y) -> np.ndarray:
    """Each point's distance to the polyline ``x``, ``y``."""
    ax, ay, dx, dy = x[:-1], y[:-1], np.diff(x), np.diff(y)
    length2 = np.maximum(dx * dx + dy * dy, 1e-18)
    u = np.clip(((px[:, None] - ax) * dx + (py[:, None] - ay) * dy) / length2, 0.0, 1.0)
    return np.min(np.hypot(ax + u * dx - px[:, None], ay + u * dy - py[:, None]), axis=1)


def test_osi_lanes_follow_the_maps_lanes_within_a_centimetre(tmp_path: Path):
    from osi3trace.osi_trace import OSITrace

    source = ROOT / "examples" / "rural_road_following.osc"
    prepared = prepare_checked(check_file(source))
    result = execute(prepared, duration=0.5, export=ExportTargets(osi=tmp_path / "r.osi"))
    trace = OSITrace(str(tmp_path / "r.osi"), "GroundTruth")
    first = next(iter(trace))
    trace.close()
    network = prepared.world.network
    lanes = sum(len(sec.lanes) for road in network.roads.values() for sec in road.sections)
    assert len(first.lane) == lanes
    driving = [lane for lane in first.lane if lane.classification.type == 2]  # TYPE_DRIVING
    assert driving
    for lane in driving:
        road, lane_id = lane.source_reference[0].identifier
        path = network.lane_path(LaneRef(road, 0, int(lane_id)))
        points = lane.classification.centerline
        x = np.array([p.x for p in points])
        y = np.array([p.y for p in points])
        assert len(x) < 400  # simplified: a 980 m road of arcs and clothoids
        assert _distance_to_polyline(x, y, path.x, path.y).max() <= 0.01
    assert all(len(channels["tick"]) == 11 for channels in result.telemetry.values())


# ---------------------------------------------------------------------- command line


def osc2run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "osc2runner", *args],
        capture_output=True, text=True, cwd=ROOT, timeout=600,
    )  # fmt: skip


@pytest.mark.slow
def test_command_writes_both_exports_and_says_so(tmp_path: Path):
    xosc, osi = tmp_path / "new" / "cut.xosc", tmp_path / "new" / "cut.osi"
    done = osc2run(
        "examples/ncap/ccrs.osc", "--export-xosc", str(xosc), "--export-osi", str(osi), "-q"
    )
    assert done.returncode == 1, done.stderr  # the example's car hits the target
    for path in (xosc, xosc.with_suffix(".xodr"), osi):
        assert f"wrote {path}" in done.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--export-xosc", "out.osi"], "--export-xosc out.osi: the file name must end in .xosc"),
        (["--export-osi", "out.xosc"], "--export-osi out.xosc: the file name must end in .osi"),
        (["--export", "xosc"], "--export needs --out DIR"),
        (["--export", "pdf", "--out", "x"], "--export pdf: formats are xosc, osi"),
        (["--runs", "2", "--out", "x", "--export-xosc", "a.xosc"], "a campaign takes --export"),
    ],
)
def test_bad_export_options_are_usage_errors(args: list[str], message: str, tmp_path: Path):
    done = osc2run("examples/cut_in_and_stop.osc", *args)
    assert done.returncode == 2
    assert done.stderr.startswith("osc2run: error: ") and message in done.stderr
    assert done.stderr.count("\n") == 1


def test_without_the_extra_the_command_names_it(monkeypatch: pytest.MonkeyPatch, capsys):
    import importlib.util

    from osc2runner.cli import main

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *a: None if name == "scenariogeneration" else real(name, *a),
    )
    assert missing_extra(["osi"]) is None
    status = main(["examples/cut_in_and_stop.osc", "--export-xosc", "x.xosc"])
    err = capsys.readouterr().err
    assert status == 2
    assert err == (
        "osc2run: error: exporting needs the export extra (scenariogeneration missing): "
        'pip install "osc2-toolkit[export]"\n'
    )


# ---------------------------------------------------------------------- campaigns


@pytest.mark.slow
def test_campaign_exports_every_run_and_the_report_links_them(tmp_path: Path):
    from osc2runner.campaign import CampaignOptions, run_campaign

    source = tmp_path / "s.osc"
    source.write_text(
        HEADER
        + """\
    car: vehicle
    v: speed with:
        keep(it in [10kph..40kph])
    do car.drive(duration: 1s) with:
        speed(v)
"""
    )
    out = tmp_path / "campaign"
    result = run_campaign(
        CampaignOptions(file=str(source), runs=3, out=str(out), jobs=1, export=("xosc",))
    )
    assert result.status == "complete"
    report = (out / "report.html").read_text()
    for record in result.records:
        run_dir = out / record.folder
        assert {"scenario.xosc", "scenario.xodr"} <= set(record.files)
        assert_valid(run_dir / "scenario.xosc")
        assert f'href="{record.folder}/scenario.xosc"' in report
    assert result.document["options"]["export"] == ["xosc"]
