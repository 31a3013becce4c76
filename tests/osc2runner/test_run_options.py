"""RunOptions: one class of a run's options, its defaults written once, made once by the
command and by run(), extended by a campaign's options, the source of a replay command."""

from __future__ import annotations

import dataclasses
import inspect
from pathlib import Path

import pytest

from osc2runner import runner
from osc2runner.campaign.campaign import CampaignOptions
from osc2runner.campaign.outputs import replay_command
from osc2runner.campaign.worker import CampaignSetup
from osc2runner.cli import _parse, build_parser
from osc2runner.options import (
    DT_CONTROL,
    DT_PHYSICS,
    TIME_LIMIT,
    OptionError,
    RunOptions,
    check_seed,
    check_steps,
)
from osc2runner.sut.loading import SutSpec

EXAMPLE = Path(__file__).parents[2] / "examples" / "cut_in_and_stop.osc"


def test_run_options_defaults_are_the_api_and_command_defaults() -> None:
    options = RunOptions()
    assert (options.dt_control, options.dt_physics, options.time_limit) == (
        DT_CONTROL,
        DT_PHYSICS,
        TIME_LIMIT,
    )
    for entry in (runner.run, runner.prepare, runner.prepare_checked, runner.build_world):
        parameters = inspect.signature(entry).parameters
        assert parameters["dt_control"].default == DT_CONTROL, entry.__name__
        assert parameters["dt_physics"].default == DT_PHYSICS, entry.__name__
    args = build_parser().parse_args(["f.osc"])
    assert (float(args.dt_control), float(args.dt_physics)) == (DT_CONTROL, DT_PHYSICS)


def test_run_options_are_frozen() -> None:
    with pytest.raises(dataclasses.FrozenInstanceError):
        RunOptions().seed = 1  # type: ignore[misc]


@pytest.mark.parametrize(
    ("kwargs", "check"),
    [
        ({"seed": -1}, lambda: check_seed(-1)),
        ({"seed": 1.5}, lambda: check_seed(1.5)),
        ({"dt_control": 0.05, "dt_physics": 0.03}, lambda: check_steps(0.05, 0.03)),
        ({"dt_physics": 0.0}, lambda: check_steps(DT_CONTROL, 0.0)),
    ],
)
def test_checked_options_refuse_as_the_checks_do(kwargs, check) -> None:
    with pytest.raises(OptionError) as made:
        RunOptions.checked(**kwargs)
    with pytest.raises(OptionError) as checked:
        check()
    assert str(made.value) == str(checked.value)


def test_checked_options_take_good_values() -> None:
    options = RunOptions.checked(seed=7, duration=12, dt_control=0.1, dt_physics=0.001)
    assert options == RunOptions(seed=7, duration=12.0, dt_control=0.1, dt_physics=0.001)
    assert options.time_limit == 12.0


def test_the_command_line_makes_one_run_options() -> None:
    args = _parse([str(EXAMPLE), "--seed", "3", "--dt-control", "0.1", "--duration", "9"])
    assert isinstance(args.options, RunOptions)
    assert (args.options.seed, args.options.dt_control, args.options.duration) == (3, 0.1, 9.0)
    assert args.options.dt_physics == DT_PHYSICS
    assert args.options.config is args.config


def test_campaign_options_and_setup_extend_run_options() -> None:
    spec = SutSpec("mod:Class", "ego")
    options = CampaignOptions("f.osc", runs=4, out="o", seed=5, duration=3.0, sut=spec)
    assert isinstance(options, RunOptions)
    one = options.for_seed(8)
    assert type(one) is RunOptions
    assert one == RunOptions(seed=8, duration=3.0, sut=spec)
    setup = CampaignSetup("f.osc", "text", out="o", **options.run_fields())
    assert setup.for_seed(8) == one


def test_a_replay_command_is_written_from_the_run_options() -> None:
    plain = replay_command("f.osc", RunOptions(seed=2), bin_text=None)
    assert plain == "osc2run f.osc --seed 2"
    spec = SutSpec("mod:Class", "ego")
    options = RunOptions(
        scenario="s", seed=4, duration=5.0, dt_control=0.1, dt_physics=0.001, sut=spec
    )
    assert replay_command("f.osc", options, bin_text="speed=1") == (
        "osc2run f.osc --seed 4 --scenario s --bin speed=1 --duration 5 "
        "--dt-control 0.1 --dt-physics 0.001 --sut mod:Class --sut-actor ego"
    )
