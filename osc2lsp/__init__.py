"""osc2lsp: the language server of the osc2 toolkit.

Only ``server.py`` (the handlers), ``language_server.py``, ``transport/`` and
``convert.py`` import pygls/lsprotocol; the features
under ``features/`` are plain functions over an analysis ``Snapshot`` and can
be used (and tested) without the protocol.
"""

__version__ = "0.1.0"
