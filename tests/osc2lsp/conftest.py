"""Tests of osc2lsp: the feature functions in ``features/``, the protocol in
``protocol/`` (shared helpers: ``lsp_helpers``, ``protocol/lsp_session``)."""
