"""What braking to a stop is, read from telemetry: one definition for the braking plot
(``output/plots.py``) and the campaign's ``time_to_stop_s`` (``campaign/kpis.py``)."""

from __future__ import annotations

__all__ = ["BRAKE_ONSET", "MOVING", "STANDSTILL"]

BRAKE_ONSET = 0.05  # brake pedal above this is braking
MOVING = 1.0  # m/s: braking from faster than this starts a stop
STANDSTILL = 0.1  # m/s: slower than this is stopped
