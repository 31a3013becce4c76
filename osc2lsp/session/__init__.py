"""The server's session: open documents, when they are analysed (debounce, the
analysis thread, the preview, the solver's worker process), the memory policy
and the views of a snapshot from a newer text.

Nothing here speaks the protocol: findings are handed to a publisher, and
``osc2lsp.transport`` carries them.
"""
