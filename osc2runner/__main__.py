"""``python -m osc2runner FILE ...``: the ``osc2run`` command."""

from osc2runner.cli import main

raise SystemExit(main())
