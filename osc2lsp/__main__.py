"""``python -m osc2lsp``: start the language server (stdio by default)."""

from osc2lsp.cli import main

if __name__ == "__main__":
    raise SystemExit(main())
