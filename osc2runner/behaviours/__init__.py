"""The runner's leaves, one family per module; ``compile.registry.load_registry`` collects them.

* ``motion``: drive, move, walk, speed, lane and gap actions;
* ``placement``: assign_position, assign_speed, assign_orientation;
* ``environment``: rain, fog, set_road_friction and the recorded weather actions;
* ``lights``: set_lights (toolkit);
* ``modifiers``: the movement modifiers;
* ``methods``: object_distance, road_distance, ahead_of, gaps and headways;
* ``maps``: `along`, the map modifiers (realised by the witness) and the map methods.

Importing a module marks its implementations and registers nothing.
"""
