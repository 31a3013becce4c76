"""The exact value of a numeric literal, within the budget every tool can afford.

``1e99999999`` is ten characters, and its exact value is a number of a hundred million
digits: computing it took minutes (the server froze meanwhile) and the runner could
never have turned it into a machine float. So a literal's value is worked out from its
digits and exponent without ever raising 10 to a power that was not bounded first:

* at most ``MAX_DIGITS`` digits (300: far more than any measurement has), and
* a magnitude within ``10**-MAX_MAGNITUDE`` .. ``10**MAX_MAGNITUDE`` (300 decimal
  orders, or zero): every such value is a finite, non-zero machine float (doubles
  reach 1.8e308 and 2.2e-308), so what the checker accepts the runner can run.

A literal outside is ``NumberOutOfRange`` (T209). The builder reports it; the
constants evaluator, the unit declarations and the solver's encoding all read
literals through ``exact_number``.

Arithmetic on literals can still grow numbers: every product doubles their size, so
``((1e300 * 1e300) * (1e300 * 1e300)) * ...`` nested sixteen deep is a number of
twenty million digits, and ``1e300 * 1e300`` is already beyond every machine float.
An exact value is ``representable`` when it has at most ``MAX_VALUE_BITS`` (4096 bits,
about 1,230 decimal digits) and, unless it is 0, a magnitude between 2**-1000 and
2**1000 (a finite machine float). The constants evaluator gives up on a result that
is not (not a constant), and a constraint that could compute one is left out of the
solver's problem and reported (C411) before anything computes it (``ir.fits``).
"""

from __future__ import annotations

import functools
import re
from fractions import Fraction

__all__ = [
    "MAX_DIGITS",
    "MAX_MAGNITUDE",
    "MAX_VALUE_BITS",
    "NumberOutOfRange",
    "bits",
    "exact_number",
    "representable",
]

MAX_DIGITS = 300
MAX_MAGNITUDE = 300
MAX_VALUE_BITS = 4096
MAX_BINARY_MAGNITUDE = 1000  # 2**1000 is about 1.07e301: every such value is a finite float
_DECIMAL = re.compile(r"(\d*)(?:\.(\d*))?(?:[eE]([+-]?\d+))?")
_MAX_EXPONENT_DIGITS = 6  # an exponent of more digits is out of range whatever the rest


class NumberOutOfRange(ValueError):
    """A numeric literal beyond the budget: too many digits, or else its magnitude."""

    def __init__(self, text: str, digits: bool) -> None:
        super().__init__(text)
        self.text = text
        self.digits = digits


@functools.lru_cache(maxsize=1024)  # the same literal met again (its value is immutable)
def exact_number(text: str) -> int | Fraction:
    """The exact value of a numeric literal (``42``, ``0x2A``, ``1.5``, ``2e-3``): an
    ``int`` for an integer literal, else a ``Fraction``.

    Raises ``NumberOutOfRange`` beyond the budget and ``ValueError`` for text that has
    no exact value (``inf``, ``nan``).
    """
    text = text.replace("_", "")
    if text[:2] in ("0x", "0X"):
        if len(text) > 2 + MAX_DIGITS:
            raise NumberOutOfRange(text, digits=True)
        return _bounded_int(int(text[2:], 16), text)
    match = _DECIMAL.fullmatch(text)
    if match is None or not (match.group(1) or match.group(2)):
        raise ValueError(f"`{text}` is not a number with an exact value")
    whole, fraction, exponent_text = match.group(1), match.group(2) or "", match.group(3)
    if len(whole) + len(fraction) > MAX_DIGITS:
        raise NumberOutOfRange(text, digits=True)
    if exponent_text is None and match.group(2) is None:
        return _bounded_int(int(whole), text)
    digits = (whole + fraction).lstrip("0")
    if not digits:
        return Fraction(0)
    if exponent_text and len(exponent_text.lstrip("+-").lstrip("0")) > _MAX_EXPONENT_DIGITS:
        raise NumberOutOfRange(text, digits=False)
    exponent = int(exponent_text or "0") - len(fraction)
    magnitude = exponent + len(digits) - 1  # the decimal order of the first digit
    if not -MAX_MAGNITUDE <= magnitude <= MAX_MAGNITUDE:
        raise NumberOutOfRange(text, digits=False)
    value = Fraction(int(digits))
    return value * 10**exponent if exponent >= 0 else value / Fraction(10**-exponent)


def _bounded_int(value: int, text: str) -> int:
    if value >= 10 ** (MAX_MAGNITUDE + 1):
        raise NumberOutOfRange(text, digits=False)
    return value


def bits(value: int | Fraction) -> int:
    """The size of an exact number: the bits of its numerator and denominator."""
    if isinstance(value, int):
        return value.bit_length()
    return value.numerator.bit_length() + value.denominator.bit_length()


def representable(value: int | Fraction) -> bool:
    """Whether an exact value is within the budget (see the module's docstring)."""
    if not value:
        return True
    if bits(value) > MAX_VALUE_BITS:
        return False
    magnitude = abs(value.numerator).bit_length() - value.denominator.bit_length()
    return abs(magnitude) <= MAX_BINARY_MAGNITUDE
