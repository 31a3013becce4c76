"""The compiler: an analysed scenario and its parameter values -> a py_trees behaviour tree.

* ``tree``: the entry point :func:`compile_scenario`, one method per OSC2 construct;
* ``composites``: serial, parallel, one_of (race), duration bounds, labels, the root;
* ``conditions``: wait, emit, until, on, call and the watches over event specs;
* ``registry``: the MethodRegistry of actions, modifiers and methods.
"""

from osc2runner.compile.registry import Entry, MethodRegistry, registry

__all__ = ["Entry", "MethodRegistry", "registry"]
