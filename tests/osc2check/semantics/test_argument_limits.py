"""Messages of the physical argument limits shared by the checker and the runner."""

from __future__ import annotations

import pytest

from osc2check.semantics.stdlib import standard_library
from osc2check.world.limits import friction_problem, mps_to_mmph, rain_problem


def test_a_rain_intensity_reads_back_in_the_unit_it_was_written_in():
    """The standard declares `mmph` with the factor 0.000000278 (not 1/3,600,000): a
    scenario's -5mmph is -5 mm/h in the message, not -5.004."""
    unit = standard_library().model.unit("mmph")
    assert unit is not None and unit.factor is not None
    value = float(-5 * unit.factor)  # as the runner gets it: SI, number times factor
    assert mps_to_mmph(value) == pytest.approx(-5.0, rel=1e-12)
    assert rain_problem(value) == "rain intensity must be finite and not negative, got -5 mm/h"
    assert rain_problem(-value) is None


def test_friction_outside_its_range_is_named():
    assert friction_problem(0.5) is None
    assert friction_problem(0.0) == "road friction must be in (0, 2], got 0"
