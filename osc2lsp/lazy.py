"""A cached property that never blocks another thread.

``functools.cached_property`` of Python 3.11 takes one lock per property for all
instances of the class (removed in 3.12): a request asking for ``Snapshot.names``
of the latest snapshot waits while the analysis thread computes the same property
of the next one, sharing the interpreter lock with it. This one computes without
a lock; two threads asking at once both compute it, and one value is kept, which
is harmless for values that only depend on the instance.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Generic, TypeVar, overload

T = TypeVar("T")

__all__ = ["cached_property"]


class cached_property(Generic[T]):  # named as the one it replaces
    """Computed on first access, then stored in the instance's ``__dict__``."""

    def __init__(self, func: Callable[[Any], T]) -> None:
        self.func = func
        self.name = func.__name__
        self.__doc__ = func.__doc__

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    @overload
    def __get__(self, instance: None, owner: type | None = None) -> cached_property[T]: ...

    @overload
    def __get__(self, instance: object, owner: type | None = None) -> T: ...

    def __get__(self, instance: object | None, owner: type | None = None) -> Any:
        if instance is None:
            return self
        value = self.func(instance)
        instance.__dict__[self.name] = value
        return value
