"""Compiling a scenario instance to a py_trees behaviour tree.

* ``environment``: what compiling reads (model, values, registry, the run context);
* ``tree``: ``compile_scenario``, one method per OSC2 construct;
* ``arguments``: an invocation's arguments and an invoked scenario's fields;
* ``composites``: serial, parallel, one_of, duration bounds, labels;
* ``preparation``: an ``at: start`` of a later phase brought about; the ``one_of`` choice;
* ``conditions``: wait, emit, until, on, call and the event watches;
* ``expressions``: expressions to closures over the run context (and the ``Environment``
  Protocol the compilers take);
* ``sampling``: ``sample(...)``; ``coverage``: ``cover`` and ``record``;
* ``text``: OSC2 text of expressions and display names;
* ``registry``: OSC2 actions, modifiers and methods -> their implementations.
"""
