"""``osc2lsp``: the language server's command line (stdio by default, or ``--tcp``).

stdout carries JSON-RPC: nothing here may print; logging goes to stderr.
"""

from __future__ import annotations

import argparse
import gc
import logging
import os
import sys

from osc2check import cache
from osc2lsp import __version__
from osc2lsp.server import SERVER
from osc2lsp.session.memory import SWITCH, warm_up


def main(argv: list[str] | None = None) -> int:
    """``osc2lsp [--tcp [--host H] [--port P]] [--log-level L] [--log-file F]``."""
    parser = argparse.ArgumentParser(
        prog="osc2lsp", description="Language server for ASAM OpenSCENARIO DSL 2.x"
    )
    parser.add_argument(
        "--tcp",
        action="store_true",
        help="serve the first client to connect on TCP instead of stdio",
    )
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=2087)
    parser.add_argument(
        "--log-level",
        default=os.environ.get("OSC2LSP_LOG_LEVEL", "WARNING"),
        choices=["DEBUG", "INFO", "WARNING", "ERROR"],
    )
    parser.add_argument("--log-file", help="log here instead of to stderr")
    parser.add_argument(
        "--no-cache",
        action="store_true",
        help="neither read nor write the start-up cache (the parser's tables, the analysed "
        "standard library; OSC2_CACHE_DIR says where it is)",
    )
    parser.add_argument("--version", action="version", version=f"osc2lsp {__version__}")
    args = parser.parse_args(argv)
    if args.no_cache:
        cache.set_enabled(False)
    handler = (
        logging.FileHandler(args.log_file) if args.log_file else logging.StreamHandler(sys.stderr)
    )
    logging.basicConfig(
        level=args.log_level,
        handlers=[handler],
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
    )
    # Analyses make many long-lived objects; collect young ones less often so that a
    # collection does not land in the middle of a keystroke's request.
    gc.set_threshold(20_000, 20, 50)
    # The analysis thread gives way to requests quickly (see session.memory.SWITCH).
    sys.setswitchinterval(SWITCH)
    # the grammar, the library and the analysis's modules load while the client and the
    # server say hello: the first analysis, queued behind this, needs them all
    SERVER.state.executor.submit(warm_up)
    if args.tcp:
        SERVER.start_tcp(args.host, args.port)
    else:
        SERVER.start_io()
    return 0
