"""The registered leaves of the runner, one family per module.

Importing this package fills :data:`osc2runner.compile.registry.registry`:

* ``motion``: drive, move, walk, speed, lane and gap actions;
* ``placement``: assign_position, assign_speed, assign_orientation;
* ``environment``: rain, fog, set_road_friction and the recorded weather actions;
* ``lights``: set_lights (toolkit);
* ``modifiers``: the movement modifiers;
* ``methods``: object_distance, road_distance, ahead_of, gaps and headways.
"""

from osc2runner.behaviours import environment, lights, methods, modifiers, motion, placement

__all__ = ["environment", "lights", "methods", "modifiers", "motion", "placement"]
