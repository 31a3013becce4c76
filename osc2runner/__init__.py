"""osc2runner: the reference runner of the osc2 toolkit.

Scenarios are compiled to py_trees behaviour trees (``compile/``) and ticked
against a MuJoCo world of vehicles (``sim/``) at a fixed control rate.
"""
