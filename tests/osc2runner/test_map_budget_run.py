"""``osc2run`` on a map beyond what a road can be: refused before tick 0 with the
checker's L516 (a paramPoly3 with coefficients of 1e300 passed the checker and crashed
the runner converting NaN to an integer)."""

from __future__ import annotations

from osc2runner.cli import main
from tests.osc2check.world.maptext import road_xml, scenario_on, xodr

WILD = (
    '<paramPoly3 aU="0" bU="1" cU="0" dU="1e300" aV="0" bV="0" cV="0" dV="1e300" '
    'pRange="arcLength"/>'
)


def test_a_map_beyond_what_a_road_can_be_is_refused_before_the_run(tmp_path, capsys):
    (tmp_path / "wild.xodr").write_text(xodr(road_xml(length=50, geometry=WILD)), "utf-8")
    (tmp_path / "wild.osc").write_text(scenario_on("wild.xodr"), "utf-8")
    assert main([str(tmp_path / "wild.osc"), "--out", str(tmp_path / "out"), "-q"]) == 2
    err = capsys.readouterr().err
    assert "L516" in err and "paramPoly3" in err and "nothing ran" in err
    assert "internal error" not in err
    assert not (tmp_path / "out").exists()
