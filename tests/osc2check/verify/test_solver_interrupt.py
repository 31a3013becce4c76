"""Ctrl-C while z3 solves stops the command (``z3_backend.decided``): z3 takes SIGINT for
itself during a call (its ``ctrl_c`` option, on by default), cancels the call and answers
unknown, so without ``decided`` the check went on, the call reported inconclusive."""

from __future__ import annotations

import os
import signal
import threading

import pytest

from osc2check.verify.z3_backend import decided, load_z3, new_context


def _pigeons(z3, n: int):  # n pigeons in n - 1 holes: unsatisfiable, and slow to prove
    holes = [z3.Int(f"p{i}") for i in range(n)]
    solver = z3.Solver()
    for h in holes:
        solver.add(h >= 0, h < n - 1)
    solver.add(z3.Distinct(*holes))
    return solver


@pytest.mark.skipif(not hasattr(signal, "SIGINT"), reason="no SIGINT here")
def test_ctrl_c_during_a_solver_call_is_a_keyboard_interrupt():
    z3 = load_z3()
    solver = _pigeons(z3, 40)
    # Python's own handler, as in a terminal (a script's background job ignores SIGINT)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            decided(solver)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)


def test_an_answer_is_given_back():
    z3 = load_z3()
    x = z3.Int("x")
    solver = z3.Solver()
    solver.add(x > 1, x < 3)
    assert decided(solver) == z3.sat
    assert decided(solver, x != 2) == z3.unsat


@pytest.mark.skipif(not hasattr(signal, "SIGINT"), reason="no SIGINT here")
def test_a_process_that_ignores_ctrl_c_goes_on_solving():
    z3 = load_z3()
    x = z3.Int("x")
    solver = z3.Solver()
    solver.add(x * x == 49, x > 0)
    calls = []

    class Interrupted:  # z3's answer to a SIGINT the first time, then the real one
        def check(self, *assumptions):
            calls.append(assumptions)
            return z3.unknown if len(calls) == 1 else solver.check(*assumptions)

        def reason_unknown(self):
            return "interrupted from keyboard"

    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        assert decided(Interrupted()) == z3.sat
    finally:
        signal.signal(signal.SIGINT, previous)
    assert len(calls) == 2


@pytest.mark.skipif(not hasattr(signal, "SIGINT"), reason="no SIGINT here")
def test_ctrl_c_while_a_context_is_made_is_raised_once_it_is_whole(monkeypatch):
    """A z3 context interrupted half made reports an error when it is freed (at the
    process's exit): the interrupt is held until the context is whole."""
    z3 = load_z3()
    real, made = z3.Context, []

    class Context:  # z3's, with a Ctrl-C in the middle of making it
        def __init__(self) -> None:
            os.kill(os.getpid(), signal.SIGINT)
            made.append(real())

    monkeypatch.setattr(z3, "Context", Context)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            new_context()
        assert len(made) == 1  # whole before the interrupt
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGINT, previous)
