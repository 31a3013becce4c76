"""Compiling a scenario instance to a py_trees behaviour tree.

* ``environment``: what compiling reads (model, values, registry, the run context);
* ``tree``: ``compile_scenario``, one method per OSC2 construct;
* ``composites``: serial, parallel, one_of, duration bounds, labels;
* ``conditions``: wait, emit, until, on, call and the event watches;
* ``expressions``: expressions to closures over the run context;
* ``registry``: OSC2 actions, modifiers and methods -> their implementations.
"""
