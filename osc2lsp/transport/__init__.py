"""The server's transport: frames, pygls' protocol with its overrides, serving over
stdio or TCP, the watch on the editor and on the server (``lifeline``), and the
guard around handlers.

``pygls_contract.py`` records each pygls method overridden or relied on here, with
the pygls versions it was checked against; a test fails when one changes.
"""
