"""One catalogue: the body the runner builds has the footprint the checker placed.

For every vehicle category (DSL 2.2's list, which has 2.1's names too),
simulator model name and actor kind of ``osc2check.world.catalogue``, a
scenario places one actor of it; the checker's
witness records its row and size, and the world the runner builds from that
witness has a collision box (and, for vehicles and objects, a MuJoCo geometry)
of exactly that length and width.
"""

from __future__ import annotations

import mujoco
import pytest

from osc2check.config import Config
from osc2check.world.catalogue import CATEGORIES, CATEGORY_ALIASES, MODELS, kind_row
from osc2runner.runner import prepare, run

DSL_2_2 = Config(osc_version="2.2")
# one name a row: 2.2's aliases of 2.1 categories (heavy_truck = truck) share its row
ROWS = [c for c in CATEGORIES if c not in CATEGORY_ALIASES]

VEHICLE = """\
import osc.standard

scenario s:
    hero: vehicle with:
        keep({constraint})
    do serial:
        hero.assign_position() with:
            lane(1, at: start)
            position(distance: 100m, at: start)
"""

OTHER = """\
import osc.standard

scenario s:
    thing: {kind}
    do serial:
        thing.assign_position() with:
            lane(1, at: start)
            position(distance: 100m, at: start)
"""

CASES = [
    *[(f"it.vehicle_category == {c}", "vehicle", CATEGORIES[c]) for c in ROWS],
    *[(f'it.model == "{m}"', "vehicle", MODELS[m]) for m in MODELS],
    *[(None, k, kind_row(k)) for k in ("person", "animal", "stationary_object")],
]


def _geometry_footprint(world, name: str) -> tuple[float, float] | None:
    """Length and width of the actor's MuJoCo box (None for kinematic walkers)."""
    prefix = f"a{world.names.index(name)}"  # the world names bodies by position
    for suffix in ("_chassis", "_box"):
        gid = mujoco.mj_name2id(world.model, mujoco.mjtObj.mjOBJ_GEOM, f"{prefix}{suffix}")
        if gid >= 0:
            size = world.model.geom_size[gid]
            return 2 * float(size[0]), 2 * float(size[1])
    return None


@pytest.mark.parametrize(("constraint", "kind", "row"), CASES, ids=[row.key for _, _, row in CASES])
def test_the_body_has_the_footprint_the_checker_placed(constraint, kind, row):
    if constraint is not None:
        text = VEHICLE.format(constraint=constraint)
    elif kind == "stationary_object":  # it cannot be moved: the witness places it freely
        text = f"import osc.standard\n\nscenario s:\n    thing: {kind}\n"
    else:
        text = OTHER.format(kind=kind)
    prepared = prepare(f"<{row.key}>.osc", source=text, config=DSL_2_2)
    (start,) = prepared.instance.witness.actors
    assert (start.model, start.category) == (row.key, row.category)
    assert (start.length, start.width) == (row.length, row.width)
    world = prepared.world
    name = start.name
    params = world.params(name)
    assert (params.length, params.width) == (float(row.length), float(row.width))
    geometry = _geometry_footprint(world, name)
    if row.body in ("person", "animal"):
        assert geometry is None  # kinematic walker: its collision box is the footprint
    else:
        assert geometry == pytest.approx((float(row.length), float(row.width)))


TRUCK_AHEAD = """\
import osc.standard

scenario s:
    hero: vehicle with:
        keep(it.vehicle_category == car)
    npc: vehicle with:
        keep(it.model == "vehicle.carlamotors.carlacola")
    do serial:
        parallel:
            hero.assign_position() with:
                lane(1, at: start)
                position(distance: 100m, at: start)
            npc.assign_position() with:
                lane(1, at: start)
                position(distance: 2m, ahead_of: hero, at: start)
        parallel(duration: 3s):
            hero.drive()
            npc.drive()
"""


def test_a_truck_two_metres_ahead_of_a_car_starts_two_metres_ahead():
    result = run("<truck_ahead>.osc", source=TRUCK_AHEAD)
    assert result.outcome.status == "success", result.outcome.reason
    assert not [r for r in result.events if r.kind == "collision"]
    hero, npc = result.telemetry["hero"], result.telemetry["npc"]
    truck = MODELS["vehicle.carlamotors.carlacola"]
    gap = (npc["x"][0] - float(truck.length) / 2) - (hero["x"][0] + 4.5 / 2)
    assert gap == pytest.approx(2.0, abs=1e-6)


def _column() -> str:
    names = ROWS
    fields = "".join(
        f"    a_{c}: vehicle with:\n        keep(it.vehicle_category == {c})\n" for c in names
    )
    places = []
    for i, c in enumerate(names):
        where = (
            "position(distance: 500m, at: start)"
            if i == 0
            else f"position(distance: 1m, behind: a_{names[i - 1]}, at: start)"
        )
        places.append(
            f"            a_{c}.assign_position() with:\n"
            f"                lane(2, at: start)\n"
            f"                {where}\n"
        )
    # a trailer has no engine: it stands where it was placed (only a tow vehicle moves it)
    drives = "".join(f"            a_{c}.drive()\n" for c in names if not CATEGORIES[c].is_trailer)
    return (
        "import osc.standard\n\nscenario column:\n"
        + fields
        + "    do serial:\n        parallel:\n"
        + "".join(places)
        + "        parallel(duration: 3s):\n"
        + drives
    )


def test_one_actor_of_each_category_one_metre_apart_runs_without_a_collision():
    result = run("<column>.osc", source=_column(), config=DSL_2_2)
    assert result.outcome.status == "success", result.outcome.reason
    assert not [r for r in result.events if r.kind == "collision"]
    starts = {a["name"]: a for a in result.metadata["witness"]["actors"]}
    for category in ROWS:
        assert starts[f"a_{category}"]["category"] == category
        assert result.metadata["actors"][f"a_{category}"]["category"] == category


UNCONSTRAINED = """\
import osc.standard

scenario s:
    hero: vehicle
    do serial:
        hero.assign_position() with:
            lane(1, at: start)
            position(distance: 100m, at: start)
"""

OPEN = """\
import osc.standard

scenario s:
    hero: vehicle with:
        keep(it.vehicle_category in [car, truck, bus])
    do serial:
        hero.assign_position() with:
            lane(1, at: start)
            position(distance: 100m, at: start)
            speed(95kph, at: start)
"""


@pytest.mark.parametrize("seed", range(6))
def test_the_witness_names_the_category_the_actor_was_placed_and_checked_as(seed):
    import osc2check
    from osc2check.analysis import SourceInput

    free = osc2check.solve(osc2check.analyze([SourceInput("u.osc", UNCONSTRAINED)]), seed=seed)
    (hero,) = free.actors
    assert (hero.category, hero.length) == ("car", CATEGORIES["car"].length)
    assert free.parameter("hero.vehicle_category").text == "car"
    # left open among three: the solver picks one, and the size and top speed follow it
    # (95 kph is above a truck's 90 kph, so never a truck)
    chosen = osc2check.solve(osc2check.analyze([SourceInput("o.osc", OPEN)]), seed=seed)
    (hero,) = chosen.actors
    row = CATEGORIES[hero.category]
    assert hero.category in ("car", "bus")
    assert chosen.parameter("hero.vehicle_category").text == hero.category
    assert (hero.length, hero.width) == (row.length, row.width)
