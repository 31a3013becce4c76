"""Editor features as plain functions over a ``Snapshot`` (no pygls, no lsprotocol).

Positions are code-point offsets into the snapshot's text; results carry
``osc2check`` spans or small dataclasses that ``osc2lsp.convert`` turns into
LSP types.
"""
